#include "tether/dynamics/solvers/sparse_ldlt.h"

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <queue>
#include <type_traits>

#include "tether/dynamics/scalars/scalar.h"

namespace tether {
namespace {

// The breadth-first order is kept while it fills L at most this much more than the minimum-degree order.
constexpr double kBreadthFirstFillAllowance = 1.25;

// Above this many entries the updates out of the supernodes are found as the factorization goes instead of
// listed: the list holds one index per entry a supernode's rows below update, which for the dense block of rows a
// hub body couples (1090 rows on MuJoCo's softbox) is more memory than everything else together.
constexpr std::int64_t kMaxListedUpdates = std::int64_t{1} << 23;

// S's values are placed in L's storage by a block copy where this many or more land in consecutive slots, one by
// one through their slots below that (a call to memmove costs more than a short run's stores: a 100-particle tree,
// whose fill-in cuts S into short runs, stepped 5% slower with every run copied).
constexpr int kCopiedRun = 16;

// The widest supernode factored as one (sparse_ldlt.h): the widest joint's block, a weld's six rows.
constexpr int kWidestSupernode = 6;

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
  for (int k : pattern.by_column()) {  // not the storage order, which the factorization itself sets (schur_solver.h)
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

// Whether the `count` rows of K entries at t are all zero.
template <int K>
inline bool AllZero(const double* t, int count) {
  for (int i = 0; i < count * K; ++i) {
    if (t[i] != 0.0) return false;
  }
  return true;
}

// Calls visit(std::integral_constant<int, W>{}) with W = width (1 ... kWidestSupernode), so that loops over a
// supernode's columns unroll.
template <typename Visit>
inline void WithWidth(int width, Visit&& visit) {
  static_assert(kWidestSupernode == 6);
  switch (width) {
    case 1:
      return visit(std::integral_constant<int, 1>{});
    case 2:
      return visit(std::integral_constant<int, 2>{});
    case 3:
      return visit(std::integral_constant<int, 3>{});
    case 4:
      return visit(std::integral_constant<int, 4>{});
    case 5:
      return visit(std::integral_constant<int, 5>{});
    default:
      return visit(std::integral_constant<int, 6>{});
  }
}

// Supernode s of those starting at supernode_start: alone(first column) where it is one column, else
// block(std::integral_constant<int, width>).
template <typename Alone, typename Block>
inline void VisitSupernode(const std::vector<int>& supernode_start, size_t s, Alone&& alone, Block&& block) {
  const int first = supernode_start[s], width = supernode_start[s + 1] - first;
  if (width == 1) return alone(first);
  WithWidth(width, block);
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

int SparseLdlt::Slot(int row, int column) const {
  if (row == column) return nonzeros() + row;
  const auto column_rows = lower_row_.begin() + column_start_[column];
  const auto end = lower_row_.begin() + column_start_[column + 1];
  return static_cast<int>(std::lower_bound(column_rows, end, row) - lower_row_.begin());
}

void SparseLdlt::PlanNumericPhase(const SchurPattern& pattern) {
  const int n = pattern.size();
  const int nnz = nonzeros();
  std::vector<int> new_index(n);
  for (int k = 0; k < n; ++k) new_index[order_[k]] = k;
  value_slot_.resize(pattern.nonzeros());
  std::vector<bool> from_s(nnz + n, false);
  for (int v = 0; v < pattern.nonzeros(); ++v) {
    const int a = new_index[pattern.row_index()[v]], b = new_index[pattern.column_index()[v]];
    value_slot_[v] = Slot(std::max(a, b), std::min(a, b));
    from_s[value_slot_[v]] = true;
  }
  FindValueRuns();
  fill_slot_.clear();
  for (int position = 0; position < nnz; ++position) {
    if (!from_s[position]) fill_slot_.push_back(position);
  }
  updates_ = 0;
  for (int j = 0; j < n; ++j) {
    const std::int64_t count = column_start_[j + 1] - column_start_[j];
    updates_ += count * (count + 1) / 2;
  }
  lower_value_.assign(nnz + n, 0.0);
  d_.setZero(n);  // size() from here on
  inverse_d_.setZero(n);
  diagonal_.setZero(n);
  work_.assign(static_cast<size_t>(n) * kJetStride, 0.0);  // room for a Jet's parts: a solve allocates nothing
  FindSupernodes();
  ListUpdates();
}

// Column j + 1 joins column j's supernode where column j's rows are j + 1 and then column j + 1's. One wider than
// kWidestSupernode is cut into as few pieces as there must be, of nearly equal widths (each piece's rows are then
// its own columns, those of the pieces after it and the rows below).
void SparseLdlt::FindSupernodes() {
  const int n = size();
  supernode_start_.assign(1, 0);
  for (int j = 0; j < n; ++j) {
    const int count = column_start_[j + 1] - column_start_[j];
    const bool joins_next = j + 1 < n && count > 0 && lower_row_[column_start_[j]] == j + 1 &&
                            count == column_start_[j + 2] - column_start_[j + 1] + 1;
    if (joins_next) continue;
    const int first = supernode_start_.back(), width = j + 1 - first;
    const int pieces = (width + kWidestSupernode - 1) / kWidestSupernode;
    for (int piece = 1; piece <= pieces; ++piece) supernode_start_.push_back(first + width * piece / pieces);
  }
  supernode_of_.resize(n);
  int widest_below = 0;
  for (size_t s = 0; s + 1 < supernode_start_.size(); ++s) {
    const int first = supernode_start_[s], width = supernode_start_[s + 1] - first;
    for (int j = first; j < first + width; ++j) supernode_of_[j] = static_cast<int>(s);
    widest_below = std::max(widest_below, CountBelow(first, width));
  }
  below_position_.assign(widest_below, 0);
  unscaled_.assign(static_cast<size_t>(widest_below + kWidestSupernode) * kWidestSupernode, 0.0);
  // supernodes of one or two columns on average (rows that share few neighbours, as a chain of particles'):
  // column by column, each update's entry listed, costs fewer instructions than the supernodes' bookkeeping (10% of
  // a 10-particle chain's step); as CHOLMOD, which factors supernodally only where supernodes are wide
  simplicial_ = 2 * (static_cast<int>(supernode_start_.size()) - 1) > n && updates_ <= kMaxListedUpdates;
}

// Column by column (simplicial_): for each column j and its rows r_q <= r_p, the entry (r_p, r_q). Supernode by
// supernode: for each q and each p > q of the rows b below it, the entry (b_p, b_q), unless there are more than
// kMaxListedUpdates of those (listed_updates_).
void SparseLdlt::ListUpdates() {
  update_target_.clear();
  listed_updates_ = true;
  if (simplicial_) {
    for (int j = 0; j < size(); ++j) {
      for (int p = column_start_[j]; p < column_start_[j + 1]; ++p) {
        for (int q = column_start_[j]; q <= p; ++q) update_target_.push_back(Slot(lower_row_[p], lower_row_[q]));
      }
    }
    return;
  }
  std::int64_t listed = 0;
  for (size_t s = 0; s + 1 < supernode_start_.size(); ++s) {
    const std::int64_t below = CountBelow(supernode_start_[s], supernode_start_[s + 1] - supernode_start_[s]);
    listed += below * (below - 1) / 2;
  }
  listed_updates_ = listed <= kMaxListedUpdates;
  for (size_t s = 0; listed_updates_ && s + 1 < supernode_start_.size(); ++s) {
    const int first = supernode_start_[s], width = supernode_start_[s + 1] - first;
    const int* b = RowsBelow(first, width);
    const int below = CountBelow(first, width);
    for (int q0 = 0; q0 < below;) {
      const int q1 = LocateBelow(first, width, q0);
      for (int q = q0; q < q1; ++q) {
        for (int p = q + 1; p < below; ++p) {
          update_target_.push_back(column_start_[b[q]] - below_position_[q] - 1 + below_position_[p]);
        }
      }
      q0 = q1;
    }
  }
}

// Raw pointers marked __restrict: the arrays never overlap, and without the promise every store would force the
// next load to wait for it.
bool SparseLdlt::Factor(const std::vector<double>& values, double pivot_floor) {
  root_inverse_d_.resize(0);
  double* __restrict f = lower_value_.data();
  const double* __restrict value = values.data();
  const int* __restrict slot = value_slot_.data();
  for (const ValueRun& run : value_runs_) {
    if (run.count >= kCopiedRun) {
      std::copy(value + run.value, value + run.value + run.count, f + run.slot);
    } else {  // through the slots, which the compiler cannot turn into the memmove call this avoids
      for (int v = run.value; v < run.value + run.count; ++v) f[slot[v]] = value[v];
    }
  }
  for (int position : fill_slot_) f[position] = 0.0;
  if (pivot_floor > 0.0) diagonal_ = Eigen::Map<const Eigen::VectorXd>(f + nonzeros(), size());
  if (simplicial_) return FactorColumns(pivot_floor);
  const int* target = update_target_.data();  // when listed_updates_
  for (size_t s = 0; s + 1 < supernode_start_.size(); ++s) {
    const int first = supernode_start_[s], width = supernode_start_[s + 1] - first;
    bool factored = false;
    WithWidth(width, [&](auto w) { factored = FactorSupernode<decltype(w)::value>(first, pivot_floor, &target); });
    if (!factored) return false;
  }
  return true;
}

std::vector<int> SparseLdlt::FactorOrder() const {
  std::vector<int> by_slot(value_slot_.size());
  std::iota(by_slot.begin(), by_slot.end(), 0);
  std::sort(by_slot.begin(), by_slot.end(), [this](int x, int y) { return value_slot_[x] < value_slot_[y]; });
  std::vector<int> position(value_slot_.size());
  for (size_t k = 0; k < by_slot.size(); ++k) position[by_slot[k]] = static_cast<int>(k);
  return position;
}

void SparseLdlt::StoreValuesAt(const std::vector<int>& position) {
  std::vector<int> slot(value_slot_.size());
  for (size_t v = 0; v < position.size(); ++v) slot[position[v]] = value_slot_[v];
  value_slot_.swap(slot);
  FindValueRuns();
}

void SparseLdlt::FindValueRuns() {
  value_runs_.clear();
  for (int v = 0; v < static_cast<int>(value_slot_.size()); ++v) {
    if (!value_runs_.empty()) {
      ValueRun& last = value_runs_.back();
      if (v == last.value + last.count && value_slot_[v] == last.slot + last.count) {
        ++last.count;
        continue;
      }
    }
    value_runs_.push_back({v, value_slot_[v], 1});
  }
}

// Column by column, right-looking: d_j = A(j, j), A(r_p, r_q) -= L(r_p, j) d_j L(r_q, j) for the rows r_q <= r_p of
// column j, each at its listed entry, then L(., j) /= d_j.
bool SparseLdlt::FactorColumns(double pivot_floor) {
  const int n = size();
  double* __restrict f = lower_value_.data();
  double* __restrict diagonal = f + nonzeros();
  const int* __restrict target = update_target_.data();
  for (int j = 0; j < n; ++j) {
    if (pivot_floor > 0.0) diagonal[j] = std::max(diagonal[j], pivot_floor * diagonal_[j]);
    const double d = diagonal[j];
    if (d == 0.0 || !std::isfinite(d)) return false;
    const double inverse = 1.0 / d;
    d_[j] = d;
    inverse_d_[j] = inverse;
    const int begin = column_start_[j], end = column_start_[j + 1];
    for (int p = begin; p < end; ++p) {  // f still holds d_j L(., j)
      const double l = f[p] * inverse;
      for (int q = begin; q <= p; ++q) f[*target++] -= l * f[q];
    }
    for (int p = begin; p < end; ++p) f[p] *= inverse;
  }
  return true;
}

// below_position_[p] for the rows b_p, p >= q0, below supernode [first, first + width): their index in the rows
// R_T of the supernode T that holds column b_q0 (R_T[0] = T's first column, R_T[i] = L(., T's first column)'s row
// i - 1). R_T holds every b_p, p > q0, in increasing order (the elimination tree's reach), so one walk finds them.
// Returns the end of the run of b_q in T, whose columns share these positions.
int SparseLdlt::LocateBelow(int first, int width, int q0) {
  const int* __restrict row = lower_row_.data();
  const int* __restrict b = RowsBelow(first, width);
  const int below = CountBelow(first, width);
  const int t = supernode_of_[b[q0]], t_first = supernode_start_[t];
  int q1 = q0 + 1;
  while (q1 < below && supernode_of_[b[q1]] == t) ++q1;
  const int* __restrict t_rows = row + column_start_[t_first] - 1;  // R_T[i] for i >= 1
  int* __restrict position = below_position_.data();
  position[q0] = b[q0] - t_first;
  for (int p = q0 + 1, i = position[q0] + 1; p < below; ++p, ++i) {
    while (t_rows[i] != b[p]) ++i;
    position[p] = i;
  }
  return q1;
}

// Supernode [first, first + kWidth) with rows R (its own columns, then the m rows b_p below them): every column
// shares R, so L(R[i], first + c) = column(c)[i] for i > c, at a fixed offset from where column c starts.
//   Its columns, left-looking over the earlier ones of the supernode (the later supernodes' updates are in):
//     d_k = A(k, k) - sum_c L(k, c) d_c L(k, c),   L(i, k) = (A(i, k) - sum_c L(i, c) d_c L(k, c)) / d_k.
//   Then the rows below update the later columns they name, A(b_p, b_q) -= sum_c L(b_p, c) d_c L(b_q, c): column
//   b_q of L keeps rows b_p >= b_q, and consecutive b_q lie in one later supernode T whose columns share its rows
//   R_T, so where each b_p sits in R_T is found once for them all by walking R_T (it holds every b_p, b_p > b_q,
//   in increasing order, as the elimination tree has it).
// The width is known at compile time, so that the sums over c unroll (`#pragma GCC unroll` takes a literal:
// kWidestSupernode's 6).
template <int kWidth>
TETHER_HOT_INLINE bool SparseLdlt::FactorSupernode(int first, double pivot_floor, const int** target) {
  double* __restrict f = lower_value_.data();
  double* __restrict diagonal = f + nonzeros() + first;
  const int* __restrict start = column_start_.data() + first;
  double* __restrict d = d_.data() + first;
  double* __restrict inverse_d = inverse_d_.data() + first;
  // d_c L(R[i], c) at [i * kWidth + c], kept from before the division: one multiply less from pivot to pivot
  double* __restrict unscaled = unscaled_.data();
  double inverse_of[kWidth];  // d_c^-1, in registers
  const auto column = [&](int c) { return f + start[c] - c - 1; };
  const int rows = start[1] - start[0] + 1;
#pragma GCC unroll 6
  for (int k = 0; k < kWidth; ++k) {
    double pivot = diagonal[k];
#pragma GCC unroll 6
    for (int c = 0; c < k; ++c) pivot -= unscaled[k * kWidth + c] * column(c)[k];
    if (pivot_floor > 0.0) pivot = std::max(pivot, pivot_floor * diagonal_[first + k]);
    if (pivot == 0.0 || !std::isfinite(pivot)) return false;
    const double inverse = 1.0 / pivot;
    d[k] = pivot;
    inverse_d[k] = inverse_of[k] = inverse;
    double* __restrict l = column(k);
    for (int i = k + 1; i < rows; ++i) {
      double a = l[i];
#pragma GCC unroll 6
      for (int c = 0; c < k; ++c) a -= column(c)[i] * unscaled[k * kWidth + c];
      unscaled[i * kWidth + k] = a;
      l[i] = a * inverse;
    }
  }

  double* __restrict all_diagonal = f + nonzeros();
  const int* __restrict b = RowsBelow(first, kWidth);
  const int below = rows - kWidth;
  // (d_c L)^2 d_c^-1 from registers: L(b_q, c), just stored, would wait for its store on the way from one pivot to
  // the next; sums start from their first term (from a zero, one add more)
  const auto update_column = [&](int q, auto&& target_of) {
    const double* __restrict dl = unscaled + (kWidth + q) * kWidth;  // d_c L(b_q, c)
    double update = dl[0] * dl[0] * inverse_of[0];
#pragma GCC unroll 6
    for (int c = 1; c < kWidth; ++c) update += dl[c] * dl[c] * inverse_of[c];
    all_diagonal[b[q]] -= update;
    for (int p = q + 1; p < below; ++p) {
      double sum = column(0)[kWidth + p] * dl[0];
#pragma GCC unroll 6
      for (int c = 1; c < kWidth; ++c) sum += column(c)[kWidth + p] * dl[c];
      f[target_of(p)] -= sum;
    }
  };
  if (listed_updates_) {
    for (int q = 0; q < below; ++q) update_column(q, [&](int) { return *(*target)++; });
    return true;
  }
  const int* __restrict position = below_position_.data();
  for (int q0 = 0; q0 < below;) {
    const int q1 = LocateBelow(first, kWidth, q0);
    for (int q = q0; q < q1; ++q) {
      const int column_b_q = column_start_[b[q]] - position[q] - 1;  // + i: column b_q's row R_T[i]
      update_column(q, [&](int p) { return column_b_q + position[p]; });
    }
    q0 = q1;
  }
  return true;
}

void SparseLdlt::SolveInPlace(Eigen::VectorXd* x) { Substitute<1>(lower_value_.data(), inverse_d_.data(), x->data()); }

template <int K>
void SparseLdlt::SolveInPlace(Eigen::Matrix<double, Eigen::Dynamic, K, Eigen::RowMajor>* x) {
  Substitute<K>(lower_value_.data(), inverse_d_.data(), x->data());
}
template void SparseLdlt::SolveInPlace<kJetStride>(Eigen::Matrix<double, Eigen::Dynamic, kJetStride, Eigen::RowMajor>*);

void SparseLdlt::SolveInPlace(const Numeric& numeric, Eigen::VectorXd* x) {
  Substitute<1>(numeric.lower.data(), numeric.inverse_d.data(), x->data());
}

bool SparseLdlt::HalfSolveInPlace(Eigen::VectorXd* x) {
  const int n = size();
  if (root_inverse_d_.size() != n) {  // once per factorization
    if (!(inverse_d_.minCoeff() > 0.0)) return false;
    root_inverse_d_ = inverse_d_.cwiseSqrt();
  }
  double* __restrict t = work_.data();
  double* __restrict b = x->data();
  for (int k = 0; k < n; ++k) t[k] = b[order_[k]];
  ForwardSubstitute<1, true>(lower_value_.data(), t);  // L z = P b, b mostly zeros
  for (int k = 0; k < n; ++k) b[k] = t[k] * root_inverse_d_[k];
  return true;
}

void SparseLdlt::Save(Numeric* numeric) const {
  numeric->lower.assign(lower_value_.begin(), lower_value_.begin() + nonzeros());
  numeric->inverse_d = inverse_d_;
}

template <int K>
void SparseLdlt::Substitute(const double* lower, const double* inverse_d, double* x) {
  const int n = size();
  static_assert(K <= kJetStride);
  double* __restrict t = work_.data();
  double* __restrict b = x;
  for (int k = 0; k < n; ++k) {
    for (int c = 0; c < K; ++c) t[k * K + c] = b[order_[k] * K + c];
  }
  ForwardSubstitute<K, false>(lower, t);   // L Z = P B
  BackSubstitute<K>(lower, inverse_d, t);  // L^T W = D^-1 Z
  for (int k = 0; k < n; ++k) {
    for (int c = 0; c < K; ++c) b[order_[k] * K + c] = t[k * K + c];
  }
}

// Supernode by supernode (column by column where simplicial_): its own rows from its columns (a dense unit lower
// triangle), then the rows below it,
//   t(first + i) -= sum_{c < i} L(first + i, first + c) t(first + c),   t(b_p) -= sum_c L(b_p, first + c) t(first + c);
// a supernode whose entries are still zero changes nothing, and kSkipZeros passes it by (a right-hand side with
// few nonzeros reaches only their ancestors).
template <int K, bool kSkipZeros>
TETHER_HOT_INLINE void SparseLdlt::ForwardSubstitute(const double* lower, double* t) {
  const auto column_alone = [&](int j) {  // its rows straight from L
    const int* __restrict row = lower_row_.data();
    double tj[K];
    for (int r = 0; r < K; ++r) tj[r] = t[j * K + r];
    for (int p = column_start_[j]; p < column_start_[j + 1]; ++p) {
      for (int r = 0; r < K; ++r) t[row[p] * K + r] -= lower[p] * tj[r];
    }
  };
  if (simplicial_) {
    for (int j = 0; j < size(); ++j) {
      if (!kSkipZeros || !AllZero<K>(t + j * K, 1)) column_alone(j);
    }
    return;
  }
  for (size_t s = 0; s + 1 < supernode_start_.size(); ++s) {
    const int first = supernode_start_[s];
    if (kSkipZeros && AllZero<K>(t + first * K, supernode_start_[s + 1] - first)) continue;
    VisitSupernode(supernode_start_, s, column_alone, [&](auto w) {
      constexpr int kWidth = decltype(w)::value;
      const int* __restrict start = column_start_.data() + first;
      const auto column = [&](int c) { return lower + start[c] - c - 1; };  // L(R[i], first + c), i > c
      // in registers, each column applied as soon as it is final (read back from memory, entries stored one by
      // one would stall the paired loads the compiler makes of them)
      double own[kWidth][K];
      for (int i = 0; i < kWidth; ++i) {
        for (int r = 0; r < K; ++r) own[i][r] = t[(first + i) * K + r];
      }
#pragma GCC unroll 6
      for (int c = 0; c < kWidth; ++c) {
#pragma GCC unroll 6
        for (int i = c + 1; i < kWidth; ++i) {
          for (int r = 0; r < K; ++r) own[i][r] -= column(c)[i] * own[c][r];
        }
        for (int r = 0; r < K; ++r) t[(first + c) * K + r] = own[c][r];
      }
      const int below = CountBelow(first, kWidth);
      const int* __restrict b = RowsBelow(first, kWidth);
      for (int p = 0; p < below; ++p) {
        double sum[K];
        for (int r = 0; r < K; ++r) sum[r] = column(0)[kWidth + p] * own[0][r];  // not from a zero: one add less
        for (int c = 1; c < kWidth; ++c) {
          for (int r = 0; r < K; ++r) sum[r] += column(c)[kWidth + p] * own[c][r];
        }
        for (int r = 0; r < K; ++r) t[b[p] * K + r] -= sum[r];
      }
    });
  }
}

// Supernode by supernode from the last: with u the solution on the rows below it (final already),
//   t(first + i) = d_i^-1 t(first + i) - sum_p L(b_p, first + i) u(b_p) - sum_{c > i} L(first + c, first + i) t(c'),
// t(c') = t(first + c), from its last column to its first.
template <int K>
TETHER_HOT_INLINE void SparseLdlt::BackSubstitute(const double* lower, const double* inverse_d, double* t) {
  const auto column_alone = [&](int j) {  // as in the forward substitution
    const int* __restrict row = lower_row_.data();
    double tj[K];
    for (int r = 0; r < K; ++r) tj[r] = t[j * K + r] * inverse_d[j];
    for (int p = column_start_[j]; p < column_start_[j + 1]; ++p) {
      for (int r = 0; r < K; ++r) tj[r] -= lower[p] * t[row[p] * K + r];
    }
    for (int r = 0; r < K; ++r) t[j * K + r] = tj[r];
  };
  if (simplicial_) {
    for (int j = size() - 1; j >= 0; --j) column_alone(j);
    return;
  }
  for (size_t s = supernode_start_.size() - 1; s-- > 0;) {
    const int first = supernode_start_[s];
    VisitSupernode(supernode_start_, s, column_alone, [&](auto w) {
      constexpr int kWidth = decltype(w)::value;
      const int* __restrict start = column_start_.data() + first;
      const auto column = [&](int c) { return lower + start[c] - c - 1; };
      double own[kWidth][K];  // in registers, as in the forward substitution
      for (int i = 0; i < kWidth; ++i) {
        for (int r = 0; r < K; ++r) own[i][r] = t[(first + i) * K + r] * inverse_d[first + i];
      }
      const int below = CountBelow(first, kWidth);
      const int* __restrict b = RowsBelow(first, kWidth);
      for (int p = 0; p < below; ++p) {
        for (int c = 0; c < kWidth; ++c) {
          for (int r = 0; r < K; ++r) own[c][r] -= column(c)[kWidth + p] * t[b[p] * K + r];
        }
      }
#pragma GCC unroll 6
      for (int c = kWidth - 1; c >= 0; --c) {
#pragma GCC unroll 6
        for (int i = 0; i < c; ++i) {
          for (int r = 0; r < K; ++r) own[i][r] -= column(i)[c] * own[c][r];
        }
        for (int r = 0; r < K; ++r) t[(first + c) * K + r] = own[c][r];
      }
    });
  }
}

}  // namespace tether
