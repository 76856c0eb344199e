// Solving the (regularized) Schur system S x = b of schur_system.h, for double and for Jet scalars.
//
// Two factorizations of the double matrix, chosen by KktSolver:
//   kSparse  LDL^T with an approximate-minimum-degree ordering (sparse_ldlt.h), whose symbolic analysis is
//            done once per solver (per run) and only the numeric factorization per solve. For a chain the
//            ordering keeps S banded and the cost is linear in its length;
//   kDense   Cholesky (LLT) of S held as a dense matrix: a reference path, and a fallback for a user who wants
//            to compare.
// kAuto is kSparse: measured with bench/chain_bench.cc, it is faster than kDense at every size from one row up
// (0.49 against 0.88 us per rk4 step of a one-particle chain, 4.0 against 5.7 us of the four-bar;
// studies/scaling).
//
// Jets (the implicit function theorem): with S = S0 + sum_k dS_k e_k and b = b0 + sum_k db_k e_k,
//   x0 = S0^-1 b0,   dx_k = S0^-1 (db_k - dS_k x0),
// so the double matrix S0 is factored once and every derivative direction costs one more pair of triangular
// solves. The right-hand sides db_k - dS_k x0 are the derivative parts of the Jet residual b - S x0.
// Factoring the matrix of Jets itself (same dense or sparse method, in Jet arithmetic) is kept only as a test
// oracle and a benchmark baseline (factor_jet_matrices).
//
// Conditioning. Every factorization S = P^T L D L^T P (D = diag(L)^2 for the dense Cholesky) also reveals how
// close the rows are to dependence: the pivot ratio d_i / S_ii (ordered as the factorization orders the rows) is
// sin^2 of the angle, in the M^-1 metric, between row i's Jacobian and the span of the rows before it. A ratio
// below kNearSingularPivotRatio but above kRedundantPivotRatio marks a configuration near a singular one (a
// mechanism at a dead centre or a bifurcation, a light body between nearly collinear rods): the solver records
// it, and the simulator then projects the state back onto the constraints (simulator.cc). Ratios at the
// regularization's floor belong to exactly redundant rows, which the regularization already handles.
//
// Refinement. Where every pivot ratio is above kNearSingularPivotRatio and the diagonal of S spans at least
// kRefinedDiagonalSpread (the bias eps S_ii lambda_i matters only where some S_ii dwarfs the others: a thin
// rod's spin; on a chain of particles it is a relative 1e-12 and the extra solves would cost 15% of a step),
// every solve removes the regularization's bias by one refinement step (schur_system.h): x = (S + eps D)^-1 b, then
// x += (S + eps D)^-1 (eps D x), one more pair of triangular solves on the same factors. Where rows are redundant
// the regularized solution is the wanted one, and near a singular configuration the refinement would undo the
// damping of the nearly dependent direction that carries a mechanism through it (a four-bar's singular pass
// diverges with it). For Jets the value part is refined; the derivative parts are solved with S + eps D as they
// are, a relative bias of eps cond(S) (1e-11 on the test chain) that no gradient use resolves, where refining
// them too would double the Jet path's solves.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/SparseCore>
#include <memory>

#include "tether/dynamics/schur_system.h"
#include "tether/dynamics/sparse_ldlt.h"

namespace tether {

inline constexpr double kNearSingularPivotRatio = 1e-4;
inline constexpr double kRedundantPivotRatio = 1e-9;
inline constexpr double kRefinedDiagonalSpread = 1e3;

// The path a request takes: kAuto becomes kSparse.
KktSolver ResolveSolver(KktSolver requested);

class SchurSolver {
 public:
  // Analyzes the pattern once; `kind` may be kAuto.
  SchurSolver(const SchurPattern& pattern, KktSolver kind, bool factor_jet_matrices = false);

  KktSolver kind() const { return kind_; }

  // Whether a factorization since the last call to ForgetConditioning() was near a singular configuration.
  bool saw_near_singular() const { return saw_near_singular_; }
  void ForgetConditioning() { saw_near_singular_ = false; }

  // x = S^-1 b, S given by its stored values (AssembleSchur). Returns false, leaving x unchanged, when the
  // factorization fails (a non-finite or indefinite matrix: the run is diverging).
  template <typename T>
  bool Solve(const std::vector<T>& values, const VecX<T>& b, VecX<T>* x);

 private:
  bool Factor(const std::vector<double>& values);
  void NoteConditioning(const std::vector<double>& values, const Eigen::VectorXd& pivots,
                        const Eigen::VectorXi* order);
  void SolveInPlace(Eigen::VectorXd* x);
  // x = S^-1 b with the last factorization, refined where refine_ says
  void SolveRefined(const std::vector<double>& values, Eigen::VectorXd* x);
  bool SolveByFactoringJets(const std::vector<Jet>& values, const VecX<Jet>& b, VecX<Jet>* x);

  const SchurPattern* pattern_;
  KktSolver kind_;
  Eigen::MatrixXd dense_;
  Eigen::LLT<Eigen::MatrixXd> dense_factor_;
  SparseLdlt sparse_factor_;
  Eigen::VectorXd pivots_;
  bool saw_near_singular_ = false;
  bool refine_ = false;  // the last factorization's rows are well conditioned and their diagonal spread
  Eigen::VectorXd correction_;
  // scratch for the Jet path
  std::vector<double> value_part_;
  Eigen::VectorXd x0_, column_;
  VecX<Jet> product_;
  // the oracle path
  bool factor_jet_matrices_;
  Eigen::Matrix<Jet, Eigen::Dynamic, Eigen::Dynamic> jet_dense_;
  Eigen::SparseMatrix<Jet> jet_sparse_;
};

}  // namespace tether
