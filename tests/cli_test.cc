// `tether simulate` through the real binary: CSV on stdout or in -o, --every, flags that override the scene,
// exit status 2 with a message naming the flag or file for bad input, and exit status 1 with no output file
// left behind for a run that diverges.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "test_files.h"
#include "tether/dynamics/integration/default_gains.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/io/scene_reader.h"
#include "tether/dynamics/io/trajectory_csv.h"

namespace tether {
namespace {

using ::tether::testing::Lines;

using testing::Outcome;
using testing::ReadText;

bool Exists(const std::string& path) { return std::ifstream(path).good(); }

double FirstField(const std::string& line) { return std::strtod(line.c_str(), nullptr); }

// A scratch folder holding the scene files and outputs of one test (test_files.h); Tether() runs the binary.
class CliTest : public ::testing::Test {
 protected:
  std::string Path(const std::string& name) const { return folder_.Path(name); }
  std::string WriteScene(const std::string& name, const std::string& text) const { return folder_.Write(name, text); }
  Outcome Tether(const std::string& args) const { return testing::RunTether(args, folder_); }
  std::vector<std::string> Entries() const { return folder_.Entries(); }

  // No temporary output ("NAME.partial.PID") anywhere in the folder.
  void ExpectNoPartialFiles() const {
    for (const std::string& name : Entries()) EXPECT_EQ(name.find(".partial."), std::string::npos) << name;
  }

  testing::TempFolder folder_{"tether_cli"};
};

// The acceptance checks' pendulum: a 1 kg bob on a 0.7 m rod from 60 degrees, here for 0.1 s.
const char* kPendulum = R"({"dimension": 2,
  "bodies": [{"name": "bob", "type": "particle", "mass": 1.0, "position": [0.60621778264910708, -0.34999999999999992]}],
  "constraints": [{"type": "distance", "bodies": ["world", "bob"], "length": 0.7}],
  "effects": [{"type": "gravity", "acceleration": [0.0, -9.81]}],
  "simulation": {"integrator": "rk4", "step": 0.001, "duration": 0.1},
  "stabilization": {"method": "baumgarte", "alpha": 10.0, "beta": 25.0}})";

// The CSV the library writes for `model`, in process: what the command line must reproduce byte for byte.
std::string ExpectedCsv(const Model<double>& model, int every = 1) {
  std::ostringstream out;
  TrajectoryCsvWriter writer(model, &out);
  Simulate<double>(model, RunOptions{every}, [&writer](const Sample<double>& s) { writer.Write(s); });
  return out.str();
}

TEST_F(CliTest, SimulateWritesTheCsvToStdout) {
  const std::string scene = WriteScene("pendulum.json", kPendulum);
  const Outcome run = Tether("simulate '" + scene + "'");
  ASSERT_EQ(run.status, 0) << run.err;
  const std::vector<std::string> lines = Lines(run.out);
  ASSERT_EQ(lines.size(), 102u);  // header and t = 0, 0.001, ..., 0.1
  EXPECT_EQ(lines[0], "t,bob.x,bob.y,bob.vx,bob.vy,constraint_error,energy");
  EXPECT_EQ(FirstField(lines.back()), 0.1);
  EXPECT_EQ(run.out, ExpectedCsv(ReadSceneFile(scene).model));
}

// a step far too large for the scene drifts off the constraints: said once on stderr, never a silent exit 0; the
// scene's own step says nothing
TEST_F(CliTest, ARunThatDriftsOffItsConstraintsIsWarnedOfOnce) {
  const std::string scene = WriteScene("pendulum.json", kPendulum);
  const Outcome coarse = Tether("simulate '" + scene + "' --step 0.2 --duration 2 -o '" + Path("coarse.csv") + "'");
  ASSERT_EQ(coarse.status, 0) << coarse.err;
  EXPECT_NE(coarse.err.find("the constraints have drifted by"), std::string::npos) << coarse.err;
  EXPECT_NE(coarse.err.find("of the scene's length scale 0.7 m"), std::string::npos) << coarse.err;
  EXPECT_EQ(coarse.err.find("drifted"), coarse.err.rfind("drifted")) << "warned more than once: " << coarse.err;
  const Outcome fine = Tether("simulate '" + scene + "' --duration 2 -o '" + Path("fine.csv") + "'");
  ASSERT_EQ(fine.status, 0) << fine.err;
  EXPECT_EQ(fine.err, "");
}

