// Time integration of the first-order system q' = N(q) v, v' = a(t, q, v) (a from constrained_dynamics.h), on
// the configuration space of configuration_space.h ((+): Integrate):
//
//   euler             q_{n+1} = q_n (+) h v_n,            v_{n+1} = v_n + h a(t_n, q_n, v_n)
//   symplectic_euler  v_{n+1} = v_n + h a(t_n, q_n, v_n), q_{n+1} = q_n (+) h v_{n+1}
//   rk4, rk45         Runge-Kutta-Munthe-Kaas: with the method's tableau (a, b, c), the stages are
//                       theta_i = h sum_j a_ij K_j,  q_i = q_n (+) theta_i,  v_i = v_n + h sum_j a_ij A_j,
//                       A_i = a(t_n + c_i h, q_i, v_i),  K_i = DexpInv(theta_i, v_i),
//                     and q_{n+1} = q_n (+) h sum_i b_i K_i, v_{n+1} = v_n + h sum_i b_i A_i: the method applied
//                     to the vector-space system (theta, v), so it keeps its order on rotations (Munthe-Kaas
//                     1998). On translations and planar angles K_i = v_i and this is the classical method.
//   rk4               the classical four-stage tableau
//   rk45              Dormand-Prince 5(4) with local error control: a step is accepted when the RMS over
//                     components of e_i / (tol (1 + max(|y_i|, |y_new_i|))) is at most 1 (the error of the
//                     configuration taken in the tangent space, sum_i e_i K_i, with |y_i| = 1 for a 3D body's
//                     rotation), and the next step is
//                     h * min(5, max(0.2, 0.9 err^(-1/5))). Internal steps never cross an output step, so the
//                     output lies on the grid t_k = k h. The error control looks at values only: with Jets the
//                     derivatives are those of the accepted steps. With the projection stabilization the
//                     error (e_q, e_v) is first projected onto the tangent space at the new state,
//                     e <- e - M^-1 J^T S^-1 J e, because the projection after the step removes the normal
//                     part: only the tangential part stays in the solution. Near a singular configuration the
//                     normal part is large (stage states off the constraints carry drift C into motion of
//                     order C / sigma); controlling it would shrink the steps until the stages sit on the
//                     singularity, and each of the many projections there costs energy (docs/numerics.md).
// The stable range of h * omega for the Baumgarte error dynamics depends on the method (default_gains.h).
//
// After every step that an integrator takes (for rk45: every accepted internal step), `settle` may move the
// state back onto the constraints (the projection stabilization, or the guard near singular configurations in
// simulator.cc); it returns whether it changed the state.
//
// A run's integrator owns its state (TimeIntegrator: the stages and, for rk45, the step-size controller); what
// the rest of tether knows of a method (order, stages, stability) is its descriptor (integrator_descriptor.h).
#pragma once

#include <array>
#include <functional>

#include "tether/dynamics/integration/integrator_descriptor.h"
#include "tether/dynamics/solvers/workspace.h"

namespace tether {

enum class StepStatus { kOk, kSolveFailed, kStepSizeUnderflow };

template <typename T>
using SettleState = std::function<bool(double t, VecX<T>* q, VecX<T>* v)>;

// What an integrator carries from one step of a run to the next (a checkpoint's part of it, stepper.h): rk45's
// next internal step (0: not started). Plain data, the same for every scalar. (rk45's first stage carries over
// only between the internal steps of one step: each step starts afresh.)
struct IntegratorMemory {
  double step = 0.0;
};

// The stages and trial states of a step (v-shaped: Munthe-Kaas stage derivatives K and accelerations) and rk45's
// controller.
template <typename T>
struct IntegratorScratch {
  explicit IntegratorScratch(const Model<T>& model);
  std::array<VecX<T>, 7> stage_q, stage_v;
  VecX<T> theta;  // a stage's increment h sum a_ij K_j (size nv)
  VecX<T> trial_q, trial_v, next_q, next_v;
  VecX<T> error_q, error_v;             // rk45's local error estimate (size nv each)
  double rk45_step = 0.0;               // rk45's current internal step (0: not started)
  bool rk45_first_stage_valid = false;  // first-same-as-last: stage 0 holds f at the current state
};

// The model's integrator with its state, for one run.
template <typename T>
class TimeIntegrator {
 public:
  explicit TimeIntegrator(const Model<T>& model);

  // Advances (q, v) from t to t + h; `settle` may be empty.
  StepStatus Advance(double t, double h, Workspace<T>* ws, VecX<T>* q, VecX<T>* v, const SettleState<T>& settle = {});

  IntegratorMemory memory() const { return {scratch_.rk45_step}; }
  void Restore(const IntegratorMemory& memory) { scratch_.rk45_step = memory.step; }

  using Method = StepStatus (*)(const Model<T>&, double, double, Workspace<T>*, IntegratorScratch<T>*, VecX<T>*,
                                VecX<T>*, const SettleState<T>&);

 private:
  const Model<T>& model_;
  Method method_;  // the model's, chosen once
  IntegratorScratch<T> scratch_;
};

}  // namespace tether
