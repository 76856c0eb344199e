#include "tether/dynamics/solvers/constrained_dynamics.h"

#include <Eigen/LU>
#include <algorithm>
#include <limits>
#include <type_traits>

#include "tether/dynamics/adjoint/recorded.h"
#include "tether/dynamics/effects/effects.h"

namespace tether {
namespace {

// Dot(model, g, x) for a row's block g on a 3D body whose translation is known (RowTranslation; kSign: -1 on the
// row's first body, whose point-row block is -e_k, +1 on its second), with Dot's sum and its exact zero terms left
// out: Dot adds (t_0 x_0 + t_1 x_1) + (((t_2 x_2 + r_0 x_3) + r_1 x_4) + r_2 x_5). kKnown false: Dot itself.
template <int kSign, bool kKnown, typename S, typename T>
TETHER_HOT_INLINE T RowBlockDot(const Model<S>& model, const BodyVector<T>& g, RowTranslation translation,
                                const VecX<T>& x) {
  if constexpr (!kKnown) return Dot(model, g, x);
  if (g.body == kWorld) return T(0.0);
  const Body<S>& body = model.bodies[g.body];
  if (translation == RowTranslation::kEvaluated || body.kind != BodyKind::kRigid3d) return Dot(model, g, x);
  const T* x_b = x.data() + body.v_offset;
  if (translation == RowTranslation::kZero)
    return (g.rotation[0] * x_b[3] + g.rotation[1] * x_b[4]) + g.rotation[2] * x_b[5];
  const int axis = TranslationAxis(translation);
  const T along = kSign > 0 ? x_b[axis] : T(-x_b[axis]);
  if (axis == 2) return ((along + g.rotation[0] * x_b[3]) + g.rotation[1] * x_b[4]) + g.rotation[2] * x_b[5];
  return along + ((g.rotation[0] * x_b[3] + g.rotation[1] * x_b[4]) + g.rotation[2] * x_b[5]);
}

// rhs = J x + Jdot v + beta C, row by row (x = u + alpha v).
template <bool kKnown, typename S, typename T>
TETHER_HOT_INLINE void SchurRightHandSide(const Model<S>& model, const SchurPattern& pattern,
                                          const std::vector<ConstraintRow<T>>& rows, const VecX<T>& x, const T& beta,
                                          VecX<T>* rhs) {
  const RowTranslation* translation = pattern.row_translations().data();
  for (size_t i = 0; i < rows.size(); ++i) {
    const ConstraintRow<T>& row = rows[i];
    (*rhs)[i] = RowBlockDot<-1, kKnown>(model, row.a, translation[i], x) +
                RowBlockDot<1, kKnown>(model, row.b, translation[i], x) + row.bias + beta * row.value;
  }
}

// A 3D body's share of f -= J^T lambda, its blocks' terms summed in registers (f_b + sum_p s_p g_p with s_p = -lambda
// of block p's row). Its blocks come in row order, so each component takes the same terms in the same order as row by
// row through memory, to the bit, without one block's store waiting on the one before. kKnown: RowBlockDot's known
// translations (+-s on one axis, or none) without their zero terms.
template <bool kKnown, typename S, typename T>
TETHER_HOT_INLINE void SubtractBodyReaction(const Model<S>& model, const SchurPattern& pattern,
                                            const SchurPattern::DenseBody& dense,
                                            const std::vector<ConstraintRow<T>>& rows, const VecX<T>& lambda,
                                            VecX<T>* force) {
  T* f_b = force->data() + model.bodies[dense.body].v_offset;
  T t0 = f_b[0], t1 = f_b[1], t2 = f_b[2], r0 = f_b[3], r1 = f_b[4], r2 = f_b[5];
  const RowTranslation* translation = pattern.row_translations().data();
  const std::pair<int, int>* block = pattern.blocks().data() + dense.first_block;
  for (int p = 0; p < dense.count; ++p) {
    const auto [row, slot] = block[p];
    const BodyVector<T>& g = slot == 0 ? rows[row].a : rows[row].b;
    const T scale = -lambda[row];
    if (kKnown && translation[row] != RowTranslation::kEvaluated) {
      const T along = slot == 0 ? T(-scale) : scale;
      switch (translation[row]) {
        case RowTranslation::kAxisX:
          t0 += along;
          break;
        case RowTranslation::kAxisY:
          t1 += along;
          break;
        case RowTranslation::kAxisZ:
          t2 += along;
          break;
        default:
          break;  // kZero
      }
    } else {
      t0 += scale * g.translation[0];
      t1 += scale * g.translation[1];
      t2 += scale * g.translation[2];
    }
    r0 += scale * g.rotation[0];
    r1 += scale * g.rotation[1];
    r2 += scale * g.rotation[2];
  }
  f_b[0] = t0;
  f_b[1] = t1;
  f_b[2] = t2;
  f_b[3] = r0;
  f_b[4] = r1;
  f_b[5] = r2;
}

// f -= J^T lambda: 3D bodies body by body, particles and planar bodies (the pattern's terms) row by row.
template <bool kKnown, typename S, typename T>
TETHER_HOT_INLINE void SubtractReaction(const Model<S>& model, const SchurPattern& pattern,
                                        const std::vector<ConstraintRow<T>>& rows, const VecX<T>& lambda,
                                        VecX<T>* force) {
  const bool spatial = !pattern.dense_bodies().empty();
  for (const SchurPattern::DenseBody& dense : pattern.dense_bodies()) {
    SubtractBodyReaction<kKnown>(model, pattern, dense, rows, lambda, force);
  }
  if (pattern.terms().empty()) return;
  const auto planar_or_particle = [&model](const BodyVector<T>& g) {
    return g.body != kWorld && model.bodies[g.body].kind != BodyKind::kRigid3d;
  };
  for (size_t i = 0; i < rows.size(); ++i) {
    if (!spatial || planar_or_particle(rows[i].a)) AddScaled(model, rows[i].a, T(-lambda[i]), force);
    if (!spatial || planar_or_particle(rows[i].b)) AddScaled(model, rows[i].b, T(-lambda[i]), force);
  }
}

}  // namespace

template <typename T>
bool ComputeAcceleration(const Model<T>& model, double t, const VecX<T>& q, const VecX<T>& v, Workspace<T>* ws,
                         VecX<T>* a) {
  UpdateFrames(model, q, v, true, &ws->frames);
  ws->force.setZero();
  AccumulateForces(model, ws->coordinates, ws->principal_inertia, ws->frames, t, q, v, &ws->force);
  if (ws->rows.empty()) {
    ApplyInverseMass(model, ws->inverse_mass, ws->force, a);  // v' = M^-1 f
    return true;
  }
  if (ws->constraints.contacts.empty()) ws->sliding.clear();  // none slides where none touches (a tree included)
  if constexpr (!std::is_same_v<T, Rev>) {  // a tree's elimination from the primitives, unless the adjoint keeps the
                                            // Schur path's solves; it leaves the rows' values only
    if (ws->tree != nullptr && ws->kkt_log == nullptr &&
        TreeAcceleration(model, *ws->tree, ws->constraints, ws->frames, ws->principal_inertia,
                         ws->inverse_mass.diagonal, ws->inverse_mass.rotational, q, v, ws->alpha, ws->beta, ws->force,
                         &ws->tree_work, &ws->rows, a)) {
      return true;
    }
  }
  EvaluateConstraintRows(model, ws->constraints, ws->frames, q, v, true, &ws->rows);
  if (!ws->constraints.contacts.empty()) {
    EvaluateSliding(model, ws->constraints, ws->frames, q, v, static_cast<int>(ws->rows.size()), &ws->sliding);
  }
  return SolveKkt(model, v, ws, a);
}

template <typename S, typename T>
TETHER_FLATTEN bool KktAcceleration(const Model<S>& model, const std::vector<BodyLayout>& layout,
                                    const SchurPattern& pattern, SchurSolver* solver,
                                    const std::vector<ConstraintRow<T>>& rows, const InverseMass<T>& inverse_mass,
                                    const VecX<T>& v, const T& alpha, const T& beta, VecX<T>* force, KktSystem<T>* kkt,
                                    VecX<T>* a) {
  ApplyInverseMass(model, inverse_mass, *force, a);  // unconstrained acceleration u = M^-1 f
  // J u + Jdot v + alpha J v + beta C, with the two products by J taken as one, J (u + alpha v)
  kkt->u_plus_alpha_v = *a + alpha * v;
  // the known translations' zeros skipped where a 3D body has them; elsewhere (particles, planar bodies) Dot as it is
  const bool known = pattern.known_translations_on_3d_bodies();
  if (known) {
    SchurRightHandSide<true>(model, pattern, rows, kkt->u_plus_alpha_v, beta, &kkt->rhs);
  } else {
    SchurRightHandSide<false>(model, pattern, rows, kkt->u_plus_alpha_v, beta, &kkt->rhs);
  }
  AssembleSchur(layout, pattern, rows, inverse_mass.diagonal, inverse_mass.rotational, &kkt->assembly_scratch,
                &kkt->schur);
  if (!solver->Solve(kkt->schur, kkt->rhs, &kkt->lambda,
                     {layout, rows, inverse_mass.diagonal, inverse_mass.rotational})) {
    a->setConstant(T(std::numeric_limits<double>::quiet_NaN()));
    return false;
  }
  // v' = M^-1 (f - J^T lambda)
  if (known) {
    SubtractReaction<true>(model, pattern, rows, kkt->lambda, force);
  } else {
    SubtractReaction<false>(model, pattern, rows, kkt->lambda, force);
  }
  ApplyInverseMass(model, inverse_mass, *force, a);
  return true;
}

namespace {

// M^-1 g^T for a row's blocks g.
template <typename S, typename T>
void InverseMassTimes(const Model<S>& model, const InverseMass<T>& inverse_mass, const BodyVector<T>& a,
                      const BodyVector<T>& b, VecX<T>* out) {
  out->setZero();
  AddScaled(model, a, T(1.0), out);
  AddScaled(model, b, T(1.0), out);
  ApplyInverseMass(model, inverse_mass, *out, out);
}

// S' = J M^-1 (J - F)^T as a dense matrix, regularized as the solver regularizes S (schur_system.h): where rows are
// redundant (coplanar contacts) S^-1 multiplies by 1 / eps in their null space, and Woodbury's formula would add and
// cancel such terms.
template <typename S, typename T>
Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> RegularizedSlidingSchur(const Model<S>& model,
                                                                         const std::vector<ConstraintRow<T>>& rows,
                                                                         const std::vector<SlidingRow<T>>& sliding,
                                                                         const InverseMass<T>& inverse_mass,
                                                                         const std::vector<VecX<T>>& friction_columns) {
  const int m = static_cast<int>(rows.size());
  Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> matrix(m, m);
  VecX<T> column(friction_columns.empty() ? 0 : friction_columns[0].size());
  double largest = 0.0;
  for (int c = 0; c < m; ++c) {
    InverseMassTimes(model, inverse_mass, rows[c].a, rows[c].b, &column);
    for (int i = 0; i < m; ++i) matrix(i, c) = Dot(model, rows[i].a, column) + Dot(model, rows[i].b, column);
    largest = std::max(largest, Value(matrix(c, c)));
  }
  for (int c = 0; c < m; ++c) {
    matrix(c, c) += T(kSchurRegularization) * (matrix(c, c) + T(kSchurDiagonalFloor * largest));
  }
  for (size_t j = 0; j < sliding.size(); ++j) {
    for (int i = 0; i < m; ++i) {
      matrix(i, sliding[j].row) -=
          Dot(model, rows[i].a, friction_columns[j]) + Dot(model, rows[i].b, friction_columns[j]);
    }
  }
  return matrix;
}

}  // namespace

template <typename S, typename T>
int SlidingKktAcceleration(const Model<S>& model, const std::vector<BodyLayout>& layout, SchurSolver* solver,
                           const std::vector<ConstraintRow<T>>& rows, const std::vector<SlidingRow<T>>& sliding,
                           const InverseMass<T>& inverse_mass, VecX<T>* force, KktSystem<T>* kkt, VecX<T>* a) {
  const int m = static_cast<int>(rows.size()), k = static_cast<int>(sliding.size());
  const bool redundant = solver->starts_regularized();               // the factorization of S just made was regularized
  std::vector<VecX<T>> friction_columns(k, VecX<T>(force->size()));  // M^-1 (mu J_s)_j^T
  for (int j = 0; j < k; ++j) InverseMassTimes(model, inverse_mass, sliding[j].a, sliding[j].b, &friction_columns[j]);
  VecX<T> change;
  if (redundant) {
    change =
        RegularizedSlidingSchur(model, rows, sliding, inverse_mass, friction_columns).partialPivLu().solve(kkt->rhs) -
        kkt->lambda;
  } else {
    Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> z(m, k), coupling(k, k);
    VecX<T> w(m), solved(m);
    for (int j = 0; j < k; ++j) {  // Z = S^-1 W, W's column j = J M^-1 (mu J_s)_j^T
      for (int i = 0; i < m; ++i) {
        w[i] = Dot(model, rows[i].a, friction_columns[j]) + Dot(model, rows[i].b, friction_columns[j]);
      }
      if (!solver->Solve(kkt->schur, w, &solved, {layout, rows, inverse_mass.diagonal, inverse_mass.rotational})) {
        return sliding[j].row;
      }
      z.col(j) = solved;
    }
    VecX<T> lambda_k(k);
    for (int i = 0; i < k; ++i) {
      lambda_k[i] = kkt->lambda[sliding[i].row];
      for (int j = 0; j < k; ++j) coupling(i, j) = T(i == j ? 1.0 : 0.0) - z(sliding[i].row, j);
    }
    const auto lu = coupling.partialPivLu();
    if (!(Value(lu.determinant()) > 0.0)) return sliding[0].row;
    change = z * lu.solve(lambda_k);
  }
  kkt->lambda += change;
  for (int i = 0; i < m; ++i) {  // f - (J - F)^T lambda, from f - J^T lambda0
    AddScaled(model, rows[i].a, T(-change[i]), force);
    AddScaled(model, rows[i].b, T(-change[i]), force);
  }
  for (int j = 0; j < k; ++j) {
    AddScaled(model, sliding[j].a, kkt->lambda[sliding[j].row], force);
    AddScaled(model, sliding[j].b, kkt->lambda[sliding[j].row], force);
  }
  ApplyInverseMass(model, inverse_mass, *force, a);
  return -1;
}

template <typename T>
bool SolveKkt(const Model<T>& model, const VecX<T>& v, Workspace<T>* ws, VecX<T>* a) {
  if (const std::optional<bool> recorded = RecordedKktAcceleration(model, v, ws, a)) return *recorded;
  bool solved = KktAcceleration(model, ws->layout, *ws->pattern, ws->solver, ws->rows, ws->inverse_mass, v, ws->alpha,
                                ws->beta, &ws->force, &ws->kkt, a);
  if (solved && !ws->sliding.empty()) {
    ws->painleve = SlidingKktAcceleration(model, ws->layout, ws->solver, ws->rows, ws->sliding, ws->inverse_mass,
                                          &ws->force, &ws->kkt, a);
    solved = ws->painleve < 0;
  }
  if constexpr (std::is_same_v<T, double>) {
    if (solved && ws->kkt_log) ws->kkt_log->Keep(ws->kkt.lambda, *ws->solver);
  }
  return solved;
}

#define TETHER_INSTANTIATE_DYNAMICS(T)                                                                         \
  template bool ComputeAcceleration<T>(const Model<T>&, double, const VecX<T>&, const VecX<T>&, Workspace<T>*, \
                                       VecX<T>*);
TETHER_FOR_EACH_SCALAR(TETHER_INSTANTIATE_DYNAMICS)
// the recorded KKT solve's values in double (kkt_adjoint.cc)
template bool KktAcceleration<Rev, double>(const Model<Rev>&, const std::vector<BodyLayout>&, const SchurPattern&,
                                           SchurSolver*, const std::vector<ConstraintRow<double>>&,
                                           const InverseMass<double>&, const VecX<double>&, const double&,
                                           const double&, VecX<double>*, KktSystem<double>*, VecX<double>*);

}  // namespace tether
