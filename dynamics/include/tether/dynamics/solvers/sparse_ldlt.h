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
// Symbolic phase (the constructor, once per run): the ordering (of S's entries column by column, whatever order its
// values are stored in); the elimination tree; for every row k the pattern of L(k, :) (the reach of row k's entries
// up the tree, Davis's LDL), hence the storage of L by columns; where each of S's stored values lands in it; and the
// supernodes: runs of consecutive columns j, j + 1, ... where each column's rows are the next column and then that
// column's rows. A joint's rows couple each other and the same neighbours, so they form one (a hinge's five, a
// ball's three). A run wider than six is cut into nearly equal pieces, so that every loop over a supernode's columns
// is unrolled for its width (1 to 6).
//
// Numeric phase (Factor, every evaluation), supernode by supernode in elimination order, with A starting as S
// placed in L's pattern (the fill-in at zero). A simulation stores S in that order (SchurSolver::StoreInFactorOrder),
// so S arrives as one block copy where L has no fill, and as a copy per run of 16 or more consecutive values where it
// has (shorter runs value by value, through their slots, as before): 0.92 -> 0.82 us for the 10-rod hinge
// chain's factorization, 1.14 -> 1.04 us for humanoid.xml's (EvaluationPart, minima of three alternated runs), where
// placing its values one by one through a list of slots took a fifth of it. The columns c of a supernode share its
// rows R, so L(R[i], c) sits at a fixed offset from where column c starts:
//   - left-looking inside the supernode, column k after the earlier ones,
//       d_k = A(k, k) - sum_{c<k} L(k, c) d_c L(k, c),   L(i, k) = (A(i, k) - sum_{c<k} L(i, c) d_c L(k, c)) / d_k;
//   - then right-looking out of it: the rows b below it update the later columns they name,
//       A(b_p, b_q) -= sum_c L(b_p, c) d_c L(b_q, c),   b_p >= b_q,
//     each at an entry listed once per run (where b_p sits among the rows of b_q's supernode, found by walking
//     them), or, past a bound on the list (the dense block of a hub's rows), found by that walk as it goes.
// The sums over a supernode's columns are unrolled, and a solve keeps a supernode's own entries in registers.
// Where the supernodes are one or two columns wide on average (rows of particles), their bookkeeping costs more
// than it saves, and the factorization goes column by column instead, each update's entry listed: CHOLMOD's choice
// between its supernodal and simplicial factorizations. Work, either way: sum over the columns of L of
// count (count + 1) / 2 multiply-adds (nnz(L) for a banded S without fill, O(n) for a chain).
// Against the column-by-column factorization with a listed entry per update that it replaced (EvaluationPart in
// bench/evaluation_bench.cc, medians of three): the humanoid tree's 51 rows in blocks of 3 to 5 factor in 0.61 us
// instead of 0.81 and solve in 0.22 us instead of 0.38; the 10-rod hinge chain's 50, 0.68 and 0.28 us instead of
// 1.00 and 0.50.
//
// Solve (x = S^-1 b in place): permute, forward substitution with L, divide by D, back substitution with L^T,
// permute back; 2 nnz(L) + n multiply-adds, a supernode at a time: its own triangle, then the rows below it. K
// right-hand sides at once (a Jet's derivative parts) take one pass over L, each entry of L applied to the K of them
// side by side, in the same order as K solves of one.
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

  // Where each of S's stored values would go for S to be stored in the order of L's storage (by columns in
  // elimination order, the diagonal after them): position[v] for SchurPattern::StoreValuesAt.
  std::vector<int> FactorOrder() const;
  // Follows the pattern's values to `position` (SchurPattern::StoreValuesAt after FactorOrder): a factorization
  // then places them in L's storage as a few block copies (one where there is no fill-in) instead of one by one.
  void StoreValuesAt(const std::vector<int>& position);

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
  // For the ordering chosen: where S's values land, the fill-in, the supernodes, the listed updates and the
  // numeric storage.
  void PlanNumericPhase(const SchurPattern& pattern);
  // value_runs_ from value_slot_.
  void FindValueRuns();
  // Where L(row, column) is stored in lower_value_ (nnz + row on the diagonal).
  int Slot(int row, int column) const;
  // supernode_start_, supernode_of_, the work arrays they size, and simplicial_.
  void FindSupernodes();
  // update_target_ and listed_updates_.
  void ListUpdates();
  // Factors supernode [first, first + kWidth)'s columns and applies their updates to the later ones (*target
  // runs along their listed entries, when listed_updates_); false on a zero or non-finite pivot.
  template <int kWidth>
  bool FactorSupernode(int first, double pivot_floor, const int** target);
  // The factorization column by column, where the supernodes are one or two columns wide on average (simplicial_).
  bool FactorColumns(double pivot_floor);
  // The rows b below supernode [first, first + width), b_p = R[width + p] (all rows of its first column past its
  // own columns): how many, and where they start in lower_row_.
  int CountBelow(int first, int width) const { return column_start_[first + 1] - column_start_[first] + 1 - width; }
  const int* RowsBelow(int first, int width) const { return lower_row_.data() + column_start_[first] + width - 1; }
  // Where the rows below a supernode, from its q0-th on, sit in the supernode of column b_q0 (below_position_);
  // returns the end of the run of those b_q that are its columns.
  int LocateBelow(int first, int width, int q0);
  // x = S^-1 x for x's K columns (row-major) with L's values `lower` and D^-1 `inverse_d`: the permutations
  // around the two triangular solves below, on t = P x.
  template <int K>
  void Substitute(const double* lower, const double* inverse_d, double* x);
  // t <- L^-1 t; kSkipZeros passes by the supernodes where t is still zero.
  template <int K, bool kSkipZeros>
  void ForwardSubstitute(const double* lower, double* t);
  // t <- L^-T D^-1 t.
  template <int K>
  void BackSubstitute(const double* lower, const double* inverse_d, double* t);

  Eigen::VectorXd diagonal_;       // S's diagonal in elimination order (for a pivot floor)
  Eigen::VectorXi order_;          // elimination order: new index -> S's row
  std::vector<int> column_start_;  // L by columns: rows lower_row_ and values lower_value_
  std::vector<int> lower_row_;
  std::vector<double> lower_value_;  // nnz(L) entries, then n slots for the diagonal during Factor
  std::vector<int> value_slot_;      // per stored value of S: its index in lower_value_
  std::vector<int> fill_slot_;       // the entries of L where S has none (they start at zero)
  // Runs of consecutive values that land in consecutive slots, copied as one (value_slot_ by runs).
  struct ValueRun {
    int value, slot, count;
  };
  std::vector<ValueRun> value_runs_;
  std::vector<int> supernode_start_;  // first columns of the supernodes, then n
  std::vector<int> supernode_of_;     // per column
  std::vector<int> below_position_;   // where each row below a supernode sits in the rows of a later one
  std::vector<double> unscaled_;      // d_c L(r, c) on a supernode's rows, before the division by d_c
  std::vector<int> update_target_;    // supernode by supernode, q by q: L(b_p, b_q)'s index for p > q (column by
                                      // column, for p >= q, where simplicial_)
  bool listed_updates_ = true;
  bool simplicial_ = false;
  std::int64_t updates_ = 0;
  Eigen::VectorXd d_, inverse_d_;  // D and its inverse (so that the solves multiply)
  Eigen::VectorXd root_inverse_d_;  // D^-1/2 once a half solve has asked for it (empty after Factor)
  std::vector<double> work_;        // the permuted x of a solve (n x K, row-major)
};

}  // namespace tether
