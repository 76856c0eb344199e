// Trajectory optimisation with `tether fit` (tuning/src/trajectory_fit.h): effort, inequality targets, starts.
// Checked through the command line:
//   - a rotor (a rod turning about its centre, no gravity, a motor at its axle) brought from rest to 1 rad at rest
//     in 1 s with the least effort int tau^2 dt: the exact optimum is the linear torque tau(t) = 6 I theta / T^2
//     (1 - 2 t / T) (the minimum-energy control of a double integrator), which a schedule with knots on the
//     integrator's grid represents exactly, and which rk4 integrates exactly (the angle is cubic between knots);
//     the written scene, run by `tether simulate`, gives the constraint values the report states, digit for digit;
//   - a pendulum with a 2 N m motor (less than the 4.9 N m that holds it level) swung up to within 0.14 rad of
//     upright and at rest within 0.2 rad/s in 3 s: by multiple shooting (6 segments, its continuity closed) both
//     starts reach it, at the cost single shooting reaches from the hanging pendulum;
//   - an unreachable target: exit status 1, the closest result's JSON with "feasible": false and the stopping
//     reason, a message on stderr, and no -o file;
//   - the rotor's turn with its rate bounded over the whole run (a path constraint): the exact optimum, which
//     accelerates to the bound, cruises on it and brakes;
//   - bad flags: exit status 2 naming the flag;
//   - examples on shipped 3D scenes: the cart-pole swung up by the force on its rail, the 7-joint arm's fingertip
//     put into a 1 cm box; the written scenes reproduce the reported values.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "test_files.h"

