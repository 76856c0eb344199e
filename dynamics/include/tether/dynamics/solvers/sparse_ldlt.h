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
// Symbolic phase (the constructor, once per run): the ordering; the elimination tree; for every row k the
// pattern of L(k, :) (the reach of row k's entries up the tree, Davis's LDL), hence the storage of L by columns;
// where each of S's stored values lands in it; and, for every column j, the list of entries its elimination
// updates.
//
// Numeric phase (Factor, every evaluation): right-looking, a column at a time,
//   d_j = A(j, j),   A(r_p, r_q) -= L(r_p, j) d_j L(r_q, j) for the rows r_q <= r_p of column j,   L(., j) /= d_j
// (A starts as S scattered into L's pattern, the fill-in at zero). Every update of a column is independent of the
// others, so they pipeline; the up-looking order (a triangular solve per row, each update waiting for the one
// before) took 1.09 us where this takes 0.83 us on the humanoid tree's 51 rows, which come in dense blocks of 3
// to 5. Work: sum over the columns of L of count (count + 1) / 2, nnz(L) for a banded S without fill (a chain:
// one entry per column, so O(n)); nothing is allocated or searched. Where the updates are too many to list (a hub
// body's rows form a dense block: count^3 / 6 of them), each column's targets are found by walking the columns
// it updates instead, in the same order and so with the same result; memory then stays O(nnz(L)).
//
// Solve (x = S^-1 b in place): permute, forward substitution with L, divide by D, back substitution with L^T,
// permute back; 2 nnz(L) + n multiply-adds. K right-hand sides at once (a Jet's derivative parts) take one pass
// over L, each entry of L applied to the K of them side by side, in the same order as K solves of one.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "tether/dynamics/solvers/schur_system.h"

namespace tether {

class SparseLdlt {
 public:
  SparseLdlt() = default;
  explicit SparseLdlt(const SchurPattern& pattern);

  // Factors S given by its stored values (pattern order). Returns false on a zero or non-finite pivot. With a
  // pivot_floor, a pivot d_j below pivot_floor times its diagonal entry S_jj is raised to that: the factors are
  // those of S + E with E diagonal and non-negative (a modified Cholesky factorization).
  bool Factor(const std::vector<double>& values, double pivot_floor = 0.0);

  // x = S^-1 x with the last successful factorization.
  void SolveInPlace(Eigen::VectorXd* x);
  // The same for the K columns of x (row-major, so that row k holds every column's k-th entry).
  template <int K>
  void SolveInPlace(Eigen::Matrix<double, Eigen::Dynamic, K, Eigen::RowMajor>* x);
  // x <- D^-1/2 L^-1 P x, so that x^T S^-1 x' is the dot product of two such (half the work of a solve); false,
  // with x unchanged, where a pivot is not positive.
  bool HalfSolveInPlace(Eigen::VectorXd* x);

  // A factorization's numeric part (L below its diagonal, D^-1), kept to solve with after later ones.
  struct Numeric {
    std::vector<double> lower;
    Eigen::VectorXd inverse_d;
  };
  void Save(Numeric* numeric) const;
  // x = S^-1 x with a saved factorization (of a matrix of this pattern).
  void SolveInPlace(const Numeric& numeric, Eigen::VectorXd* x);

  int size() const { return static_cast<int>(d_.size()); }
  int nonzeros() const { return static_cast<int>(lower_row_.size()); }  // of L below its diagonal
  std::int64_t updates() const { return updates_; }                     // multiply-adds of a factorization
  const Eigen::VectorXd& pivots() const { return d_; }                  // D, in elimination order
  const Eigen::VectorXi& order() const { return order_; }               // order[k]: S's row eliminated k-th

 private:
  // The structure of L for one ordering (new index -> S's row): order_, column_start_, lower_row_.
  void Analyze(const SchurPattern& pattern, const Eigen::VectorXi& order);
  // For the ordering chosen: where S's values land, the fill-in, every column's updates (their number is the
  // factorization's work, so they are listed only for the order kept), and the numeric storage.
  void PlanNumericPhase(const SchurPattern& pattern);
  // Column j's updates found by walking L's columns (when they are too many to list), d_j^-1 = `inverse`.
  void UpdateUnlisted(int j, double inverse);
  // The two triangular solves with L's values `lower` and D^-1 `inverse_d`.
  void Substitute(const double* lower, const double* inverse_d, Eigen::VectorXd* x);

  Eigen::VectorXd diagonal_;       // S's diagonal in elimination order (for a pivot floor)
  Eigen::VectorXi order_;          // elimination order: new index -> S's row
  std::vector<int> column_start_;  // L by columns: rows lower_row_ and values lower_value_
  std::vector<int> lower_row_;
  std::vector<double> lower_value_;  // nnz(L) entries, then n slots for the diagonal during Factor
  std::vector<int> value_slot_;      // per stored value of S: its index in lower_value_
  std::vector<int> fill_slot_;       // the entries of L where S has none (they start at zero)
  std::vector<int> update_target_;   // column by column, for its (p, q), q <= p in that order: the index in
                                     // lower_value_ of the entry that pair updates (when listed_updates_)
  std::int64_t updates_ = 0;
  bool listed_updates_ = true;
  Eigen::VectorXd d_, inverse_d_;  // D and its inverse (so that the solves multiply)
  Eigen::VectorXd root_inverse_d_;  // D^-1/2 once a half solve has asked for it (empty after Factor)
  Eigen::VectorXd work_;           // the permuted x of a solve
  std::vector<double> columns_work_;  // the permuted x of a solve of several columns
};

}  // namespace tether
