#include "tether/dynamics/sparse_ldlt.h"

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <queue>

namespace tether {
namespace {

// The breadth-first order is kept while it fills L at most this much more than the minimum-degree order.
constexpr double kBreadthFirstFillAllowance = 1.25;

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

}  // namespace

SparseLdlt::SparseLdlt(const SchurPattern& pattern) {
  Analyze(pattern, MinimumDegreeOrder(pattern));
  const int minimum_degree_fill = nonzeros();
  Analyze(pattern, BreadthFirstOrder(pattern));
  if (nonzeros() > kBreadthFirstFillAllowance * minimum_degree_fill) Analyze(pattern, MinimumDegreeOrder(pattern));
}

void SparseLdlt::Analyze(const SchurPattern& pattern, const Eigen::VectorXi& order) {
  const int n = pattern.size();
  order_ = order;
  row_entries_.clear();
  pattern_.clear();
  std::vector<int> new_index(n);
  for (int k = 0; k < n; ++k) new_index[order_[k]] = k;

  // S's stored values in the permuted lower triangle, by rows
  diagonal_value_.assign(n, -1);
  std::vector<std::vector<RowEntry>> rows(n);
  for (int v = 0; v < pattern.nonzeros(); ++v) {
    const int a = new_index[pattern.row_index()[v]], b = new_index[pattern.column_index()[v]];
    if (a == b) {
      diagonal_value_[a] = v;
    } else {
      rows[std::max(a, b)].push_back({std::min(a, b), v});
    }
  }
  row_entry_start_.assign(1, 0);
  std::vector<int> row_columns;
  for (const std::vector<RowEntry>& row : rows) {
    for (const RowEntry& entry : row) {
      row_entries_.push_back(entry);
      row_columns.push_back(entry.column);
    }
    row_entry_start_.push_back(static_cast<int>(row_entries_.size()));
  }
  const std::vector<int> parent = EliminationTree(row_entry_start_, row_columns);

  // row k's pattern: the paths up the tree from its entries towards k, each stopping where an earlier one
  // passed; read back as the later paths first, each from the bottom up, a column comes after every column
  // below it in the tree (topological order, as in Davis's LDL)
  std::vector<int> flag(n, -1), path, stack;
  std::vector<std::vector<int>> patterns(n);
  std::vector<int> column_count(n, 0);
  for (int k = 0; k < n; ++k) {
    flag[k] = k;
    stack.clear();
    for (int e = row_entry_start_[k]; e < row_entry_start_[k + 1]; ++e) {
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

  // L by columns; rows are appended to a column in increasing order, so each position is known now
  column_start_.assign(n + 1, 0);
  for (int i = 0; i < n; ++i) column_start_[i + 1] = column_start_[i] + column_count[i];
  lower_row_.resize(column_start_[n]);
  lower_value_.assign(column_start_[n], 0.0);
  std::vector<int> filled(column_start_.begin(), column_start_.end() - 1);
  pattern_start_.assign(1, 0);
  for (int k = 0; k < n; ++k) {
    for (int i : patterns[k]) {
      const int position = filled[i]++;
      lower_row_[position] = k;
      pattern_.push_back({i, position});
    }
    pattern_start_.push_back(static_cast<int>(pattern_.size()));
  }
  d_.setZero(n);
  inverse_d_.setZero(n);
  work_.setZero(n);
}

bool SparseLdlt::Factor(const std::vector<double>& values) {
  const int n = size();
  double* y = work_.data();
  for (int k = 0; k < n; ++k) {
    for (int e = row_entry_start_[k]; e < row_entry_start_[k + 1]; ++e)
      y[row_entries_[e].column] = values[row_entries_[e].value];
    double d = values[diagonal_value_[k]];
    for (int e = pattern_start_[k]; e < pattern_start_[k + 1]; ++e) {
      const int i = pattern_[e].column;
      const double yi = y[i];
      y[i] = 0.0;
      for (int p = column_start_[i]; p < pattern_[e].position; ++p) y[lower_row_[p]] -= lower_value_[p] * yi;
      const double l = yi * inverse_d_[i];
      d -= l * yi;
      lower_value_[pattern_[e].position] = l;
    }
    if (d == 0.0 || !std::isfinite(d)) return false;  // y is clean again: every entry of row k was visited
    d_[k] = d;
    inverse_d_[k] = 1.0 / d;
  }
  return true;
}

void SparseLdlt::SolveInPlace(Eigen::VectorXd* x) {
  const int n = size();
  double* t = work_.data();
  for (int k = 0; k < n; ++k) t[k] = (*x)[order_[k]];
  for (int j = 0; j < n; ++j) {  // L z = P b
    for (int p = column_start_[j]; p < column_start_[j + 1]; ++p) t[lower_row_[p]] -= lower_value_[p] * t[j];
  }
  for (int j = 0; j < n; ++j) t[j] *= inverse_d_[j];
  for (int j = n - 1; j >= 0; --j) {  // L^T w = D^-1 z
    for (int p = column_start_[j]; p < column_start_[j + 1]; ++p) t[j] -= lower_value_[p] * t[lower_row_[p]];
  }
  for (int k = 0; k < n; ++k) {
    (*x)[order_[k]] = t[k];
    t[k] = 0.0;  // Factor expects a zero work row
  }
}

}  // namespace tether
