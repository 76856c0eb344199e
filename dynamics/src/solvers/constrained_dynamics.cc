#include "tether/dynamics/solvers/constrained_dynamics.h"

#include <limits>
#include <type_traits>

#include "tether/dynamics/adjoint/recorded.h"
#include "tether/dynamics/effects/effects.h"

namespace tether {

template <typename T>
bool ComputeAcceleration(const Model<T>& model, double t, const VecX<T>& q, const VecX<T>& v, Workspace<T>* ws,
                         VecX<T>* a) {
  UpdateFrames(model, q, v, true, &ws->frames);
  ws->force.setZero();
  AccumulateForces(model, ws->coordinates, ws->frames, t, q, v, &ws->force);
  if (ws->rows.empty()) {
    ApplyInverseMass(model, ws->inverse_mass, ws->force, a);  // v' = M^-1 f
    return true;
  }
  EvaluateConstraintRows(model, ws->constraints, ws->frames, q, v, true, &ws->rows);
  return SolveKkt(model, v, ws, a);
}

template <typename S, typename T>
bool KktAcceleration(const Model<S>& model, const std::vector<BodyLayout>& layout, const SchurPattern& pattern,
                     SchurSolver* solver, const std::vector<ConstraintRow<T>>& rows, const InverseMass<T>& inverse_mass,
                     const VecX<T>& v, const T& alpha, const T& beta, VecX<T>* force, KktSystem<T>* kkt, VecX<T>* a) {
  ApplyInverseMass(model, inverse_mass, *force, a);  // unconstrained acceleration u = M^-1 f
  // J u + Jdot v + alpha J v + beta C, with the two products by J taken as one, J (u + alpha v)
  kkt->u_plus_alpha_v = *a + alpha * v;
  for (size_t i = 0; i < rows.size(); ++i) {
    const ConstraintRow<T>& row = rows[i];
    kkt->rhs[i] =
        Dot(model, row.a, kkt->u_plus_alpha_v) + Dot(model, row.b, kkt->u_plus_alpha_v) + row.bias + beta * row.value;
  }
  AssembleSchur(layout, pattern, rows, inverse_mass.diagonal, inverse_mass.rotational, &kkt->assembly_scratch,
                &kkt->schur);
  if (!solver->Solve(kkt->schur, kkt->rhs, &kkt->lambda)) {
    a->setConstant(T(std::numeric_limits<double>::quiet_NaN()));
    return false;
  }
  // v' = M^-1 (f - J^T lambda)
  for (size_t i = 0; i < rows.size(); ++i) {
    AddScaled(model, rows[i].a, T(-kkt->lambda[i]), force);
    AddScaled(model, rows[i].b, T(-kkt->lambda[i]), force);
  }
  ApplyInverseMass(model, inverse_mass, *force, a);
  return true;
}

template <typename T>
bool SolveKkt(const Model<T>& model, const VecX<T>& v, Workspace<T>* ws, VecX<T>* a) {
  if (const std::optional<bool> recorded = RecordedKktAcceleration(model, v, ws, a)) return *recorded;
  const bool solved = KktAcceleration(model, ws->layout, *ws->pattern, ws->solver, ws->rows, ws->inverse_mass, v,
                                      ws->alpha, ws->beta, &ws->force, &ws->kkt, a);
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