namespace tether {
namespace {

using nlohmann::json;
using testing::Outcome;
using testing::ReadText;

// A rod pinned to the world by the joint "axle" (at its centre, or at its end under gravity, hanging), its motor
// scheduled on `knots` knots over [0, duration], zero everywhere.
json Rod(bool pendulum, double duration, int knots) {
  std::vector<double> times, values(knots, 0.0);
  for (int k = 0; k < knots; ++k) times.push_back(duration * k / (knots - 1));
  json effects = {{{"type", "joint_torque"}, {"joint", "axle"}, {"schedule", {{"times", times}, {"values", values}}}}};
  if (pendulum) effects.insert(effects.begin(), json{{"type", "gravity"}, {"acceleration", {0.0, -9.81}}});
  return {{"dimension", 2},
          {"bodies",
           {{{"name", "rod"},
             {"type", "rigid"},
             {"mass", 1.0},
             {"inertia", pendulum ? 1.0 / 12 : 0.5},
             {"position", {0.0, pendulum ? -0.5 : 0.0}},
             {"angle", pendulum ? -M_PI / 2 : 0.0}}}},
          {"constraints",
           {{{"type", "pin"},
             {"name", "axle"},
             {"bodies", {"world", "rod"}},
             {"points", {{0.0, 0.0}, {pendulum ? -0.5 : 0.0, 0.0}}}}}},
          {"effects", effects},
          {"simulation", {{"integrator", "rk4"}, {"step", 0.01}, {"duration", duration}}}};
}

class TrajectoryFitTest : public ::testing::Test {
 protected:
  Outcome Tether(const std::string& args) const { return testing::RunTether(args, folder_); }
  std::string Write(const std::string& name, const std::string& text) const { return folder_.Write(name, text); }
  std::string Path(const std::string& name) const { return folder_.Path(name); }
  testing::TempFolder folder_{"tether_trajectory_fit"};
};

// Every value of a CSV column, row by row.
std::vector<double> Column(const std::string& csv, const std::string& column) {
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  std::istringstream header(line);
  for (std::string cell; std::getline(header, cell, ',');) names.push_back(cell);
  const size_t c = std::find(names.begin(), names.end(), column) - names.begin();
  std::vector<double> values;
  if (c == names.size()) {
    ADD_FAILURE() << "no column " << column;
    return values;
  }
  while (std::getline(in, line)) {
    std::istringstream row(line);
    std::vector<std::string> cells;
    for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
    if (c < cells.size()) values.push_back(std::stod(cells[c]));
  }
  return values;
}

// The value of a CSV column in the last row.
double LastValue(const std::string& csv, const std::string& column) {
  const std::vector<double> values = Column(csv, column);
  return values.empty() ? NAN : values.back();
}

TEST_F(TrajectoryFitTest, TheLeastEffortRotorTurnIsTheLinearTorqueAndTheWrittenSceneReproducesIt) {
  const std::string scene = Write("rotor.json", Rod(false, 1.0, 11).dump());
  const std::string fitted = Path("rotor_fit.json");
  const Outcome run = Tether("fit '" + scene + "' --param '/effects/0/schedule/values/*' --bound "
                             "'/effects/0/schedule/values/*=-10:10' --effort 1 --at-least axle.angle=1@1 --at-most "
                             "axle.angle=1.001@1 --at-least axle.omega=-0.001@1 --at-most axle.omega=0.001@1 -o '" +
                             fitted + "'");
  ASSERT_EQ(run.status, 0) << run.err;
  const json out = json::parse(run.out);
  EXPECT_TRUE(out["feasible"].get<bool>());
  EXPECT_FALSE(out["failed"].get<bool>());
  EXPECT_EQ(out["gradient_method"], "jet");
  // tau(t) = 6 I theta / T^2 (1 - 2t) = 3 (1 - 2t); the omega band of 1e-3 rad/s moves it by about 1e-3
  for (int k = 0; k <= 10; ++k) {
    const std::string pointer = "/effects/0/schedule/values/" + std::to_string(k);
    EXPECT_NEAR(out["parameters"][pointer].get<double>(), 3.0 * (1.0 - 2.0 * k / 10.0), 0.01) << pointer;
  }
  EXPECT_NEAR(out["final_cost"].get<double>(), 3.0, 0.01);  // W int tau^2 = 9 / 3
  ASSERT_EQ(out["constraints"].size(), 4u);
  for (const json& c : out["constraints"]) EXPECT_TRUE(c["met"].get<bool>()) << c;

  // the scene written at full precision does what the report says
  const Outcome simulated = Tether("simulate '" + fitted + "'");
  ASSERT_EQ(simulated.status, 0) << simulated.err;
  for (const json& c : out["constraints"]) {
    EXPECT_EQ(LastValue(simulated.out, c["column"].get<std::string>()), c["simulated"].get<double>()) << c;
  }
}

// The same turn with the rate held to at most 1.2 rad/s over the whole run (a path constraint, met at every
// step): the exact optimum accelerates on u = I w (2 / t1 - 2 t / t1^2) until t1 = 0.25 s, where it meets the
// bound (u continuous, so zero, at the junction; 1.2 (1 - 2 t1 / 3) = 1 rad), cruises, and mirrors that at the
// end; its effort is 2 * 4 I^2 w^2 / (3 t1) = 3.84. Knots every 0.05 s hold this profile exactly.
TEST_F(TrajectoryFitTest, APathConstraintHoldsAtEveryStepAndGivesTheExactBoundedOptimum) {
  const std::string scene = Write("rotor.json", Rod(false, 1.0, 21).dump());
  const std::string fitted = Path("rotor_fit.json");
  const Outcome run = Tether("fit '" + scene + "' --param '/effects/0/schedule/values/*' --bound "
                             "'/effects/0/schedule/values/*=-10:10' --effort 1 --at-least axle.angle=1@1 --at-most "
                             "axle.angle=1.001@1 --at-least axle.omega=-0.001@1 --at-most axle.omega=0.001@1 "
                             "--at-most axle.omega=1.2@0:1 -o '" + fitted + "'");
  ASSERT_EQ(run.status, 0) << run.err;
  const json out = json::parse(run.out);
  EXPECT_TRUE(out["feasible"].get<bool>());
  for (int k = 0; k <= 20; ++k) {
    const double t = k / 20.0, exact = t < 0.25 ? 4.8 - 19.2 * t : t < 0.75 ? 0.0 : -19.2 * (t - 0.75);
    const std::string pointer = "/effects/0/schedule/values/" + std::to_string(k);
    EXPECT_NEAR(out["parameters"][pointer].get<double>(), exact, 0.02) << pointer;
  }
  EXPECT_NEAR(out["final_cost"].get<double>(), 3.84, 0.01);
  // the path constraint, reported once, where it comes closest to its bound (on the cruise)
  ASSERT_EQ(out["constraints"].size(), 5u);
  const json& path = out["constraints"][4];
  EXPECT_EQ(path["from"], 0.0);
  EXPECT_EQ(path["t"], 1.0);
  EXPECT_GE(path["at"].get<double>(), 0.25 - 1e-9);
  EXPECT_LE(path["at"].get<double>(), 0.75 + 1e-9);
  EXPECT_TRUE(path["met"].get<bool>());
  // one run of the written scene stays under the bound at every step
  const Outcome simulated = Tether("simulate '" + fitted + "'");
  ASSERT_EQ(simulated.status, 0) << simulated.err;
  const std::vector<double> rate = Column(simulated.out, "axle.omega");
  ASSERT_EQ(rate.size(), 101u);
  const double fastest = *std::max_element(rate.begin(), rate.end());
  EXPECT_LE(fastest, 1.2 + 1.2e-6);
  EXPECT_GT(fastest, 1.2 - 1e-3);  // the bound is active
}

TEST_F(TrajectoryFitTest, MultipleShootingSwingsAWeakPendulumUpFromEveryStart) {
  const std::string scene = Write("pendulum.json", Rod(true, 3.0, 13).dump());
  const std::string common = "fit '" + scene + "' --param '/effects/1/schedule/values/*' --bound "
                             "'/effects/1/schedule/values/*=-2:2' --effort 0.1 --at-least axle.angle=3@3 --at-most "
                             "axle.angle=3.3@3 --at-least axle.omega=-0.2@3 --at-most axle.omega=0.2@3";
  const Outcome multiple = Tether(common + " --starts 2 --segments 6 -o '" + Path("swung.json") + "'");
  ASSERT_EQ(multiple.status, 0) << multiple.err;
  const json m = json::parse(multiple.out);
  EXPECT_EQ(m["segments"], 6);
  EXPECT_EQ(m["starts"]["count"], 2);
  EXPECT_EQ(m["starts"]["feasible"], 2);
  const Outcome single = Tether(common + " --segments 1");  // from the hanging pendulum, which reaches it too
  ASSERT_EQ(single.status, 0) << single.err;
  const json s = json::parse(single.out);
  EXPECT_NEAR(m["final_cost"].get<double>(), s["final_cost"].get<double>(), 1e-5);
  const Outcome simulated = Tether("simulate '" + Path("swung.json") + "'");
  ASSERT_EQ(simulated.status, 0) << simulated.err;
  EXPECT_GE(LastValue(simulated.out, "axle.angle"), 3.0 - 1e-6);
  EXPECT_LE(std::abs(LastValue(simulated.out, "axle.omega")), 0.2 + 1e-6);
}

TEST_F(TrajectoryFitTest, AnUnreachableTargetFailsHonestlyAndWritesNoScene) {
  const std::string scene = Write("rotor.json", Rod(false, 1.0, 11).dump());
  const std::string fitted = Path("never.json");
  const Outcome run = Tether("fit '" + scene + "' --param '/effects/0/schedule/values/*' --bound "
                             "'/effects/0/schedule/values/*=-0.1:0.1' --at-least axle.angle=1@1 --starts 2 -o '" +
                             fitted + "'");
  EXPECT_EQ(run.status, 1) << run.err;
  const json out = json::parse(run.out);
  EXPECT_FALSE(out["feasible"].get<bool>());
  EXPECT_TRUE(out["failed"].get<bool>());
  EXPECT_EQ(out["stopping_reason"], "infeasible");
  EXPECT_EQ(out["starts"]["feasible"], 0);
  EXPECT_FALSE(out["constraints"][0]["met"].get<bool>());
  // the torque bound allows 0.1 rad: the closest result pushes against it
  EXPECT_NEAR(out["constraints"][0]["simulated"].get<double>(), 0.1, 1e-3);
  EXPECT_NE(run.err.find("the constraints are not met"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("--at-least axle.angle=1@1"), std::string::npos) << run.err;
  EXPECT_FALSE(std::filesystem::exists(fitted));
}

TEST_F(TrajectoryFitTest, BadFlagsExitTwoNamingTheFlag) {
  const std::string scene = Write("rotor.json", Rod(false, 1.0, 11).dump());
  const std::string fit = "fit '" + scene + "' --param '/effects/0/schedule/values/*' ";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--at-least axle.angle=1", "--at-least"},
      {"--at-most axle.angle=x@1", "--at-most"},
      {"--at-least nothing.x=1@1", "--at-least"},
      {"--at-least axle.angle=1@2", "--at-least"},  // after the duration
      {"--at-least axle.angle=1@0.5:0.2", "--at-least"},  // an interval backwards
      {"--at-most axle.angle=1@0.101:0.102", "--at-most"},  // no step within the interval
      {"--at-most axle.angle=1@0.5:2", "--at-most"},  // past the duration
      {"--at-least axle.angle=1@1 --starts 0", "--starts"},
      {"--at-least axle.angle=1@1 --effort -1", "--effort"},
      {"--at-least axle.angle=1@1 --optimizer ceres", "--optimizer"},
      {"--effort 1", "--data"},  // neither targets nor constraints
  };
  for (const auto& [flags, named] : cases) {
    const Outcome run = Tether(fit + flags);
    EXPECT_EQ(run.status, 2) << flags << ": " << run.err;
    EXPECT_NE(run.err.find(named), std::string::npos) << flags << ": " << run.err;
    EXPECT_TRUE(run.out.empty()) << flags;
  }
}

// The examples on shipped scenes (3D joints: a prismatic joint's force motor, hinges; a marker target). They run
// for seconds and exercise no code the tests above do not, so the sanitized run leaves them out (scripts/dev).
class TrajectoryFitExamples : public TrajectoryFitTest {
 protected:
  // Fits `scene` with `flags` writing -o, checks the report feasible, then runs the written scene by `tether
  // simulate`: each constrained column's last value is the reported one (to 1e-12) and within its bound.
  void FitsAndTheWrittenSceneReproducesIt(const std::string& scene, const std::string& flags, int segments) const {
    const std::string fitted = Path("fitted.json");
    const Outcome run = Tether("fit '" + scene + "' " + flags + " -o '" + fitted + "'");
    ASSERT_EQ(run.status, 0) << run.err;
    const json out = json::parse(run.out);
    EXPECT_TRUE(out["feasible"].get<bool>());
    EXPECT_EQ(out["segments"], segments);
    const Outcome simulated = Tether("simulate '" + fitted + "'");
    ASSERT_EQ(simulated.status, 0) << simulated.err;
    for (const json& c : out["constraints"]) {
      const double last = LastValue(simulated.out, c["column"].get<std::string>());
      EXPECT_NEAR(last, c["simulated"].get<double>(), 1e-12 * std::max(1.0, std::abs(last))) << c;
      const double tolerance = 1e-6 * (1.0 + std::abs(last));
      if (c.contains("at_least")) EXPECT_GE(last, c["at_least"].get<double>() - tolerance) << c;
      if (c.contains("at_most")) EXPECT_LE(last, c["at_most"].get<double>() + tolerance) << c;
    }
  }
};

// scenes/cart_pole.json: a force on the rail swings the hanging pole up to within 0.05 rad of upright, pole and
// cart at rest within 0.1 (rad or m)/s, the cart within 0.5 m of where it started, |force| <= 20 N.
TEST_F(TrajectoryFitExamples, TheCartPoleSwingsUp) {
  FitsAndTheWrittenSceneReproducesIt(
      std::string(TETHER_SOURCE_DIR) + "/scenes/cart_pole.json",
      "--param '/effects/1/schedule/values/*' --bound '/effects/1/schedule/values/*=-20:20' --effort 0.001 "
      "--at-least pivot.angle=3.0916@3 --at-most pivot.angle=3.1916@3 --at-least pivot.omega=-0.1@3 "
      "--at-most pivot.omega=0.1@3 --at-least rail.speed=-0.1@3 --at-most rail.speed=0.1@3 "
      "--at-least rail.displacement=-0.5@3 --at-most rail.displacement=0.5@3 --max-evaluations 200",
      1);
}

// scenes/robot_arm.json over 1 s at 10 ms steps, its motors' knots at 0, 0.5 and 1 s: the middle torques of
// three joints put the fingertip marker into a 1 cm box about a point, with the least effort. Single shooting
// gets there from the scene's torques (it did not before its reach took non-monotonic steps and stopped where the
// constraints are met; fit then went to multiple shooting).
TEST_F(TrajectoryFitExamples, TheArmReachesAMarkerTarget) {
  json arm = json::parse(ReadText(std::string(TETHER_SOURCE_DIR) + "/scenes/robot_arm.json"));
  arm["simulation"]["step"] = 0.01;
  arm["simulation"]["duration"] = 1.0;
  for (json& effect : arm["effects"]) {
    if (effect["type"] == "joint_torque") effect["schedule"]["times"] = {0.0, 0.5, 1.0};
  }
  FitsAndTheWrittenSceneReproducesIt(
      Write("arm.json", arm.dump()),
      "--param /effects/1/schedule/values/1 --param /effects/2/schedule/values/1 --param "
      "/effects/4/schedule/values/1 --effort 0.001 --at-least fingertip.x=-0.059@1 --at-most fingertip.x=-0.049@1 "
      "--at-least fingertip.y=0.452@1 --at-most fingertip.y=0.462@1 --at-least fingertip.z=-2.007@1 "
      "--at-most fingertip.z=-1.997@1",
      1);
}

// scenes/acrobot.json, README's swing-up from the hanging acrobot alone (one start): single shooting does not get
// there, and fit goes to multiple shooting (10 segments) by itself.
TEST_F(TrajectoryFitExamples, TheAcrobotSwingsUpByMultipleShootingFromRest) {
  FitsAndTheWrittenSceneReproducesIt(
      std::string(TETHER_SOURCE_DIR) + "/scenes/acrobot.json",
      "--param '/effects/1/schedule/values/*' --bound '/effects/1/schedule/values/*=-6:6' --effort 0.01 "
      "--at-least shoulder.angle=3.1016@5 --at-most shoulder.angle=3.1816@5 --at-least tip.x=-0.009@5 "
      "--at-most tip.x=0.009@5 --at-least upper.omega=-0.1@5 --at-most upper.omega=0.1@5 "
      "--at-least lower.omega=-0.1@5 --at-most lower.omega=0.1@5",
      10);
}

// docs/examples/swing_up/against_a_stop.json: the weak pendulum (|torque| <= 2 N m) with an elastic stop at
// -0.35 rad swings up to within [3, 3.3] rad in 2.5 s, bouncing off the stop (against_a_stop.py); without the
// stop the same fit meets no constraint set.
TEST_F(TrajectoryFitExamples, ThePendulumSwingsUpAgainstAStopWhereWithoutItNoSwingDoes) {
  const std::string scene = std::string(TETHER_SOURCE_DIR) + "/docs/examples/swing_up/against_a_stop.json";
  const std::string flags =
      "--param '/effects/1/schedule/values/*' --bound '/effects/1/schedule/values/*=-2:2' --effort 0.1 "
      "--at-least axle.angle=3@2.5 --at-most axle.angle=3.3@2.5 --at-least axle.omega=-0.2@2.5 "
      "--at-most axle.omega=0.2@2.5 --segments 6 --starts 2";
  FitsAndTheWrittenSceneReproducesIt(scene, flags, 6);
  const std::string events = Path("events.csv");
  ASSERT_EQ(Tether("simulate '" + Path("fitted.json") + "' --events '" + events + "'").status, 0);
  EXPECT_GE(Column(ReadText(events), "speed_before").size(), 1u) << "the swing never bounces off the stop";
  json free = json::parse(ReadText(scene));
  free["constraints"][0].erase("range");
  free["constraints"][0].erase("restitution");
  const Outcome without = Tether("fit '" + Write("free.json", free.dump()) + "' " + flags);
  EXPECT_EQ(without.status, 1) << without.out;
  EXPECT_EQ(json::parse(without.out)["starts"]["feasible"], 0);
}

}  // namespace
}  // namespace tether
