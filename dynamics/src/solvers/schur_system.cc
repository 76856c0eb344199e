#include "tether/dynamics/solvers/schur_system.h"

#include <algorithm>
#include <limits>
#include <map>
#include <type_traits>

namespace tether {
namespace {

// t_p . t_q for two blocks (row, slot) whose translations are known: a point row's is -e_k on its first body (slot
// 0) and +e_k on its second, an angle row's zero.
double KnownTranslationProduct(const std::vector<RowInfo>& infos, std::pair<int, int> p, std::pair<int, int> q) {
  const RowTranslation tp = infos[p.first].translation, tq = infos[q.first].translation;
  if (tp == RowTranslation::kZero || tp != tq) return 0.0;
  return p.second == q.second ? 1.0 : -1.0;
}

}  // namespace

SchurPattern::SchurPattern(const std::vector<RowInfo>& infos, int num_bodies)
    : SchurPattern(infos, std::vector<BodyLayout>(num_bodies)) {}

SchurPattern::SchurPattern(const std::vector<RowInfo>& infos, const std::vector<BodyLayout>& layout)
    : size_(static_cast<int>(infos.size())) {
  const int num_bodies = static_cast<int>(layout.size());
  // rows touching each body, with the slot (0: first body of the row, 1: second)
  std::vector<std::vector<std::pair<int, int>>> touching(num_bodies);
  for (int i = 0; i < size_; ++i) {
    if (infos[i].body_a != kWorld) touching[infos[i].body_a].push_back({i, 0});
    if (infos[i].body_b != kWorld) touching[infos[i].body_b].push_back({i, 1});
    row_translations_.push_back(infos[i].translation);
    const auto spatial = [&layout](int body) { return body != kWorld && layout[body].kind == BodyKind::kRigid3d; };
    if (infos[i].translation != RowTranslation::kEvaluated && (spatial(infos[i].body_a) || spatial(infos[i].body_b))) {
      known_translations_on_3d_bodies_ = true;
    }
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
  for (int j = 0; j < size_; ++j) {
    std::vector<int>& rows = rows_of_column[j];
    std::sort(rows.begin(), rows.end());
    rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
    for (int i : rows) {
      index[{i, j}] = static_cast<int>(row_index_.size());
      by_column_.push_back(static_cast<int>(row_index_.size()));
      row_index_.push_back(i);
      column_index_.push_back(j);
    }
  }
  diagonal_.resize(size_);
  for (int i = 0; i < size_; ++i) diagonal_[i] = index.at({i, i});
  for (int body = 0; body < num_bodies; ++body) {
    const std::vector<std::pair<int, int>>& list = touching[body];  // rows in increasing order
    if (layout[body].kind == BodyKind::kRigid3d) {
      const int count = static_cast<int>(list.size());
      const bool known = std::all_of(list.begin(), list.end(), [&infos](const std::pair<int, int>& block) {
        return infos[block.first].translation != RowTranslation::kEvaluated;
      });
      dense_bodies_.push_back(
          {body, static_cast<int>(blocks_.size()), count, static_cast<int>(entries_.size()), known});
      largest_dense_count_ = std::max(largest_dense_count_, count);
      blocks_.insert(blocks_.end(), list.begin(), list.end());
      for (int p = 0; p < count; ++p) {
        for (int q = 0; q <= p; ++q) {
          entries_.push_back(index.at({list[p].first, list[q].first}));
          translation_products_.push_back(known ? KnownTranslationProduct(infos, list[p], list[q]) : 0.0);
        }
      }
      continue;
    }
    for (const auto& [i, si] : list) {
      for (const auto& [j, sj] : list) {
        if (i >= j) terms_.push_back({body, i, si, j, sj, index.at({i, j})});
      }
    }
  }
  // visit values in storage order: friendlier to the cache during assembly
  std::sort(terms_.begin(), terms_.end(), [](const Term& x, const Term& y) { return x.value < y.value; });
}

void SchurPattern::StoreValuesAt(const std::vector<int>& position) {
  std::vector<int> row(row_index_.size()), column(column_index_.size());
  for (size_t v = 0; v < position.size(); ++v) {
    row[position[v]] = row_index_[v];
    column[position[v]] = column_index_[v];
  }
  row_index_.swap(row);
  column_index_.swap(column);
  for (int& d : diagonal_) d = position[d];
  for (int& k : by_column_) k = position[k];
  for (int& e : entries_) e = position[e];
  for (Term& term : terms_) term.value = position[term.value];
  std::stable_sort(terms_.begin(), terms_.end(), [](const Term& x, const Term& y) { return x.value < y.value; });
}

template <typename T>
std::vector<BodyLayout> LayoutOf(const Model<T>& model) {
  std::vector<BodyLayout> layout;
  for (const Body<T>& body : model.bodies) layout.push_back({body.kind, body.v_offset});
  return layout;
}

namespace {

// Whether a scalar is zero with every derivative it carries (a recorded reverse-mode value may carry any: never).
bool ExactZero(double x) { return x == 0.0; }
bool ExactZero(const Jet& x) { return x.a == 0.0 && (x.v.array() == 0.0).all(); }
bool ExactZero(const Rev&) { return false; }

// I_P^-1 of a 3D body has exact zeros off its diagonal where its inertia tensor is diagonal in body axes (the
// principal axes are the body's): its products then take the diagonal alone. The sums lose only terms that are
// products by zero, so they are the same to the bit but for the sign of a zero.
template <typename T>
bool ExactlyDiagonal(const Mat3<T>& m) {
  return ExactZero(m(1, 0)) && ExactZero(m(2, 0)) && ExactZero(m(0, 1)) && ExactZero(m(2, 1)) && ExactZero(m(0, 2)) &&
         ExactZero(m(1, 2));
}

template <bool kDiagonal, typename T>
TETHER_HOT_INLINE Vec3<T> InverseInertiaTimes(const Mat3<T>& inverse_inertia, const Vec3<T>& r) {
  if constexpr (kDiagonal) {
    return Vec3<T>(inverse_inertia(0, 0) * r[0], inverse_inertia(1, 1) * r[1], inverse_inertia(2, 2) * r[2]);
  } else {
    return inverse_inertia * r;
  }
}

// G (k x 6) of a 3D body gathered, W = G M_b^-1, and the lower triangle of G W^T added at its entries.
template <bool kDiagonal, typename T>
TETHER_HOT_INLINE void AddDenseBody(const SchurPattern& pattern, const SchurPattern::DenseBody& dense,
                                    const std::vector<ConstraintRow<T>>& rows, const T& inverse_mass,
                                    const Mat3<T>& inverse_inertia, T* __restrict G, T* __restrict W,
                                    T* __restrict value) {
  for (int p = 0; p < dense.count; ++p) {
    const auto [row, slot] = pattern.blocks()[dense.first_block + p];
    const BodyVector<T>& g = slot == 0 ? rows[row].a : rows[row].b;
    const Vec3<T> w = InverseInertiaTimes<kDiagonal>(inverse_inertia, g.rotation);
    for (int k = 0; k < 3; ++k) {
      G[6 * p + k] = g.translation[k];
      G[6 * p + 3 + k] = g.rotation[k];
      W[6 * p + k] = g.translation[k] * inverse_mass;
      W[6 * p + 3 + k] = w[k];
    }
  }
  const int* entry = pattern.entries().data() + dense.first_entry;
  for (int p = 0; p < dense.count; ++p) {
    const T g0 = G[6 * p], g1 = G[6 * p + 1], g2 = G[6 * p + 2], g3 = G[6 * p + 3], g4 = G[6 * p + 4],
            g5 = G[6 * p + 5];
    for (int q = 0; q <= p; ++q) {
      const T* wq = W + 6 * q;
      value[*entry++] += (g0 * wq[0] + g1 * wq[1]) + (g2 * wq[2] + g3 * wq[3]) + (g4 * wq[4] + g5 * wq[5]);
    }
  }
}

// The same for a body whose translations are known: (t_p . t_q) / m + r_p . I^-1 r_q, its rotational parts r (k x
// 3) gathered in G and I^-1 r in W by component (W_c[q] at W[c k + q]), so that two pairs (p, q), (p, q + 1) are
// summed side by side in one vector register. The sums are AddDenseBody's with its exact zero terms left out.
template <bool kDiagonal, typename T>
TETHER_HOT_INLINE void AddKnownTranslationBody(const SchurPattern& pattern, const SchurPattern::DenseBody& dense,
                                               const std::vector<ConstraintRow<T>>& rows, const T& inverse_mass,
                                               const Mat3<T>& inverse_inertia, T* __restrict G, T* __restrict W,
                                               T* __restrict value) {
  const int count = dense.count;
  for (int p = 0; p < count; ++p) {
    const auto [row, slot] = pattern.blocks()[dense.first_block + p];
    const Vec3<T>& r = slot == 0 ? rows[row].a.rotation : rows[row].b.rotation;
    const Vec3<T> w = InverseInertiaTimes<kDiagonal>(inverse_inertia, r);
    for (int k = 0; k < 3; ++k) {
      G[3 * p + k] = r[k];
      W[k * count + p] = w[k];
    }
  }
  using Two = Eigen::Array<T, 2, 1>;
  const T* __restrict W0 = W;
  const T* __restrict W1 = W + count;
  const T* __restrict W2 = W + 2 * count;
  const int* entry = pattern.entries().data() + dense.first_entry;
  const double* translation = pattern.translation_products().data() + dense.first_entry;
  for (int p = 0; p < count; ++p, entry += p, translation += p) {
    const T r0 = G[3 * p], r1 = G[3 * p + 1], r2 = G[3 * p + 2];
    int q = 0;
    for (; q < p; q += 2) {
      const Two sum = (Eigen::Map<const Eigen::Array2d>(translation + q).template cast<T>() * inverse_mass +
                       r0 * Eigen::Map<const Two>(W0 + q)) +
                      (r1 * Eigen::Map<const Two>(W1 + q) + r2 * Eigen::Map<const Two>(W2 + q));
      value[entry[q]] += sum[0];
      value[entry[q + 1]] += sum[1];
    }
    if (q == p) value[entry[p]] += (translation[p] * inverse_mass + r0 * W0[p]) + (r1 * W1[p] + r2 * W2[p]);
  }
}

}  // namespace

template <typename T>
void AssembleSchur(const std::vector<BodyLayout>& layout, const SchurPattern& pattern,
                   const std::vector<ConstraintRow<T>>& rows, const VecX<T>& inverse_diagonal,
                   const std::vector<Mat3<T>>& inverse_rotational, std::vector<T>* scratch, std::vector<T>* values) {
  std::fill(values->begin(), values->end(), T(0.0));
  // 3D rigid bodies: G (k x 6) gathered, W = G M_b^-1, the lower triangle of G W^T scattered
  scratch->resize(12 * static_cast<size_t>(pattern.largest_dense_count()));
  // G, W and the values never overlap: said, so that a store into values does not reload the blocks
  T* __restrict G = scratch->data();
  T* __restrict W = G + 6 * pattern.largest_dense_count();
  T* __restrict value = values->data();
  for (const SchurPattern::DenseBody& dense : pattern.dense_bodies()) {
    const T& inverse_mass = inverse_diagonal[layout[dense.body].v_offset];
    const Mat3<T>& inverse_inertia = inverse_rotational[dense.body];
    const auto add = [&](auto diagonal) {
      constexpr bool kDiagonal = decltype(diagonal)::value;
      if (dense.known_translations) {
        AddKnownTranslationBody<kDiagonal>(pattern, dense, rows, inverse_mass, inverse_inertia, G, W, value);
      } else {
        AddDenseBody<kDiagonal>(pattern, dense, rows, inverse_mass, inverse_inertia, G, W, value);
      }
    };
    if (ExactlyDiagonal(inverse_inertia)) {
      add(std::true_type());
    } else {
      add(std::false_type());
    }
  }
  // particles and planar rigid bodies: term by term
  for (const SchurPattern::Term& term : pattern.terms()) {
    const BodyVector<T>& gi = term.slot_i == 0 ? rows[term.row_i].a : rows[term.row_i].b;
    const BodyVector<T>& gj = term.slot_j == 0 ? rows[term.row_j].a : rows[term.row_j].b;
    const BodyLayout& body = layout[term.body];
    // translational coordinates share one inverse mass
    T entry = gi.translation.dot(gj.translation) * inverse_diagonal[body.v_offset];
    if (body.kind == BodyKind::kPlanar) entry += gi.rotation[2] * gj.rotation[2] * inverse_diagonal[body.v_offset + 2];
    (*values)[term.value] += entry;
  }
}

template <typename T>
double SchurSource<T>::SmallestShare(int row) const {
  double smallest = std::numeric_limits<double>::infinity();
  for (const BodyVector<T>* g : {&rows[row].a, &rows[row].b}) {
    if (g->body == kWorld) continue;
    const BodyLayout& body = layout[g->body];
    T share = g->translation.squaredNorm() * inverse_diagonal[body.v_offset];  // as AssembleSchur takes it
    if (body.kind == BodyKind::kRigid3d) share += g->rotation.dot(inverse_rotational[g->body] * g->rotation);
    if (body.kind == BodyKind::kPlanar) share += g->rotation[2] * g->rotation[2] * inverse_diagonal[body.v_offset + 2];
    smallest = std::min(smallest, Value(share));
  }
  return smallest;
}

template <typename T>
void Regularize(const SchurPattern& pattern, std::vector<T>* values) {
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
  for (int k : pattern.by_column()) {
    const int i = row[k], j = column[k];
    (*y)[i] += values[k] * x[j];
    if (i != j) (*y)[j] += values[k] * x[i];
  }
}

#define TETHER_INSTANTIATE_SCHUR_SYSTEM(T)                                                                          \
  template std::vector<BodyLayout> LayoutOf<T>(const Model<T>&);                                                    \
  template void AssembleSchur<T>(const std::vector<BodyLayout>&, const SchurPattern&,                               \
                                 const std::vector<ConstraintRow<T>>&, const VecX<T>&, const std::vector<Mat3<T>>&, \
                                 std::vector<T>*, std::vector<T>*);                                                 \
  template struct SchurSource<T>;                                                                                   \
  template void Regularize<T>(const SchurPattern&, std::vector<T>*);                                                \
  template void MultiplySymmetric<T, T>(const SchurPattern&, const std::vector<T>&, const VecX<T>&, VecX<T>*);
TETHER_FOR_EACH_SCALAR(TETHER_INSTANTIATE_SCHUR_SYSTEM)
template void MultiplySymmetric<Jet, double>(const SchurPattern&, const std::vector<Jet>&, const VecX<double>&,
                                             VecX<Jet>*);

}  // namespace tether
