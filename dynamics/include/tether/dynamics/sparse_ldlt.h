// A sparse LDL^T factorization of the Schur matrix S (schur_system.h) whose structure is worked out once.
//
//   P S P^T = L D L^T,   L unit lower triangular, D diagonal, P an ordering of the rows.
//
// P is a breadth-first (Cuthill-McKee) order of the rows from the scene's first constraint where that fills L by
// at most 25% more than an approximate-minimum-degree order does, and the latter otherwise. A chain listed from
// its base fills nothing breadth first, and its pivots then measure each joint against the joints nearer the
// base, as the near-singularity flag of schur_solver.h wants; the minimum-degree order of a chain, equally free
// of fill, ends in its middle, and the last pivot ratio there falls with the fourth power of the length without
// any singularity (1.6e-8 on a 200-rod hinge chain, against 0.067 breadth first).
//
// Symbolic phase (the constructor, once per run): the ordering; the positions of S's stored values in the
// permuted lower triangle; the elimination tree; for every row k the pattern of L(k, :) in topological order
// (the reach of row k's entries up the tree, Davis's LDL); and the storage of L by columns with the position of
// every L(k, i) fixed in advance.
//
// Numeric phase (Factor, every evaluation): the up-looking recurrence, row k at a time,
//   y = A(k, 0:k-1)^T,   for i in pattern(k):  y_j -= L(j, i) y_i for the rows j < k of column i,
//                                                L(k, i) = y_i / d_i,   d_k -= L(k, i) y_i,
//   d_k starts at A(k, k),
// which touches only the entries of L and allocates nothing. Work: sum over the columns of L of their count
// squared, nnz(L) for a banded S without fill (a chain: one entry per row, so O(n)).
//
// Solve (x = S^-1 b in place): permute, forward substitution with L, divide by D, back substitution with L^T,
// permute back; 2 nnz(L) + n multiply-adds.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "tether/dynamics/schur_system.h"

namespace tether {

class SparseLdlt {
 public:
  SparseLdlt() = default;
  explicit SparseLdlt(const SchurPattern& pattern);

  // Factors S given by its stored values (pattern order). Returns false on a zero or non-finite pivot.
  bool Factor(const std::vector<double>& values);

  // x = S^-1 x with the last successful factorization.
  void SolveInPlace(Eigen::VectorXd* x);

  int size() const { return static_cast<int>(d_.size()); }
  int nonzeros() const { return static_cast<int>(lower_row_.size()); }  // of L below its diagonal
  const Eigen::VectorXd& pivots() const { return d_; }                  // D, in elimination order
  const Eigen::VectorXi& order() const { return order_; }               // order[k]: S's row eliminated k-th

 private:
  // The symbolic phase for one ordering (new index -> S's row).
  void Analyze(const SchurPattern& pattern, const Eigen::VectorXi& order);

  // An off-diagonal entry A(k, column) of the permuted lower triangle of row k, and where S stores its value.
  struct RowEntry {
    int column;
    int value;
  };
  // Entry i of row k's pattern: L(k, i), stored at lower_value_[position]; column i's entries before it are
  // lower_value_[column_start_[i] .. position).
  struct PatternEntry {
    int column;
    int position;
  };

  Eigen::VectorXi order_;             // elimination order: new index -> S's row
  std::vector<int> diagonal_value_;   // per new row, the index of S_kk among the stored values
  std::vector<int> row_entry_start_;  // row k's entries are row_entries_[start[k] .. start[k + 1])
  std::vector<RowEntry> row_entries_;
  std::vector<int> pattern_start_;  // row k's pattern is pattern_[start[k] .. start[k + 1])
  std::vector<PatternEntry> pattern_;
  std::vector<int> column_start_;  // L by columns: rows lower_row_ and values lower_value_
  std::vector<int> lower_row_;
  std::vector<double> lower_value_;
  Eigen::VectorXd d_, inverse_d_;  // D and its inverse (so that the solves multiply)
  Eigen::VectorXd work_;           // zero between calls: the row y of Factor, the permuted x of a solve
};

}  // namespace tether
