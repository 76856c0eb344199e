// The constrained equations of motion: v' from the KKT system (DESIGN.md, seed lecture)
//   [M J^T; J 0] [v'; lambda] = [f; -Jdot v - alpha J v - beta C]
// which is Baumgarte's C'' + alpha C' + beta C = 0 (alpha = beta = 0 keeps C'' = 0). It is solved through the
// Schur complement (schur_system.h): S lambda = J M^-1 f + Jdot v + alpha J v + beta C, then
// v' = M^-1 (f - J^T lambda). f includes the gyroscopic torques of 3D bodies (effects.h).
#pragma once

#include "tether/dynamics/workspace.h"

namespace tether {

// Writes v' at (t, q, v) into *a, with the gains and joint coordinates in ws. Returns false when the Schur system
// could not be factored (non-finite or indefinite: the run is diverging); *a is then filled with NaN.
template <typename T>
bool ComputeAcceleration(const Model<T>& model, double t, const VecX<T>& q, const VecX<T>& v, Workspace<T>* ws,
                         VecX<T>* a);

}  // namespace tether
