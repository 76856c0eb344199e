#include "tether/tuning/gain_tuning.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "tether/dynamics/integration/default_gains.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/model/errors.h"
#include "tether/tuning/stability.h"

namespace tether {
namespace {

// min over zeta in the box of B(zeta), on a fine grid of zeta
double SmallestBound(Integrator integrator) {
  double smallest = INFINITY;
  for (int k = 0; k <= 48; ++k) {
    smallest = std::min(smallest, StabilityBound(integrator, kMinZeta + (kMaxZeta - kMinZeta) * k / 48.0));
  }
  return smallest;
}

}  // namespace

GainMetrics MeasureGains(const Model<double>& model, const std::string& name, double alpha, double beta,
                         const GainObjective& objective) {
  GainMetrics m;
  m.name = name;
  m.alpha = alpha;
  m.beta = beta;
  if (beta > 0.0) m.objective = objective.Value(0.5 * std::log(beta), alpha / (2.0 * std::sqrt(beta)));
  const ReferenceMotion& reference = objective.reference();
  Trajectory<double> run;
  const auto begin = std::chrono::steady_clock::now();
  try {
    run = Record(WithGains(model, alpha, beta));
  } catch (const SimulationDiverged& e) {
    m.diverged = true;
    m.divergence = e.what();
    return m;
  }
  m.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  if (!reference.q.empty()) m.rms_position_error = RmsPositionError(model, reference, run);
  m.max_constraint_error = run.LargestViolation();
  m.energy_drift = run.EnergyDrift();
  return m;
}

TuneResult TuneGains(const Model<double>& model, const TuneSettings& settings) {
  CheckOptimizerName(settings.optimizer.name, "optimizer");
  const GainObjective objective(model, settings.objective);
  const double h = model.simulation.step;
  const Integrator integrator = model.simulation.integrator;

  TuneResult result;
  result.omega_upper = kStabilityMargin * SmallestBound(integrator) / h;
  const std::vector<double> lower = {std::log(kMinOmega), kMinZeta};
  const std::vector<double> upper = {std::log(result.omega_upper), kMaxZeta};
  const Gains rule = DefaultGains(integrator, h);
  // the search starts from the best of the presets that lie in the box (all critically damped)
  std::vector<double> start;
  double best = INFINITY;
  for (const double omega : {std::sqrt(rule.beta), 10.0, 50.0}) {
    const double log_omega = std::log(omega);
    if (log_omega < lower[0] || log_omega > upper[0]) continue;
    const double value = objective.Value(log_omega, 1.0);
    if (value < best || start.empty()) {
      best = value;
      start = {log_omega, 1.0};
    }
  }
  if (start.empty()) start = {std::clamp(std::log(std::sqrt(rule.beta)), lower[0], upper[0]), 1.0};

  const ResidualFunction residuals = [&objective](const std::vector<double>& x, Eigen::VectorXd* r,
                                                  Eigen::MatrixXd* jacobian) {
    return objective.Evaluate(x[0], x[1], r, jacobian);
  };
  result.optimizer = Minimize(residuals, start, lower, upper, settings.optimizer);
  result.omega = std::exp(result.optimizer.x[0]);
  result.zeta = result.optimizer.x[1];
  result.alpha = 2.0 * result.zeta * result.omega;
  result.beta = result.omega * result.omega;
  result.objective = objective.Value(result.optimizer.x[0], result.optimizer.x[1]);
  result.window = objective.window();
  result.bound = StabilityBound(integrator, result.zeta);
  result.margin = 1.0 - h * result.omega / result.bound;

  result.comparison.push_back(MeasureGains(model, "tuned", result.alpha, result.beta, objective));
  for (const NamedGains& preset : GainPresets(integrator, h)) {
    result.comparison.push_back(MeasureGains(model, preset.name, preset.alpha, preset.beta, objective));
  }
  return result;
}

std::vector<NamedGains> GainPresets(Integrator integrator, double step) {
  const Gains rule = DefaultGains(integrator, step);
  return {{"none", 0.0, 0.0}, {"rbdl", 20.0, 100.0}, {"mujoco", 100.0, 2500.0}, {"default_rule", rule.alpha, rule.beta}};
}

}  // namespace tether
