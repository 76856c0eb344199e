// Hard settings (issue 7): gains at the edge of the stability bound, tiny and huge steps, and optimizers that
// probe parameters where the simulation diverges.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "test_files.h"
#include "test_scenes.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/io/scene_reader.h"
#include "tether/dynamics/model/errors.h"
#include "tether/tuning/gain_objective.h"
#include "tether/tuning/stability.h"

namespace tether {
namespace {

// Largest constraint violation of a run; throws SimulationDiverged like Simulate.
double WorstViolation(const Model<double>& model) {
  double worst = 0.0;
  Simulate<double>(model, RunOptions{}, [&](const Sample<double>& s) { worst = std::max(worst, s.constraint_error); });
  return worst;
}

// Critically damped gains with h omega at `fraction` of the integrator's bound B(1): inside the bound the
// error dynamics are stable (the run stays on its rod), past it they grow from rounding until the run diverges,
// and the divergence is reported as such.
TEST(StiffGains, InsideTheBoundHoldAndPastItDivergeWithAMessage) {
  for (const char* name : {"rk4", "symplectic_euler", "euler"}) {
    SCOPED_TRACE(name);
    const Model<double> base = testing::Pendulum60(name, 0.01, 3.0);
    const double bound = StabilityBound(base.simulation.integrator, 1.0) / base.simulation.step;
    const double inside = 0.9 * bound, outside = 1.2 * bound;
    EXPECT_LT(WorstViolation(WithGains(base, 2.0 * inside, inside * inside)), 0.05);
    try {
      WorstViolation(WithGains(base, 2.0 * outside, outside * outside));
      ADD_FAILURE() << "gains past the bound did not diverge";
    } catch (const SimulationDiverged& e) {
      EXPECT_NE(std::string(e.what()).find("diverged at"), std::string::npos) << e.what();
    }
  }
}

// A step of 1e-7 s keeps the rod to rounding; a step of 0.5 s (a third of the pendulum's period) either runs
// or stops with SimulationDiverged, never anything else.
TEST(Steps, TinyStepsHoldTheRodAndHugeStepsEndCleanly) {
  EXPECT_LT(WorstViolation(testing::Pendulum60("rk4", 1e-7, 1e-3)), 1e-12);
  for (const char* name : {"euler", "symplectic_euler", "rk4", "rk45"}) {
    SCOPED_TRACE(name);
    try {
      EXPECT_TRUE(std::isfinite(WorstViolation(testing::Pendulum60(name, 0.5, 5.0))));
    } catch (const SimulationDiverged& e) {
      EXPECT_NE(std::string(e.what()).find("diverged at"), std::string::npos) << e.what();
    }
  }
}

// A cart on a slider pulled by a spring of stiffness 40 N/m (0.5 kg, rk4 at 2 ms): identifying the stiffness
// inside [1, 1e9] N/m lets the optimizers try stiffnesses where rk4 diverges (h sqrt(k / m) > 2.8 beyond about
// 1e6 N/m). Every optimizer, global ones included, must come back with the truth and exit 0.
TEST(DivergingTrials, IdentificationKeepsGoingAndFindsTheTruth) {
  testing::TempFolder folder("tether_diverging_trials");
  auto scene = [](double stiffness) {
    return nlohmann::json{
        {"dimension", 2},
        {"bodies", {{{"name", "cart"}, {"type", "particle"}, {"mass", 0.5}, {"position", {0.3, 0.0}}}}},
        {"constraints",
         {{{"type", "slider"}, {"bodies", {"world", "cart"}}, {"points", {{0.0, 0.0}, {0.0, 0.0}}},
           {"axis", {1.0, 0.0}}}}},
        {"effects",
         {{{"type", "spring"}, {"bodies", {"world", "cart"}}, {"points", {{-1.0, 0.0}, {0.0, 0.0}}},
           {"stiffness", stiffness}, {"rest_length", 1.0}}}},
        {"simulation", {{"integrator", "rk4"}, {"step", 2e-3}, {"duration", 1.0}}}};
  };
  std::vector<double> times;
  for (int k = 1; k <= 20; ++k) times.push_back(0.05 * k);
  // the recording: t and cart.x (the first two columns of the trajectory CSV)
  std::string recording;
  for (const std::string& line :
       testing::Lines(testing::TrajectoryCsvAt(ParseScene(scene(40.0), "truth.json").model, times))) {
    const std::vector<std::string> cells = testing::CsvCells(line);
    recording += cells[0] + "," + cells[1] + "\n";
  }
  folder.Write("recording.csv", recording);
  const std::string guess = folder.Write("guess.json", scene(30.0).dump());
  for (const char* optimizer : {"ceres", "nlopt:LN_BOBYQA", "nlopt:GN_DIRECT_L"}) {
    SCOPED_TRACE(optimizer);
    const testing::Outcome run = testing::RunTether(
        "identify '" + guess + "' --data '" + folder.Path("recording.csv") +
            "' --param /effects/0/stiffness --bound /effects/0/stiffness=1:1e9 --optimizer " + optimizer,
        folder);
    ASSERT_EQ(run.status, 0) << run.err;
    const nlohmann::json out = nlohmann::json::parse(run.out);
    EXPECT_NEAR(out["parameters"]["/effects/0/stiffness"].get<double>(), 40.0, 0.4) << run.out;
    EXPECT_LT(out["final_cost"].get<double>(), out["initial_cost"].get<double>());
  }
}

}  // namespace
}  // namespace tether
