#include "tether/dynamics/solvers/schur_solver.h"

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <stdexcept>

namespace tether {

KktSolver ResolveSolver(KktSolver requested, const SparseLdlt& analysis) {
  if (requested != KktSolver::kAuto) return requested;
  const std::int64_t n = analysis.size();
  const bool dense_block = n >= kDenseBlockRows && analysis.updates() > n * n * n / 24;
  return dense_block ? KktSolver::kDense : KktSolver::kSparse;
}

SchurSolver::SchurSolver(const SchurPattern& pattern, KktSolver kind, bool factor_jet_matrices)
    : pattern_(&pattern), kind_(kind), factor_jet_matrices_(factor_jet_matrices) {
  if (kind_ != KktSolver::kDense) {
    sparse_factor_ = SparseLdlt(pattern);
    kind_ = ResolveSolver(kind, sparse_factor_);
  }
  if (kind_ == KktSolver::kDense) {
    sparse_factor_ = SparseLdlt();
    dense_.setZero(pattern.size(), pattern.size());
  }
  regularized_values_.reserve(pattern.nonzeros());  // a step allocates nothing, regularized or not
  regularized_jets_.reserve(pattern.nonzeros());
}

void SchurSolver::StoreInFactorOrder(SchurPattern* pattern) {
  if (pattern != pattern_) throw std::logic_error("StoreInFactorOrder: not the solver's pattern");
  if (kind_ != KktSolver::kSparse) return;
  const std::vector<int> position = sparse_factor_.FactorOrder();
  pattern->StoreValuesAt(position);
  sparse_factor_.StoreValuesAt(position);
}

template <typename T>
bool SchurSolver::Factor(const std::vector<double>& values, const SchurSource<T>& source) {
  close_to_pass_ = false;
  if (!regularized_ && FactorAsGiven(values) && WellConditioned(values, false, source)) return true;
  regularized_values_ = values;
  Regularize(*pattern_, &regularized_values_);
  if (!FactorAsGiven(regularized_values_, pass_floor_ ? kPassPivotFloor : 0.0)) return false;
  regularized_ = !WellConditioned(regularized_values_, true, source);
  // out of a near-singular stretch: S itself again, when it factors (it should, being well conditioned)
  if (!regularized_ && !FactorAsGiven(values)) {
    regularized_ = true;
    return FactorAsGiven(regularized_values_, pass_floor_ ? kPassPivotFloor : 0.0);
  }
  return true;
}

// A non-finite entry of S reaches a pivot of the sparse LDL^T (every L(r, j) adds L(r, j)^2 d_j to d_r), which
// Factor checks; Eigen's Cholesky can pass a NaN through, so the dense path checks the entries.
bool SchurSolver::FactorAsGiven(const std::vector<double>& values, double pivot_floor) {
  if (kind_ == KktSolver::kSparse) return sparse_factor_.Factor(values, pivot_floor);
  for (double v : values) {
    if (!std::isfinite(v)) return false;
  }
  const std::vector<int>& row = pattern_->row_index();
  const std::vector<int>& column = pattern_->column_index();
  for (size_t k = 0; k < values.size(); ++k) dense_(row[k], column[k]) = values[k];
  dense_factor_.compute(dense_);
  if (dense_factor_.info() != Eigen::Success) return false;
  pivots_ = dense_factor_.matrixLLT().diagonal().cwiseAbs2();
  return true;
}

void SchurSolver::SaveFactorization(Factorization* factorization) const {
  if (kind_ == KktSolver::kDense) {
    factorization->dense = dense_factor_;
  } else {
    sparse_factor_.Save(&factorization->sparse);
  }
}

void SchurSolver::SolveWith(const Factorization& factorization, Eigen::VectorXd* x) {
  if (kind_ == KktSolver::kDense) {
    factorization.dense.solveInPlace(*x);
  } else {
    sparse_factor_.SolveInPlace(factorization.sparse, x);
  }
}

// pivot i belongs to row order[i] of S (the identity for the dense Cholesky)
template <typename T>
bool SchurSolver::WellConditioned(const std::vector<double>& values, bool note_near_singular,
                                  const SchurSource<T>& source) {
  const bool sparse = kind_ == KktSolver::kSparse;
  const Eigen::VectorXd& pivots = sparse ? sparse_factor_.pivots() : pivots_;
  const double* __restrict pivot = pivots.data();
  const double* __restrict value = values.data();
  const int* __restrict diagonal = pattern_->diagonal().data();
  const int* __restrict order = sparse ? sparse_factor_.order().data() : nullptr;
  const int n = static_cast<int>(pivots.size());
  // the plain test alone up to the first small ratio (in most scenes every row passes it): no call in that loop
  int i = 0;
  while (i < n && pivot[i] >= kNearSingularPivotRatio * value[diagonal[sparse ? order[i] : i]]) ++i;
  bool all_above = true, near_singular = false, close_to_pass = false;
  for (; i < n; ++i) {
    const int row = sparse ? order[i] : i;
    const double s_ii = value[diagonal[row]];  // > 0 once factored
    if (pivot[i] >= kNearSingularPivotRatio * s_ii) continue;
    const double scale = std::min(s_ii, kLightShareSpread * source.SmallestShare(row));  // light bodies (header)
    if (pivot[i] >= kNearSingularPivotRatio * scale) continue;
    all_above = false;
    if (!note_near_singular) return false;
    if (pivot[i] > kRedundantPivotRatio * s_ii) near_singular = true;
    if (pivot[i] <= kSingularPassRatio * scale) close_to_pass = true;
  }
  if (note_near_singular) NoteConditioning(near_singular, close_to_pass);
  return all_above;
}

void SchurSolver::SolveInPlace(Eigen::VectorXd* x) {
  if (kind_ == KktSolver::kDense) {
    dense_factor_.solveInPlace(*x);
  } else {
    sparse_factor_.SolveInPlace(x);
  }
}

bool SchurSolver::HalfSolveInPlace(Eigen::VectorXd* b) {
  if (kind_ == KktSolver::kDense) {
    dense_factor_.matrixL().solveInPlace(*b);
    return true;
  }
  return sparse_factor_.HalfSolveInPlace(b);
}

const std::vector<Jet>& SchurSolver::FactoredJets(const std::vector<Jet>& values) {
  if (!regularized_) return values;
  regularized_jets_ = values;
  Regularize(*pattern_, &regularized_jets_);
  return regularized_jets_;
}

template <>
bool SchurSolver::Solve<double>(const std::vector<double>& values, const VecX<double>& b, VecX<double>* x,
                                const SchurSource<double>& source) {
  if (!Factor(values, source)) return false;
  *x = b;
  SolveInPlace(x);
  return true;
}

template <>
bool SchurSolver::Solve<Jet>(const std::vector<Jet>& values, const VecX<Jet>& b, VecX<Jet>* x,
                             const SchurSource<Jet>& source) {
  if (factor_jet_matrices_) return SolveByFactoringJets(values, b, x, source);
  value_part_.resize(values.size());
  for (size_t k = 0; k < values.size(); ++k) value_part_[k] = values[k].a;
  if (!Factor(value_part_, source)) return false;
  const int n = pattern_->size();
  x0_.resize(n);
  for (int i = 0; i < n; ++i) x0_[i] = b[i].a;
  SolveInPlace(&x0_);
  // residual b - S x0: its value part is ~0, its derivative parts are db_k - dS_k x0
  MultiplySymmetric(*pattern_, FactoredJets(values), x0_, &product_);
  x->resize(n);
  columns_.resize(n, kJetStride);
  for (int i = 0; i < n; ++i) columns_.row(i) = b[i].v - product_[i].v;
  if (kind_ == KktSolver::kDense) {
    for (int k = 0; k < kJetStride; ++k) {
      column_ = columns_.col(k);
      SolveInPlace(&column_);
      columns_.col(k) = column_;
    }
  } else {
    sparse_factor_.SolveInPlace(&columns_);
  }
  for (int i = 0; i < n; ++i) {
    (*x)[i].a = x0_[i];
    (*x)[i].v = columns_.row(i).transpose();
  }
  return true;
}

// Rev: the solution's values as for double, recorded as an external operation. Its adjoint is one more solve
// with the matrix factored (S symmetric): from S x = b, b_bar = S^-1 x_bar and S_bar = -b_bar x^T, a stored
// off-diagonal value standing for S_ij and S_ji. The regularization adds eps S_ii to a diagonal value (the floor
// is a constant, as for Jets).
template <>
bool SchurSolver::Solve<Rev>(const std::vector<Rev>& values, const VecX<Rev>& b, VecX<Rev>* x,
                             const SchurSource<Rev>& source) {
  value_part_.resize(values.size());
  bool recorded = false;
  for (size_t k = 0; k < values.size(); ++k) {
    value_part_[k] = values[k].a;
    recorded = recorded || values[k].index >= 0;
  }
  if (!Factor(value_part_, source)) return false;
  const int n = pattern_->size();
  x0_.resize(n);
  for (int i = 0; i < n; ++i) {
    x0_[i] = b[i].a;
    recorded = recorded || b[i].index >= 0;
  }
  SolveInPlace(&x0_);
  x->resize(n);
  if (!recorded || n == 0) {
    for (int i = 0; i < n; ++i) (*x)[i] = Rev(x0_[i]);
    return true;
  }
  std::vector<int> value_nodes(values.size()), rhs_nodes(n);
  for (size_t k = 0; k < values.size(); ++k) value_nodes[k] = values[k].index;
  for (int i = 0; i < n; ++i) rhs_nodes[i] = b[i].index;
  const double diagonal_factor = regularized_ ? 1.0 + kSchurRegularization : 1.0;
  auto factorization = std::make_shared<Factorization>();
  SaveFactorization(factorization.get());
  auto backward = [this, n, factorization, solution = x0_, value_nodes = std::move(value_nodes),
                   rhs_nodes = std::move(rhs_nodes), diagonal_factor](const double* x_bar, Tape* tape) {
    Eigen::VectorXd b_bar = Eigen::Map<const Eigen::VectorXd>(x_bar, n);
    SolveWith(*factorization, &b_bar);  // the matrix factored forward
    for (int i = 0; i < n; ++i) tape->AddAdjoint(rhs_nodes[i], b_bar[i]);
    const std::vector<int>& row = pattern_->row_index();
    const std::vector<int>& column = pattern_->column_index();
    for (size_t k = 0; k < value_nodes.size(); ++k) {
      const int i = row[k], j = column[k];
      const double adjoint =
          i == j ? -b_bar[i] * solution[i] * diagonal_factor : -(b_bar[i] * solution[j] + b_bar[j] * solution[i]);
      tape->AddAdjoint(value_nodes[k], adjoint);
    }
  };
  const int first = ActiveTape()->RecordExternal(n, std::move(backward));
  for (int i = 0; i < n; ++i) (*x)[i] = Rev(x0_[i], first + i);
  return true;
}

// The oracle's substitutions are written out: Eigen's triangular solves skip right-hand-side entries that
// compare equal to zero, and a Jet compares by its value only, so a zero value with non-zero derivatives would
// lose them. It regularizes where the double path does (the conditioning of the value part decides).
bool SchurSolver::SolveByFactoringJets(const std::vector<Jet>& given, const VecX<Jet>& b, VecX<Jet>* x,
                                       const SchurSource<Jet>& source) {
  value_part_.resize(given.size());
  for (size_t k = 0; k < given.size(); ++k) value_part_[k] = given[k].a;
  if (!Factor(value_part_, source)) return false;
  const std::vector<Jet>& values = FactoredJets(given);
  const int n = pattern_->size();
  const std::vector<int>& row = pattern_->row_index();
  const std::vector<int>& column = pattern_->column_index();
  std::function<void(VecX<Jet>*)> solve_in_place;
  Eigen::Matrix<Jet, Eigen::Dynamic, Eigen::Dynamic> lower_dense;
  Eigen::SparseMatrix<Jet> lower_sparse;
  VecX<Jet> d;
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> permutation;
  if (kind_ == KktSolver::kDense) {
    jet_dense_.setZero(n, n);
    for (size_t k = 0; k < values.size(); ++k) jet_dense_(row[k], column[k]) = values[k];
    const Eigen::LLT<Eigen::Matrix<Jet, Eigen::Dynamic, Eigen::Dynamic>> factor(jet_dense_);
    if (factor.info() != Eigen::Success) return false;
    lower_dense = factor.matrixL();
    solve_in_place = [&](VecX<Jet>* y) {
      for (int i = 0; i < n; ++i) {  // L z = y
        for (int k = 0; k < i; ++k) (*y)[i] -= lower_dense(i, k) * (*y)[k];
        (*y)[i] /= lower_dense(i, i);
      }
      for (int i = n - 1; i >= 0; --i) {  // L^T w = z
        for (int k = i + 1; k < n; ++k) (*y)[i] -= lower_dense(k, i) * (*y)[k];
        (*y)[i] /= lower_dense(i, i);
      }
    };
  } else {
    std::vector<Eigen::Triplet<Jet>> entries;
    for (size_t k = 0; k < values.size(); ++k) entries.emplace_back(row[k], column[k], values[k]);
    jet_sparse_.resize(n, n);
    jet_sparse_.setFromTriplets(entries.begin(), entries.end());
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<Jet>, Eigen::Lower, Eigen::AMDOrdering<int>> factor(jet_sparse_);
    if (factor.info() != Eigen::Success) return false;
    // S = P^T L D L^T P with L unit lower triangular (its strictly lower part stored by columns)
    lower_sparse = factor.matrixL().nestedExpression();
    d = factor.vectorD();
    permutation = factor.permutationP();
    solve_in_place = [&](VecX<Jet>* x_in_out) {
      VecX<Jet> y = permutation * (*x_in_out);
      for (int j = 0; j < n; ++j) {  // L z = P b
        for (Eigen::SparseMatrix<Jet>::InnerIterator it(lower_sparse, j); it; ++it) {
          if (it.row() > j) y[it.row()] -= it.value() * y[j];
        }
      }
      for (int j = 0; j < n; ++j) y[j] /= d[j];
      for (int j = n - 1; j >= 0; --j) {  // L^T w = D^-1 z
        for (Eigen::SparseMatrix<Jet>::InnerIterator it(lower_sparse, j); it; ++it) {
          if (it.row() > j) y[j] -= it.value() * y[it.row()];
        }
      }
      *x_in_out = permutation.inverse() * y;
    };
  }
  *x = b;
  solve_in_place(x);
  return true;
}

}  // namespace tether
