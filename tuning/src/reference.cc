#include "tether/tuning/reference.h"

#include <algorithm>
#include <cmath>

#include "tether/dynamics/integration/simulator.h"

namespace tether {

ReferenceMotion ComputeReference(const Model<double>& model) {
  Model<double> accurate = model;
  accurate.simulation.integrator = Integrator::kRk45;
  accurate.simulation.tolerance = kReferenceTolerance;
  accurate.stabilization.method = Stabilization::kProjection;
  accurate.simulation.contact = ContactMode::kEvents;  // a time-stepping scene's true motion has its events located
  return Record(accurate);
}

double RmsPositionError(const Model<double>& model, const ReferenceMotion& reference, const Trajectory<double>& run) {
  const std::vector<VecX<double>>& q = run.q;
  double squared = 0.0;
  const size_t samples = std::min(q.size(), reference.q.size());
  for (size_t k = 1; k < samples; ++k) {  // the first sample is the common initial state
    for (const Body<double>& body : model.bodies) {
      for (int i = body.q_offset; i < body.q_offset + model.dimension; ++i) squared += std::pow(q[k][i] - reference.q[k][i], 2);
    }
  }
  return std::sqrt(squared / std::max<size_t>(1, samples - 1));
}

}  // namespace tether
