// The gain tuner (gain_tuning.h, gain_objective.h, optimizer.h) on the shipped pendulum, double pendulum and
// four-bar, shortened to 2 s, at a coarse (1e-2 s) and a fine (1e-3 s) step: the tuned gains are no worse than
// any preset on the objective, do not diverge and keep h omega inside the stability bound; Ceres and NLopt
// agree; a global NLopt algorithm, the drift objective and several samples run; the objective's Jacobian
// matches central differences; Minimize handles infeasible trials.
#include "tether/tuning/gain_tuning.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "tether/dynamics/io/scene_reader.h"
#include "tether/dynamics/model/errors.h"
#include "tether/tuning/stability.h"

namespace tether {
namespace {

const char* const kScenes[] = {"pendulum", "double_pendulum", "four_bar"};
const double kSteps[] = {1e-2, 1e-3};

// A shipped scene (scenes/NAME.json) run for 2 s at step h.
Model<double> ShippedScene(const std::string& name, double h, double duration = 2.0) {
  Model<double> model = ReadSceneFile(std::string(TETHER_SOURCE_DIR) + "/scenes/" + name + ".json").model;
  model.simulation.step = h;
  model.simulation.duration = duration;
  return model;
}

TuneSettings Settings(const std::string& optimizer = "ceres", GainObjectiveKind kind = GainObjectiveKind::kReference,
                      int samples = 1, int max_evaluations = 200) {
  TuneSettings settings;
  settings.optimizer.name = optimizer;
  settings.optimizer.max_evaluations = max_evaluations;
  settings.objective.kind = kind;
  settings.objective.samples = samples;
  return settings;
}

// TuneGains is the expensive part: each (scene, step, settings) is tuned once and shared between tests.
const TuneResult& Tuned(const std::string& scene, double h, const TuneSettings& settings) {
  static std::map<std::string, TuneResult> cache;
  const std::string key = scene + " " + std::to_string(h) + " " + settings.optimizer.name + " " +
                          std::to_string(static_cast<int>(settings.objective.kind)) + " " +
                          std::to_string(settings.objective.samples) + " " +
                          std::to_string(settings.optimizer.max_evaluations);
  auto found = cache.find(key);
  if (found == cache.end()) found = cache.emplace(key, TuneGains(ShippedScene(scene, h), settings)).first;
  return found->second;
}

std::string Describe(const std::string& scene, double h) { return scene + " at h = " + std::to_string(h); }

// The tuned point lies in the search box and inside the integrator's stability bound, as reported.
void ExpectInsideTheBox(const TuneResult& r, const Model<double>& model) {
  const double h = model.simulation.step;
  const Integrator integrator = model.simulation.integrator;
  EXPECT_GE(r.zeta, kMinZeta);
  EXPECT_LE(r.zeta, kMaxZeta);
  EXPECT_GE(r.omega, kMinOmega * (1 - 1e-12));  // 1e-12: exp(log(omega)) round trip
  EXPECT_LE(r.omega, r.omega_upper * (1 + 1e-12));
  EXPECT_NEAR(r.alpha, 2.0 * r.zeta * r.omega, 1e-12 * r.alpha);
  EXPECT_NEAR(r.beta, r.omega * r.omega, 1e-12 * r.beta);
  EXPECT_DOUBLE_EQ(r.bound, StabilityBound(integrator, r.zeta));
  EXPECT_NEAR(r.margin, 1.0 - h * r.omega / r.bound, 1e-12);
  EXPECT_GT(r.margin, 0.0);
  EXPECT_LT(h * r.omega, r.bound);
  // the box's promise: omega_upper keeps every zeta of the box within kStabilityMargin of its bound (a grid 5
  // times finer than the tuner's own, 1e-12 for the bisection's last digits)
  for (int k = 0; k <= 240; ++k) {
    const double zeta = kMinZeta + (kMaxZeta - kMinZeta) * k / 240.0;
    EXPECT_LE(h * r.omega_upper, kStabilityMargin * StabilityBound(integrator, zeta) * (1 + 1e-12)) << zeta;
  }
}

TEST(GainTuning, TunedGainsBeatEveryPresetAndStayInsideTheStabilityBound) {
  const std::vector<std::string> names = {"tuned", "none", "rbdl", "mujoco", "default_rule"};
  for (const std::string& scene : kScenes) {
    for (double h : kSteps) {
      SCOPED_TRACE(Describe(scene, h));
      const Model<double> model = ShippedScene(scene, h);
      const TuneSettings settings = Settings();
      const TuneResult& r = Tuned(scene, h, settings);
      ExpectInsideTheBox(r, model);
      ASSERT_EQ(r.comparison.size(), names.size());
      for (size_t i = 0; i < names.size(); ++i) EXPECT_EQ(r.comparison[i].name, names[i]);

      // the tuned gains: not diverged, measured, and the objective as reported
      const GainMetrics& tuned = r.comparison[0];
      EXPECT_FALSE(tuned.diverged) << tuned.divergence;
      EXPECT_TRUE(std::isfinite(tuned.rms_position_error));
      EXPECT_TRUE(std::isfinite(tuned.max_constraint_error));
      EXPECT_GT(r.objective, 0.0);
      EXPECT_DOUBLE_EQ(tuned.objective, r.objective);  // the same deterministic evaluation

      // an independent GainObjective gives the same numbers, and no preset does better
      const GainObjective objective(model, settings.objective);
      EXPECT_DOUBLE_EQ(objective.Value(std::log(r.omega), r.zeta), r.objective);
      for (size_t i = 1; i < r.comparison.size(); ++i) {
        const GainMetrics& preset = r.comparison[i];
        SCOPED_TRACE(preset.name);
        if (preset.beta == 0.0) {  // not a point of the (log omega, zeta) objective
          EXPECT_TRUE(std::isnan(preset.objective));
          continue;
        }
        const double value =
            objective.Value(0.5 * std::log(preset.beta), preset.alpha / (2.0 * std::sqrt(preset.beta)));
        EXPECT_NEAR(preset.objective, value, 1e-12 * value);  // 1e-12: log/sqrt round trip of the gains
        // no worse than any preset (1e-12 relative for that same round trip)
        EXPECT_LE(r.objective, value * (1 + 1e-12));
        EXPECT_LE(r.objective, preset.objective * (1 + 1e-12));
      }
    }
  }
}

TEST(GainTuning, OptimizerValueIsTheCostAtTheReturnedPoint) {
  // OptimizerResult::value is documented as 1/2 |r|^2 at x; TuneResult::objective is |r| recomputed at x.
  // 1e-9 relative: the scaling by 1 / |r(start)| and back, and Jet against double evaluations (1e-12 here)
  for (const std::string& scene : kScenes) {
    for (double h : kSteps) {
      const TuneResult& r = Tuned(scene, h, Settings());
      const double half_squared = 0.5 * r.objective * r.objective;
      EXPECT_NEAR(r.optimizer.value, half_squared, 1e-9 * half_squared)
          << Describe(scene, h) << ": x = (" << r.optimizer.x[0] << ", " << r.optimizer.x[1] << "), "
          << r.optimizer.message;
    }
  }
}

TEST(GainTuning, CeresAndNloptAgreeOnTheObjective) {
  // the coarse step, where the objective is well above the reference's noise floor: 5% on the objective
  for (const std::string& scene : kScenes) {
    const double h = 1e-2;
    const Model<double> model = ShippedScene(scene, h);
    const double ceres = Tuned(scene, h, Settings()).objective;
    for (const std::string optimizer : {"nlopt:LD_LBFGS", "nlopt:LN_BOBYQA"}) {
      SCOPED_TRACE(Describe(scene, h) + " " + optimizer);
      const TuneResult& r = Tuned(scene, h, Settings(optimizer));
      EXPECT_NEAR(r.objective, ceres, 0.05 * ceres);
      ExpectInsideTheBox(r, model);
      EXPECT_FALSE(r.comparison[0].diverged) << r.comparison[0].divergence;
    }
  }
}

TEST(GainTuning, GlobalAlgorithmsRunOnASmallBudgetAndStayInTheBox) {
  const std::string scene = "pendulum";
  const double h = 1e-2;
  const Model<double> model = ShippedScene(scene, h);
  for (const std::string optimizer : {"nlopt:GN_DIRECT_L", "nlopt:GN_CRS2_LM"}) {
    SCOPED_TRACE(optimizer);
    const TuneResult& r = Tuned(scene, h, Settings(optimizer, GainObjectiveKind::kReference, 1, 30));
    ExpectInsideTheBox(r, model);
    EXPECT_TRUE(std::isfinite(r.objective));
    EXPECT_FALSE(r.comparison[0].diverged) << r.comparison[0].divergence;
    // the budget holds: 30 for NLopt plus Minimize's evaluations of the start and of the returned point
    EXPECT_GT(r.optimizer.evaluations, 2);
    EXPECT_LE(r.optimizer.evaluations, 32);
  }
}

TEST(GainTuning, DriftObjectiveGivesFiniteGainsNoWorseThanThePresets) {
  for (const std::string& scene : {"pendulum", "four_bar"}) {
    const double h = 1e-2;
    SCOPED_TRACE(Describe(scene, h));
    const Model<double> model = ShippedScene(scene, h);
    const TuneResult& r = Tuned(scene, h, Settings("ceres", GainObjectiveKind::kDrift));
    EXPECT_TRUE(std::isfinite(r.alpha) && r.alpha > 0.0) << r.alpha;
    EXPECT_TRUE(std::isfinite(r.beta) && r.beta > 0.0) << r.beta;
    EXPECT_TRUE(std::isfinite(r.objective) && r.objective > 0.0) << r.objective;
    ExpectInsideTheBox(r, model);
    ASSERT_EQ(r.comparison.size(), 5u);
    EXPECT_FALSE(r.comparison[0].diverged) << r.comparison[0].divergence;
    // no reference with the drift objective: no position error, but the other measures
    EXPECT_TRUE(std::isnan(r.comparison[0].rms_position_error));
    EXPECT_TRUE(std::isfinite(r.comparison[0].max_constraint_error));
    for (size_t i = 2; i < r.comparison.size(); ++i) {  // presets with beta > 0
      EXPECT_LE(r.objective, r.comparison[i].objective * (1 + 1e-12)) << r.comparison[i].name;
    }
  }
}

TEST(GainTuning, SeveralSamplesStackTheirResiduals) {
  const std::string scene = "pendulum";
  const double h = 1e-2;
  const Model<double> model = ShippedScene(scene, h);
  const TuneResult& r = Tuned(scene, h, Settings("ceres", GainObjectiveKind::kReference, 3));
  ExpectInsideTheBox(r, model);
  EXPECT_TRUE(std::isfinite(r.objective) && r.objective > 0.0);
  EXPECT_FALSE(r.comparison[0].diverged) << r.comparison[0].divergence;
  for (size_t i = 2; i < r.comparison.size(); ++i) {
    EXPECT_LE(r.objective, r.comparison[i].objective * (1 + 1e-12)) << r.comparison[i].name;
  }
  // the objective stacks three runs: three times the residuals of one (the regular pendulum has one window),
  // and the first third is the scene's own run (the same numbers up to the normalization by sqrt(samples))
  GainObjectiveSettings one, three;
  three.samples = 3;
  Eigen::VectorXd r1, r3;
  ASSERT_TRUE(GainObjective(model, one).Evaluate(std::log(10.0), 1.0, &r1, nullptr));
  ASSERT_TRUE(GainObjective(model, three).Evaluate(std::log(10.0), 1.0, &r3, nullptr));
  ASSERT_EQ(r3.size(), 3 * r1.size());
  for (int i = 0; i < r1.size(); ++i) ASSERT_NEAR(r3[i] * std::sqrt(3.0), r1[i], 1e-12 * r1.norm()) << i;
  // the perturbed runs differ from the scene's own
  EXPECT_GT((r3.segment(r1.size(), r1.size()) * std::sqrt(3.0) - r1).norm(), 1e-3 * r1.norm());
}

// d r / d(log omega, zeta) by central differences of Evaluate's residuals, Richardson-extrapolated from steps
// e and e / 2: (4 D(e / 2) - D(e)) / 3, whose error is O(e^4).
Eigen::MatrixXd CentralDifferences(const GainObjective& objective, double log_omega, double zeta, double step) {
  auto difference = [&](int j, double e) {
    Eigen::VectorXd plus, minus;
    const double dx = j == 0 ? e : 0.0, dz = j == 1 ? e : 0.0;
    EXPECT_TRUE(objective.Evaluate(log_omega + dx, zeta + dz, &plus, nullptr));
    EXPECT_TRUE(objective.Evaluate(log_omega - dx, zeta - dz, &minus, nullptr));
    return Eigen::VectorXd((plus - minus) / (2.0 * e));
  };
  Eigen::MatrixXd jacobian;
  for (int j = 0; j < 2; ++j) {
    const Eigen::VectorXd coarse = difference(j, step), fine = difference(j, 0.5 * step);
    if (j == 0) jacobian.resize(fine.size(), 2);
    jacobian.col(j) = (4.0 * fine - coarse) / 3.0;
  }
  return jacobian;
}

TEST(GainObjective, JacobianMatchesCentralDifferences) {
  // tolerance: 1e-6 of each column's norm; 1e-5 on the four-bar, whose passes through its singular
  // configurations amplify round-off to ~1e-14 m in the residuals (a scan of steps from 1e-5 to 4e-2 finds no
  // central difference closer than ~1e-6 there)
  struct Case {
    const char* scene;
    GainObjectiveKind kind;
    double tolerance;
  };
  const Case cases[] = {{"pendulum", GainObjectiveKind::kReference, 1e-6},
                        {"four_bar", GainObjectiveKind::kReference, 1e-5},
                        {"double_pendulum", GainObjectiveKind::kDrift, 1e-6}};
  for (const Case& c : cases) {
    SCOPED_TRACE(std::string(c.scene) + (c.kind == GainObjectiveKind::kDrift ? " drift" : " reference"));
    GainObjectiveSettings settings;
    settings.kind = c.kind;
    const GainObjective objective(ShippedScene(c.scene, 1e-2, 1.0), settings);
    for (const double omega : {20.0, 60.0}) {
      for (const double zeta : {0.5, 1.2}) {
        Eigen::VectorXd r, value_only;
        Eigen::MatrixXd jacobian;
        ASSERT_TRUE(objective.Evaluate(std::log(omega), zeta, &r, &jacobian));
        ASSERT_TRUE(objective.Evaluate(std::log(omega), zeta, &value_only, nullptr));
        ASSERT_EQ(jacobian.rows(), r.size());
        ASSERT_EQ(jacobian.cols(), 2);
        // the Jet run's values are the double run's up to round-off: residuals are differences of O(1 m)
        // coordinates, so 1e-13 m absolute (a few hundred ulps of 1 m, summed over the run) plus 1e-12 relative
        EXPECT_LT((r - value_only).norm(), 1e-13 + 1e-12 * r.norm());
        // extrapolated central differences with step 4e-3: truncation O(e^4) ~1e-10 relative, round-off
        // 1e-16 m / 4e-3 against columns of 1e-7 or more (gains of 20 and 60 rad/s move the run measurably)
        const Eigen::MatrixXd fd = CentralDifferences(objective, std::log(omega), zeta, 4e-3);
        for (int j = 0; j < 2; ++j) {
          EXPECT_GT(jacobian.col(j).norm(), 1e-7);
          EXPECT_LT((fd.col(j) - jacobian.col(j)).norm(), c.tolerance * jacobian.col(j).norm())
              << "omega " << omega << " zeta " << zeta << " column " << j << ": |J| " << jacobian.col(j).norm()
              << ", |J - fd| " << (fd.col(j) - jacobian.col(j)).norm();
        }
      }
    }
  }
}

// A residual function on x = (u, w) whose Gauss-Newton step from u = -3 overshoots into an infeasible region:
// r = (atan(u - 1), w - 0.5), minimum at (1, 0.5); infeasible (false, with r and the Jacobian filled with NaN, so
// that a back end that passed them on would be caught) for u > 1.5. Records every trial point.
struct Trials {
  std::vector<std::vector<double>> points;
  int infeasible = 0;
};

ResidualFunction OvershootingResiduals(Trials* trials, double edge) {
  return [trials, edge](const std::vector<double>& x, Eigen::VectorXd* r, Eigen::MatrixXd* jacobian) {
    trials->points.push_back(x);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    r->resize(2);
    if (jacobian) jacobian->resize(2, 2);
    if (!(x[0] <= edge)) {
      ++trials->infeasible;
      r->setConstant(nan);
      if (jacobian) jacobian->setConstant(nan);
      return false;
    }
    *r << std::atan(x[0] - 1.0), x[1] - 0.5;
    if (jacobian) *jacobian << 1.0 / (1.0 + (x[0] - 1.0) * (x[0] - 1.0)), 0.0, 0.0, 1.0;
    return true;
  };
}

TEST(Minimize, InfeasibleTrialsAreRejectedAndTheFeasibleMinimumIsFound) {
  const std::vector<double> start = {-2.0, -1.0}, lower = {-3.0, -3.0}, upper = {12.0, 3.0};
  for (const std::string name : {"ceres", "nlopt:LD_LBFGS", "nlopt:LN_BOBYQA"}) {
    SCOPED_TRACE(name);
    Trials trials;
    OptimizerSettings settings;
    settings.name = name;
    const OptimizerResult result = Minimize(OvershootingResiduals(&trials, 1.5), start, lower, upper, settings);
    // the minimum (1, 0.5), value 0, to 1e-4 in x (the tolerances are relative 1e-8 on x and the cost)
    ASSERT_EQ(result.x.size(), 2u);
    EXPECT_NEAR(result.x[0], 1.0, 1e-4);
    EXPECT_NEAR(result.x[1], 0.5, 1e-4);
    EXPECT_TRUE(std::isfinite(result.value));
    EXPECT_LT(result.value, 1e-8);
    // every trial point the back end asked for was a number inside the box: nothing NaN came back to it
    for (const std::vector<double>& x : trials.points) {
      for (int i = 0; i < 2; ++i) {
        ASSERT_TRUE(std::isfinite(x[i]));
        ASSERT_GE(x[i], lower[i]);
        ASSERT_LE(x[i], upper[i]);
      }
    }
    EXPECT_EQ(result.evaluations, static_cast<int>(trials.points.size()));
    // Ceres' first step is the Gauss-Newton one, u = -3 + 12.5 (1 + 9) / 10 far beyond the edge: it must have
    // met the infeasible region and rejected it
    if (name == "ceres") EXPECT_GT(trials.infeasible, 0);
  }
}

TEST(Minimize, StaysFeasibleWhenTheUnconstrainedMinimumIsInfeasible) {
  // the same residuals with the edge at u = 0.5: the best feasible point is (0.5, 0.5), cost 1/2 atan(-0.5)^2.
  // Infeasibility is not a bound the back ends know: every back end must end on a feasible point, better than
  // the start, and report its true cost; the NLopt methods reach the edge's optimum to 1% in cost. (Ceres only
  // shrinks its whole step when a trial fails, so it stalls at the edge with w unconverged: here u = 0.5,
  // w = -0.255, cost 0.39; not asserted, as optimizer.h promises only that the step is rejected.)
  const std::vector<double> start = {-2.0, -1.0}, lower = {-3.0, -3.0}, upper = {12.0, 3.0};
  const double start_value = 0.5 * (std::pow(std::atan(-3.0), 2) + 1.5 * 1.5);
  const double edge_value = 0.5 * std::pow(std::atan(-0.5), 2);
  for (const std::string name : {"ceres", "nlopt:LD_LBFGS", "nlopt:LN_BOBYQA"}) {
    SCOPED_TRACE(name);
    Trials trials;
    OptimizerSettings settings;
    settings.name = name;
    const OptimizerResult result = Minimize(OvershootingResiduals(&trials, 0.5), start, lower, upper, settings);
    EXPECT_GT(trials.infeasible, 0);  // the edge was met
    ASSERT_LE(result.x[0], 0.5);
    EXPECT_NEAR(result.x[0], 0.5, 1e-2);  // pressed against the edge
    // the reported value is the cost at x (1e-12 relative), never the infeasible marker or NaN
    const double cost = 0.5 * (std::pow(std::atan(result.x[0] - 1.0), 2) + std::pow(result.x[1] - 0.5, 2));
    EXPECT_NEAR(result.value, cost, 1e-12 * cost);
    EXPECT_LT(result.value, start_value);
    EXPECT_GE(result.value, edge_value * (1 - 1e-12));
    if (name != "ceres") EXPECT_LT(result.value, 1.01 * edge_value);
    for (const std::vector<double>& x : trials.points) ASSERT_TRUE(std::isfinite(x[0]) && std::isfinite(x[1]));
  }
}

TEST(Minimize, RefusesAnInfeasibleStartAndUnknownNames) {
  Trials trials;
  OptimizerSettings settings;
  EXPECT_THROW(Minimize(OvershootingResiduals(&trials, 1.5), {2.0, 0.0}, {-3.0, -3.0}, {12.0, 3.0}, settings),
               InputError);
  for (const std::string name : {"foo", "nlopt:XX_NOPE", "nlopt:"}) {
    settings.name = name;
    try {
      Minimize(OvershootingResiduals(&trials, 1.5), {0.0, 0.0}, {-3.0, -3.0}, {12.0, 3.0}, settings);
      ADD_FAILURE() << name << " was accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("optimizer: unknown", 0), 0u) << e.what();  // the settings field
    }
  }
}

}  // namespace
}  // namespace tether
