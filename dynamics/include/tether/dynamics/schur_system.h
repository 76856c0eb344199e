// The Schur complement of the KKT system, assembled in its sparsity pattern.
//
// Each derivative evaluation solves  [M J^T; J 0] [q''; lambda] = [f; gamma].  M is diagonal, so eliminating
// q'' = M^-1 (f - J^T lambda) leaves
//   S lambda = J M^-1 f - gamma,      S = J M^-1 J^T,      S_ij = sum_b g_ib . M_b^-1 g_jb
// over the bodies b that rows i and j share (g_ib: row i's Jacobian block on body b). S therefore has the
// sparsity of the constraint graph: banded for a chain, tree-shaped for a tree, a few extra entries per loop.
//
// Regularization: what is assembled is S + eps (diag(S) + delta max diag(S)), eps = kSchurRegularization. For
// full-rank S this moves lambda by a relative eps; for redundant rows (a duplicated rod, a parallelogram's
// extra bar) it selects the multipliers of least norm, as Tikhonov regularization does when eps -> 0, instead of
// dividing by a round-off pivot.
//
// The pattern (lower triangle, compressed columns, rows sorted) and the scatter list are built once per model;
// assembly is then a loop over the scatter list with no allocation.
#pragma once

#include <vector>

#include "tether/dynamics/constraint_rows.h"

namespace tether {

inline constexpr double kSchurRegularization = 1e-12;
inline constexpr double kSchurDiagonalFloor = 1e-12;  // delta above, for rows whose Jacobian vanishes

class SchurPattern {
 public:
  SchurPattern() = default;
  // `infos` as DescribeRows(model); `num_bodies` the model's body count.
  SchurPattern(const std::vector<RowInfo>& infos, int num_bodies);

  int size() const { return size_; }
  int nonzeros() const { return static_cast<int>(row_index_.size()); }
  const std::vector<int>& column_start() const { return column_start_; }  // size() + 1 entries
  const std::vector<int>& row_index() const { return row_index_; }        // row of each stored value
  const std::vector<int>& column_index() const { return column_index_; }  // column of each stored value
  const std::vector<int>& diagonal() const { return diagonal_; }          // value index of S_ii

  // One term g_i . M_b^-1 g_j of entry `value` (slots: 0 = the row's first body block, 1 = its second).
  struct Term {
    int body;
    int row_i, slot_i;
    int row_j, slot_j;
    int value;
  };
  const std::vector<Term>& terms() const { return terms_; }

 private:
  int size_ = 0;
  std::vector<int> column_start_, row_index_, column_index_, diagonal_;
  std::vector<Term> terms_;
};

// What the assembly needs of a body, compact: its kind and where its velocities start.
struct BodyLayout {
  BodyKind kind = BodyKind::kParticle;
  int v_offset = 0;
};
template <typename T>
std::vector<BodyLayout> LayoutOf(const Model<T>& model);

// values (sized pattern.nonzeros()) = the regularized S at the given rows, for M^-1 given by its diagonal over the
// velocities (translations, planar angles) and the rotational blocks of 3D bodies (workspace.h's InverseMass);
// `weighted` is scratch (I_P^-1 times the rotational blocks of 3D bodies, two per row).
template <typename T>
void AssembleSchur(const std::vector<BodyLayout>& layout, const SchurPattern& pattern,
                   const std::vector<ConstraintRow<T>>& rows, const VecX<T>& inverse_diagonal,
                   const std::vector<Mat3<T>>& inverse_rotational, std::vector<Vec3<T>>* weighted,
                   std::vector<T>* values);

// y = S x for the symmetric S stored as its lower triangle.
template <typename S, typename X>
void MultiplySymmetric(const SchurPattern& pattern, const std::vector<S>& values, const VecX<X>& x, VecX<S>* y);

}  // namespace tether
