#include "tether/dynamics/solvers/kkt_log.h"

namespace tether {

void KktLog::Keep(const Eigen::VectorXd& lambda, const SchurSolver& solver) {
  if (kept == solves.size()) solves.emplace_back();
  KktSolve& solve = solves[kept++];
  solve.lambda = lambda;
  solver.SaveFactorization(&solve.factorization);
  solve.regularized = solver.starts_regularized();
  solve.near_singular = solver.saw_near_singular();
  solve.close_to_pass = solver.was_close_to_pass();
}

std::int64_t KktLog::Bytes() const {
  std::int64_t bytes = static_cast<std::int64_t>(sizeof(KktLog) + solves.capacity() * sizeof(KktSolve));
  for (size_t k = 0; k < kept; ++k) {
    const KktSolve& solve = solves[k];
    const std::int64_t values = solve.lambda.size() +
                                static_cast<std::int64_t>(solve.factorization.sparse.lower.size()) +
                                solve.factorization.sparse.inverse_d.size() +
                                solve.factorization.dense.rows() * solve.factorization.dense.cols();
    bytes += values * static_cast<std::int64_t>(sizeof(double));
  }
  return bytes;
}

}  // namespace tether
