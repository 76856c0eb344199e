#include "tether/autodiff/adjoint.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <vector>

namespace tether {
namespace {

using Carry = Stepper<Rev>::Carry;

// The state's values as fresh recorded inputs.
void RecordInputs(Tape* tape, Carry* carry) {
  for (VecX<Rev>* x : {&carry->q, &carry->v}) {
    for (int i = 0; i < x->size(); ++i) (*x)[i] = tape->Variable((*x)[i].a);
  }
}

void AddAdjoints(Tape* tape, const Carry& carry, const Eigen::VectorXd& q_bar, const Eigen::VectorXd& v_bar) {
  for (int i = 0; i < carry.q.size(); ++i) tape->AddAdjoint(carry.q[i], q_bar[i]);
  for (int i = 0; i < carry.v.size(); ++i) tape->AddAdjoint(carry.v[i], v_bar[i]);
}

void ReadAdjoints(const Tape& tape, const Carry& carry, Eigen::VectorXd* q_bar, Eigen::VectorXd* v_bar) {
  for (int i = 0; i < carry.q.size(); ++i) (*q_bar)[i] = tape.Adjoint(carry.q[i]);
  for (int i = 0; i < carry.v.size(); ++i) (*v_bar)[i] = tape.Adjoint(carry.v[i]);
}

}  // namespace

LossGradient AdjointGradient(const Model<double>& model, const ParameterSet& parameters, const RunOptions& options,
                             const SampleLoss& loss, std::int64_t interval, AdjointReport* report) {
  Tape tape;
  // two copies of the model in Rev: one of constants (runs that record nothing), one whose parameters are the
  // recorded inputs
  const Model<Rev> plain_model = CastModel<Rev>(model);
  Model<Rev> recorded_model = CastModel<Rev>(model);
  std::vector<Rev> inputs;
  for (int i = 0; i < parameters.size(); ++i) {
    Rev& field = parameters.Field(&recorded_model, i);
    field = tape.Variable(field.a);
    inputs.push_back(field);
  }

  // forward: the loss, and a checkpoint every `interval` steps
  LossGradient result;
  bool forward = true;  // the segments run again backwards do not add to the loss
  Stepper<Rev> plain(plain_model, options, [&](const Sample<Rev>& s) {
    if (forward && s.stop >= 0) result.loss += loss(plain_model, s).a;
  });
  plain.Start();
  const std::int64_t planned = StepCount(model.simulation) + static_cast<std::int64_t>(options.stops.size());
  const std::int64_t k = interval > 0 ? interval : std::max<std::int64_t>(1, std::ceil(std::sqrt(double(planned))));
  std::vector<Carry> checkpoints;
  std::int64_t steps = 0;
  for (; !plain.done(); ++steps) {
    if (steps % k == 0) checkpoints.push_back(plain.Save());
    plain.Step();
  }

  forward = false;

  // the recorded run: its construction and start (the initial state and its loss) are the prefix, swept last
  Rev recorded_loss(0.0);
  Stepper<Rev> recorded(recorded_model, options, [&](const Sample<Rev>& s) {
    if (s.stop >= 0) recorded_loss += loss(recorded_model, s);
  });
  recorded.Start();
  const Rev start_loss = recorded_loss;
  const Carry start = recorded.Save();
  const int prefix = tape.size();
  std::int64_t largest_record = prefix;

  // backward, segment by segment: run the segment again keeping its states, then sweep its steps in reverse
  const int nq = plain_model.NumCoordinates(), nv = plain_model.NumVelocities();
  Eigen::VectorXd q_bar = Eigen::VectorXd::Zero(nq), v_bar = Eigen::VectorXd::Zero(nv);
  std::vector<Carry> segment;
  for (std::int64_t c = static_cast<std::int64_t>(checkpoints.size()) - 1; c >= 0; --c) {
    const std::int64_t first = c * k, count = std::min(k, steps - first);
    plain.Restore(checkpoints[c]);
    segment.clear();
    for (std::int64_t n = 0; n < count; ++n) {
      segment.push_back(plain.Save());
      plain.Step();
    }
    for (std::int64_t n = count - 1; n >= 0; --n) {
      Carry in = segment[n];
      RecordInputs(&tape, &in);
      recorded.Restore(in);
      recorded_loss = Rev(0.0);
      recorded.Step();
      const Carry out = recorded.Save();
      largest_record = std::max<std::int64_t>(largest_record, tape.size() - prefix);
      tape.AddAdjoint(recorded_loss, 1.0);
      AddAdjoints(&tape, out, q_bar, v_bar);
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
    const std::int64_t state_bytes = static_cast<std::int64_t>(nq + nv) * sizeof(Rev);
    report->steps = steps;
    report->interval = k;
    report->checkpoints = static_cast<std::int64_t>(checkpoints.size());
    report->largest_record = largest_record;
    report->memory_bytes = (report->checkpoints + k) * state_bytes + largest_record * Tape::kBytesPerNode;
  }
  return result;
}

LossGradient AdjointLossGradient(const Model<double>& model, const ParameterSet& parameters,
                                 const Observations& observations, std::int64_t interval, AdjointReport* report) {
  RunOptions options;
  options.every = INT_MAX;  // no output rows are needed, only the stops
  options.stops = observations.times;
  const SampleLoss loss = [&observations](const Model<Rev>& m, const Sample<Rev>& s) {
    Rev sum(0.0);
    ObservedResiduals(m, observations, s.stop, s, [&sum](size_t, const Rev& r) { sum += 0.5 * r * r; });
    return sum;
  };
  return AdjointGradient(model, parameters, options, loss, interval, report);
}

}  // namespace tether
