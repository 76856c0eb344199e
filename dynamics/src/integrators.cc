#include "tether/dynamics/integrators.h"

#include <algorithm>
#include <cmath>

#include "tether/dynamics/configuration_space.h"
#include "tether/dynamics/constrained_dynamics.h"
#include "tether/dynamics/elementwise.h"
#include "tether/dynamics/projection.h"

namespace tether {
namespace {

// x + c y, for Elementwise
struct AddScaledBy {
  double c;
  template <typename T>
  T operator()(const T& x, const T& y) const {
    return x + c * y;
  }
};

template <typename T>
StepStatus Euler(const Model<T>& model, double t, double h, Workspace<T>* ws, VecX<T>* q, VecX<T>* v) {
  VecX<T>& a = ws->stage_v[0];
  if (!ComputeAcceleration(model, t, *q, *v, ws, &a)) return StepStatus::kSolveFailed;
  Integrate(model, *q, *v, h, &ws->next_q);
  q->swap(ws->next_q);
  Elementwise(v, AddScaledBy{h}, *v, a);
  return StepStatus::kOk;
}

template <typename T>
StepStatus SymplecticEuler(const Model<T>& model, double t, double h, Workspace<T>* ws, VecX<T>* q, VecX<T>* v) {
  VecX<T>& a = ws->stage_v[0];
  if (!ComputeAcceleration(model, t, *q, *v, ws, &a)) return StepStatus::kSolveFailed;
  Elementwise(v, AddScaledBy{h}, *v, a);
  Integrate(model, *q, *v, h, &ws->next_q);
  q->swap(ws->next_q);
  return StepStatus::kOk;
}

// A Munthe-Kaas stage at the state ws->trial_q = q (+) theta, ws->trial_v: its acceleration into *a and its stage
// derivative DexpInv(theta, v_stage) into *k (without 3D bodies K_i is v_i, and ws->theta is not read).
template <typename T>
bool StageAt(const Model<T>& model, double t, Workspace<T>* ws, VecX<T>* k, VecX<T>* a) {
  if (!ComputeAcceleration(model, t, ws->trial_q, ws->trial_v, ws, a)) return false;
  if (model.spatial_bodies.empty()) {
    *k = ws->trial_v;
  } else {
    DexpInv(model, ws->theta, ws->trial_v, k);
  }
  return true;
}

// The same from q and the increment ws->theta.
template <typename T>
bool Stage(const Model<T>& model, double t, const VecX<T>& q, Workspace<T>* ws, VecX<T>* k, VecX<T>* a) {
  Integrate(model, q, ws->theta, 1.0, &ws->trial_q);
  return StageAt(model, t, ws, k, a);
}

template <typename T>
StepStatus Rk4(const Model<T>& model, double t, double h, Workspace<T>* ws, VecX<T>* q, VecX<T>* v) {
  auto& kq = ws->stage_q;
  auto& kv = ws->stage_v;
  const double c[4] = {0.0, 0.5, 0.5, 1.0};
  const bool spatial = !model.spatial_bodies.empty();
  for (int s = 0; s < 4; ++s) {  // theta_s = c_s h K_{s-1}: q (+) theta_s is Integrate(q, K_{s-1}, c_s h)
    if (s == 0) {
      ws->trial_q = *q;
      ws->trial_v = *v;
      if (spatial) ws->theta.setZero();
    } else {
      Integrate(model, *q, kq[s - 1], c[s] * h, &ws->trial_q);
      Elementwise(&ws->trial_v, AddScaledBy{c[s] * h}, *v, kv[s - 1]);
      if (spatial) Elementwise(&ws->theta, [ch = c[s] * h](const auto& k) { return ch * k; }, kq[s - 1]);
    }
    if (!StageAt(model, t + c[s] * h, ws, &kq[s], &kv[s])) return StepStatus::kSolveFailed;
  }
  const double sixth = h / 6.0;
  const auto increment = [sixth](const auto& k0, const auto& k1, const auto& k2, const auto& k3) {
    return sixth * (k0 + 2.0 * k1 + 2.0 * k2 + k3);
  };
  Elementwise(&ws->theta, increment, kq[0], kq[1], kq[2], kq[3]);
  Integrate(model, *q, ws->theta, 1.0, &ws->next_q);
  q->swap(ws->next_q);
  const auto step = [&increment](const auto& x, const auto& k0, const auto& k1, const auto& k2, const auto& k3) {
    return x + increment(k0, k1, k2, k3);
  };
  Elementwise(v, step, *v, kv[0], kv[1], kv[2], kv[3]);
  return StepStatus::kOk;
}

// Dormand-Prince 5(4) tableau; the last row of A is the fifth-order solution (first same as last).
constexpr double kC[7] = {0.0, 1.0 / 5, 3.0 / 10, 4.0 / 5, 8.0 / 9, 1.0, 1.0};
constexpr double kA[7][6] = {
    {0, 0, 0, 0, 0, 0},
    {1.0 / 5, 0, 0, 0, 0, 0},
    {3.0 / 40, 9.0 / 40, 0, 0, 0, 0},
    {44.0 / 45, -56.0 / 15, 32.0 / 9, 0, 0, 0},
    {19372.0 / 6561, -25360.0 / 2187, 64448.0 / 6561, -212.0 / 729, 0, 0},
    {9017.0 / 3168, -355.0 / 33, 46732.0 / 5247, 49.0 / 176, -5103.0 / 18656, 0},
    {35.0 / 384, 0, 500.0 / 1113, 125.0 / 192, -2187.0 / 6784, 11.0 / 84}};
// fifth-order minus fourth-order weights: the local error estimate
constexpr double kE[7] = {71.0 / 57600,      0, -71.0 / 16695, 71.0 / 1920, -17253.0 / 339200,
                          22.0 / 525, -1.0 / 40};

// The size of each velocity component's configuration for rk45's error scale: |q_i| for translations and planar
// angles (their q_i), 1 for a 3D body's rotation (a unit quaternion).
template <typename T>
double ConfigurationScale(const VecX<T>& q, const Body<T>& body, int k) {
  if (body.kind == BodyKind::kRigid3d && k >= 3) return 1.0;
  return std::abs(Value(q[body.q_offset + k]));
}

// One Dormand-Prince trial step of size h from (q, v); the result is left in ws->next_q/next_v and the
// scaled error norm is returned (infinity when a stage or the error's projection failed).
template <typename T>
double DormandPrinceTrial(const Model<T>& model, double t, double h, double tolerance, const VecX<T>& q,
                          const VecX<T>& v, Workspace<T>* ws) {
  auto& kq = ws->stage_q;
  auto& kv = ws->stage_v;
  if (!ws->rk45_first_stage_valid) {
    kq[0] = v;
    if (!ComputeAcceleration(model, t, q, v, ws, &kv[0])) return INFINITY;
    ws->rk45_first_stage_valid = true;
  }
  for (int s = 1; s < 7; ++s) {
    ws->theta.setZero();
    ws->trial_v = v;
    for (int j = 0; j < s; ++j) {
      if (kA[s][j] == 0.0) continue;
      Elementwise(&ws->theta, AddScaledBy{h * kA[s][j]}, ws->theta, kq[j]);
      Elementwise(&ws->trial_v, AddScaledBy{h * kA[s][j]}, ws->trial_v, kv[j]);
    }
    if (!Stage(model, t + kC[s] * h, q, ws, &kq[s], &kv[s])) return INFINITY;
  }
  ws->next_q = ws->trial_q;  // stage 6 is evaluated at the fifth-order solution
  ws->next_v = ws->trial_v;
  VecX<T>& error_q = ws->error_q;
  VecX<T>& error_v = ws->error_v;
  error_q.setZero();
  error_v.setZero();
  for (int s = 0; s < 7; ++s) {
    error_q += kE[s] * kq[s];
    error_v += kE[s] * kv[s];
  }
  if (model.stabilization.method == Stabilization::kProjection) {
    // the projection after the step removes the error's part normal to the constraints: control the rest
    if (!ProjectVelocities(model, ws->next_q, ws, &error_q) || !ProjectVelocities(model, ws->next_q, ws, &error_v)) {
      return INFINITY;
    }
  }
  double sum = 0.0;
  const int n = static_cast<int>(v.size());
  for (const Body<T>& body : model.bodies) {
    for (int k = 0; k < body.v_size; ++k) {
      const int i = body.v_offset + k;
      const double eq = Value(error_q[i]), ev = Value(error_v[i]);
      const double scale_q =
          tolerance * (1.0 + std::max(ConfigurationScale(q, body, k), ConfigurationScale(ws->next_q, body, k)));
      const double scale_v = tolerance * (1.0 + std::max(std::abs(Value(v[i])), std::abs(Value(ws->next_v[i]))));
      sum += (h * eq / scale_q) * (h * eq / scale_q) + (h * ev / scale_v) * (h * ev / scale_v);
    }
  }
  const double norm = std::sqrt(sum / (2.0 * n));
  return std::isfinite(norm) ? norm : INFINITY;
}

template <typename T>
StepStatus Rk45(const Model<T>& model, double t, double h, Workspace<T>* ws, VecX<T>* q, VecX<T>* v,
                const SettleState<T>& settle) {
  const double tolerance = model.simulation.tolerance;
  const double t_end = t + h;
  const double smallest = 1e-12 * h;
  if (ws->rk45_step <= 0.0) ws->rk45_step = h;
  ws->rk45_first_stage_valid = false;  // the state may have been changed (projection) since the last step
  while (t_end - t > smallest) {
    const double remaining = t_end - t;
    const double trial = std::min(ws->rk45_step, remaining);
    const double error = DormandPrinceTrial(model, t, trial, tolerance, *q, *v, ws);
    const double factor = error == 0.0 ? 5.0 : std::min(5.0, std::max(0.2, 0.9 * std::pow(error, -0.2)));
    if (error <= 1.0) {
      t += trial;
      q->swap(ws->next_q);
      v->swap(ws->next_v);
      std::swap(ws->stage_v[0], ws->stage_v[6]);  // first same as last: the acceleration at the new state,
      ws->stage_q[0] = *v;                        // and the stage derivative there (theta = 0)
      if (settle && settle(t, q, v)) ws->rk45_first_stage_valid = false;
      // a step cut short to land on the grid says nothing about the next one
      if (trial == ws->rk45_step || factor < 1.0) ws->rk45_step = trial * factor;
    } else {
      ws->rk45_step = trial * (std::isfinite(error) ? factor : 0.2);
      if (!std::isfinite(error)) ws->rk45_first_stage_valid = false;
      if (ws->rk45_step < smallest) return StepStatus::kStepSizeUnderflow;
    }
  }
  return StepStatus::kOk;
}

}  // namespace

template <typename T>
StepStatus Advance(const Model<T>& model, double t, double h, Workspace<T>* ws, VecX<T>* q, VecX<T>* v,
                   const SettleState<T>& settle) {
  StepStatus status = StepStatus::kOk;
  switch (model.simulation.integrator) {
    case Integrator::kEuler:
      status = Euler(model, t, h, ws, q, v);
      break;
    case Integrator::kSymplecticEuler:
      status = SymplecticEuler(model, t, h, ws, q, v);
      break;
    case Integrator::kRk4:
      status = Rk4(model, t, h, ws, q, v);
      break;
    case Integrator::kRk45:
      return Rk45(model, t, h, ws, q, v, settle);  // settles after each of its internal steps
  }
  if (status == StepStatus::kOk && settle) settle(t + h, q, v);
  return status;
}

#define TETHER_INSTANTIATE_INTEGRATORS(T) \
  template StepStatus Advance<T>(const Model<T>&, double, double, Workspace<T>*, VecX<T>*, VecX<T>*, \
                                 const SettleState<T>&);
TETHER_FOR_EACH_SCALAR(TETHER_INSTANTIATE_INTEGRATORS)

}  // namespace tether
