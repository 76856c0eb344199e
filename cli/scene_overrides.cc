#include "scene_overrides.h"

#include <cmath>
#include <sstream>

#include "tether/dynamics/default_gains.h"
#include "tether/dynamics/errors.h"
#include "tether/dynamics/names.h"

namespace tether::cli {
namespace {

double Checked(const std::optional<double>& value, const char* flag, bool zero_allowed) {
  if (!(zero_allowed ? *value >= 0 : *value > 0) || !std::isfinite(*value)) {
    std::ostringstream message;
    message << flag << ": must be " << (zero_allowed ? ">= 0" : "> 0") << ", got " << *value;
    throw InputError(message.str());
  }
  return *value;
}

}  // namespace

void SceneOverrides::Register(CLI::App* app) {
  app->add_option("--duration", duration, "simulated time, s (overrides /simulation/duration)");
  app->add_option("--step", step, "time step h, s (overrides /simulation/step)");
  app->add_option("--integrator", integrator, "euler, symplectic_euler, rk4 or rk45");
  app->add_option("--alpha", alpha, "Baumgarte alpha, 1/s (selects the baumgarte method)");
  app->add_option("--beta", beta, "Baumgarte beta, 1/s^2 (selects the baumgarte method)");
  app->add_option("--solver", solver, "KKT solver path: auto, dense or sparse");
  app->add_option("--stabilization", stabilization, "none, baumgarte or projection");
}

void SceneOverrides::Apply(Model<double>* model) const {
  SimulationSettings& sim = model->simulation;
  StabilizationSettings<double>& st = model->stabilization;
  if (duration) sim.duration = Checked(duration, "--duration", false);
  if (step) sim.step = Checked(step, "--step", false);
  if (integrator) sim.integrator = ParseIntegrator(*integrator, "--integrator");
  if (solver) sim.solver = ParseKktSolver(*solver, "--solver");
  if (stabilization) st.method = ParseStabilization(*stabilization, "--stabilization");
  if (duration || step) CheckStepCount(sim, duration && step ? "--duration/--step" : duration ? "--duration" : "--step");
  if (alpha || beta) {
    if (stabilization && st.method != Stabilization::kBaumgarte) {
      throw InputError("--alpha/--beta: gains apply to the baumgarte method only, not --stabilization " + *stabilization);
    }
    if (st.gains_from_rule) {  // the flag not given keeps the rule's value at the final integrator and step
      const Gains rule = DefaultGains(sim.integrator, sim.step);
      st.alpha = rule.alpha;
      st.beta = rule.beta;
    }
    st.method = Stabilization::kBaumgarte;
    st.gains_from_rule = false;
    if (alpha) st.alpha = Checked(alpha, "--alpha", true);
    if (beta) st.beta = Checked(beta, "--beta", true);
  }
}

}  // namespace tether::cli
