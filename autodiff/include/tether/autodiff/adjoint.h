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
// sweeping the record back at once: the derivative of exactly the computation that was run, the KKT solves by one
// more solve with the forward matrix (schur_solver.h), the projection by the derivative of its Gauss-Newton
// iterations (as Jets differentiate them). The run itself is in double; a step is replayed in Rev from the double
// state it started from, and takes the same branches (rk45's accepted steps, where the Schur matrix is regularized,
// a joint angle's branch) because Rev computes the same doubles: they are plain data, not differentiated.
//
// Memory (the simpler rule the issue allows, not Griewank's binomial revolve), for a plan of N steps of states of
// B bytes and a budget of kAdjointMemoryBudget bytes: every state is kept (K = 1) while N states fit; beyond, the
// forward run keeps a checkpoint every K steps, the smallest K for which ceil(N / K) checkpoints and one segment of
// K states fit, and backwards each segment is run again in double from its checkpoint, keeping its states; when
// not even 2 sqrt(N) states fit, K = ceil(sqrt(N)), the fewest. Besides the states, one step's record is held
// (the tape's buffers): the first step is recorded once before the run to measure it, and twice its size is set
// aside from the budget for it (a later step's record can be longer, and the buffers grow by doubling); and the
// KKT solves (multipliers and factorization, kkt_log.h) of the steps whose states are kept, as long as they fit
// in what the states leave: a step replayed with its solves kept does not assemble, factor and solve S again (a
// segment's last step, and the steps past the budget, do). A run whose fewest states and record exceed the
// budget is refused before it starts (InputError). Not counted: the model, the two steppers' workspaces and the
// externals' records, a few states' worth.
// Time: one double run, one more for the segments (none when K = 1), and one recorded replay and sweep per step.
#pragma once

#include <cstdint>
#include <functional>

#include "tether/autodiff/residuals.h"
#include "tether/dynamics/integration/stepper.h"

namespace tether {

struct AdjointReport {
  std::int64_t steps = 0;        // steps of the plan (grid steps and steps onto stop times)
  std::int64_t interval = 0;     // K: steps between checkpoints
  std::int64_t checkpoints = 0;  // states kept by the forward run
  std::int64_t largest_record = 0;  // nodes of the largest record (one step, or the initial state)
  std::int64_t kkt_solve_bytes = 0;  // the KKT solves kept at once (all steps', or a segment's)
  std::int64_t memory_bytes = 0;     // states kept (checkpoints and one segment), solves and the tape's buffers
};

// The loss of one stop sample: in double for the forward run, and in Rev arithmetic for the recorded replay (the
// same function twice, e.g. a generic lambda).
struct SampleLoss {
  std::function<double(const Model<double>&, const Sample<double>&)> plain;
  std::function<Rev(const Model<Rev>&, const Sample<Rev>&)> recorded;
};

// States the adjoint may keep (checkpoints and one segment): every state of a run that fits, else checkpoints.
inline constexpr std::int64_t kAdjointMemoryBudget = std::int64_t{256} << 20;  // 256 MiB

// K, the steps between checkpoints: 1 (every state kept) when all `steps` states fit in the budget, else the
// smallest K whose ceil(steps / K) checkpoints and K segment states fit, else ceil(sqrt(steps)), which keeps
// fewest (2 sqrt(steps)).
std::int64_t CheckpointInterval(std::int64_t steps, std::int64_t state_bytes, std::int64_t budget_bytes);

// The loss sum over the stop samples of a run of `model` with `options`, and its gradient with respect to the
// parameters. `interval` overrides K (0: CheckpointInterval within kAdjointMemoryBudget, less the record's
// share). Throws as Simulate does, and InputError when not even the fewest checkpoints fit.
LossGradient AdjointGradient(const Model<double>& model, const ParameterSet& parameters, const RunOptions& options,
                             const SampleLoss& loss, std::int64_t interval = 0, AdjointReport* report = nullptr);

// The loss against observations (residuals.h) and its gradient, by the adjoint.
LossGradient AdjointLossGradient(const Model<double>& model, const ParameterSet& parameters,
                                 const Observations& observations, std::int64_t interval = 0,
                                 AdjointReport* report = nullptr);

}  // namespace tether
