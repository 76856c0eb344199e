// `tether identify` and `tether fit` through the real binary (TETHER_EXECUTABLE): the JSON on stdout (parameters,
// standard_deviation, initial_cost, final_cost, correlation, residuals, warnings), equal to the library's
// Identify; --data repeated; -o writing the scene with the estimates in place, which `tether simulate` accepts;
// the acceptance check's ball fit; and exit status 2 with a message naming the flag, file, line or pointer for
// bad input, without any -o file left behind.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "test_files.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/io/scene_reader.h"
#include "tether/tuning/identify.h"

namespace tether {
namespace {

using nlohmann::json;
using testing::Outcome;
using testing::ReadText;

bool Contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// A 0.5 kg cart on a horizontal slider, pulled back by a damped spring (the guess: stiffness 30, damping 0.3;
// the truth: 40 and 0.6), released at x = 0.3, for 1.5 s with rk4 at 2e-3 s.
json SliderSpring(double stiffness, double damping) {
  return {{"dimension", 2},
          {"bodies", {{{"name", "cart"}, {"type", "particle"}, {"mass", 0.5}, {"position", {0.3, 0.0}}}}},
          {"constraints",
           {{{"type", "slider"},
             {"bodies", {"world", "cart"}},
             {"points", {{0.0, 0.0}, {0.0, 0.0}}},
             {"axis", {1.0, 0.0}}}}},
          {"effects",
           {{{"type", "gravity"}, {"acceleration", {0.0, -9.81}}},
            {{"type", "spring"},
             {"bodies", {"world", "cart"}},
             {"points", {{-1.0, 0.0}, {0.0, 0.0}}},
             {"stiffness", stiffness},
             {"rest_length", 1.0},
             {"damping", damping}}}},
          {"simulation", {{"integrator", "rk4"}, {"step", 2e-3}, {"duration", 1.5}, {"tolerance", 1e-10}}},
          {"stabilization", {{"method", "baumgarte"}, {"alpha", 20.0}, {"beta", 100.0}}}};
}

const std::vector<std::string> kPointers = {"/effects/1/stiffness", "/effects/1/damping"};
const std::vector<double> kTruth = {40.0, 0.6};
constexpr double kNoise = 1e-3;  // m and m/s

class IdentifyCliTest : public ::testing::Test {
 protected:
  Outcome Tether(const std::string& args) const { return testing::RunTether(args, folder_); }
  std::string Write(const std::string& name, const std::string& text) const { return folder_.Write(name, text); }
  std::string Path(const std::string& name) const { return folder_.Path(name); }

  // The guess scene and two recordings of the truth (rk45, tolerance 1e-10) with N(0, 1e-3^2) noise: cart.x
  // every 0.03 s, and cart.vx every 0.1 s from 0.05 s.
  void WriteSliderProblem() {
    scene_ = Write("slider.json", SliderSpring(30.0, 0.3).dump(2));
    json truth = SliderSpring(kTruth[0], kTruth[1]);
    truth["simulation"]["integrator"] = "rk45";
    truth["simulation"]["step"] = 1e-3;
    const Model<double> model = ParseScene(truth, "truth.json").model;
    std::mt19937 generator(7);
    std::normal_distribution<double> noise(0.0, kNoise);
    auto record = [&](const std::string& name, const std::string& column, double first, double spacing) {
      std::ostringstream csv;
      csv.precision(17);
      csv << "t," << column << "\n";
      RunOptions run;
      run.every = 1 << 30;
      for (double t = first; t <= 1.5 + 1e-12; t += spacing) run.stops.push_back(t);
      Simulate<double>(model, run, [&](const Sample<double>& s) {
        if (s.stop >= 0) csv << s.t << "," << (column == "cart.x" ? s.q[0] : s.v[0]) + noise(generator) << "\n";
      });
      return Write(name, csv.str());
    };
    positions_ = record("positions.csv", "cart.x", 0.03, 0.03);
    velocities_ = record("velocities.csv", "cart.vx", 0.05, 0.1);
  }

  std::string Problem() const {
    std::string args = "'" + scene_ + "' --data '" + positions_ + "' --data '" + velocities_ + "'";
    for (const std::string& p : kPointers) args += " --param " + p;
    return args;
  }

  // Runs `command` (bad input), expects exit status 2 with every one of `parts` in the message, nothing on stdout
  // and no -o file.
  void ExpectInputError(const std::string& command, const std::vector<std::string>& parts) {
    const std::string output = Path("never.json");
    const Outcome run = Tether(command + " -o '" + output + "'");
    EXPECT_EQ(run.status, 2) << command << "\n" << run.err;
    for (const std::string& part : parts) EXPECT_TRUE(Contains(run.err, part)) << command << ": " << run.err;
    EXPECT_EQ(run.out, "") << command;
    for (const std::string& name : folder_.Entries()) {  // neither the file nor a temporary one beside it
      EXPECT_EQ(name.find("never"), std::string::npos) << command << " left " << name;
    }
  }

