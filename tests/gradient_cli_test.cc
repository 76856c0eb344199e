// `tether gradient` through the real binary: JSON with the loss, the gradient keyed by pointer, the seconds and
// the method, equal to the library's; --method fd close to --method jet; exit status 2 with a message naming the
// flag, file, pointer or CSV line for bad input; exit status 1 for a run that diverges.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "test_files.h"
#include "tether/autodiff/gradient_method.h"
#include "tether/dynamics/io/scene_reader.h"
#include "tether/dynamics/io/trajectory_csv.h"

namespace tether {
namespace {

using testing::Outcome;

// The acceptance checks' pendulum (a 1 kg bob on a 0.7 m rod from 60 degrees), here for 0.3 s, with damping.
const char* kPendulum = R"({"dimension": 2,
  "bodies": [{"name": "bob", "type": "particle", "mass": 1.0, "position": [0.60621778264910708, -0.34999999999999992]}],
  "constraints": [{"type": "distance", "bodies": ["world", "bob"], "length": 0.7}],
  "effects": [{"type": "gravity", "acceleration": [0.0, -9.81]}, {"type": "damping", "coefficient": 0.3}],
  "simulation": {"integrator": "rk4", "step": 0.001, "duration": 0.3},
  "stabilization": {"method": "baumgarte", "alpha": 10.0, "beta": 25.0}})";

const std::vector<std::string> kParameters = {"/bodies/0/mass", "/constraints/0/length", "/effects/0/acceleration/1",
                                              "/effects/1/coefficient"};

// A scratch folder with the scene and data files of one test (test_files.h); Tether() runs the binary.
class GradientCliTest : public ::testing::Test {
 protected:
  std::string Write(const std::string& name, const std::string& text) const { return folder_.Write(name, text); }
  Outcome Tether(const std::string& args) const { return testing::RunTether(args, folder_); }

  // The pendulum scene and observations of its trajectory with the bob 10% heavier and the rod 2% longer, at
  // times on and off the grid, with a position, a velocity and the energy.
  void WritePendulumProblem() {
    scene_ = Write("pendulum.json", kPendulum);
    nlohmann::json truth = nlohmann::json::parse(kPendulum);
    truth["bodies"][0]["mass"] = 1.1;
    truth["constraints"][0]["length"] = 0.714;
    const Model<double> model = ParseScene(truth, "truth.json").model;
    std::ostringstream csv;
    csv.precision(17);
    csv << "t,bob.x,bob.vy,energy\n";
    RunOptions run;
    run.every = 1 << 30;
    run.stops = {0.05, 0.1234, 0.2, 0.25, 0.3};
    Simulate<double>(model, run, [&csv](const Sample<double>& s) {
      if (s.stop >= 0) csv << s.t << "," << s.q[0] << "," << s.v[1] << "," << s.energy << "\n";
    });
    data_ = Write("obs.csv", csv.str());
  }

  // `tether gradient` on the pendulum problem with --method `method`: its JSON, or null (and a failure) when it
  // does not exit 0.
  nlohmann::json GradientBy(const std::string& method) const {
    const Outcome run = Tether("gradient '" + scene_ + "' --data '" + data_ + "'" + Params() + " --method " + method);
    EXPECT_EQ(run.status, 0) << method << ": " << run.err;
    return run.status == 0 ? nlohmann::json::parse(run.out) : nlohmann::json();
  }

  std::string Params(const std::vector<std::string>& pointers = kParameters) const {
    std::string out;
    for (const std::string& p : pointers) out += " --param " + p;
    return out;
  }

  testing::TempFolder folder_{"tether_gradient_cli"};
  std::string scene_, data_;
};

