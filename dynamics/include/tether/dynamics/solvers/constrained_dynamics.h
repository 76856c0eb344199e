// The constrained equations of motion: v' from the KKT system (docs/architecture.md, "The physics")
//   [M J^T; J 0] [v'; lambda] = [f; -Jdot v - alpha J v - beta C]
// which is Baumgarte's C'' + alpha C' + beta C = 0 (alpha = beta = 0 keeps C'' = 0). It is solved through the
// Schur complement (schur_system.h): S lambda = J M^-1 f + Jdot v + alpha J v + beta C, then
// v' = M^-1 (f - J^T lambda). f includes the gyroscopic torques of 3D bodies (effects.h).
// Sliding contacts (contact_friction.h) turn the force direction of their normal rows K to J_K - mu J_s, so that
// S' = J M^-1 (J - F)^T, F holding mu J_s on the rows K: S' lambda = rhs is solved with S's factorization
// (Sherman-Morrison-Woodbury): with W = J M^-1 F^T's columns K, S Z = W, lambda0 = S^-1 rhs,
//   (1 - Z_K) lambda_K = lambda0_K,   lambda = lambda0 + Z lambda_K,   v' = M^-1 (f - (J - F)^T lambda).
// det(1 - Z_K) = det S' / det S <= 0 is Painleve's paradox (no consistent accelerations: a normal force that
// pushes the bodies together): the solve fails and names the contact (Workspace::painleve). Where the rows are
// redundant (S was regularized: coplanar contacts), S^-1 multiplies by 1 / eps in their null space and the
// formula's terms would cancel: S' itself is factored instead, dense and regularized as S is, and Painleve's
// paradox is not detected there.
//
// In Rev arithmetic (reverse.h) the KKT part, from the rows and forces to v', is recorded as one operation whose
// adjoint is written out (adjoint/recorded.h; kkt_adjoint.cc): a node per velocity instead of a few dozen per row.
#pragma once

#include "tether/dynamics/solvers/workspace.h"

namespace tether {

// Writes v' at (t, q, v) into *a, with the gains and joint coordinates in ws. Returns false when the Schur system
// could not be factored (non-finite or indefinite: the run is diverging); *a is then filled with NaN. Where the rows
// are a tree (ws->tree) the tree elimination takes the constraint primitives (tree_elimination.h) and leaves only the
// rows' values in ws->rows (what LargestViolation reads); the Schur path evaluates the rows whole.
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

// The sliding contacts' part (above), after KktAcceleration's solve of S lambda0 = rhs (in kkt->lambda): lambda
// and v' turned by their friction. Returns the sliding row where det(1 - Z_K) <= 0 (Painleve), else -1.
template <typename S, typename T>
int SlidingKktAcceleration(const Model<S>& model, const std::vector<BodyLayout>& layout, SchurSolver* solver,
                           const std::vector<ConstraintRow<T>>& rows, const std::vector<SlidingRow<T>>& sliding,
                           const InverseMass<T>& inverse_mass, VecX<T>* force, KktSystem<T>* kkt, VecX<T>* a);

// KktAcceleration on the workspace's rows, frames, force and gains at (q, v); for Rev, recorded as one operation. A
// double run with a KKT log (ws->kkt_log) keeps each solve there, and a recorded replay takes them back (kkt_log.h).
template <typename T>
bool SolveKkt(const Model<T>& model, const VecX<T>& v, Workspace<T>* ws, VecX<T>* a);

}  // namespace tether