  testing::TempFolder folder_{"tether_identify_cli"};
  std::string scene_, positions_, velocities_;
};

TEST_F(IdentifyCliTest, PrintsTheReportAndWritesTheSceneWithTheEstimates) {
  WriteSliderProblem();
  const std::string fitted = Path("fitted.json");
  const Outcome run = Tether("identify " + Problem() + " -o '" + fitted + "'");
  ASSERT_EQ(run.status, 0) << run.err;
  const json out = json::parse(run.out);
  for (const char* key :
       {"parameters", "standard_deviation", "initial_cost", "final_cost", "correlation", "residuals", "warnings"}) {
    EXPECT_TRUE(out.contains(key)) << key << " missing from " << run.out;
  }
  ASSERT_TRUE(out["parameters"].is_object());
  ASSERT_TRUE(out["warnings"].is_array());
  EXPECT_TRUE(out["warnings"].empty()) << out["warnings"];
  EXPECT_LT(out["final_cost"].get<double>(), out["initial_cost"].get<double>());
  for (size_t i = 0; i < kPointers.size(); ++i) {
    const double estimate = out["parameters"][kPointers[i]].get<double>();
    const double deviation = out["standard_deviation"][kPointers[i]].get<double>();
    EXPECT_NEAR(estimate, kTruth[i], 0.02 * kTruth[i]) << kPointers[i];  // 2%
    EXPECT_GT(deviation, 0.0);
    EXPECT_LE(std::abs(estimate - kTruth[i]), 4 * deviation) << kPointers[i];  // covered by 4 sigma
    EXPECT_NEAR(out["correlation"][kPointers[i]][kPointers[i]].get<double>(), 1.0, 1e-12);
  }
  // --data repeated: the residuals of both recordings, a row per file and column
  ASSERT_EQ(out["residuals"].size(), 2u) << out["residuals"];
  EXPECT_EQ(out["residuals"][0]["file"], positions_);
  EXPECT_EQ(out["residuals"][0]["column"], "cart.x");
  EXPECT_EQ(out["residuals"][0]["count"], 50);
  EXPECT_EQ(out["residuals"][1]["file"], velocities_);
  EXPECT_EQ(out["residuals"][1]["column"], "cart.vx");
  EXPECT_EQ(out["residuals"][1]["count"], 15);

  // the library in process gives the same estimates (JSON prints doubles in round-trip form)
  const Scene scene = ReadSceneFile(scene_);
  const IdentifyResult r =
      Identify(scene.model, ParameterSet(scene, kPointers),
               {ReadObservations(positions_, scene.model), ReadObservations(velocities_, scene.model)}, {});
  for (size_t i = 0; i < kPointers.size(); ++i) {
    EXPECT_NEAR(out["parameters"][kPointers[i]].get<double>(), r.estimate[i], 1e-12 * std::abs(r.estimate[i]));
  }
  EXPECT_NEAR(out["final_cost"].get<double>(), r.final_cost, 1e-12 * r.final_cost);

  // -o: the guess scene with the estimates in place and nothing else changed
  const json written = json::parse(ReadText(fitted));
  json expected = json::parse(ReadText(scene_));
  for (const std::string& p : kPointers) expected[json::json_pointer(p)] = out["parameters"][p];
  EXPECT_EQ(written, expected);
  // ... which `tether simulate` runs
  const std::string trajectory = Path("trajectory.csv");
  const Outcome simulate = Tether("simulate '" + fitted + "' -o '" + trajectory + "'");
  ASSERT_EQ(simulate.status, 0) << simulate.err;
  const std::string csv = ReadText(trajectory);
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "t,cart.x,cart.y,cart.vx,cart.vy,constraint_error,energy");
  EXPECT_GT(std::count(csv.begin(), csv.end(), '\n'), 700);  // 750 steps of 2e-3 s plus the header
}

TEST_F(IdentifyCliTest, FitFindsTheBallsInitialVelocity) {
  // the acceptance check: reach (2, 0.5) at t = 1 from the origin under gravity
  const json ball = {
      {"dimension", 2},
      {"bodies",
       {{{"name", "ball"}, {"type", "particle"}, {"mass", 0.5}, {"position", {0.0, 0.0}}, {"velocity", {1.0, 1.0}}}}},
      {"constraints", json::array()},
      {"effects", {{{"type", "gravity"}, {"acceleration", {0.0, -9.81}}}}},
      {"simulation", {{"integrator", "rk4"}, {"step", 1e-3}, {"duration", 1.0}}},
      {"stabilization", {{"method", "none"}}}};
  const std::string scene = Write("fit_ball.json", ball.dump());
  const std::string targets = Write("fit_targets.csv", "t,ball.x,ball.y\n1.0,2.0,0.5\n");
  const std::string fitted = Path("fitted.json");
  const Outcome run = Tether("fit '" + scene + "' --data '" + targets +
                             "' --param /bodies/0/velocity/0 --param /bodies/0/velocity/1 -o '" + fitted + "'");
  ASSERT_EQ(run.status, 0) << run.err;
  const json out = json::parse(run.out);
  for (const char* key : {"parameters", "standard_deviation", "initial_cost", "final_cost", "warnings"}) {
    EXPECT_TRUE(out.contains(key)) << key;
  }
  // 1e-6 m/s: rk4 is exact for constant acceleration (the acceptance check allows 1e-4)
  EXPECT_NEAR(out["parameters"]["/bodies/0/velocity/0"].get<double>(), 2.0, 1e-6);
  EXPECT_NEAR(out["parameters"]["/bodies/0/velocity/1"].get<double>(), 0.5 + 9.81 / 2, 1e-6);
  // an exact fit has no standard deviation: null
  EXPECT_TRUE(out["standard_deviation"]["/bodies/0/velocity/1"].is_null()) << out["standard_deviation"];
  const json written = json::parse(ReadText(fitted));
  EXPECT_NEAR(written["bodies"][0]["velocity"][1].get<double>(), 0.5 + 9.81 / 2, 1e-6);
  EXPECT_TRUE(Tether("simulate '" + fitted + "' -o '" + Path("ball.csv") + "'").status == 0);
}

TEST_F(IdentifyCliTest, BadFlagsExitTwoNamingTheFlag) {
  WriteSliderProblem();
  const std::string identify = "identify " + Problem();
  ExpectInputError(identify + " --bound /effects/1/stiffness", {"--bound", "/effects/1/stiffness"});
  ExpectInputError(identify + " --bound /effects/1/stiffness=a:50", {"--bound", "'a'"});
  ExpectInputError(identify + " --bound /effects/1/stiffness=50:10", {"--bound"});
  ExpectInputError(identify + " --bound /bodies/0/mass=0.1:10", {"--bound", "/bodies/0/mass"});
  ExpectInputError(identify + " --bound /effects/1/stiffness=45:60", {"--bound", "/effects/1/stiffness", "30"});
  ExpectInputError(identify + " --loss foo", {"--loss", "foo"});
  ExpectInputError(identify + " --loss huber:0", {"--loss"});
  ExpectInputError(identify + " --segments 0", {"--segments"});
  ExpectInputError(identify + " --optimizer nlopt:NOPE", {"--optimizer", "NOPE"});
  ExpectInputError(identify + " --optimizer simplex", {"--optimizer", "simplex"});
  ExpectInputError("fit " + Problem() + " --smooth -1", {"--smooth"});
}

TEST_F(IdentifyCliTest, BadDataAndParametersExitTwoNamingTheFileLineAndPointer) {
  WriteSliderProblem();
  const std::string unknown = Write("unknown.csv", "t,cart.x,cart.z\n0.1,0.2,0.0\n");
  ExpectInputError(
      "identify '" + scene_ + "' --data '" + positions_ + "' --data '" + unknown + "' --param /effects/1/stiffness",
      {"unknown.csv", "line 1", "cart.z"});
  const std::string bad_cell = Write("bad_cell.csv", "t,cart.x\n0.1,0.2\n0.2,abc\n");
  ExpectInputError("identify '" + scene_ + "' --data '" + bad_cell + "' --param /effects/1/stiffness",
                   {"bad_cell.csv", "line 3"});
  // a parameter that is not in the scene
  ExpectInputError("identify '" + scene_ + "' --data '" + positions_ + "' --param /effects/7/stiffness",
                   {"slider.json", "/effects/7/stiffness"});
  ExpectInputError("fit '" + scene_ + "' --data '" + positions_ + "' --param /bodies/0/spin",
                   {"slider.json", "/bodies/0/spin"});
  // a missing --data or --param is a usage error
  ExpectInputError("identify '" + scene_ + "' --param /effects/1/stiffness", {"--data"});
  ExpectInputError("identify '" + scene_ + "' --data '" + positions_ + "'", {"--param"});
}

}  // namespace
}  // namespace tether