bool Contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST_F(GradientCliTest, PrintsLossGradientSecondsAndMethodAsTheLibraryComputesThem) {
  WritePendulumProblem();
  const Outcome run = Tether("gradient '" + scene_ + "' --data '" + data_ + "'" + Params());
  ASSERT_EQ(run.status, 0) << run.err;
  const nlohmann::json out = nlohmann::json::parse(run.out);
  ASSERT_TRUE(out["loss"].is_number()) << run.out;
  ASSERT_TRUE(out["gradient"].is_object()) << run.out;
  ASSERT_TRUE(out["seconds"].is_number()) << run.out;
  EXPECT_GE(out["seconds"].get<double>(), 0.0);
  EXPECT_EQ(out["method"], "jet");  // auto, the default, with fewer parameters than kAdjointCrossover
  EXPECT_EQ(out["gradient"].size(), kParameters.size());

  // the library in process gives the same numbers (JSON prints doubles in round-trip form: 1e-15 relative)
  const Scene scene = ReadSceneFile(scene_);
  const ParameterSet parameters(scene, kParameters);
  const LossGradient expected = JetLossGradient(scene.model, parameters, ReadObservations(data_, scene.model));
  EXPECT_GT(expected.loss, 1e-6);
  EXPECT_NEAR(out["loss"].get<double>(), expected.loss, 1e-15 * expected.loss);
  for (size_t i = 0; i < kParameters.size(); ++i) {
    ASSERT_TRUE(out["gradient"].contains(kParameters[i])) << run.out;
    const double g = out["gradient"][kParameters[i]].get<double>();
    EXPECT_NEAR(g, expected.gradient[i], 1e-15 * std::abs(expected.gradient[i])) << kParameters[i];
    EXPECT_NE(g, 0.0) << kParameters[i];
  }
}

TEST_F(GradientCliTest, CentralDifferencesAgreeWithJets) {
  WritePendulumProblem();
  const nlohmann::json a = GradientBy("jet"), b = GradientBy("fd");
  ASSERT_FALSE(a.is_null() || b.is_null());
  EXPECT_EQ(a["method"], "jet");
  EXPECT_EQ(b["method"], "fd");
  // the same loss: both evaluate it with a double-valued run (Jet value parts equal it to round-off)
  EXPECT_NEAR(a["loss"].get<double>(), b["loss"].get<double>(), 1e-12 * a["loss"].get<double>());
  double scale = 0.0;
  for (const std::string& p : kParameters) scale = std::max(scale, std::abs(a["gradient"][p].get<double>()));
  for (const std::string& p : kParameters) {
    // the library's central differences (step 1e-5 relative, no extrapolation) are accurate to about
    // h^2 ~ 1e-10 relative plus round-off 1e-14 / 1e-5: 1e-6 of the largest component is ample
    EXPECT_NEAR(b["gradient"][p].get<double>(), a["gradient"][p].get<double>(), 1e-6 * scale) << p;
  }
}

// --method adjoint gives the Jets' numbers to 1e-8 (the same derivative taken in reverse); auto's choice by the
// parameter count is checked on the library's rule (the pendulum has fewer parameters than the crossover).
TEST_F(GradientCliTest, TheAdjointAgreesWithJetsAndAutoChoosesByTheParameterCount) {
  WritePendulumProblem();
  const nlohmann::json a = GradientBy("jet"), b = GradientBy("adjoint");
  ASSERT_FALSE(a.is_null() || b.is_null());
  EXPECT_EQ(b["method"], "adjoint");
  // what it kept: 300 steps of 1 ms and one onto t = 0.1234, every state (they fit in the budget)
  EXPECT_EQ(b["adjoint"]["steps"], 301) << b;
  EXPECT_EQ(b["adjoint"]["interval"], 1) << b;
  EXPECT_GT(b["adjoint"]["memory_bytes"].get<double>(), 0.0) << b;
  EXPECT_FALSE(a.contains("adjoint")) << a;
  EXPECT_NEAR(b["loss"].get<double>(), a["loss"].get<double>(), 1e-12 * a["loss"].get<double>());
  for (const std::string& p : kParameters) {
    const double g = a["gradient"][p].get<double>();
    EXPECT_NEAR(b["gradient"][p].get<double>(), g, 1e-8 * std::abs(g)) << p;
  }
  EXPECT_EQ(ResolveGradientMethod(GradientMethod::kAuto, kAdjointCrossover - 1), GradientMethod::kJet);
  EXPECT_EQ(ResolveGradientMethod(GradientMethod::kAuto, kAdjointCrossover), GradientMethod::kAdjoint);
  EXPECT_EQ(ResolveGradientMethod(GradientMethod::kCentral, 1000), GradientMethod::kCentral);
}

