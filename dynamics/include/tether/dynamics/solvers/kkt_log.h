// The KKT solves of one step of a double run, kept for the discrete adjoint's recorded replay of the same step
// (autodiff/adjoint.h, kkt_adjoint.cc).
//
// A step's evaluations solve S lambda = rhs, S = J M^-1 J^T, once per integrator stage. The replay computes the
// same doubles (reverse.h), so it need not assemble, factor and solve S again: it takes the multipliers lambda of
// each solve in order, forms a = M^-1 (f - J^T lambda) from its own f and J, and keeps the factorization for its
// backward solve rbar = S^-1 lambdabar. The solver's conditioning state after each solve (whether it regularized,
// whether it saw a near-singular configuration) travels with it, since the step's projection and the next solve
// depend on it. A step whose solves were not kept (a budget ran out) is replayed solving them again.
#pragma once

#include <cstdint>
#include <vector>

#include "tether/dynamics/solvers/schur_solver.h"

namespace tether {

struct KktSolve {
  Eigen::VectorXd lambda;
  SchurSolver::Factorization factorization;  // of S as solved: regularized or not
  bool regularized = false;                  // S + eps D was factored (SchurSolver::starts_regularized after)
  bool near_singular = false;                // SchurSolver::saw_near_singular after the solve
  bool close_to_pass = false;                // SchurSolver::was_close_to_pass after the solve
};

struct KktLog {
  std::vector<KktSolve> solves;  // in the order the step made them; entries past `kept` are spare buffers
  size_t kept = 0;               // solves written by the double run
  size_t taken = 0;              // solves read back by the replay

  // Forgets the solves (keeping their buffers).
  void Clear() { kept = taken = 0; }
  // Appends the solve `solver` just made, with multipliers `lambda`.
  void Keep(const Eigen::VectorXd& lambda, const SchurSolver& solver);
  // The next solve for the replay, or nullptr when none is left.
  KktSolve* Take() { return taken < kept ? &solves[taken++] : nullptr; }
  // Bytes the kept solves hold.
  std::int64_t Bytes() const;
};

}  // namespace tether
