// Fitting (identification.h, the `fit` use of Identify): initial conditions and force schedules chosen so that a
// run passes through target keyframes. Checked: a ball's initial velocity that hits a target (the acceptance
// check's case: vx = 2, vy = 0.5 + g/2 to reach (2, 0.5) at t = 1); a puck's force schedule recovered from
// keyframes (a few rows of a few columns); and --smooth W, which makes an under-determined schedule unique and
// smooth where the plain fit keeps whatever the initial guess put in the directions the keyframes cannot see.
//
// The targets are made by a run of the true scene with rk45 at a tight tolerance and fitted with rk4 at
// 2e-3 s; a force that is piecewise linear in time makes the puck's position piecewise cubic, which rk4
// integrates exactly on a grid holding the schedule's times, so the recovery is limited by rk45's error only.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "test_files.h"
#include "tether/dynamics/io/scene_reader.h"
#include "tether/dynamics/io/trajectory_csv.h"
#include "tether/dynamics/model/errors.h"
#include "tether/tuning/identify.h"

namespace tether {
namespace {

using nlohmann::json;
using testing::TempFolder;

constexpr double kG = 9.81;

json Simulation(const std::string& integrator, double step, double duration) {
  return {{"integrator", integrator}, {"step", step}, {"duration", duration}, {"tolerance", 1e-10}};
}

// A free puck in the plane (no gravity) pushed by one scheduled force.
json Puck(double mass, const std::vector<double>& times, const std::vector<std::vector<double>>& values) {
  return {
      {"dimension", 2},
      {"bodies",
       {{{"name", "puck"}, {"type", "particle"}, {"mass", mass}, {"position", {0.0, 0.0}}, {"velocity", {0.2, -0.1}}}}},
      {"effects", {{{"type", "force"}, {"body", "puck"}, {"schedule", {{"times", times}, {"values", values}}}}}},
      {"stabilization", {{"method", "none"}}}};
}

// Targets: `columns` of the run of `truth` (rk45, tolerance 1e-10) at `times`, as a CSV read back against
// `fitted`. Column k of the CSV is q[index[k]] or v[index[k]] as the name says (.x/.y: position, .vx/.vy:
// velocity of the single particle).
Observations Targets(const json& truth, const Model<double>& fitted, const std::vector<std::string>& columns,
                     const std::vector<double>& times, const TempFolder& folder) {
  json d = truth;
  d["simulation"] = Simulation("rk45", 1e-3, fitted.simulation.duration);
  const Model<double> model = ParseScene(d, "truth.json").model;
  std::ostringstream csv;
  csv.precision(17);
  csv << "t";
  for (const std::string& c : columns) csv << "," << c;
  csv << "\n";
  RunOptions run;
  run.every = 1 << 30;
  run.stops = times;
  Simulate<double>(model, run, [&](const Sample<double>& s) {
    if (s.stop < 0) return;
    csv << s.t;
    for (const std::string& c : columns) {
      const std::string field = c.substr(c.find('.') + 1);
      csv << "," << (field == "x" ? s.q[0] : field == "y" ? s.q[1] : field == "vx" ? s.v[0] : s.v[1]);
    }
    csv << "\n";
  });
  return ReadObservations(folder.Write("targets.csv", csv.str()), fitted);
}

std::vector<std::string> SchedulePointers(int count, int component) {
  std::vector<std::string> out;
  for (int j = 0; j < count; ++j) {
    out.push_back("/effects/0/schedule/values/" + std::to_string(j) + "/" + std::to_string(component));
  }
  return out;
}

// Sum of squared consecutive differences: the roughness of a schedule.
double Roughness(const std::vector<double>& s) {
  double sum = 0.0;
  for (size_t j = 1; j < s.size(); ++j) sum += (s[j] - s[j - 1]) * (s[j] - s[j - 1]);
  return sum;
}

TEST(Fit, BallInitialVelocityHitsATarget) {
  // the acceptance check: from the origin, reach (2, 0.5) at t = 1 under gravity
  const json d = {
      {"dimension", 2},
      {"bodies",
       {{{"name", "ball"}, {"type", "particle"}, {"mass", 0.5}, {"position", {0.0, 0.0}}, {"velocity", {1.0, 1.0}}}}},
      {"effects", {{{"type", "gravity"}, {"acceleration", {0.0, -kG}}}}},
      {"simulation", Simulation("rk4", 1e-3, 1.0)},
      {"stabilization", {{"method", "none"}}}};
  const Scene scene = ParseScene(d, "fit_ball.json");
  TempFolder folder("tether_fit");
  const Observations targets =
      ReadObservations(folder.Write("fit_targets.csv", "t,ball.x,ball.y\n1.0,2.0,0.5\n"), scene.model);
  const ParameterSet parameters(scene, {"/bodies/0/velocity/0", "/bodies/0/velocity/1"});
  const IdentifyResult r = Identify(scene.model, parameters, {targets}, IdentifySettings{});
  // rk4 is exact for constant acceleration: only the optimizer's stopping rule (relative cost decrease 1e-8)
  // limits the answer; we observe 1.5e-8 m/s, and allow 1e-6 (the acceptance check allows 1e-4)
  EXPECT_NEAR(r.estimate[0], 2.0, 1e-6);
  EXPECT_NEAR(r.estimate[1], 0.5 + kG / 2, 1e-6);
  EXPECT_LT(r.final_cost, 1e-12);
  EXPECT_GT(r.initial_cost, 1.0);  // the guess (1, 1) misses by (1, 4.4) m
  // two targets for two unknowns: an exact fit, whose uncertainty cannot be estimated, says so
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("as many unknowns as residuals"), std::string::npos) << r.warnings[0];
  EXPECT_TRUE(std::isnan(r.standard_deviation[0]));
}

TEST(Fit, ForceScheduleFromKeyframes) {
  const std::vector<double> times = {0.0, 1.0, 2.0};
  const std::vector<std::vector<double>> truth = {{1.0, -0.5}, {-0.5, 1.5}, {2.0, 0.5}};
  const std::vector<std::vector<double>> zero(3, {0.0, 0.0});
  json guess = Puck(0.5, times, zero);
  guess["simulation"] = Simulation("rk4", 2e-3, 2.0);
  const Scene scene = ParseScene(guess, "puck.json");
  TempFolder folder("tether_fit");
  // four keyframes of three columns: 12 cells for 6 unknowns
  const Observations targets =
      Targets(Puck(0.5, times, truth), scene.model, {"puck.x", "puck.y", "puck.vx"}, {0.5, 1.0, 1.5, 2.0}, folder);
  ASSERT_EQ(targets.CellCount(), 12);
  std::vector<std::string> pointers;
  for (int j = 0; j < 3; ++j) {
    for (int k = 0; k < 2; ++k) pointers.push_back(SchedulePointers(3, k)[j]);
  }
  const IdentifyResult r = Identify(scene.model, ParameterSet(scene, pointers), {targets}, IdentifySettings{});
  ASSERT_EQ(r.estimate.size(), 6u);
  for (int j = 0; j < 3; ++j) {
    for (int k = 0; k < 2; ++k) {
      // rk45's error at tolerance 1e-10 over 2 s, seen through sensitivities ~0.1-1 m/N: 1e-6 N
      EXPECT_NEAR(r.estimate[2 * j + k], truth[j][k], 1e-6) << pointers[2 * j + k];
    }
  }
  EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
  EXPECT_LT(r.final_cost, 1e-14);
}

TEST(Fit, SmoothingMakesAnUnderdeterminedScheduleUniqueAndSmooth) {
  // nine schedule values of the x force; four target cells (x and vx at 1 s and 2 s) cannot determine them
  std::vector<double> times;
  std::vector<std::vector<double>> truth;
  for (int j = 0; j < 9; ++j) {
    times.push_back(0.25 * j);
    truth.push_back({1.0 + 0.5 * std::sin(2.0 * times.back()), 0.0});
  }
  const std::vector<std::string> pointers = SchedulePointers(9, 0);
  TempFolder folder("tether_fit");
  auto fit = [&](const std::vector<double>& start, double smooth) {
    std::vector<std::vector<double>> values;
    for (double s : start) values.push_back({s, 0.0});
    json d = Puck(1.0, times, values);
    d["simulation"] = Simulation("rk4", 2e-3, 2.0);
    const Scene scene = ParseScene(d, "puck.json");
    const Observations targets =
        Targets(Puck(1.0, times, truth), scene.model, {"puck.x", "puck.vx"}, {1.0, 2.0}, folder);
    IdentifySettings settings;
    settings.smooth = smooth;
    return Identify(scene.model, ParameterSet(scene, pointers), {targets}, settings);
  };
  const std::vector<double> zigzag = {0, 2, 0, 2, 0, 2, 0, 2, 0}, flat(9, 1.0);
  const IdentifyResult plain = fit(zigzag, 0.0);
  const IdentifyResult plain_flat = fit(flat, 0.0);
  const double w = 1e-4;  // small: the targets still dominate
  const IdentifyResult smooth = fit(zigzag, w);
  const IdentifyResult smooth_flat = fit(flat, w);

  // without smoothing: the targets are met but the solution depends on the start, and it is reported
  EXPECT_LT(plain.final_cost, 1e-12);
  EXPECT_TRUE(!plain.warnings.empty());
  double start_dependence = 0.0;
  for (int j = 0; j < 9; ++j)
    start_dependence = std::max(start_dependence, std::abs(plain.estimate[j] - plain_flat.estimate[j]));
  EXPECT_GT(start_dependence, 0.1);

  // with smoothing: the same answer from both starts (1e-5 N), far smoother, and the targets still met
  for (int j = 0; j < 9; ++j) EXPECT_NEAR(smooth.estimate[j], smooth_flat.estimate[j], 1e-5) << pointers[j];
  const double rough_plain = Roughness(plain.estimate), rough_smooth = Roughness(smooth.estimate);
  EXPECT_LT(rough_smooth, 0.1 * rough_plain);
  double largest_step_plain = 0.0, largest_step_smooth = 0.0;
  for (int j = 1; j < 9; ++j) {
    largest_step_plain = std::max(largest_step_plain, std::abs(plain.estimate[j] - plain.estimate[j - 1]));
    largest_step_smooth = std::max(largest_step_smooth, std::abs(smooth.estimate[j] - smooth.estimate[j - 1]));
  }
  EXPECT_LT(largest_step_smooth, largest_step_plain);
  ASSERT_EQ(smooth.residuals.size(), 2u);
  // the penalty trades a little of the targets for smoothness: observed 0.35 mm with W = 1e-4; 1 mm (and 1 mm/s)
  for (const ResidualStatistics& s : smooth.residuals) EXPECT_LT(s.largest, 1e-3) << s.column;
  EXPECT_TRUE(smooth.warnings.empty()) << smooth.warnings.front();
  std::cout << "schedule roughness (sum of squared consecutive differences): plain " << rough_plain << " (largest step "
            << largest_step_plain << " N), smoothed " << rough_smooth << " (largest step " << largest_step_smooth
            << " N); start dependence without smoothing " << start_dependence << " N\n";
}

// ---------------------------------------------------------------------------------------------------------------
// derivatives by the adjoint (identification.h: Derivatives)

// A puck's 17-value x-force schedule fitted to x and vx at four times, with smoothing and a robust loss.
struct ScheduleFit {
  Scene scene;
  Observations targets;
  std::vector<std::string> pointers;
};

ScheduleFit SeventeenKnots(const TempFolder& folder) {
  std::vector<double> times;
  std::vector<std::vector<double>> truth, start;
  for (int j = 0; j < 17; ++j) {
    times.push_back(0.125 * j);
    truth.push_back({1.0 + 0.5 * std::sin(2.0 * times.back()), 0.0});
    start.push_back({j % 2 == 0 ? 0.0 : 2.0, 0.0});
  }
  json d = Puck(1.0, times, start);
  d["simulation"] = Simulation("rk4", 2e-3, 2.0);
  ScheduleFit f{ParseScene(d, "puck.json"), {}, SchedulePointers(17, 0)};
  f.targets = Targets(Puck(1.0, times, truth), f.scene.model, {"puck.x", "puck.vx"}, {0.5, 1.0, 1.5, 2.0}, folder);
  return f;
}

// The cost's gradient by the adjoint is J^T rho'(r^2) r by the Jets (1e-8 relative to the largest component),
// robust loss, smoothing and log-space parameters (the mass) included.
TEST(FitByAdjoint, TheCostGradientEqualsTheJets) {
  TempFolder folder("tether_fit");
  ScheduleFit f = SeventeenKnots(folder);
  f.pointers.push_back("/bodies/0/mass");
  const ParameterSet parameters(f.scene, f.pointers);
  IdentifySettings settings;
  settings.optimizer.loss = ParseRobustLoss("huber:0.05", "--loss");
  settings.smooth = 1e-3;
  const LossGradient jet = IdentifyCostGradient(f.scene.model, parameters, {f.targets}, settings, GradientMethod::kJet);
  const LossGradient adjoint =
      IdentifyCostGradient(f.scene.model, parameters, {f.targets}, settings, GradientMethod::kAdjoint);
  EXPECT_NEAR(adjoint.loss, jet.loss, 1e-12 * jet.loss);
  double scale = 0.0;
  for (double g : jet.gradient) scale = std::max(scale, std::abs(g));
  ASSERT_GT(scale, 0.0);
  for (size_t j = 0; j < f.pointers.size(); ++j) {
    EXPECT_NEAR(adjoint.gradient[j], jet.gradient[j], 1e-8 * scale) << f.pointers[j];
  }
}

// L-BFGS on the adjoint's gradients reaches the minimum it reaches on the Jets' (unique, with the smoothing).
TEST(FitByAdjoint, LbfgsReachesTheMinimumItReachesWithJets) {
  TempFolder folder("tether_fit");
  const ScheduleFit f = SeventeenKnots(folder);
  IdentifySettings settings;
  settings.optimizer.name = "nlopt:LD_LBFGS";
  settings.optimizer.max_evaluations = 100;
  settings.optimizer.loss = ParseRobustLoss("huber:0.05", "--loss");
  settings.smooth = 1e-3;
  const ParameterSet parameters(f.scene, f.pointers);
  settings.method = GradientMethod::kJet;
  const IdentifyResult jet = Identify(f.scene.model, parameters, {f.targets}, settings);
  settings.method = GradientMethod::kAuto;  // 17 unknowns: at or above the crossover
  const IdentifyResult adjoint = Identify(f.scene.model, parameters, {f.targets}, settings);
  EXPECT_EQ(jet.gradient_method, "jet");
  EXPECT_EQ(adjoint.gradient_method, "adjoint");
  EXPECT_LT(adjoint.final_cost, 1e-3 * adjoint.initial_cost);
  EXPECT_NEAR(adjoint.final_cost, jet.final_cost, 1e-6 * jet.final_cost);
  for (size_t j = 0; j < f.pointers.size(); ++j) {
    EXPECT_NEAR(adjoint.estimate[j], jet.estimate[j], 1e-4) << f.pointers[j];
  }
}

TEST(FitByAdjoint, WhereTheAdjointCannotServeItIsRefusedOrLeftToJets) {
  TempFolder folder("tether_fit");
  const ScheduleFit f = SeventeenKnots(folder);
  const ParameterSet parameters(f.scene, f.pointers);
  IdentifySettings settings;
  settings.optimizer.max_evaluations = 4;
  auto message = [&](const IdentifySettings& s) -> std::string {
    try {
      Identify(f.scene.model, parameters, {f.targets}, s);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  settings.method = GradientMethod::kAdjoint;  // Levenberg-Marquardt needs the Jacobian
  EXPECT_NE(message(settings).find("needs the residuals' Jacobian"), std::string::npos) << message(settings);
  settings.optimizer.name = "nlopt:LN_BOBYQA";  // no derivatives at all
  EXPECT_NE(message(settings).find("uses no derivatives"), std::string::npos) << message(settings);
  settings.optimizer.name = "nlopt:LD_LBFGS";
  settings.segments = 2;  // multiple shooting's start states
  EXPECT_NE(message(settings).find("multiple shooting"), std::string::npos) << message(settings);
  settings.method = GradientMethod::kCentral;
  settings.segments = 1;
  EXPECT_NE(message(settings).find("--method fd"), std::string::npos) << message(settings);
  // auto: Jets for Levenberg-Marquardt and for multiple shooting, nothing for a derivative-free algorithm
  settings.method = GradientMethod::kAuto;
  settings.optimizer.name = "ceres";
  EXPECT_EQ(Identify(f.scene.model, parameters, {f.targets}, settings).gradient_method, "jet");
  settings.optimizer.name = "nlopt:LN_BOBYQA";
  EXPECT_EQ(Identify(f.scene.model, parameters, {f.targets}, settings).gradient_method, "none");
  settings.optimizer.name = "nlopt:LD_LBFGS";
  settings.segments = 2;
  EXPECT_EQ(Identify(f.scene.model, parameters, {f.targets}, settings).gradient_method, "jet");
}

}  // namespace
}  // namespace tether