TEST_F(GradientCliTest, MissingDataFlagExitsTwo) {
  WritePendulumProblem();
  const Outcome run = Tether("gradient '" + scene_ + "'" + Params());
  EXPECT_EQ(run.status, 2) << run.err;
  EXPECT_TRUE(Contains(run.err, "--data")) << run.err;
  EXPECT_EQ(run.out, "");
}

TEST_F(GradientCliTest, UnknownPointerExitsTwoNamingFileAndPointer) {
  WritePendulumProblem();
  const Outcome run = Tether("gradient '" + scene_ + "' --data '" + data_ + "'" + Params({"/bodies/0/mass", "/bodies/3/mass"}));
  EXPECT_EQ(run.status, 2) << run.err;
  EXPECT_TRUE(Contains(run.err, "pendulum.json")) << run.err;
  EXPECT_TRUE(Contains(run.err, "/bodies/3/mass")) << run.err;
  EXPECT_EQ(run.out, "");
}

// --tie: the rod's length follows the mass (a made-up law), so d loss / d mass counts the length's change too; a
// tie naming an unknown pointer, or giving a value the scene format refuses, exits 2 naming the flag and the
// pointer, with nothing on stdout.
TEST_F(GradientCliTest, ATiedPointerFollowsItsExpressionAndAnUnknownOneExitsTwo) {
  WritePendulumProblem();
  const std::string base = "gradient '" + scene_ + "' --data '" + data_ + "' --param /bodies/0/mass";
  const Outcome free = Tether(base);
  const Outcome tied = Tether(base + " --tie '/constraints/0/length={/bodies/0/mass}*0.7'");
  const Outcome tied_adjoint = Tether(base + " --tie '/constraints/0/length={/bodies/0/mass}*0.7' --method adjoint");
  ASSERT_EQ(free.status, 0) << free.err;
  ASSERT_EQ(tied.status, 0) << tied.err;
  ASSERT_EQ(tied_adjoint.status, 0) << tied_adjoint.err;
  const auto g = [](const Outcome& run) { return nlohmann::json::parse(run.out)["gradient"]["/bodies/0/mass"].get<double>(); };
  // at mass 1 the tie leaves the length 0.7 as written: the same loss, another gradient
  EXPECT_EQ(nlohmann::json::parse(tied.out)["loss"], nlohmann::json::parse(free.out)["loss"]);
  EXPECT_GT(std::abs(g(tied) - g(free)), 1e-3 * std::abs(g(free)));
  EXPECT_NEAR(g(tied_adjoint), g(tied), 1e-8 * std::abs(g(tied)));
  const Outcome unknown = Tether(base + " --tie '/constraints/0/length={/bodies/4/mass}'");
  EXPECT_EQ(unknown.status, 2) << unknown.err;
  EXPECT_TRUE(Contains(unknown.err, "--tie")) << unknown.err;
  EXPECT_TRUE(Contains(unknown.err, "/bodies/4/mass")) << unknown.err;
  EXPECT_EQ(unknown.out, "");
  // a tied value the scene format refuses is refused as a file's would be, naming the flag and the pointer
  for (const std::string& tie : {"/constraints/0/length=-0.7", "/constraints/0/length={/bodies/0/mass}-1"}) {
    const Outcome refused = Tether(base + " --tie '" + tie + "'");
    EXPECT_EQ(refused.status, 2) << tie << ": " << refused.err;
    EXPECT_TRUE(Contains(refused.err, "--tie")) << refused.err;
    EXPECT_TRUE(Contains(refused.err, tie.substr(0, tie.find('=')))) << refused.err;
    EXPECT_EQ(refused.out, "");
  }
}

