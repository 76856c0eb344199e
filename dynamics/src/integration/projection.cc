#include "tether/dynamics/integration/projection.h"

#include "tether/dynamics/model/configuration_space.h"

namespace tether {
namespace {

// sum C_i^2 over the rows: the merit of the robust projection
template <typename T>
double SquaredViolation(const std::vector<ConstraintRow<T>>& rows) {
  double sum = 0.0;
  for (const ConstraintRow<T>& row : rows) sum += Value(row.value) * Value(row.value);
  return sum;
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
  const VecX<T>& unused_velocity = ws->force;  // position-only evaluation does not read velocities
  ws->projection_q = *q;                       // the target q_t
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
    Difference(model, ws->projection_q, *q, &ws->reaction);
    MultiplyJacobian(model, ws->reaction, ws);
    for (size_t i = 0; i < ws->rows.size(); ++i) ws->kkt.rhs[i] = ws->rows[i].value - ws->kkt.rhs[i];
    AssembleSchur(ws);
    if (!ws->solver->Solve(ws->kkt.schur, ws->kkt.rhs, &ws->kkt.lambda, SchurSourceOf(*ws))) break;
    ApplyReaction(model, ws, &ws->reaction);
    Integrate(model, ws->projection_q, ws->reaction, -1.0, q);
  }
  return result;
}

template <typename T>
ProjectionResult ProjectPositionsRobustly(const Model<T>& model, double tolerance, Workspace<T>* ws, VecX<T>* q) {
  constexpr int kMaxIterations = 200;
  constexpr double kLargestDamping = 1e12;
  ProjectionResult result;
  // the steps are taken in the unit metric (every mass and moment 1): masses a millionfold apart would make
  // the mass-weighted direction all but ignore the heavy body that has to move
  const InverseMass<T> inverse_mass = ws->inverse_mass;
  for (int i = 0; i < ws->inverse_mass.diagonal.size(); ++i) {
    if (ws->inverse_mass.diagonal[i] != T(0.0)) ws->inverse_mass.diagonal[i] = T(1.0);
  }
  for (Mat3<T>& block : ws->inverse_mass.rotational) {
    if (!block.isZero()) block = Mat3<T>::Identity();
  }
  const VecX<T>& unused_velocity = ws->force;
  EvaluateRows(model, *q, unused_velocity, false, ws);
  double merit = SquaredViolation(ws->rows), damping = 1e-3;
  for (result.iterations = 0; result.iterations < kMaxIterations; ++result.iterations) {
    if (LargestViolation(ws->infos, ws->rows).largest <= tolerance) break;
    // (S + mu diag S) nu = C(q_k), q_{k+1} = q_k (+) (-M^-1 J^T nu): accepted when |C|^2 decreases (mu / 3),
    // else mu * 4 and again from q_k
    AssembleSchur(ws);
    const std::vector<T> schur = ws->kkt.schur;
    const std::vector<ConstraintRow<T>> rows = ws->rows;
    ws->projection_q = *q;
    bool decreased = false;
    while (!decreased && damping <= kLargestDamping) {
      ws->kkt.schur = schur;
      for (int d : ws->pattern->diagonal()) ws->kkt.schur[d] *= T(1.0 + damping);
      for (size_t i = 0; i < rows.size(); ++i) ws->kkt.rhs[i] = rows[i].value;
      ws->rows = rows;
      if (!ws->solver->Solve(ws->kkt.schur, ws->kkt.rhs, &ws->kkt.lambda, SchurSourceOf(*ws))) break;
      ApplyReaction(model, ws, &ws->reaction);
      Integrate(model, ws->projection_q, ws->reaction, -1.0, q);
      EvaluateRows(model, *q, unused_velocity, false, ws);
      const double trial = SquaredViolation(ws->rows);
      decreased = trial < merit;
      if (decreased) {
        merit = trial;
        damping = std::max(damping / 3.0, 1e-12);
      } else {
        damping *= 4.0;
      }
    }
    if (!decreased) {  // no damping helps: stop where it was
      *q = ws->projection_q;
      EvaluateRows(model, *q, unused_velocity, false, ws);
      break;
    }
  }
  ws->inverse_mass = inverse_mass;
  result.violation = LargestViolation(ws->infos, ws->rows);
  result.converged = result.violation.largest <= tolerance;
  return result;
}

template <typename T>
bool ProjectVelocities(const Model<T>& model, const VecX<T>& q, Workspace<T>* ws, VecX<T>* v) {
  if (ws->rows.empty()) return true;
  EvaluateRows(model, q, *v, false, ws);
  MultiplyJacobian(model, *v, ws);
  AssembleSchur(ws);
  if (!ws->solver->Solve(ws->kkt.schur, ws->kkt.rhs, &ws->kkt.lambda, SchurSourceOf(*ws))) return false;
  ApplyReaction(model, ws, &ws->reaction);
  *v -= ws->reaction;
  return true;
}

#define TETHER_INSTANTIATE_PROJECTION(T)                                                                   \
  template ProjectionResult ProjectPositions<T>(const Model<T>&, double, Workspace<T>*, VecX<T>*);         \
  template ProjectionResult ProjectPositionsRobustly<T>(const Model<T>&, double, Workspace<T>*, VecX<T>*); \
  template bool ProjectVelocities<T>(const Model<T>&, const VecX<T>&, Workspace<T>*, VecX<T>*);
TETHER_FOR_EACH_SCALAR(TETHER_INSTANTIATE_PROJECTION)

}  // namespace tether
