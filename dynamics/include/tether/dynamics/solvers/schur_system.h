// The Schur complement of the KKT system, assembled in its sparsity pattern.
//
// Each derivative evaluation solves  [M J^T; J 0] [q''; lambda] = [f; gamma].  M is diagonal, so eliminating
// q'' = M^-1 (f - J^T lambda) leaves
//   S lambda = J M^-1 f - gamma,      S = J M^-1 J^T,      S_ij = sum_b g_ib . M_b^-1 g_jb
// over the bodies b that rows i and j share (g_ib: row i's Jacobian block on body b). S therefore has the
// sparsity of the constraint graph: banded for a chain, tree-shaped for a tree, a few extra entries per loop.
//
// Regularization (applied by SchurSolver only where the rows are close to dependence, schur_solver.h):
//   S + eps (diag(S) + delta max diag(S)),   eps = kSchurRegularization, delta = kSchurDiagonalFloor.
// For redundant rows (a duplicated rod, a parallelogram's extra bar) it selects the multipliers of least norm, as
// Tikhonov regularization does when eps -> 0, instead of dividing by a round-off pivot.
//
// The pattern (lower triangle, built column by column with sorted rows, then stored in the order its factorization
// reads it) and the scatter list are built once per model;
// assembly is then a loop over the scatter list with no allocation. A 3D rigid body, whose blocks have six
// numbers each and which enters many entries (a hinge puts five rows on each of its bodies), is assembled as a
// small dense product instead: its k blocks G (k x 6) are gathered once, W = G M_b^-1, and the k (k + 1) / 2
// entries of G W^T are added where the pattern puts them. Where every block's translation is known before the
// evaluation (point and angle rows: RowTranslation), g_p . M_b^-1 g_q = (t_p . t_q) / m + r_p . I^-1 r_q with
// t_p . t_q in {-1, 0, 1} from the pattern, and only the rotational parts r are gathered: three products a pair
// instead of six, with the same sums bit for bit (the skipped products are exact zeros and ones).
#pragma once

#include <vector>

#include "tether/dynamics/constraints/constraint_rows.h"

namespace tether {

inline constexpr double kSchurRegularization = 1e-12;
inline constexpr double kSchurDiagonalFloor = 1e-12;  // delta above, for rows whose Jacobian vanishes
// Every pair of rows acting on one body shares an entry of S, so a body held by k rows (a hub: MuJoCo's softbox
// has 1090 on its centre) makes a dense k x k block, of memory k^2 and factorization time k^3. A scene may put at
// most this many rows on one body (the scene reader refuses more): a block of 32 MiB a copy, factored in about half
// a second (a star of 2048 particles on one hub: 2 rk4 steps in 4.6 s, 285 MB).
inline constexpr int kMaxRowsOnOneBody = 2048;

// What the assembly needs of a body, compact: its kind and where its velocities start.
struct BodyLayout {
  BodyKind kind = BodyKind::kParticle;
  int v_offset = 0;
};
template <typename T>
std::vector<BodyLayout> LayoutOf(const Model<T>& model);

class SchurPattern {
 public:
  SchurPattern() = default;
  // `infos` as DescribeRows(model); `layout` the model's bodies (LayoutOf).
  SchurPattern(const std::vector<RowInfo>& infos, const std::vector<BodyLayout>& layout);
  // The same for `num_bodies` particles (the pattern alone: tests, the solver's analysis).
  SchurPattern(const std::vector<RowInfo>& infos, int num_bodies);

  int size() const { return size_; }
  int nonzeros() const { return static_cast<int>(row_index_.size()); }
  const std::vector<int>& row_index() const { return row_index_; }        // row of each stored value
  const std::vector<int>& column_index() const { return column_index_; }  // column of each stored value
  const std::vector<int>& diagonal() const { return diagonal_; }          // value index of S_ii
  // the value indices column by column, rows increasing (the order products with S sum in, whatever the storage)
  const std::vector<int>& by_column() const { return by_column_; }
  // RowInfo::translation of each row, for the products by J that skip the known zeros too
  const std::vector<RowTranslation>& row_translations() const { return row_translations_; }
  // whether some row with a known translation touches a 3D rigid body (the products that can skip it)
  bool known_translations_on_3d_bodies() const { return known_translations_on_3d_bodies_; }

