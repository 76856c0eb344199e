// The constrained equations of motion: v' from the KKT system (docs/architecture.md, "The physics")
//   [M J^T; J 0] [v'; lambda] = [f; -Jdot v - alpha J v - beta C]
// which is Baumgarte's C'' + alpha C' + beta C = 0 (alpha = beta = 0 keeps C'' = 0). It is solved through the
// Schur complement (schur_system.h): S lambda = J M^-1 f + Jdot v + alpha J v + beta C, then
// v' = M^-1 (f - J^T lambda). f includes the gyroscopic torques of 3D bodies (effects.h).
//
// In Rev arithmetic (reverse.h) the KKT part, from the rows and forces to v', is recorded as one operation whose
// adjoint is written out (adjoint/recorded.h; kkt_adjoint.cc): a node per velocity instead of a few dozen per row.
#pragma once

#include "tether/dynamics/solvers/workspace.h"

namespace tether {

// Writes v' at (t, q, v) into *a, with the gains and joint coordinates in ws. Returns false when the Schur system
// could not be factored (non-finite or indefinite: the run is diverging); *a is then filled with NaN.
template <typename T>
bool ComputeAcceleration(const Model<T>& model, double t, const VecX<T>& q, const VecX<T>& v, Workspace<T>* ws,
                         VecX<T>* a);

// The KKT part of it: v' from the rows, the generalized force (*force, left as f - J^T lambda), the inverse mass
// and the gains; the model gives the bodies' layout only (its scalar S may differ from T). False, with *a NaN,
// when S cannot be factored.
template <typename S, typename T>
bool KktAcceleration(const Model<S>& model, const std::vector<BodyLayout>& layout, const SchurPattern& pattern,
                     SchurSolver* solver, const std::vector<ConstraintRow<T>>& rows, const InverseMass<T>& inverse_mass,
                     const VecX<T>& v, const T& alpha, const T& beta, VecX<T>* force, KktSystem<T>* kkt, VecX<T>* a);

// KktAcceleration on the workspace's rows, force and gains; for Rev, recorded as one operation. A double run
// with a KKT log (ws->kkt_log) keeps each solve there, and a recorded replay takes them back (kkt_log.h).
template <typename T>
bool SolveKkt(const Model<T>& model, const VecX<T>& v, Workspace<T>* ws, VecX<T>* a);

}  // namespace tether