TEST_F(GradientCliTest, NonDifferentiablePointerExitsTwoNamingFileAndPointer) {
  WritePendulumProblem();
  for (const std::string& pointer : {"/simulation/step", "/bodies/0/name", "/bodies/0/position"}) {
    const Outcome run = Tether("gradient '" + scene_ + "' --data '" + data_ + "' --param " + pointer);
    EXPECT_EQ(run.status, 2) << pointer << ": " << run.err;
    EXPECT_TRUE(Contains(run.err, "pendulum.json")) << run.err;
    EXPECT_TRUE(Contains(run.err, pointer)) << run.err;
    EXPECT_EQ(run.out, "") << pointer;
  }
}

TEST_F(GradientCliTest, BadDataFileExitsTwoNamingFileAndLine) {
  WritePendulumProblem();
  const std::string unknown = Write("unknown.csv", "t,bob.x,bob.spin\n0.1,0.5,1\n");
  Outcome run = Tether("gradient '" + scene_ + "' --data '" + unknown + "'" + Params());
  EXPECT_EQ(run.status, 2) << run.err;
  EXPECT_TRUE(Contains(run.err, "unknown.csv")) << run.err;
  EXPECT_TRUE(Contains(run.err, "line 1")) << run.err;
  EXPECT_TRUE(Contains(run.err, "bob.spin")) << run.err;
  EXPECT_EQ(run.out, "");

  const std::string late = Write("late.csv", "t,bob.x\n0.1,0.5\n0.2,0.4\n0.9,0.3\n");  // after the 0.3 s run
  run = Tether("gradient '" + scene_ + "' --data '" + late + "'" + Params());
  EXPECT_EQ(run.status, 2) << run.err;
  EXPECT_TRUE(Contains(run.err, "late.csv")) << run.err;
  EXPECT_TRUE(Contains(run.err, "line 4")) << run.err;

  run = Tether("gradient '" + scene_ + "' --data '" + folder_.Path("absent.csv") + "'" + Params());
  EXPECT_EQ(run.status, 2) << run.err;
  EXPECT_TRUE(Contains(run.err, "absent.csv")) << run.err;
}

TEST_F(GradientCliTest, UnknownMethodExitsTwoNamingTheFlag) {
  WritePendulumProblem();
  const Outcome run = Tether("gradient '" + scene_ + "' --data '" + data_ + "'" + Params() + " --method xyz");
  EXPECT_EQ(run.status, 2) << run.err;
  EXPECT_TRUE(Contains(run.err, "--method")) << run.err;
  EXPECT_TRUE(Contains(run.err, "xyz")) << run.err;
  EXPECT_EQ(run.out, "");
}

TEST_F(GradientCliTest, DivergingSceneExitsOne) {
  // explicit Euler at h = 1e-2 with beta = 1e8: h^2 beta = 1e4, far outside Euler's stable range
  nlohmann::json diverging = nlohmann::json::parse(kPendulum);
  diverging["simulation"] = {{"integrator", "euler"}, {"step", 0.01}, {"duration", 2.0}};
  diverging["stabilization"] = {{"method", "baumgarte"}, {"alpha", 10.0}, {"beta", 1e8}};
  const std::string scene = Write("diverging.json", diverging.dump());
  const std::string data = Write("data.csv", "t,bob.x\n0.5,0.6\n1.5,0.6\n");
  for (const std::string method : {"jet", "fd"}) {
    const Outcome run = Tether("gradient '" + scene + "' --data '" + data + "'" + Params() + " --method " + method);
    EXPECT_EQ(run.status, 1) << method << ": " << run.err;
    EXPECT_TRUE(Contains(run.err, "diverged")) << run.err;
    EXPECT_TRUE(Contains(run.err, "diverging.json")) << run.err;
    EXPECT_TRUE(Contains(run.err, "/constraints/0")) << run.err;  // which constraint
    EXPECT_EQ(run.out, "") << method;
  }
}

}  // namespace
}  // namespace tether
