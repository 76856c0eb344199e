#include "tether/dynamics/schur_system.h"

#include <algorithm>
#include <map>

namespace tether {

SchurPattern::SchurPattern(const std::vector<RowInfo>& infos, int num_bodies) : size_(static_cast<int>(infos.size())) {
  // rows touching each body, with the slot (0: first body of the row, 1: second)
  std::vector<std::vector<std::pair<int, int>>> touching(num_bodies);
  for (int i = 0; i < size_; ++i) {
    if (infos[i].body_a != kWorld) touching[infos[i].body_a].push_back({i, 0});
    if (infos[i].body_b != kWorld) touching[infos[i].body_b].push_back({i, 1});
  }
  // entries (i >= j) of the lower triangle, column by column with sorted rows; the diagonal is always stored
  std::vector<std::vector<int>> rows_of_column(size_);
  for (int i = 0; i < size_; ++i) rows_of_column[i].push_back(i);
  for (const auto& list : touching) {
    for (const auto& [i, si] : list) {
      for (const auto& [j, sj] : list) {
        if (i > j) rows_of_column[j].push_back(i);
      }
    }
  }
  std::map<std::pair<int, int>, int> index;  // (row, column) -> value index
  column_start_.push_back(0);
  for (int j = 0; j < size_; ++j) {
    std::vector<int>& rows = rows_of_column[j];
    std::sort(rows.begin(), rows.end());
    rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
    for (int i : rows) {
      index[{i, j}] = static_cast<int>(row_index_.size());
      row_index_.push_back(i);
      column_index_.push_back(j);
    }
    column_start_.push_back(static_cast<int>(row_index_.size()));
  }
  diagonal_.resize(size_);
  for (int i = 0; i < size_; ++i) diagonal_[i] = index.at({i, i});
  for (int body = 0; body < num_bodies; ++body) {
    for (const auto& [i, si] : touching[body]) {
      for (const auto& [j, sj] : touching[body]) {
        if (i >= j) terms_.push_back({body, i, si, j, sj, index.at({i, j})});
      }
    }
  }
  // visit values in storage order: friendlier to the cache during assembly
  std::sort(terms_.begin(), terms_.end(), [](const Term& x, const Term& y) { return x.value < y.value; });
}

template <typename T>
std::vector<BodyLayout> LayoutOf(const Model<T>& model) {
  std::vector<BodyLayout> layout;
  for (const Body<T>& body : model.bodies) layout.push_back({body.kind, body.v_offset});
  return layout;
}

template <typename T>
void AssembleSchur(const std::vector<BodyLayout>& layout, const SchurPattern& pattern,
                   const std::vector<ConstraintRow<T>>& rows, const VecX<T>& inverse_diagonal,
                   const std::vector<Mat3<T>>& inverse_rotational, std::vector<Vec3<T>>* weighted,
                   std::vector<T>* values) {
  // a 3D body's rotational blocks weighted by its I_P^-1 once per row, not once per entry they enter
  weighted->resize(2 * rows.size());
  const bool spatial =
      std::any_of(layout.begin(), layout.end(), [](const BodyLayout& b) { return b.kind == BodyKind::kRigid3d; });
  for (size_t i = 0; spatial && i < rows.size(); ++i) {
    for (int slot = 0; slot < 2; ++slot) {
      const BodyVector<T>& g = slot == 0 ? rows[i].a : rows[i].b;
      if (g.body != kWorld && layout[g.body].kind == BodyKind::kRigid3d) {
        (*weighted)[2 * i + slot] = inverse_rotational[g.body] * g.rotation;
      }
    }
  }
  std::fill(values->begin(), values->end(), T(0.0));
  for (const SchurPattern::Term& term : pattern.terms()) {
    const BodyVector<T>& gi = term.slot_i == 0 ? rows[term.row_i].a : rows[term.row_i].b;
    const BodyVector<T>& gj = term.slot_j == 0 ? rows[term.row_j].a : rows[term.row_j].b;
    const BodyLayout& body = layout[term.body];
    // translational coordinates share one inverse mass
    T entry = gi.translation.dot(gj.translation) * inverse_diagonal[body.v_offset];
    if (body.kind == BodyKind::kPlanar) {
      entry += gi.rotation[2] * gj.rotation[2] * inverse_diagonal[body.v_offset + 2];
    } else if (body.kind == BodyKind::kRigid3d) {
      entry += gi.rotation.dot((*weighted)[2 * term.row_j + term.slot_j]);
    }
    (*values)[term.value] += entry;
  }
  double largest = 0.0;
  for (int d : pattern.diagonal()) largest = std::max(largest, Value((*values)[d]));
  for (int d : pattern.diagonal()) {
    (*values)[d] += kSchurRegularization * ((*values)[d] + T(kSchurDiagonalFloor * largest));
  }
}

template <typename S, typename X>
void MultiplySymmetric(const SchurPattern& pattern, const std::vector<S>& values, const VecX<X>& x, VecX<S>* y) {
  y->setZero(pattern.size());
  const std::vector<int>& row = pattern.row_index();
  const std::vector<int>& column = pattern.column_index();
  for (size_t k = 0; k < values.size(); ++k) {
    const int i = row[k], j = column[k];
    (*y)[i] += values[k] * x[j];
    if (i != j) (*y)[j] += values[k] * x[i];
  }
}

#define TETHER_INSTANTIATE_SCHUR_SYSTEM(T)                                                                      \
  template std::vector<BodyLayout> LayoutOf<T>(const Model<T>&);                                                 \
  template void AssembleSchur<T>(const std::vector<BodyLayout>&, const SchurPattern&,                           \
                                 const std::vector<ConstraintRow<T>>&, const VecX<T>&,                          \
                                 const std::vector<Mat3<T>>&, std::vector<Vec3<T>>*, std::vector<T>*);         \
  template void MultiplySymmetric<T, T>(const SchurPattern&, const std::vector<T>&, const VecX<T>&, VecX<T>*);
TETHER_FOR_EACH_SCALAR(TETHER_INSTANTIATE_SCHUR_SYSTEM)
template void MultiplySymmetric<Jet, double>(const SchurPattern&, const std::vector<Jet>&, const VecX<double>&,
                                             VecX<Jet>*);

}  // namespace tether
