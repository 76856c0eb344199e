// Mass-weighted projection onto the constraint manifold, used for the `projection` stabilization and for
// assembling an initial state that violates its constraints.
//
// Positions: q* = q_t (+) d*, d* = argmin d^T M d subject to C(q_t (+) d) = 0, by Gauss-Newton on the KKT
// conditions (configuration_space.h; d_k = q_k (-) q_t):
//   S_k mu = C(q_k) - J_k d_k,   q_{k+1} = q_t (+) (-M^-1 J_k^T mu),    S_k = J_k M^-1 J_k^T,
// iterated until max |C| <= tolerance. Velocities: v* = v - M^-1 J^T S^-1 J v, the nearest velocity (in the
// kinetic-energy metric) that satisfies J v* = 0. Both are differentiable: the iteration runs once more after
// the values converge so that Jet derivatives settle too (for every scalar, so that values never differ).
#pragma once

#include "tether/dynamics/workspace.h"

namespace tether {

struct ProjectionResult {
  bool converged = false;
  int iterations = 0;
  Violation violation;  // what is left at the end
};

template <typename T>
ProjectionResult ProjectPositions(const Model<T>& model, double tolerance, Workspace<T>* ws, VecX<T>* q);

// Returns false when the Schur system could not be factored.
template <typename T>
bool ProjectVelocities(const Model<T>& model, const VecX<T>& q, Workspace<T>* ws, VecX<T>* v);

}  // namespace tether