TEST_F(CliTest, OutputFlagWritesTheFile) {
  const std::string scene = WriteScene("pendulum.json", kPendulum);
  const Outcome run = Tether("simulate '" + scene + "' -o '" + Path("out.csv") + "'");
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(run.out, "");
  EXPECT_EQ(ReadText(Path("out.csv")), ExpectedCsv(ReadSceneFile(scene).model));
  ExpectNoPartialFiles();
}

TEST_F(CliTest, EveryWritesEveryKthStepAndTheLast) {
  const std::string scene = WriteScene("pendulum.json", kPendulum);
  const Outcome run = Tether("simulate '" + scene + "' --every 30");
  ASSERT_EQ(run.status, 0) << run.err;
  const std::vector<std::string> lines = Lines(run.out);
  ASSERT_EQ(lines.size(), 6u);  // header and t = 0, 0.03, 0.06, 0.09 and the last state 0.1
  const double times[5] = {0.0, 0.03, 0.06, 0.09, 0.1};
  for (int k = 0; k < 5; ++k) EXPECT_NEAR(FirstField(lines[k + 1]), times[k], 1e-15);
  EXPECT_EQ(run.out, ExpectedCsv(ReadSceneFile(scene).model, 30));
}

TEST_F(CliTest, FlagsOverrideTheScene) {
  const std::string scene = WriteScene("pendulum.json", kPendulum);
  const Model<double> base = ReadSceneFile(scene).model;

  Model<double> expected = base;
  expected.simulation.duration = 0.05;
  expected.simulation.step = 0.005;
  expected.simulation.integrator = Integrator::kEuler;
  Outcome run = Tether("simulate '" + scene + "' --duration 0.05 --step 0.005 --integrator euler");
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(Lines(run.out).size(), 12u);
  EXPECT_EQ(run.out, ExpectedCsv(expected));

  expected = base;
  expected.stabilization.alpha = 3.0;
  expected.stabilization.beta = 4.0;
  run = Tether("simulate '" + scene + "' --alpha 3 --beta 4");
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(run.out, ExpectedCsv(expected));
  // the gains do change the run
  EXPECT_NE(run.out, ExpectedCsv(base));

  expected = base;
  expected.simulation.integrator = Integrator::kRk45;
  run = Tether("simulate '" + scene + "' --integrator rk45");
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(run.out, ExpectedCsv(expected));
}

TEST_F(CliTest, OneGainFlagKeepsTheRuleForTheOther) {
  // a scene without "stabilization": --alpha alone takes beta from the default rule at the final integrator and
  // step (euler at 2e-3 here, whose rule differs from that of the scene's rk4 at 1e-3)
  std::string text = kPendulum;
  text = text.substr(0, text.find(",\n  \"stabilization\"")) + "}";
  const std::string scene = WriteScene("rule.json", text);
  Model<double> expected = ReadSceneFile(scene).model;
  ASSERT_TRUE(expected.stabilization.gains_from_rule);
  ASSERT_NE(DefaultGains(Integrator::kEuler, 0.002).beta, DefaultGains(Integrator::kRk4, 0.001).beta);
  expected.simulation.integrator = Integrator::kEuler;
  expected.simulation.step = 0.002;
  expected.stabilization.gains_from_rule = false;
  expected.stabilization.alpha = 5.0;
  expected.stabilization.beta = DefaultGains(Integrator::kEuler, 0.002).beta;
  const Outcome run = Tether("simulate '" + scene + "' --alpha 5 --integrator euler --step 0.002");
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(run.out, ExpectedCsv(expected));
}

TEST_F(CliTest, BadFlagValuesExitTwoNamingTheFlag) {
  const std::string scene = WriteScene("pendulum.json", kPendulum);
  const struct {
    std::string flags, named;
  } cases[] = {{"--step -1", "--step"},
               {"--step 0", "--step"},
               {"--step abc", "--step"},
               {"--duration 0", "--duration"},
               {"--integrator rk9", "--integrator"},
               {"--every 0", "--every"},
               {"--alpha -1", "--alpha"},
               {"--no-such-flag", "--no-such-flag"}};
  for (const auto& c : cases) {
    const Outcome run = Tether("simulate '" + scene + "' " + c.flags + " -o '" + Path("out.csv") + "'");
    EXPECT_EQ(run.status, 2) << c.flags << ": " << run.err;
    EXPECT_NE(run.err.find(c.named), std::string::npos) << c.flags << ": " << run.err;
    EXPECT_EQ(run.out, "") << c.flags;
    EXPECT_FALSE(Exists(Path("out.csv"))) << c.flags;
  }
  // the unknown integrator's name is repeated to the user
  EXPECT_NE(Tether("simulate '" + scene + "' --integrator rk9").err.find("rk9"), std::string::npos);
  ExpectNoPartialFiles();
}

