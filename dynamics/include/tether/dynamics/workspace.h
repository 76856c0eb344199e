// Workspace<T>: everything a run computes into, made once per run so that a step allocates nothing
// (Pinocchio's Model/Data split). It holds the row layout, the Schur pattern and its factorization (analyzed
// once), M^-1, the gains in use, and scratch vectors for the integrators.
#pragma once

#include <array>
#include <vector>

#include "tether/dynamics/constraint_rows.h"
#include "tether/dynamics/schur_solver.h"

namespace tether {

template <typename T>
struct Workspace {
  // factor_jet_matrices: see RunOptions (a test oracle; the default applies the implicit function theorem).
  explicit Workspace(const Model<T>& model, bool factor_jet_matrices = false);
  Workspace(const Workspace&) = delete;  // the solver points into the pattern
  Workspace& operator=(const Workspace&) = delete;

  std::vector<RowInfo> infos;           // one per constraint row
  SchurPattern pattern;                 // of S = J M^-1 J^T
  SchurSolver solver;                   // its factorization
  VecX<T> inverse_mass;                 // diagonal of M^-1 (size n)
  T alpha = T(0.0), beta = T(0.0);      // Baumgarte gains in use (0 unless the method is baumgarte)

  std::vector<ConstraintRow<T>> rows;   // rows at the last evaluation
  std::vector<T> schur;                 // S at the last evaluation (pattern.nonzeros())
  VecX<T> force;                        // generalized force f (size n)
  VecX<T> rhs, lambda;                  // Schur right-hand side and multipliers (size m)
  VecX<T> reaction;                     // M^-1 J^T lambda (size n)

  // integrator scratch: stage derivatives and trial states (size n each)
  std::array<VecX<T>, 7> stage_q, stage_v;
  VecX<T> trial_q, trial_v, next_q, next_v;
  VecX<T> error_q, error_v;             // rk45's local error estimate
  double rk45_step = 0.0;               // rk45's current internal step (0: not started)
  bool rk45_first_stage_valid = false;  // first-same-as-last: stage 0 holds f at the current state
};

}  // namespace tether
