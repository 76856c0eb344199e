#include "tether/dynamics/integration/integrators.h"

#include <algorithm>
#include <cmath>

#include "tether/dynamics/integration/projection.h"
#include "tether/dynamics/model/configuration_space.h"
#include "tether/dynamics/model/elementwise.h"
#include "tether/dynamics/solvers/constrained_dynamics.h"

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
StepStatus Euler(const Model<T>& model, double t, double h, Workspace<T>* ws, IntegratorScratch<T>* s, VecX<T>* q,
                 VecX<T>* v) {
  VecX<T>& a = s->stage_v[0];
  if (!ComputeAcceleration(model, t, *q, *v, ws, &a)) return StepStatus::kSolveFailed;
  Integrate(model, *q, *v, h, &s->next_q);
  q->swap(s->next_q);
  Elementwise(v, AddScaledBy{h}, *v, a);
  return StepStatus::kOk;
}

template <typename T>
StepStatus SymplecticEuler(const Model<T>& model, double t, double h, Workspace<T>* ws, IntegratorScratch<T>* s,
                           VecX<T>* q, VecX<T>* v) {
  VecX<T>& a = s->stage_v[0];
  if (!ComputeAcceleration(model, t, *q, *v, ws, &a)) return StepStatus::kSolveFailed;
  Elementwise(v, AddScaledBy{h}, *v, a);
  Integrate(model, *q, *v, h, &s->next_q);
  q->swap(s->next_q);
  return StepStatus::kOk;
}

// A Munthe-Kaas stage at the state s->trial_q = q (+) theta, s->trial_v: its acceleration into *a and its stage
// derivative DexpInv(theta, v_stage) into *k (without 3D bodies K_i is v_i, and s->theta is not read).
template <typename T>
bool StageAt(const Model<T>& model, double t, Workspace<T>* ws, IntegratorScratch<T>* s, VecX<T>* k, VecX<T>* a) {
  if (!ComputeAcceleration(model, t, s->trial_q, s->trial_v, ws, a)) return false;
  if (model.spatial_bodies.empty()) {
    *k = s->trial_v;
  } else {
    DexpInv(model, s->theta, s->trial_v, k);
  }
  return true;
}

// The same from q and the increment s->theta.
template <typename T>
bool Stage(const Model<T>& model, double t, const VecX<T>& q, Workspace<T>* ws, IntegratorScratch<T>* s, VecX<T>* k,
           VecX<T>* a) {
  Integrate(model, q, s->theta, 1.0, &s->trial_q);
  return StageAt(model, t, ws, s, k, a);
}

template <typename T>
StepStatus Rk4(const Model<T>& model, double t, double h, Workspace<T>* ws, IntegratorScratch<T>* s, VecX<T>* q,
               VecX<T>* v) {
  auto& kq = s->stage_q;
  auto& kv = s->stage_v;
  const double c[4] = {0.0, 0.5, 0.5, 1.0};
  const bool spatial = !model.spatial_bodies.empty();
  // the first stage at (q, v) itself: theta_1 = 0, where DexpInv(0, v) is v
  if (!ComputeAcceleration(model, t, *q, *v, ws, &kv[0])) return StepStatus::kSolveFailed;
  kq[0] = *v;
  for (int st = 1; st < 4; ++st) {  // theta_s = c_s h K_{s-1}: q (+) theta_s is Integrate(q, K_{s-1}, c_s h)
    Integrate(model, *q, kq[st - 1], c[st] * h, &s->trial_q);
    Elementwise(&s->trial_v, AddScaledBy{c[st] * h}, *v, kv[st - 1]);
    if (spatial)
      Elementwise(
          &s->theta, [ch = c[st] * h](const auto& k) { return ch * k; }, kq[st - 1]);
    if (!StageAt(model, t + c[st] * h, ws, s, &kq[st], &kv[st])) return StepStatus::kSolveFailed;
  }
  const double sixth = h / 6.0;
  const auto increment = [sixth](const auto& k0, const auto& k1, const auto& k2, const auto& k3) {
    return sixth * (k0 + 2.0 * k1 + 2.0 * k2 + k3);
  };
  Elementwise(&s->theta, increment, kq[0], kq[1], kq[2], kq[3]);
  Integrate(model, *q, s->theta, 1.0, &s->next_q);
  q->swap(s->next_q);
  const auto step = [&increment](const auto& x, const auto& k0, const auto& k1, const auto& k2, const auto& k3) {
    return x + increment(k0, k1, k2, k3);
  };
  Elementwise(v, step, *v, kv[0], kv[1], kv[2], kv[3]);
  return StepStatus::kOk;
}

