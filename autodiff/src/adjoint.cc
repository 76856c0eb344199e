#include "tether/autodiff/adjoint.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "tether/dynamics/model/errors.h"

namespace tether {
namespace {

// The states of a run in double (checkpoints, a segment) and the recorded replay's.
using PlainCarry = Stepper<double>::Carry;
using RecordedCarry = Stepper<Rev>::Carry;

// A state of the double run as recorded inputs of a replay (into *carry, whose buffers serve again).
void RecordInputs(Tape* tape, const PlainCarry& plain, RecordedCarry* carry) {
  carry->q.resize(plain.q.size());
  carry->v.resize(plain.v.size());
  for (int i = 0; i < plain.q.size(); ++i) carry->q[i] = tape->Variable(plain.q[i]);
  for (int i = 0; i < plain.v.size(); ++i) carry->v[i] = tape->Variable(plain.v[i]);
  carry->memory = plain.memory;
}

void AddAdjoints(Tape* tape, const State<Rev>& state, const Eigen::VectorXd& q_bar, const Eigen::VectorXd& v_bar) {
  for (int i = 0; i < state.q.size(); ++i) tape->AddAdjoint(state.q[i], q_bar[i]);
  for (int i = 0; i < state.v.size(); ++i) tape->AddAdjoint(state.v[i], v_bar[i]);
}

void ReadAdjoints(const Tape& tape, const RecordedCarry& carry, Eigen::VectorXd* q_bar, Eigen::VectorXd* v_bar) {
  for (int i = 0; i < carry.q.size(); ++i) (*q_bar)[i] = tape.Adjoint(carry.q[i]);
  for (int i = 0; i < carry.v.size(); ++i) (*v_bar)[i] = tape.Adjoint(carry.v[i]);
}

// What one kept state takes: the carry, its vectors' values and their heap blocks (glibc's chunk headers).
std::int64_t StateBytes(const PlainCarry& carry) {
  constexpr std::int64_t kHeapBlock = 16;
  const std::int64_t values = carry.q.size() + carry.v.size();
  return static_cast<std::int64_t>(sizeof(PlainCarry)) + values * static_cast<std::int64_t>(sizeof(double)) +
         carry.memory.HeapBytes() + 4 * kHeapBlock;
}

}  // namespace

std::int64_t CheckpointInterval(std::int64_t steps, std::int64_t state_bytes, std::int64_t budget_bytes) {
  const std::int64_t states = budget_bytes / std::max<std::int64_t>(state_bytes, 1);
  if (steps <= states) return 1;
  const auto kept = [steps](std::int64_t k) { return (steps + k - 1) / k + k; };  // checkpoints and a segment
  const auto root = static_cast<std::int64_t>(std::ceil(std::sqrt(static_cast<double>(steps))));
  if (kept(root) > states) return root;
  // the smallest K with N / K + K <= states (the root of K^2 - states K + N), then rounding settled exactly
  const double s = static_cast<double>(states), n = static_cast<double>(steps);
  std::int64_t k = std::max<std::int64_t>(1, static_cast<std::int64_t>((s - std::sqrt(s * s - 4.0 * n)) / 2.0));
  while (k > 1 && kept(k - 1) <= states) --k;
  while (kept(k) > states) ++k;
  return k;
}

LossGradient AdjointGradient(const Model<double>& given, const ParameterSet& parameters, const RunOptions& options,
                             const SampleLoss& loss, std::int64_t interval, AdjointReport* report) {
  Model<double> tied;  // the model with its tied fields set from the others, where there are ties
  if (parameters.tied()) {
    tied = given;
    parameters.ApplyTies(&tied);
  }
  const Model<double>& model = parameters.tied() ? tied : given;
  // the recorded run, whose parameters are the tape's inputs: its construction and start (the initial state
  // and its loss) are the prefix, swept last
  Tape tape;
  std::vector<Rev> inputs;
  const Model<Rev> recorded_model = parameters.Recorded(model, &tape, &inputs);
  Rev recorded_loss(0.0);
  Stepper<Rev> recorded(recorded_model, options, [&](const Sample<Rev>& s) {
    if (s.stop >= 0) recorded_loss += loss.recorded(recorded_model, s);
  });
  recorded.Start();
  const Rev start_loss = recorded_loss;
  const State<Rev> start = recorded.state();
  const int prefix = tape.size();

  // forward, in double: the loss, and a checkpoint every `interval` steps
  LossGradient result;
  bool forward = true;  // the segments run again backwards do not add to the loss
  Stepper<double> plain(model, options, [&](const Sample<double>& s) {
    if (forward && s.stop >= 0) result.loss += loss.plain(model, s);
  });
  plain.Start();
  const int nq = model.NumCoordinates(), nv = model.NumVelocities();
  RecordedCarry in;
  // the budget holds the record of a step too: the first step's, recorded once to measure it (a later step's
  // may differ: an impact, more projection iterations), twice over for the tape's growth
  RecordInputs(&tape, plain.Save(), &in);
  recorded.Restore(in);
  recorded.Step();
  const std::int64_t record_reserve = 2 * tape.Bytes();
  tape.Rewind(prefix);
  const std::int64_t state_bytes = StateBytes(plain.Save());
  const std::int64_t planned = StepCount(model.simulation) + static_cast<std::int64_t>(options.stops.size());
  const std::int64_t budget = kAdjointMemoryBudget - record_reserve;
  const std::int64_t k = interval > 0 ? interval : CheckpointInterval(planned, state_bytes, budget);
  const std::int64_t least = ((planned + k - 1) / k + (k > 1 ? k : 0)) * state_bytes + record_reserve;
  if (interval == 0 && least > kAdjointMemoryBudget) {
    throw InputError("the adjoint cannot hold this run in its " + std::to_string(kAdjointMemoryBudget >> 20) +
                     " MiB: " + std::to_string(planned) + " steps of states of " + std::to_string(state_bytes) +
                     " bytes and a step's record of " + std::to_string(record_reserve / 2) + " bytes need " +
                     std::to_string((least + (1 << 20) - 1) >> 20) +
                     " MiB even with the fewest checkpoints; use --method jet, or fewer steps");
  }
  std::vector<PlainCarry> checkpoints;
  checkpoints.reserve(static_cast<size_t>(planned / k + 2));
  // the KKT solves of the steps whose states are kept (all when K = 1, else a segment's), while they fit in what
  // the states leave of the budget; the replay takes them instead of solving again
  const std::int64_t solve_budget = budget - ((planned + k - 1) / k + (k > 1 ? k : 0)) * state_bytes;
  std::vector<KktLog> logs;  // K = 1: the first steps', one each, as long as they fit; K > 1: a segment's
  std::int64_t solve_bytes = 0, largest_solve_bytes = 0;
  const auto step_keeping_solves = [&](KktLog* log) {  // one double step, its solves kept in *log if they fit
    log->Clear();
    plain.set_kkt_log(log);
    plain.Step();
    const std::int64_t bytes = log->Bytes();
    if (solve_bytes + bytes > solve_budget) {
      log->Clear();  // its replay solves again
      return false;
    }
    solve_bytes += bytes;
    largest_solve_bytes = std::max(largest_solve_bytes, solve_bytes);
    return true;
  };
  std::int64_t steps = 0;
  bool keeping = k == 1;
  for (; !plain.done(); ++steps) {
    if (steps % k == 0) checkpoints.push_back(plain.Save());
    if (keeping) {
      keeping = step_keeping_solves(&logs.emplace_back());
      if (!keeping) logs.pop_back();
    } else {
      plain.set_kkt_log(nullptr);
      plain.Step();
    }
  }
  plain.set_kkt_log(nullptr);
  forward = false;
  std::int64_t largest_record = prefix, largest_tape_bytes = tape.Bytes();

  // backward, segment by segment: run the segment again keeping the states its steps start from, then replay
  // its steps recorded, in reverse, each swept back at once
  Eigen::VectorXd q_bar = Eigen::VectorXd::Zero(nq), v_bar = Eigen::VectorXd::Zero(nv);
  std::vector<PlainCarry> segment;  // the states after a checkpoint that the segment's steps start from
  segment.reserve(static_cast<size_t>(k));
  for (std::int64_t c = static_cast<std::int64_t>(checkpoints.size()) - 1; c >= 0; --c) {
    const std::int64_t count = std::min(k, steps - c * k);
    segment.clear();
    if (k > 1) {
      solve_bytes = 0;
      logs.resize(static_cast<size_t>(k));
      for (KktLog& log : logs) log.Clear();
    }
    if (count > 1) plain.Restore(checkpoints[c]);
    for (std::int64_t n = 1; n < count; ++n) {  // the segment's last step is replayed solving its own KKT systems
      step_keeping_solves(&logs[n - 1]);
      segment.push_back(plain.Save());
    }
    plain.set_kkt_log(nullptr);
    for (std::int64_t n = count - 1; n >= 0; --n) {
      RecordInputs(&tape, n == 0 ? checkpoints[c] : segment[n - 1], &in);
      recorded.Restore(in);
      recorded_loss = Rev(0.0);
      const std::int64_t step = c * k + n;
      KktLog* log = k > 1 ? &logs[n] : step < static_cast<std::int64_t>(logs.size()) ? &logs[step] : nullptr;
      recorded.set_kkt_log(log);
      recorded.Step();
      if (log && log->taken != log->kept) {
        throw std::logic_error("the adjoint's replay of step " + std::to_string(step) +
                               " made other KKT solves than the double run");
      }
      largest_record = std::max<std::int64_t>(largest_record, tape.size() - prefix);
      largest_tape_bytes = std::max(largest_tape_bytes, tape.Bytes());
      tape.AddAdjoint(recorded_loss, 1.0);
      AddAdjoints(&tape, recorded.state(), q_bar, v_bar);
      tape.Backward(prefix);
      ReadAdjoints(tape, in, &q_bar, &v_bar);
      tape.Rewind(prefix);
    }
  }
  AddAdjoints(&tape, start, q_bar, v_bar);
  tape.AddAdjoint(start_loss, 1.0);
  tape.Backward(0);
  for (const Rev& input : inputs) result.gradient.push_back(tape.Adjoint(input));

  if (report) {
    report->steps = steps;
    report->interval = k;
    report->checkpoints = static_cast<std::int64_t>(checkpoints.size());
    report->largest_record = largest_record;
    report->kkt_solve_bytes = largest_solve_bytes;
    report->memory_bytes =
        (report->checkpoints + (k > 1 ? k : 0)) * state_bytes + largest_solve_bytes + largest_tape_bytes;
  }
  return result;
}

LossGradient AdjointLossGradient(const Model<double>& model, const ParameterSet& parameters,
                                 const Observations& observations, std::int64_t interval, AdjointReport* report) {
  RunOptions options;
  options.every = INT_MAX;  // no output rows are needed, only the stops
  options.stops = observations.times;
  options.energy = ObservesEnergy(observations);
  const auto loss = [&observations](const auto& m, const auto& s) {
    using T = std::decay_t<decltype(s.energy)>;
    T sum(0.0);
    ObservedResiduals(m, observations, s.stop, s, [&sum](size_t, const T& r) { sum += 0.5 * r * r; });
    return sum;
  };
  return AdjointGradient(model, parameters, options, {loss, loss}, interval, report);
}

}  // namespace tether
