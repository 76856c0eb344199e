#include "tether/dynamics/solvers/sparse_ldlt.h"

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <queue>
#include <type_traits>

#include "tether/dynamics/scalars/scalar.h"

namespace tether {
namespace {

// The breadth-first order is kept while it fills L at most this much more than the minimum-degree order.
constexpr double kBreadthFirstFillAllowance = 1.25;

// Above this many updates the numeric phase finds its targets as it goes instead of listing them: the list
// holds one index per multiply-add of a factorization, which for the dense block of rows a hub body couples
// (1090 rows on MuJoCo's softbox: 2.2e8 updates) is more memory than everything else together.
constexpr std::int64_t kMaxListedUpdates = std::int64_t{1} << 23;

// The approximate-minimum-degree ordering of S's pattern, as new index -> S's row.
Eigen::VectorXi MinimumDegreeOrder(const SchurPattern& pattern) {
  const int n = pattern.size();
  Eigen::SparseMatrix<double, Eigen::ColMajor, int> lower(n, n);
  std::vector<Eigen::Triplet<double, int>> entries;
  entries.reserve(pattern.nonzeros());
  for (int k = 0; k < pattern.nonzeros(); ++k)
    entries.emplace_back(pattern.row_index()[k], pattern.column_index()[k], 1.0);
  lower.setFromTriplets(entries.begin(), entries.end());
  Eigen::AMDOrdering<int>::PermutationType new_to_old;  // Eigen's orderings compute the inverse permutation
  Eigen::AMDOrdering<int>()(lower, new_to_old);         // of the symmetric pattern lower + lower^T
  return new_to_old.indices();
}

// Cuthill-McKee: breadth first through the rows' graph (rows adjacent where S couples them) from its first row
// (a scene's first joint, typically the one at its base), each row's unvisited neighbours taken by increasing
// degree; every component in turn.
Eigen::VectorXi BreadthFirstOrder(const SchurPattern& pattern) {
  const int n = pattern.size();
  std::vector<std::vector<int>> neighbours(n);
  for (int k = 0; k < pattern.nonzeros(); ++k) {
    const int a = pattern.row_index()[k], b = pattern.column_index()[k];
    if (a == b) continue;
    neighbours[a].push_back(b);
    neighbours[b].push_back(a);
  }
  for (std::vector<int>& list : neighbours) {
    std::stable_sort(list.begin(), list.end(),
                     [&](int x, int y) { return neighbours[x].size() < neighbours[y].size(); });
  }
  Eigen::VectorXi order(n);
  std::vector<bool> visited(n, false);
  int next = 0;
  for (int start = 0; start < n; ++start) {
    if (visited[start]) continue;
    std::queue<int> queue;
    queue.push(start);
    visited[start] = true;
    while (!queue.empty()) {
      const int row = queue.front();
      queue.pop();
      order[next++] = row;
      for (int neighbour : neighbours[row]) {
        if (visited[neighbour]) continue;
        visited[neighbour] = true;
        queue.push(neighbour);
      }
    }
  }
  return order;
}

// The elimination tree of the permuted matrix (parent of each new row; -1 at a root), from its lower rows.
std::vector<int> EliminationTree(const std::vector<int>& row_start, const std::vector<int>& row_columns) {
  const int n = static_cast<int>(row_start.size()) - 1;
  std::vector<int> parent(n, -1), ancestor(n, -1);
  for (int k = 0; k < n; ++k) {
    for (int e = row_start[k]; e < row_start[k + 1]; ++e) {
      // climb from column i < k to the root of its current subtree, pointing the path at k
      for (int i = row_columns[e]; i != -1 && i < k;) {
        const int next = ancestor[i];
        ancestor[i] = k;
        if (next == -1) parent[i] = k;
        i = next;
      }
    }
  }
  return parent;
}

// t <- L^-1 t with L unit lower triangular, stored by columns (rows lower_row, values lower); kSparseRight skips the
// columns whose entry of t is still zero (a right-hand side with few nonzeros reaches only their ancestors)
template <bool kSparseRight>
inline void ForwardSubstitute(int n, const int* __restrict start, const int* __restrict lower_row,
                              const double* __restrict lower, double* __restrict t) {
  for (int j = 0; j < n; ++j) {
    const double tj = t[j];
    if (kSparseRight && tj == 0.0) continue;
    for (int p = start[j]; p < start[j + 1]; ++p) t[lower_row[p]] -= lower[p] * tj;
  }
}

}  // namespace

SparseLdlt::SparseLdlt(const SchurPattern& pattern) {
  Analyze(pattern, MinimumDegreeOrder(pattern));
  const int minimum_degree_fill = nonzeros();
  Analyze(pattern, BreadthFirstOrder(pattern));
  if (nonzeros() > kBreadthFirstFillAllowance * minimum_degree_fill) Analyze(pattern, MinimumDegreeOrder(pattern));
  PlanNumericPhase(pattern);
}

void SparseLdlt::Analyze(const SchurPattern& pattern, const Eigen::VectorXi& order) {
  const int n = pattern.size();
  order_ = order;
  std::vector<int> new_index(n);
  for (int k = 0; k < n; ++k) new_index[order_[k]] = k;

  // the columns of S's off-diagonal entries in each row of the permuted lower triangle
  std::vector<std::vector<int>> rows(n);
  for (int v = 0; v < pattern.nonzeros(); ++v) {
    const int a = new_index[pattern.row_index()[v]], b = new_index[pattern.column_index()[v]];
    if (a != b) rows[std::max(a, b)].push_back(std::min(a, b));
  }
  std::vector<int> row_start(1, 0), row_columns;
  for (const std::vector<int>& row : rows) {
    row_columns.insert(row_columns.end(), row.begin(), row.end());
    row_start.push_back(static_cast<int>(row_columns.size()));
  }
  const std::vector<int> parent = EliminationTree(row_start, row_columns);

  // row k's pattern: the paths up the tree from its entries towards k, each stopping where an earlier one
  // passed; read back as the later paths first, each from the bottom up, a column comes after every column
  // below it in the tree (topological order, as in Davis's LDL)
  std::vector<int> flag(n, -1), path, stack;
  std::vector<std::vector<int>> patterns(n);
  std::vector<int> column_count(n, 0);
  for (int k = 0; k < n; ++k) {
    flag[k] = k;
    stack.clear();
    for (int e = row_start[k]; e < row_start[k + 1]; ++e) {
      path.clear();
      for (int i = row_columns[e]; flag[i] != k; i = parent[i]) {
        path.push_back(i);
        flag[i] = k;
      }
      stack.insert(stack.end(), path.rbegin(), path.rend());
    }
    patterns[k].assign(stack.rbegin(), stack.rend());
    for (int i : patterns[k]) ++column_count[i];
  }

  // L by columns; rows are appended to a column in increasing order
  column_start_.assign(n + 1, 0);
  for (int i = 0; i < n; ++i) column_start_[i + 1] = column_start_[i] + column_count[i];
  const int nnz = column_start_[n];
  lower_row_.resize(nnz);
  std::vector<int> filled(column_start_.begin(), column_start_.end() - 1);
  for (int k = 0; k < n; ++k) {
    for (int i : patterns[k]) lower_row_[filled[i]++] = k;
  }
}

void SparseLdlt::PlanNumericPhase(const SchurPattern& pattern) {
  const int n = pattern.size();
  const int nnz = nonzeros();
  std::vector<int> new_index(n);
  for (int k = 0; k < n; ++k) new_index[order_[k]] = k;
  // where L(row, column) is stored, or the diagonal slot nnz + row
  auto slot = [&](int row, int column) {
    if (row == column) return nnz + row;
    const auto column_rows = lower_row_.begin() + column_start_[column];
    const auto end = lower_row_.begin() + column_start_[column + 1];
    return static_cast<int>(std::lower_bound(column_rows, end, row) - lower_row_.begin());
  };
  value_slot_.resize(pattern.nonzeros());
  std::vector<bool> from_s(nnz + n, false);
  for (int v = 0; v < pattern.nonzeros(); ++v) {
    const int a = new_index[pattern.row_index()[v]], b = new_index[pattern.column_index()[v]];
    value_slot_[v] = slot(std::max(a, b), std::min(a, b));
    from_s[value_slot_[v]] = true;
  }
  fill_slot_.clear();
  for (int position = 0; position < nnz; ++position) {
    if (!from_s[position]) fill_slot_.push_back(position);
  }
  // the updates column j makes: for its rows r_p >= r_q, the entry (r_p, r_q)
  update_target_.clear();
  updates_ = 0;
  for (int j = 0; j < n; ++j) {
    const std::int64_t count = column_start_[j + 1] - column_start_[j];
    updates_ += count * (count + 1) / 2;
  }
  listed_updates_ = updates_ <= kMaxListedUpdates;
  for (int j = 0; listed_updates_ && j < n; ++j) {
    for (int p = column_start_[j]; p < column_start_[j + 1]; ++p) {
      for (int q = column_start_[j]; q <= p; ++q) update_target_.push_back(slot(lower_row_[p], lower_row_[q]));
    }
  }
  lower_value_.assign(nnz + n, 0.0);
  d_.setZero(n);
  inverse_d_.setZero(n);
  diagonal_.setZero(n);
  work_.setZero(n);
}

// Raw pointers marked __restrict: the arrays never overlap, and without the promise every store would force the
// next load to wait for it.
// The path is chosen once per factorization (listed is std::true_type or std::false_type), so that the listed
// one's loop is as tight as it was before there were two.
bool SparseLdlt::Factor(const std::vector<double>& values, double pivot_floor) {
  root_inverse_d_.resize(0);
  const auto factor = [&](auto listed) {
    const int n = size();
    double* __restrict f = lower_value_.data();
    const double* __restrict value = values.data();
    const int* __restrict slot = value_slot_.data();
    const int* __restrict target = update_target_.data();
    for (size_t v = 0; v < values.size(); ++v) f[slot[v]] = value[v];
    for (int position : fill_slot_) f[position] = 0.0;
    const int diagonal = nonzeros();  // f[diagonal + j]: A(j, j) as the updates reach it
    if (pivot_floor > 0.0) diagonal_ = Eigen::Map<const Eigen::VectorXd>(f + diagonal, n);
    for (int j = 0; j < n; ++j) {
      if (pivot_floor > 0.0) f[diagonal + j] = std::max(f[diagonal + j], pivot_floor * diagonal_[j]);
      const double d = f[diagonal + j];
      if (d == 0.0 || !std::isfinite(d)) return false;
      const double inverse = 1.0 / d;
      d_[j] = d;
      inverse_d_[j] = inverse;
      const int begin = column_start_[j], end = column_start_[j + 1];
      // A(r_p, r_q) -= L(r_p, j) d_j L(r_q, j), with f still holding d_j L(., j) (the updates land right of j)
      if constexpr (decltype(listed)::value) {
        for (int p = begin; p < end; ++p) {
          const double l = f[p] * inverse;
          for (int q = begin; q <= p; ++q) f[*target++] -= l * f[q];
        }
      } else {
        UpdateUnlisted(j, inverse);
      }
      for (int p = begin; p < end; ++p) f[p] *= inverse;
    }
    return true;
  };
  return listed_updates_ ? factor(std::true_type{}) : factor(std::false_type{});
}

// The same updates without the list: column r_q of L holds every row r_p > r_q of column j (that is where the
// update creates fill), in increasing order, so one forward walk down it finds them all.
void SparseLdlt::UpdateUnlisted(int j, double inverse) {
  double* __restrict f = lower_value_.data();
  const int* __restrict row = lower_row_.data();
  const int begin = column_start_[j], end = column_start_[j + 1];
  for (int q = begin; q < end; ++q) {
    const int column = row[q];
    const double lq = f[q];
    f[nonzeros() + column] -= f[q] * inverse * lq;
    int position = column_start_[column];
    for (int p = q + 1; p < end; ++p) {
      while (row[position] != row[p]) ++position;
      f[position] -= f[p] * inverse * lq;
    }
  }
}

void SparseLdlt::SolveInPlace(Eigen::VectorXd* x) { Substitute(lower_value_.data(), inverse_d_.data(), x); }

bool SparseLdlt::HalfSolveInPlace(Eigen::VectorXd* x) {
  const int n = size();
  if (root_inverse_d_.size() != n) {  // once per factorization
    if (!(inverse_d_.minCoeff() > 0.0)) return false;
    root_inverse_d_ = inverse_d_.cwiseSqrt();
  }
  double* __restrict t = work_.data();
  double* __restrict b = x->data();
  for (int k = 0; k < n; ++k) t[k] = b[order_[k]];
  // L z = P b, b mostly zeros (a contact's row reaches only its bodies' joints)
  ForwardSubstitute<true>(n, column_start_.data(), lower_row_.data(), lower_value_.data(), t);
  for (int k = 0; k < n; ++k) b[k] = t[k] * root_inverse_d_[k];
  return true;
}

template <int K>
void SparseLdlt::SolveInPlace(Eigen::Matrix<double, Eigen::Dynamic, K, Eigen::RowMajor>* x) {
  const int n = size();
  columns_work_.resize(static_cast<size_t>(n) * K);
  double* __restrict t = columns_work_.data();
  double* __restrict b = x->data();
  const int* __restrict lower_row = lower_row_.data();
  const int* __restrict start = column_start_.data();
  const double* __restrict lower = lower_value_.data();
  const double* __restrict inverse_d = inverse_d_.data();
  for (int k = 0; k < n; ++k) {
    for (int c = 0; c < K; ++c) t[k * K + c] = b[order_[k] * K + c];
  }
  for (int j = 0; j < n; ++j) {  // L Z = P B
    for (int p = start[j]; p < start[j + 1]; ++p) {
      for (int c = 0; c < K; ++c) t[lower_row[p] * K + c] -= lower[p] * t[j * K + c];
    }
  }
  for (int j = n - 1; j >= 0; --j) {  // L^T W = D^-1 Z
    double tj[K];
    for (int c = 0; c < K; ++c) tj[c] = t[j * K + c] * inverse_d[j];
    for (int p = start[j]; p < start[j + 1]; ++p) {
      for (int c = 0; c < K; ++c) tj[c] -= lower[p] * t[lower_row[p] * K + c];
    }
    for (int c = 0; c < K; ++c) t[j * K + c] = tj[c];
  }
  for (int k = 0; k < n; ++k) {
    for (int c = 0; c < K; ++c) b[order_[k] * K + c] = t[k * K + c];
  }
}
template void SparseLdlt::SolveInPlace<kJetStride>(Eigen::Matrix<double, Eigen::Dynamic, kJetStride, Eigen::RowMajor>*);

void SparseLdlt::Save(Numeric* numeric) const {
  numeric->lower.assign(lower_value_.begin(), lower_value_.begin() + nonzeros());
  numeric->inverse_d = inverse_d_;
}

void SparseLdlt::SolveInPlace(const Numeric& numeric, Eigen::VectorXd* x) {
  Substitute(numeric.lower.data(), numeric.inverse_d.data(), x);
}

void SparseLdlt::Substitute(const double* __restrict lower, const double* __restrict inverse_d, Eigen::VectorXd* x) {
  const int n = size();
  double* __restrict t = work_.data();
  double* __restrict b = x->data();
  const int* __restrict lower_row = lower_row_.data();
  const int* __restrict start = column_start_.data();
  const int* __restrict order = order_.data();
  for (int k = 0; k < n; ++k) t[k] = b[order[k]];
  ForwardSubstitute<false>(n, start, lower_row, lower, t);  // L z = P b
  for (int j = n - 1; j >= 0; --j) {  // L^T w = D^-1 z
    double tj = t[j] * inverse_d[j];
    for (int p = start[j]; p < start[j + 1]; ++p) tj -= lower[p] * t[lower_row[p]];
    t[j] = tj;
  }
  for (int k = 0; k < n; ++k) b[order[k]] = t[k];
}

}  // namespace tether
