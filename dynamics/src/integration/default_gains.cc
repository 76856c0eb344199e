#include "tether/dynamics/integration/default_gains.h"

#include <algorithm>

#include "tether/dynamics/integration/integrator_descriptor.h"

namespace tether {

double RealStabilityLimit(Integrator integrator) { return Describe(integrator).real_stability_limit; }

Gains DefaultGains(Integrator integrator, double step) {
  const bool first_order = Describe(integrator).order == 1;
  const double cap = first_order ? kFirstOrderMaxOmega : kHighOrderMaxOmega;
  const double omega = std::min(cap, kDefaultStabilityFraction * RealStabilityLimit(integrator) / step);
  return {2.0 * omega, omega * omega};
}

template <typename T>
void GainsInUse(const Model<T>& model, T* alpha, T* beta) {
  const StabilizationSettings<T>& s = model.stabilization;
  if (s.method != Stabilization::kBaumgarte) {
    *alpha = T(0.0);
    *beta = T(0.0);
  } else if (s.gains_from_rule) {
    const Gains g = DefaultGains(model.simulation.integrator, model.simulation.step);
    *alpha = T(g.alpha);
    *beta = T(g.beta);
  } else {
    *alpha = s.alpha;
    *beta = s.beta;
  }
}

template void GainsInUse<double>(const Model<double>&, double*, double*);
template void GainsInUse<Jet>(const Model<Jet>&, Jet*, Jet*);
template void GainsInUse<Rev>(const Model<Rev>&, Rev*, Rev*);

}  // namespace tether