// Dormand-Prince 5(4) tableau; the last row of A is the fifth-order solution (first same as last).
constexpr double kC[7] = {0.0, 1.0 / 5, 3.0 / 10, 4.0 / 5, 8.0 / 9, 1.0, 1.0};
constexpr double kA[7][6] = {{0, 0, 0, 0, 0, 0},
                             {1.0 / 5, 0, 0, 0, 0, 0},
                             {3.0 / 40, 9.0 / 40, 0, 0, 0, 0},
                             {44.0 / 45, -56.0 / 15, 32.0 / 9, 0, 0, 0},
                             {19372.0 / 6561, -25360.0 / 2187, 64448.0 / 6561, -212.0 / 729, 0, 0},
                             {9017.0 / 3168, -355.0 / 33, 46732.0 / 5247, 49.0 / 176, -5103.0 / 18656, 0},
                             {35.0 / 384, 0, 500.0 / 1113, 125.0 / 192, -2187.0 / 6784, 11.0 / 84}};
// fifth-order minus fourth-order weights: the local error estimate
constexpr double kE[7] = {71.0 / 57600, 0, -71.0 / 16695, 71.0 / 1920, -17253.0 / 339200, 22.0 / 525, -1.0 / 40};

// The size of each velocity component's configuration for rk45's error scale: |q_i| for translations and planar
// angles (their q_i), 1 for a 3D body's rotation (a unit quaternion).
template <typename T>
double ConfigurationScale(const VecX<T>& q, const Body<T>& body, int k) {
  if (body.kind == BodyKind::kRigid3d && k >= 3) return 1.0;
  return std::abs(Value(q[body.q_offset + k]));
}

// One Dormand-Prince trial step of size h from (q, v); the result is left in s->next_q/next_v and the
// scaled error norm is returned (infinity when a stage or the error's projection failed).
template <typename T>
double DormandPrinceTrial(const Model<T>& model, double t, double h, double tolerance, const VecX<T>& q,
                          const VecX<T>& v, Workspace<T>* ws, IntegratorScratch<T>* s) {
  auto& kq = s->stage_q;
  auto& kv = s->stage_v;
  if (!s->rk45_first_stage_valid) {
    kq[0] = v;
    if (!ComputeAcceleration(model, t, q, v, ws, &kv[0])) return INFINITY;
    s->rk45_first_stage_valid = true;
  }
  for (int st = 1; st < 7; ++st) {
    s->theta.setZero();
    s->trial_v = v;
    for (int j = 0; j < st; ++j) {
      if (kA[st][j] == 0.0) continue;
      Elementwise(&s->theta, AddScaledBy{h * kA[st][j]}, s->theta, kq[j]);
      Elementwise(&s->trial_v, AddScaledBy{h * kA[st][j]}, s->trial_v, kv[j]);
    }
    if (!Stage(model, t + kC[st] * h, q, ws, s, &kq[st], &kv[st])) return INFINITY;
  }
  s->next_q = s->trial_q;  // stage 6 is evaluated at the fifth-order solution
  s->next_v = s->trial_v;
  VecX<T>& error_q = s->error_q;
  VecX<T>& error_v = s->error_v;
  error_q.setZero();
  error_v.setZero();
  for (int st = 0; st < 7; ++st) {
    error_q += kE[st] * kq[st];
    error_v += kE[st] * kv[st];
  }
  if (model.stabilization.method == Stabilization::kProjection) {
    // the projection after the step removes the error's part normal to the constraints: control the rest
    if (!ProjectVelocities(model, s->next_q, ws, &error_q) || !ProjectVelocities(model, s->next_q, ws, &error_v)) {
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
          tolerance * (1.0 + std::max(ConfigurationScale(q, body, k), ConfigurationScale(s->next_q, body, k)));
      const double scale_v = tolerance * (1.0 + std::max(std::abs(Value(v[i])), std::abs(Value(s->next_v[i]))));
      sum += (h * eq / scale_q) * (h * eq / scale_q) + (h * ev / scale_v) * (h * ev / scale_v);
    }
  }
  const double norm = std::sqrt(sum / (2.0 * n));
  return std::isfinite(norm) ? norm : INFINITY;
}

