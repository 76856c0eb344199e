#include "tether/dynamics/constrained_dynamics.h"

#include <limits>

#include "tether/dynamics/effects.h"

namespace tether {

template <typename T>
bool ComputeAcceleration(const Model<T>& model, double t, const VecX<T>& q, const VecX<T>& v, Workspace<T>* ws,
                         VecX<T>* a) {
  UpdateFrames(model, q, v, true, &ws->frames);
  ws->force.setZero();
  AccumulateForces(model, ws->coordinates, ws->frames, t, q, v, &ws->force);
  ApplyInverseMass(model, ws->inverse_mass, ws->force, a);  // unconstrained acceleration u = M^-1 f
  if (ws->rows.empty()) return true;

  EvaluateConstraintRows(model, ws->constraints, ws->frames, q, v, true, &ws->rows);
  // J u + Jdot v + alpha J v + beta C, with the two products by J taken as one, J (u + alpha v)
  ws->u_plus_alpha_v = *a + ws->alpha * v;
  for (size_t i = 0; i < ws->rows.size(); ++i) {
    const ConstraintRow<T>& row = ws->rows[i];
    ws->rhs[i] = Dot(model, row.a, ws->u_plus_alpha_v) + Dot(model, row.b, ws->u_plus_alpha_v) + row.bias +
                 ws->beta * row.value;
  }
  AssembleSchur(ws);
  if (!ws->solver.Solve(ws->schur, ws->rhs, &ws->lambda)) {
    a->setConstant(T(std::numeric_limits<double>::quiet_NaN()));
    return false;
  }
  // v' = M^-1 (f - J^T lambda)
  for (size_t i = 0; i < ws->rows.size(); ++i) {
    AddScaled(model, ws->rows[i].a, T(-ws->lambda[i]), &ws->force);
    AddScaled(model, ws->rows[i].b, T(-ws->lambda[i]), &ws->force);
  }
  ApplyInverseMass(model, ws->inverse_mass, ws->force, a);
  return true;
}

#define TETHER_INSTANTIATE_DYNAMICS(T)                                                                            \
  template bool ComputeAcceleration<T>(const Model<T>&, double, const VecX<T>&, const VecX<T>&, Workspace<T>*, \
                                       VecX<T>*);
TETHER_FOR_EACH_SCALAR(TETHER_INSTANTIATE_DYNAMICS)

}  // namespace tether
