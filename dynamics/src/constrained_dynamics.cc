#include "tether/dynamics/constrained_dynamics.h"

#include <limits>

#include "tether/dynamics/effects.h"

namespace tether {

template <typename T>
VecX<T> InverseMassDiagonal(const Model<T>& model) {
  VecX<T> inverse(model.NumCoordinates());
  for (const Body<T>& body : model.bodies) {
    for (int k = 0; k < model.dimension; ++k) inverse[body.offset + k] = T(1.0) / body.mass;
    if (body.kind == BodyKind::kRigid) inverse[body.offset + 2] = T(1.0) / body.inertia;
  }
  return inverse;
}

template <typename T>
bool ComputeAcceleration(const Model<T>& model, double t, const VecX<T>& q, const VecX<T>& v, Workspace<T>* ws,
                         VecX<T>* a) {
  ws->force.setZero();
  AccumulateForces(model, t, q, v, &ws->force);
  a->noalias() = ws->inverse_mass.cwiseProduct(ws->force);  // unconstrained acceleration u = M^-1 f
  if (ws->rows.empty()) return true;

  EvaluateConstraintRows(model, q, v, true, &ws->rows);
  for (size_t i = 0; i < ws->rows.size(); ++i) {
    const ConstraintRow<T>& row = ws->rows[i];
    const T velocity = Dot(model, row.a, v) + Dot(model, row.b, v);  // C_i' = J_i q'
    ws->rhs[i] = Dot(model, row.a, *a) + Dot(model, row.b, *a) + row.bias + ws->alpha * velocity + ws->beta * row.value;
  }
  AssembleSchur(model, ws->pattern, ws->rows, ws->inverse_mass, &ws->schur);
  if (!ws->solver.Solve(ws->schur, ws->rhs, &ws->lambda)) {
    a->setConstant(T(std::numeric_limits<double>::quiet_NaN()));
    return false;
  }
  // q'' = M^-1 (f - J^T lambda)
  for (size_t i = 0; i < ws->rows.size(); ++i) {
    AddScaled(model, ws->rows[i].a, T(-ws->lambda[i]), &ws->force);
    AddScaled(model, ws->rows[i].b, T(-ws->lambda[i]), &ws->force);
  }
  a->noalias() = ws->inverse_mass.cwiseProduct(ws->force);
  return true;
}

#define TETHER_INSTANTIATE_DYNAMICS(T)                                                                     \
  template VecX<T> InverseMassDiagonal<T>(const Model<T>&);                                               \
  template bool ComputeAcceleration<T>(const Model<T>&, double, const VecX<T>&, const VecX<T>&, Workspace<T>*, \
                                       VecX<T>*);
TETHER_FOR_EACH_SCALAR(TETHER_INSTANTIATE_DYNAMICS)

}  // namespace tether