  // One term g_i . M_b^-1 g_j of entry `value` (slots: 0 = the row's first body block, 1 = its second).
  struct Term {
    int body;
    int row_i, slot_i;
    int row_j, slot_j;
    int value;
  };
  const std::vector<Term>& terms() const { return terms_; }  // the bodies that are not 3D rigid bodies

  // A 3D rigid body's share: its blocks blocks()[first_block, + count) as (row, slot), and the value indices
  // entries()[first_entry, + count (count + 1) / 2) of the pairs (p, q), q <= p, in that order. Where its blocks'
  // translations are all known, translation_products() holds t_p . t_q at the same indices.
  struct DenseBody {
    int body, first_block, count, first_entry;
    bool known_translations;
  };
  const std::vector<DenseBody>& dense_bodies() const { return dense_bodies_; }
  const std::vector<std::pair<int, int>>& blocks() const { return blocks_; }
  const std::vector<int>& entries() const { return entries_; }
  const std::vector<double>& translation_products() const { return translation_products_; }
  int largest_dense_count() const { return largest_dense_count_; }

  // Moves stored value v to index position[v] (a permutation of the stored values), so that S is stored in the
  // order its factorization reads it (SchurSolver::StoreInFactorOrder). The rows, columns, by_column() and every
  // index into the values follow, so nothing computed from the pattern changes, to the bit.
  void StoreValuesAt(const std::vector<int>& position);

 private:
  int size_ = 0;
  std::vector<int> row_index_, column_index_, diagonal_, by_column_;
  std::vector<RowTranslation> row_translations_;
  bool known_translations_on_3d_bodies_ = false;
  std::vector<Term> terms_;
  std::vector<DenseBody> dense_bodies_;
  std::vector<std::pair<int, int>> blocks_;
  std::vector<int> entries_;
  std::vector<double> translation_products_;
  int largest_dense_count_ = 0;
};

// values (sized pattern.nonzeros()) = S at the given rows, for M^-1 given by its diagonal over the
// velocities (translations, planar angles) and the rotational blocks of 3D bodies (workspace.h's InverseMass);
// `scratch` holds the dense products' G and W (12 numbers per block of the largest 3D body).
template <typename T>
void AssembleSchur(const std::vector<BodyLayout>& layout, const SchurPattern& pattern,
                   const std::vector<ConstraintRow<T>>& rows, const VecX<T>& inverse_diagonal,
                   const std::vector<Mat3<T>>& inverse_rotational, std::vector<T>* scratch, std::vector<T>* values);

// What S was assembled from (AssembleSchur's rows and M^-1), for the solver's conditioning test: where one light
// body dominates a row's diagonal S_ii, the test reads the row's pivot against the row's smallest body share
// instead (schur_solver.h, "Light bodies").
template <typename T>
struct SchurSource {
  const std::vector<BodyLayout>& layout;
  const std::vector<ConstraintRow<T>>& rows;
  const VecX<T>& inverse_diagonal;
  const std::vector<Mat3<T>>& inverse_rotational;
  // min over the bodies b the row touches of its share g_b . M_b^-1 g_b of S_ii (value parts); for a row on one
  // body, S_ii itself
  double SmallestShare(int row) const;
};

// values (a stored S, pattern order) += the regularization above, on the diagonal.
template <typename T>
void Regularize(const SchurPattern& pattern, std::vector<T>* values);

// y = S x for the symmetric S stored as its lower triangle.
template <typename S, typename X>
void MultiplySymmetric(const SchurPattern& pattern, const std::vector<S>& values, const VecX<X>& x, VecX<S>* y);

}  // namespace tether
