// The discrete adjoint: the gradient of a loss accumulated at a run's stop samples with respect to any number
// of parameters, at a cost that does not grow with their number (reverse mode), in memory that does not grow with
// the run as fast as the run (checkpoints).
//
// A run is a sequence of steps x_{n+1} = Phi_n(x_n, p) (stepper.h: one step of the plan, integrator stage,
// KKT solve, stabilization and projection included), started from x_0 = X0(p) (the initial state assembled onto
// the constraints, with the quantities the constraints and joint coordinates fix at the start), with the loss
// L = sum_n l_n(x_n, p) at its stop samples. Its adjoint runs backwards:
//   xbar_N = dl_N/dx_N,   xbar_n = dl_n/dx_n + (dPhi_n/dx_n)^T xbar_{n+1},
//   pbar = sum_n (dl_n/dp + (dPhi_n/dp)^T xbar_{n+1}) + (dX0/dp)^T xbar_0,
// each product with a transposed Jacobian taken by recording that one step in Rev arithmetic (reverse.h) and
// sweeping the record back: the derivative of exactly the computation that was run, the KKT solves by one more
// solve with the forward matrix (schur_solver.h), the projection by the derivative of its Gauss-Newton iterations
// (as Jets differentiate them). Branches (rk45's accepted steps, where the Schur matrix is regularized, a joint
// angle's branch) are plain data: the forward run in Rev arithmetic without records takes them, and a replay from
// a checkpoint takes them again, value for value.
//
// Checkpoints (the simpler rule the issue allows, not Griewank's binomial revolve): with N steps in the plan the
// forward run keeps the state every K = ceil(sqrt(N)) steps; backwards, each segment is run again from its
// checkpoint keeping its K states, then swept step by step. Memory: ceil(N / K) + K states (2 sqrt(N) of them)
// and one step's record; time: about three runs' worth of steps plus the recorded sweeps.
#pragma once

#include <cstdint>
#include <functional>

#include "tether/autodiff/residuals.h"
#include "tether/dynamics/stepper.h"

namespace tether {

struct AdjointReport {
  std::int64_t steps = 0;        // steps of the plan (grid steps and steps onto stop times)
  std::int64_t interval = 0;     // K: steps between checkpoints
  std::int64_t checkpoints = 0;  // states kept by the forward run
  std::int64_t largest_record = 0;  // nodes of the largest record (one step, or the initial state)
  std::int64_t memory_bytes = 0;    // states kept (checkpoints and one segment) and the largest record
};

// The loss of one stop sample, in Rev arithmetic (recorded when the sample is).
using SampleLoss = std::function<Rev(const Model<Rev>&, const Sample<Rev>&)>;

// The loss sum over the stop samples of a run of `model` with `options`, and its gradient with respect to the
// parameters. `interval` overrides K (0: ceil(sqrt(N))). Throws as Simulate does.
LossGradient AdjointGradient(const Model<double>& model, const ParameterSet& parameters, const RunOptions& options,
                             const SampleLoss& loss, std::int64_t interval = 0, AdjointReport* report = nullptr);

// The loss against observations (residuals.h) and its gradient, by the adjoint.
LossGradient AdjointLossGradient(const Model<double>& model, const ParameterSet& parameters,
                                 const Observations& observations, std::int64_t interval = 0,
                                 AdjointReport* report = nullptr);

}  // namespace tether