TEST_F(CliTest, MissingSceneExitsTwoNamingTheFile) {
  const Outcome run = Tether("simulate '" + Path("does_not_exist.json") + "'");
  EXPECT_EQ(run.status, 2);
  EXPECT_NE(run.err.find("does_not_exist.json"), std::string::npos) << run.err;
}

TEST_F(CliTest, InvalidSceneExitsTwoNamingFileAndPointer) {
  std::string text = kPendulum;
  text.replace(text.find("\"mass\": 1.0"), 11, "\"mass\": -1.0");
  const std::string scene = WriteScene("bad.json", text);
  const Outcome run = Tether("simulate '" + scene + "' -o '" + Path("out.csv") + "'");
  EXPECT_EQ(run.status, 2);
  EXPECT_NE(run.err.find("bad.json"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("/bodies/0/mass"), std::string::npos) << run.err;
  EXPECT_FALSE(Exists(Path("out.csv")));
  ExpectNoPartialFiles();
}

TEST_F(CliTest, UnwritableOutputExitsTwoNamingTheFile) {
  const std::string scene = WriteScene("pendulum.json", kPendulum);
  const Outcome run = Tether("simulate '" + scene + "' -o '" + Path("missing_folder/out.csv") + "'");
  EXPECT_EQ(run.status, 2);
  EXPECT_NE(run.err.find("missing_folder/out.csv"), std::string::npos) << run.err;
}

TEST_F(CliTest, NumberOverflowInTheSceneIsBadInput) {
  // 1e400 is valid JSON syntax but no double: bad input (status 2) naming the file, not a failed run (status 1)
  std::string text = kPendulum;
  text.replace(text.find("\"mass\": 1.0"), 11, "\"mass\": 1e400");
  const std::string scene = WriteScene("overflow.json", text);
  const Outcome run = Tether("simulate '" + scene + "' -o '" + Path("out.csv") + "'");
  EXPECT_EQ(run.status, 2) << run.err;
  EXPECT_NE(run.err.find("overflow.json"), std::string::npos) << run.err;
  EXPECT_FALSE(Exists(Path("out.csv")));
}

TEST_F(CliTest, SceneThatCannotBeAssembledExitsTwoNamingFileAndConstraint) {
  // two rods of lengths 1 and 3 from the origin to the same particle
  const std::string scene = WriteScene("unassemblable.json", R"({
    "bodies": [{"name": "p", "type": "particle", "mass": 1.0, "position": [1.0, 0.0]}],
    "constraints": [{"type": "distance", "bodies": ["world", "p"], "length": 1.0},
                    {"type": "distance", "bodies": ["world", "p"], "length": 3.0}]})");
  const Outcome run = Tether("simulate '" + scene + "' -o '" + Path("out.csv") + "'");
  EXPECT_EQ(run.status, 2) << run.err;
  EXPECT_NE(run.err.find("constraint"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("unassemblable.json"), std::string::npos) << run.err;  // CONTRACT: names the file
  EXPECT_FALSE(Exists(Path("out.csv")));
  ExpectNoPartialFiles();
}

TEST_F(CliTest, DivergingRunExitsOneAndLeavesNoOutput) {
  // explicit Euler at h = 1e-2 with beta = 1e8: h^2 beta = 1e4, far outside Euler's stable range
  const std::string scene = WriteScene("pendulum.json", kPendulum);
  const std::string flags = " --integrator euler --step 0.01 --duration 10 --alpha 10 --beta 1e8";
  Outcome run = Tether("simulate '" + scene + "'" + flags + " -o '" + Path("out.csv") + "'");
  EXPECT_EQ(run.status, 1) << run.err;
  EXPECT_NE(run.err.find("diverged"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("/constraints/0"), std::string::npos) << run.err;  // which constraint
  EXPECT_FALSE(Exists(Path("out.csv")));
  ExpectNoPartialFiles();
  // and to stdout: no partial CSV either
  run = Tether("simulate '" + scene + "'" + flags);
  EXPECT_EQ(run.status, 1) << run.err;
  EXPECT_EQ(run.out, "");
}

}  // namespace
}  // namespace tether