template <typename T>
StepStatus Rk45(const Model<T>& model, double t, double h, Workspace<T>* ws, IntegratorScratch<T>* s, VecX<T>* q,
                VecX<T>* v, const SettleState<T>& settle) {
  const double tolerance = model.simulation.tolerance;
  const double t_end = t + h;
  const double smallest = 1e-12 * h;
  if (s->rk45_step <= 0.0) s->rk45_step = h;
  s->rk45_first_stage_valid = false;  // the state may have been changed (projection) since the last step
  while (t_end - t > smallest) {
    const double remaining = t_end - t;
    const double trial = std::min(s->rk45_step, remaining);
    const double error = DormandPrinceTrial(model, t, trial, tolerance, *q, *v, ws, s);
    const double factor = error == 0.0 ? 5.0 : std::min(5.0, std::max(0.2, 0.9 * std::pow(error, -0.2)));
    if (error <= 1.0) {
      t += trial;
      q->swap(s->next_q);
      v->swap(s->next_v);
      std::swap(s->stage_v[0], s->stage_v[6]);  // first same as last: the acceleration at the new state,
      s->stage_q[0] = *v;                       // and the stage derivative there (theta = 0)
      if (settle && settle(t, q, v)) s->rk45_first_stage_valid = false;
      // a step cut short to land on the grid says nothing about the next one
      if (trial == s->rk45_step || factor < 1.0) s->rk45_step = trial * factor;
    } else {
      s->rk45_step = trial * (std::isfinite(error) ? factor : 0.2);
      if (!std::isfinite(error)) s->rk45_first_stage_valid = false;
      if (s->rk45_step < smallest) return StepStatus::kStepSizeUnderflow;
    }
  }
  return StepStatus::kOk;
}

// A method of one step per call, then settled.
template <typename T,
          StepStatus (*Step)(const Model<T>&, double, double, Workspace<T>*, IntegratorScratch<T>*, VecX<T>*, VecX<T>*)>
StepStatus SettledStep(const Model<T>& model, double t, double h, Workspace<T>* ws, IntegratorScratch<T>* s, VecX<T>* q,
                       VecX<T>* v, const SettleState<T>& settle) {
  const StepStatus status = Step(model, t, h, ws, s, q, v);
  if (status == StepStatus::kOk && settle) settle(t + h, q, v);
  return status;
}

template <typename T>
typename TimeIntegrator<T>::Method MethodOf(Integrator integrator) {
  switch (integrator) {
    case Integrator::kEuler:
      return SettledStep<T, Euler<T>>;
    case Integrator::kSymplecticEuler:
      return SettledStep<T, SymplecticEuler<T>>;
    case Integrator::kRk4:
      return SettledStep<T, Rk4<T>>;
    case Integrator::kRk45:
      return Rk45<T>;  // settles after each of its internal steps
  }
  return SettledStep<T, Euler<T>>;  // unreachable: every Integrator is listed
}

}  // namespace

template <typename T>
IntegratorScratch<T>::IntegratorScratch(const Model<T>& model) {
  const int nq = model.NumCoordinates(), nv = model.NumVelocities();
  for (int k = 0; k < 7; ++k) {
    stage_q[k].setZero(nv);
    stage_v[k].setZero(nv);
  }
  theta.setZero(nv);
  trial_q.setZero(nq);
  trial_v.setZero(nv);
  next_q.setZero(nq);
  next_v.setZero(nv);
  error_q.setZero(nv);
  error_v.setZero(nv);
}

template <typename T>
TimeIntegrator<T>::TimeIntegrator(const Model<T>& model)
    : model_(model), method_(MethodOf<T>(model.simulation.integrator)), scratch_(model) {}

template <typename T>
StepStatus TimeIntegrator<T>::Advance(double t, double h, Workspace<T>* ws, VecX<T>* q, VecX<T>* v,
                                      const SettleState<T>& settle) {
  return method_(model_, t, h, ws, &scratch_, q, v, settle);
}

#define TETHER_INSTANTIATE_INTEGRATORS(T) \
  template struct IntegratorScratch<T>;   \
  template class TimeIntegrator<T>;
TETHER_FOR_EACH_SCALAR(TETHER_INSTANTIATE_INTEGRATORS)

}  // namespace tether
