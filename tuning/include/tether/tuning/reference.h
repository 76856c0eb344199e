// The reference motion of a model: what tether takes for the true constrained motion when it measures the error
// of a run (gain tuning, studies). rk45 at tolerance kReferenceTolerance with projection onto the constraints and
// its events located (a time-stepping scene's too: docs/contact.md), sampled on the model's own step grid, so that
// it lines up with the model's run row for row.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "tether/dynamics/integration/trajectory.h"

namespace tether {

inline constexpr double kReferenceTolerance = 1e-10;

using ReferenceMotion = Trajectory<double>;

// Throws SimulationDiverged if even the reference diverges.
ReferenceMotion ComputeReference(const Model<double>& model);

// sqrt(mean over the samples of |x(t) - x_ref(t)|^2) over the translational coordinates (the centres of mass),
// for a run sampled on the same grid (run.q[k] at reference.t[k]).
double RmsPositionError(const Model<double>& model, const ReferenceMotion& reference, const Trajectory<double>& run);

}  // namespace tether
