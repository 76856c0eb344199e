#include "tether/dynamics/projection.h"

#include "tether/dynamics/configuration_space.h"

namespace tether {
namespace {

// ws->rhs = J x for the rows in ws.
template <typename T>
void MultiplyJacobian(const Model<T>& model, const VecX<T>& x, Workspace<T>* ws) {
  for (size_t i = 0; i < ws->rows.size(); ++i) {
    ws->rhs[i] = Dot(model, ws->rows[i].a, x) + Dot(model, ws->rows[i].b, x);
  }
}

// out = M^-1 J^T ws->lambda.
template <typename T>
void ApplyReaction(const Model<T>& model, Workspace<T>* ws, VecX<T>* out) {
  out->setZero();
  for (size_t i = 0; i < ws->rows.size(); ++i) {
    AddScaled(model, ws->rows[i].a, ws->lambda[i], out);
    AddScaled(model, ws->rows[i].b, ws->lambda[i], out);
  }
  ApplyInverseMass(model, ws->inverse_mass, *out, out);
}


}  // namespace

template <typename T>
ProjectionResult ProjectPositions(const Model<T>& model, double tolerance, Workspace<T>* ws, VecX<T>* q) {
  constexpr int kMaxIterations = 50;
  ProjectionResult result;
  if (ws->rows.empty()) {
    result.converged = true;
    return result;
  }
  const VecX<T>& unused_velocity = ws->trial_v;  // position-only evaluation does not read velocities
  ws->trial_q = *q;                              // the target q_t
  // One more iteration after the values converge lets Jet derivatives settle; doubles take it too, so that the
  // value part of a Jet run stays the double run to round-off (one code path for every scalar).
  int settle = 1;
  for (result.iterations = 0; result.iterations <= kMaxIterations; ++result.iterations) {
    EvaluateRows(model, *q, unused_velocity, false, ws);
    result.violation = LargestViolation(ws->infos, ws->rows);
    if (result.violation.largest <= tolerance) {
      result.converged = true;
      if (settle-- == 0) break;
    }
    if (result.iterations == kMaxIterations) break;
    // S mu = C(q_k) - J d_k with d_k = q_k (-) q_t, then q_{k+1} = q_t (+) (-M^-1 J^T mu)
    Difference(model, ws->trial_q, *q, &ws->reaction);
    MultiplyJacobian(model, ws->reaction, ws);
    for (size_t i = 0; i < ws->rows.size(); ++i) ws->rhs[i] = ws->rows[i].value - ws->rhs[i];
    AssembleSchur(ws);
    if (!ws->solver.Solve(ws->schur, ws->rhs, &ws->lambda)) break;
    ApplyReaction(model, ws, &ws->reaction);
    Integrate(model, ws->trial_q, ws->reaction, -1.0, q);
  }
  return result;
}

template <typename T>
bool ProjectVelocities(const Model<T>& model, const VecX<T>& q, Workspace<T>* ws, VecX<T>* v) {
  if (ws->rows.empty()) return true;
  EvaluateRows(model, q, *v, false, ws);
  MultiplyJacobian(model, *v, ws);
  AssembleSchur(ws);
  if (!ws->solver.Solve(ws->schur, ws->rhs, &ws->lambda)) return false;
  ApplyReaction(model, ws, &ws->reaction);
  *v -= ws->reaction;
  return true;
}

#define TETHER_INSTANTIATE_PROJECTION(T)                                                                  \
  template ProjectionResult ProjectPositions<T>(const Model<T>&, double, Workspace<T>*, VecX<T>*); \
  template bool ProjectVelocities<T>(const Model<T>&, const VecX<T>&, Workspace<T>*, VecX<T>*);
TETHER_FOR_EACH_SCALAR(TETHER_INSTANTIATE_PROJECTION)

}  // namespace tether
