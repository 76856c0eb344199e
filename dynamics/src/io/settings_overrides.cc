#include "tether/dynamics/io/settings_overrides.h"

#include <cmath>
#include <sstream>

#include "tether/dynamics/integration/default_gains.h"
#include "tether/dynamics/io/names.h"
#include "tether/dynamics/model/errors.h"

namespace tether {
namespace {

double Checked(const std::optional<double>& value, const std::string& name, bool zero_allowed) {
  if (!(zero_allowed ? *value >= 0 : *value > 0) || !std::isfinite(*value)) {
    std::ostringstream message;
    message << name << ": must be " << (zero_allowed ? ">= 0" : "> 0") << ", got " << *value;
    throw InputError(message.str());
  }
  return *value;
}

}  // namespace

void SettingsOverrides::Apply(Model<double>* model, const std::string& prefix) const {
  SimulationSettings& sim = model->simulation;
  StabilizationSettings<double>& st = model->stabilization;
  if (duration) sim.duration = Checked(duration, prefix + "duration", false);
  if (step) sim.step = Checked(step, prefix + "step", false);
  if (integrator) sim.integrator = ParseIntegrator(*integrator, prefix + "integrator");
  if (solver) sim.solver = ParseKktSolver(*solver, prefix + "solver");
  if (stabilization) st.method = ParseStabilization(*stabilization, prefix + "stabilization");
  if (duration || step) {
    CheckStepCount(
        sim, duration && step ? prefix + "duration/" + prefix + "step" : prefix + (duration ? "duration" : "step"));
  }
  if (alpha || beta) {
    if (stabilization && st.method != Stabilization::kBaumgarte) {
      throw InputError(prefix + "alpha/" + prefix + "beta: gains apply to the baumgarte method only, not " + prefix +
                       "stabilization " + *stabilization);
    }
    if (st.gains_from_rule) {  // the one not given keeps the rule's value at the final integrator and step
      const Gains rule = DefaultGains(sim.integrator, sim.step);
      st.alpha = rule.alpha;
      st.beta = rule.beta;
    }
    st.method = Stabilization::kBaumgarte;
    st.gains_from_rule = false;
    if (alpha) st.alpha = Checked(alpha, prefix + "alpha", true);
    if (beta) st.beta = Checked(beta, prefix + "beta", true);
  }
}

}  // namespace tether
