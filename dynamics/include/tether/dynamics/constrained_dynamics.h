// The constrained equations of motion: q'' from the KKT system (DESIGN.md, seed lecture)
//   [M J^T; J 0] [q''; lambda] = [f; -Jdot q' - alpha J q' - beta C]
// which is Baumgarte's C'' + alpha C' + beta C = 0 (alpha = beta = 0 keeps C'' = 0). It is solved through the
// Schur complement (schur_system.h): S lambda = J M^-1 f + Jdot q' + alpha J q' + beta C, then
// q'' = M^-1 (f - J^T lambda).
#pragma once

#include "tether/dynamics/workspace.h"

namespace tether {

// Writes q'' at (t, q, v) into *a, with the gains in ws. Returns false when the Schur system could not be
// factored (non-finite or indefinite: the run is diverging); *a is then filled with NaN.
template <typename T>
bool ComputeAcceleration(const Model<T>& model, double t, const VecX<T>& q, const VecX<T>& v, Workspace<T>* ws,
                         VecX<T>* a);

// M^-1 f for the model's diagonal mass matrix: 1/m on translational coordinates, 1/I on angles.
template <typename T>
VecX<T> InverseMassDiagonal(const Model<T>& model);

}  // namespace tether
