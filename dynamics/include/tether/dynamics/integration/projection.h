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

#include "tether/dynamics/solvers/workspace.h"

namespace tether {

struct ProjectionResult {
  bool converged = false;
  int iterations = 0;
  Violation violation;  // what is left at the end
};

template <typename T>
ProjectionResult ProjectPositions(const Model<T>& model, double tolerance, Workspace<T>* ws, VecX<T>* q);

// Onto C(q) = 0 from q by Levenberg-Marquardt steps on |C|^2 in the unit metric (M = 1: with masses far apart
// the mass metric all but freezes the heavy body that has to move),
//   (S_k + mu diag S_k) nu = C(q_k),   q_{k+1} = q_k (+) (-J_k^T nu),   S_k = J_k J_k^T,
// mu divided by 3 after a step that decreases |C|^2 and multiplied by 4 (the step retried) after one that does
// not. This reaches the constraints from far off, where the nearest-state iteration above, linearised about its
// target, can cycle (a bob several rod lengths from its cart, a light cart whose rows nearly align). The point
// it reaches lies on the constraints but is not in general the nearest one. For assembling an initial state.
template <typename T>
ProjectionResult ProjectPositionsRobustly(const Model<T>& model, double tolerance, Workspace<T>* ws, VecX<T>* q);

// Returns false when the Schur system could not be factored.
template <typename T>
bool ProjectVelocities(const Model<T>& model, const VecX<T>& q, Workspace<T>* ws, VecX<T>* v);

}  // namespace tether
