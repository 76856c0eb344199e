#include "shooting_problem.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <type_traits>

#include "tether/autodiff/adjoint.h"
#include "tether/dynamics/constraints/joint_coordinates.h"
#include "tether/dynamics/effects/schedule.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/model/configuration_space.h"
#include "tether/dynamics/model/errors.h"
#include "tether/dynamics/model/kinematics.h"

namespace tether {
namespace {

// With data, a shooting problem may have this many segments however few rows the data has.
constexpr int kSegmentsWithoutRows = 20;

constexpr double kUnbounded = std::numeric_limits<double>::max();

// The velocity index of configuration index i when it is a translation or a planar angle, -1 otherwise (a
// quaternion component).
int VelocityIndexOf(const Model<double>& model, int i) {
  for (const Body<double>& body : model.bodies) {
    if (i < body.q_offset || i >= body.q_offset + body.q_size) continue;
    const int k = i - body.q_offset;
    return body.kind == BodyKind::kRigid3d && k >= 3 ? -1 : body.v_offset + k;
  }
  return -1;
}

// Calls piece(length, a, b) for the pieces of [0, duration] on which a schedule (held at its end values) runs
// linearly from a to b: those between its knots within the run, and the held ends.
template <typename T, typename Piece>
void SchedulePieces(const Schedule<T>& schedule, const T& constant, double duration, Piece piece) {
  if (schedule.empty()) {
    piece(duration, constant, constant);
    return;
  }
  std::vector<double> cuts = {0.0};
  for (const double t : schedule.times) {
    if (t > 0.0 && t < duration) cuts.push_back(t);
  }
  cuts.push_back(duration);
  for (size_t j = 0; j + 1 < cuts.size(); ++j) {
    piece(cuts[j + 1] - cuts[j], ScheduleValue(schedule, cuts[j]), ScheduleValue(schedule, cuts[j + 1]));
  }
}

}  // namespace

void CheckStartWithinBounds(const ParameterSet& parameters, const std::vector<double>& values,
                            const IdentifySettings& settings) {
  for (int i = 0; i < parameters.size() && !settings.bounds.empty(); ++i) {
    const auto [lo, hi] = settings.bounds[i];
    if (!(values[i] >= lo && values[i] <= hi)) {
      std::ostringstream message;
      message << "--bound " << parameters.pointers()[i] << ": the scene's value " << values[i] << " lies outside ["
              << lo << ", " << hi << "]";
      throw InputError(message.str());
    }
  }
}

bool FittedInLogSpace(const ParameterSet& parameters, int i, double value, const IdentifySettings& settings) {
  const double lower = settings.bounds.empty() ? -kUnbounded : settings.bounds[i].first;
  const NumberDomain domain = parameters.number(i).domain;
  const bool quantity = domain == NumberDomain::kPositive || domain == NumberDomain::kNonNegative;
  return quantity && value > 0 && (lower > 0 || lower == -kUnbounded);
}
int ShootingProblem::Seeds::Slot(int unknown) const {
  for (size_t j = 0; j < unknowns.size(); ++j) {
    if (unknowns[j] == unknown) return static_cast<int>(j);
  }
  return -1;
}

ShootingProblem::ShootingProblem(const Model<double>& model, const ParameterSet& parameters,
                                 const std::vector<Observations>& recordings, const IdentifySettings& settings,
                                 StartRows start_rows, IdleCores* idle)
    : model_(model),
      parameters_(parameters),
      recordings_(recordings),
      settings_(settings),
      on_the_constraints_(start_rows == StartRows::kOnTheConstraints),
      idle_(idle) {
  const std::vector<double> values = parameters.Values(model);
  for (int i = 0; i < parameters.size(); ++i)
    log_space_.push_back(FittedInLogSpace(parameters, i, values[i], settings));
  for (const InequalityTarget& target : settings.inequalities) {
    targets_.push_back(MakeObservations(target.text, {"t", target.column}, {{target.time, target.value}}, model));
  }
  double end = 0.0;
  for (const Observations& r : recordings) {
    observed_.push_back(&r);
    data_groups_ += r.columns.size();
    end = std::max(end, r.times.back());
  }
  for (const Observations& r : targets_) {
    observed_.push_back(&r);
    end = std::max(end, r.times.back());
  }
  if (!(end > 0.0)) throw InputError("the data has no observation after t = 0: there is nothing to fit");
  const int segments = std::max(1, settings.segments);
  // each segment's start state is a block of unknowns the data and the joins determine; far past one segment a row
  // of data they only cost time (the solve is dense: 1000 segments of a pendulum with two rows ran for minutes).
  // With data, at most one a row or kSegmentsWithoutRows (fit's own choice goes to 20); targets alone (a fit
  // without data) are bounded by the step grid below.
  size_t rows = 0;
  for (const Observations& r : recordings) rows += r.times.size();
  if (!recordings.empty() && static_cast<size_t>(segments) > std::max<size_t>(rows, kSegmentsWithoutRows)) {
    throw InputError("--segments " + std::to_string(segments) + ": more segments than the " + std::to_string(rows) +
                     " rows of data (at most one a row, or " + std::to_string(kSegmentsWithoutRows) + ")");
  }
  // segment boundaries on the step grid, so that the segments step as one run does
  const double h = model.simulation.step;
  boundaries_.push_back(0.0);
  for (int k = 1; k < segments; ++k) {
    const double grid = std::round(end * k / segments / h) * h;
    if (!(grid > boundaries_.back() && grid < end)) {
      throw InputError("--segments " + std::to_string(segments) + ": more segments than steps of " +
                       std::to_string(h) + " s before the last target");
    }
    boundaries_.push_back(grid);
  }
  boundaries_.push_back(end);
  segment_rows_.assign(1, 0);
  for (int k = 0; k < segments; ++k) {  // the observed cells within each segment
    int cells = 0;
    for (const Observations& r : recordings) {
      for (size_t row = 0; row < r.times.size(); ++row) {
        const double t = r.times[row];
        if (!InSegment(t, k)) continue;
        for (double value : r.values[row]) cells += std::isnan(value) ? 0 : 1;
      }
    }
    segment_rows_.push_back(segment_rows_.back() + cells);
  }
  state_size_ = 2 * model.NumVelocities();
  if (segments > 1) references_ = SegmentStarts();
  // the smoothing pairs: consecutive values of one schedule component
  for (int a = 0; a < parameters.size(); ++a) {
    for (int b = 0; b < parameters.size(); ++b) {
      const std::optional<ScheduleKnot>&ka = parameters.number(a).knot, &kb = parameters.number(b).knot;
      if (ka && kb && kb->schedule == ka->schedule && kb->component == ka->component && kb->knot == ka->knot + 1) {
        smooth_pairs_.push_back({a, b});
      }
    }
  }
  std::vector<double> penalties;
  Penalties(model, &penalties);
  penalty_count_ = static_cast<int>(penalties.size());
}

bool ShootingProblem::InSegment(double t, int k) const {
  return (t > boundaries_[k] || (k == 0 && t == boundaries_[k])) && t <= boundaries_[k + 1];
}

double ShootingProblem::ToUnknown(int i, double p) const { return log_space_[i] ? std::log(p) : p; }
double ShootingProblem::ToParameter(int i, double x) const { return log_space_[i] ? std::exp(x) : x; }

std::vector<double> ShootingProblem::Parameters(const std::vector<double>& x) const {
  std::vector<double> out;
  for (int i = 0; i < parameters_.size(); ++i) out.push_back(ToParameter(i, x[i]));
  return out;
}

void ShootingProblem::Box(std::vector<double>* lower, std::vector<double>* upper) const {
  lower->assign(Unknowns(), -kUnbounded);
  upper->assign(Unknowns(), kUnbounded);
  for (int i = 0; i < parameters_.size() && !settings_.bounds.empty(); ++i) {
    const auto [lo, hi] = settings_.bounds[i];
    if (lo != -kUnbounded) (*lower)[i] = ToUnknown(i, lo);
    if (hi != kUnbounded) (*upper)[i] = ToUnknown(i, hi);
  }
}

std::vector<double> ShootingProblem::Start() const {
  std::vector<double> x;
  const std::vector<double> values = parameters_.Values(model_);
  for (int i = 0; i < parameters_.size(); ++i) x.push_back(ToUnknown(i, values[i]));
  for (const State<double>& reference : references_) {
    for (int i = 0; i < reference.v.size(); ++i) x.push_back(0.0);
    for (int i = 0; i < reference.v.size(); ++i) x.push_back(reference.v[i]);
  }
  return x;
}

Model<double> ShootingProblem::WithParameters(const std::vector<double>& x) const {
  Model<double> model = model_;
  for (int i = 0; i < parameters_.size(); ++i) parameters_.Field(&model, i) = ToParameter(i, x[i]);
  parameters_.ApplyTies(&model);
  return model;
}

template <typename T>
Model<T> ShootingProblem::Seeded(const Model<double>& model, const Seeds& seeds) const {
  if constexpr (IsJet<T>::value) {
    std::vector<ParameterSet::Seed> seeded;
    for (int i = 0; i < parameters_.size(); ++i) {  // d p / d x: p for log p, 1 otherwise
      const int slot = seeds.Slot(i);
      if (slot >= 0) seeded.push_back({i, slot, log_space_[i] ? parameters_.number(i).access(model) : 1.0});
    }
    return parameters_.Seeded(model, seeded);
  } else {
    return CastModel<T>(model);
  }
}

template <typename T>
State<T> ShootingProblem::SegmentStart(const Model<T>& model, const std::vector<double>& x, int k,
                                       const Seeds& seeds) const {
  const int nv = model.NumVelocities(), offset = parameters_.size() + (k - 1) * state_size_;
  VecX<T> d(nv), v(nv);
  for (int i = 0; i < 2 * nv; ++i) {
    T value(x[offset + i]);
    if constexpr (IsJet<T>::value) value = SeededJet(x[offset + i], seeds.Slot(offset + i));
    (i < nv ? d[i] : v[i - nv]) = value;
  }
  State<T> start;
  start.q.resize(model.NumCoordinates());
  Integrate(model, VecX<T>(references_[k - 1].q.template cast<T>()), d, 1.0, &start.q);
  start.v = v;
  return start;
}

template <typename T>
ShootingProblem::SegmentOutput<T> ShootingProblem::RunSegment(const Model<T>& model, const std::vector<double>& x,
                                                               int k, const Seeds& seeds,
                                                               const std::vector<double>& hint) const {
  Model<T> segment = model;
  segment.simulation.duration = boundaries_[k + 1] - boundaries_[k];
  RunOptions options;
  if (k > 0) {  // this segment's start state is an unknown, and it continues the joint coordinates
    const State<T> start = SegmentStart(model, x, k, seeds);
    segment = WithInitialState(segment, start.q, start.v);
    ContinueCoordinates(model, start.q, hint, &segment);
  }
  const double begin = boundaries_[k], end = boundaries_[k + 1];
  std::vector<double> times;  // every observed time in (begin, end] (and t = 0 in the first segment)
  for (const Observations* r : observed_) {
    for (double t : r->times) {
      if (InSegment(t, k)) times.push_back(t);
    }
  }
  times.push_back(end);
  const bool start_kept = k > 0 && on_the_constraints_;  // the start state as the run moved it onto the constraints
  if (start_kept) times.push_back(begin);
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end()), times.end());
  // the residuals are kept in recording, row, column order: collect them per stop first
  std::vector<std::vector<std::vector<std::pair<size_t, T>>>> cells(observed_.size());
  for (size_t i = 0; i < observed_.size(); ++i) cells[i].resize(observed_[i]->times.size());
  options.every = std::numeric_limits<int>::max();
  options.start_time = begin;
  options.stops = times;
  options.energy = std::any_of(observed_.begin(), observed_.end(), [](const Observations* r) { return ObservesEnergy(*r); });
  SegmentOutput<T> out;
  Simulate<T>(segment, options, [&](const Sample<T>& s) {
    if (s.stop < 0) return;
    const double t = times[s.stop];
    for (size_t i = 0; i < observed_.size(); ++i) {
      const Observations& r = *observed_[i];
      const auto row = std::lower_bound(r.times.begin(), r.times.end(), t);
      if (row == r.times.end() || *row != t || !InSegment(t, k)) continue;
      const size_t index = row - r.times.begin();
      ObservedResiduals(segment, r, index, s, [&](size_t c, const T& value) { cells[i][index].push_back({c, value}); });
    }
    if (start_kept && s.stop == 0) out.start = {s.q, s.v};
    if (s.stop + 1 != static_cast<int>(times.size())) return;
    out.end = {s.q, s.v};
    for (int i = 0; i < s.coordinates.size(); ++i) out.end_coordinates.push_back(Value(s.coordinates[i]));
  });
  if (on_the_constraints_ && k + 1 < Segments()) {  // the end the next start is held to (shooting_problem.h)
    RunReport unused;
    out.end = AssembledInitialState(WithInitialState(segment, out.end.q, out.end.v), &unused);
  }
  size_t group = 0;
  for (size_t i = 0; i < observed_.size(); ++i) {
    for (const auto& row : cells[i]) {
      for (const auto& [c, value] : row) {
        if (group < data_groups_) {
          out.data.push_back({group + c, value});
        } else {
          out.constraints.push_back({static_cast<int>(i - recordings_.size()), value});
        }
      }
    }
    group += observed_[i]->columns.size();
  }
  return out;
}

template <typename T>
void ShootingProblem::ContinueCoordinates(const Model<T>& model, const VecX<T>& q_start, const std::vector<double>& hint,
                                          Model<T>* segment) const {
  RunReport unused;
  const State<T> initial = AssembledInitialState(model, &unused);
  JointCoordinates<T> coordinates = BuildJointCoordinates(model, initial.q);
  if (coordinates.references.empty()) return;
  coordinates.last = hint;
  BodyFrames<T> frames;
  UpdateFrames(model, q_start, q_start, false, &frames);
  for (size_t c = 0; c < coordinates.references.size(); ++c) {
    const CoordinateReference<T>& reference = coordinates.references[c];
    if (reference.coordinate != JointCoordinate::kAngle) continue;
    segment->joints[reference.joint].angle =
        EvaluateCoordinate(model, coordinates, static_cast<int>(c), frames, q_start, q_start, false).value;
  }
}

template <typename T>
void ShootingProblem::Penalties(Model<T> model, std::vector<T>* out) const {
  const double smooth = std::sqrt(settings_.smooth);
  for (const auto& [a, b] : smooth_pairs_) {
    out->push_back(T(smooth) * (parameters_.Field(&model, b) - parameters_.Field(&model, a)));
  }
  if (!(settings_.effort > 0.0)) return;
  for (const JointTorqueEffect<T>& motor : model.joint_torques) {
    SchedulePieces(motor.schedule, motor.value, model.simulation.duration, [&](double length, const T& a, const T& b) {
      const double c = std::sqrt(2.0 * settings_.effort * length / 3.0);
      out->push_back(c * (a + 0.5 * b));
      out->push_back(c * (0.5 * std::sqrt(3.0)) * b);
    });
  }
}

bool ShootingProblem::ActsWithin(int i, int k) const {
  const std::optional<ScheduleKnot>& knot = parameters_.number(i).knot;
  if (parameters_.tied() || !knot) return true;
  const std::vector<double>& t = knot->times;
  const double from = knot->knot == 0 ? -INFINITY : t[knot->knot - 1];
  const double to = knot->knot + 1 == static_cast<int>(t.size()) ? INFINITY : t[knot->knot + 1];
  return from < boundaries_[k + 1] && to > boundaries_[k];
}

bool ShootingProblem::Evaluate(const std::vector<double>& x, Eigen::VectorXd* r, Eigen::MatrixXd* jacobian) const {
  const Model<double> guess = WithParameters(x);
  const int segments = Segments(), nv = model_.NumVelocities(), p = parameters_.size();
  const int continuity = DataCount(), penalty = continuity + ContinuityCount(), constraint = FirstConstraintRow();
  try {
    // values: one double run of every segment
    std::vector<double> values(DataCount(), 0.0);
    std::vector<double> constraints(ConstraintCount(), 0.0);
    std::vector<State<double>> ends, assembled;
    std::vector<std::vector<double>> hints(segments);  // each segment's start continues the previous one's end
    const Seeds none;
    for (int k = 0; k < segments; ++k) {
      SegmentOutput<double> s = RunSegment(guess, x, k, none, hints[k]);
      if (k + 1 < segments) hints[k + 1] = s.end_coordinates;
      for (size_t j = 0; j < s.data.size(); ++j) values[segment_rows_[k] + j] = s.data[j].second;
      for (const auto& [c, value] : s.constraints) constraints[c] = value;
      ends.push_back(s.end);
      assembled.push_back(s.start);
    }
    VecX<double> gap(nv);
    for (int k = 0; k + 1 < segments; ++k) {
      const State<double> start = SegmentStart(guess, x, k + 1, none);
      Difference(guess, start.q, ends[k].q, &gap);
      values.insert(values.end(), gap.data(), gap.data() + nv);
      for (int i = 0; i < nv; ++i) values.push_back(ends[k].v[i] - start.v[i]);
    }
    for (int k = 1; k < segments && on_the_constraints_; ++k) {
      const State<double> start = SegmentStart(guess, x, k, none);
      Difference(guess, assembled[k].q, start.q, &gap);
      values.insert(values.end(), gap.data(), gap.data() + nv);
      for (int i = 0; i < nv; ++i) values.push_back(start.v[i] - assembled[k].v[i]);
    }
    Penalties(guess, &values);
    values.insert(values.end(), constraints.begin(), constraints.end());
    *r = Eigen::Map<const Eigen::VectorXd>(values.data(), values.size());
    if (!jacobian) return true;

    // the Jacobian, by Jets over the unknowns each block depends on
    jacobian->setZero(r->size(), Unknowns());
    const auto chunks = [](const std::vector<int>& unknowns, auto run) {
      for (size_t first = 0; first < unknowns.size(); first += kJetStride) {
        Seeds seeds;
        for (size_t j = first; j < std::min(unknowns.size(), first + kJetStride); ++j) seeds.unknowns.push_back(unknowns[j]);
        run(seeds);
      }
    };
    const auto fill = [&](int row, const Jet& value, const Seeds& seeds) {
      for (size_t j = 0; j < seeds.unknowns.size(); ++j) (*jacobian)(row, seeds.unknowns[j]) = value.v[j];
    };
    // one task per segment and chunk of its unknowns: each fills its own columns of its own rows
    std::vector<std::function<void()>> runs;
    for (int k = 0; k < segments; ++k) {
      std::vector<int> unknowns;
      for (int i = 0; i < p; ++i) {
        if (ActsWithin(i, k)) unknowns.push_back(i);
      }
      for (int i = 0; k > 0 && i < state_size_; ++i) unknowns.push_back(p + (k - 1) * state_size_ + i);
      chunks(unknowns, [&, k](const Seeds& seeds) {
        runs.push_back([&, k, seeds] {
          const Model<Jet> model = Seeded<Jet>(guess, seeds);
          const SegmentOutput<Jet> s = RunSegment(model, x, k, seeds, hints[k]);
          for (size_t j = 0; j < s.data.size(); ++j)
            fill(segment_rows_[k] + static_cast<int>(j), s.data[j].second, seeds);
          for (const auto& [c, value] : s.constraints) fill(constraint + c, value, seeds);
          if (k > 0 && on_the_constraints_) {  // how far the start lies off the constraints
            const State<Jet> start = SegmentStart(model, x, k, seeds);
            VecX<Jet> off(nv);
            Difference(model, s.start.q, start.q, &off);
            const int row = continuity + (segments - 1 + k - 1) * state_size_;
            for (int i = 0; i < nv; ++i) fill(row + i, off[i], seeds);
            for (int i = 0; i < nv; ++i) fill(row + nv + i, start.v[i] - s.start.v[i], seeds);
          }
          if (k + 1 == segments) return;
          const State<Jet> start = SegmentStart(model, x, k + 1, Seeds{});  // the next start, constant here
          VecX<Jet> jet_gap(nv);
          Difference(model, start.q, s.end.q, &jet_gap);
          const int row = continuity + k * state_size_;
          for (int i = 0; i < nv; ++i) fill(row + i, jet_gap[i], seeds);
          for (int i = 0; i < nv; ++i) fill(row + nv + i, s.end.v[i], seeds);
        });
      });
    }
    RunTasksOnIdleCores(runs, idle_);
    for (int k = 0; k + 1 < segments; ++k) {  // the continuity rows' dependence on the next start
      std::vector<int> unknowns;
      for (int i = 0; i < state_size_; ++i) unknowns.push_back(p + k * state_size_ + i);
      const Model<Jet> model = CastModel<Jet>(guess);
      const VecX<Jet> end_q = ends[k].q.cast<Jet>();
      chunks(unknowns, [&](const Seeds& seeds) {
        const State<Jet> start = SegmentStart(model, x, k + 1, seeds);
        VecX<Jet> jet_gap(nv);
        Difference(model, start.q, end_q, &jet_gap);
        const int row = continuity + k * state_size_;
        for (int i = 0; i < nv; ++i) fill(row + i, jet_gap[i], seeds);
        for (int i = 0; i < nv; ++i) fill(row + nv + i, Jet(0.0) - start.v[i], seeds);
      });
    }
    std::vector<int> all(p);
    for (int i = 0; i < p; ++i) all[i] = i;
    chunks(all, [&](const Seeds& seeds) {
      std::vector<Jet> jets;
      Penalties(Seeded<Jet>(guess, seeds), &jets);
      for (size_t j = 0; j < jets.size(); ++j) fill(penalty + static_cast<int>(j), jets[j], seeds);
    });
    return true;
  } catch (const SimulationDiverged&) {
    return false;
  } catch (const InputError&) {  // a trial start state the simulation cannot take
    return false;
  }
}

bool ShootingProblem::CostGradient(const std::vector<double>& x, const RobustLoss& loss, double* cost,
                                   std::vector<double>* gradient) const {
  Model<double> guess = WithParameters(x);
  guess.simulation.duration = boundaries_[1];
  RunOptions options;
  options.every = std::numeric_limits<int>::max();
  options.stops = {boundaries_.back()};
  for (const Observations& r : recordings_) options.stops.insert(options.stops.end(), r.times.begin(), r.times.end());
  std::sort(options.stops.begin(), options.stops.end());
  options.stops.erase(std::unique(options.stops.begin(), options.stops.end()), options.stops.end());
  options.energy = std::any_of(recordings_.begin(), recordings_.end(), ObservesEnergy);
  const auto sample_loss = [&](const auto& model, const auto& sample) {
    using T = std::decay_t<decltype(sample.energy)>;
    T sum(0.0);
    const double t = options.stops[sample.stop];
    for (const Observations& r : recordings_) {
      const auto row = std::lower_bound(r.times.begin(), r.times.end(), t);
      if (row == r.times.end() || *row != t) continue;
      ObservedResiduals(model, r, static_cast<size_t>(row - r.times.begin()), sample,
                        [&](size_t, const T& value) { sum += 0.5 * RobustRho(loss, T(value * value)); });
    }
    return sum;
  };
  LossGradient data;
  try {
    data = AdjointGradient(guess, parameters_, options, {sample_loss, sample_loss});
  } catch (const SimulationDiverged&) {
    return false;
  } catch (const InputError&) {
    return false;
  }
  *cost = data.loss;
  gradient->resize(x.size());
  for (int i = 0; i < parameters_.size(); ++i) {  // d p / d x: p for log p, 1 otherwise
    (*gradient)[i] = data.gradient[i] * (log_space_[i] ? ToParameter(i, x[i]) : 1.0);
  }
  // the penalties: d(1/2 rho(r^2))/dx = rho'(r^2) r dr/dx, dr/dx by Jets (no simulation)
  std::vector<int> all(parameters_.size());
  for (int i = 0; i < parameters_.size(); ++i) all[i] = i;
  for (size_t first = 0; first < all.size(); first += kJetStride) {
    Seeds seeds;
    for (size_t j = first; j < std::min(all.size(), first + kJetStride); ++j) seeds.unknowns.push_back(all[j]);
    std::vector<Jet> penalties;
    Penalties(Seeded<Jet>(guess, seeds), &penalties);
    for (const Jet& r : penalties) {
      double rho[2];
      EvaluateLoss(loss, r.a * r.a, rho);
      if (first == 0) *cost += 0.5 * rho[0];
      for (size_t j = 0; j < seeds.unknowns.size(); ++j) (*gradient)[seeds.unknowns[j]] += rho[1] * r.a * r.v[j];
    }
  }
  return true;
}

std::vector<ResidualStatistics> ShootingProblem::Statistics(const std::vector<double>& x) const {
  const Model<double> guess = WithParameters(x);
  std::vector<ResidualStatistics> stats;
  for (const Observations& r : recordings_) {
    for (const TrajectoryColumn& c : r.columns) stats.push_back({r.path, c.name});
  }
  std::vector<double> hint;
  for (int k = 0; k < Segments(); ++k) {
    const SegmentOutput<double> segment = RunSegment(guess, x, k, Seeds{}, hint);
    hint = segment.end_coordinates;
    for (const auto& [group, residual] : segment.data) {
      ResidualStatistics& s = stats[group];
      ++s.count;
      s.rms += residual * residual;
      s.largest = std::max(s.largest, std::abs(residual));
    }
  }
  for (ResidualStatistics& s : stats) s.rms = s.count ? std::sqrt(s.rms / s.count) : 0.0;
  return stats;
}

std::vector<State<double>> ShootingProblem::SegmentStarts() {
  const std::vector<double> starts(boundaries_.begin() + 1, boundaries_.end() - 1);
  Model<double> whole = model_;
  whole.simulation.duration = boundaries_.back();
  std::vector<State<double>> guess(starts.size(), InitialState(model_));
  RunOptions options;
  options.every = std::numeric_limits<int>::max();
  options.stops = starts;
  try {
    Simulate<double>(whole, options, [&](const Sample<double>& s) {
      if (s.stop < 0) return;
      guess[s.stop] = {s.q, s.v};
    });
  } catch (const SimulationDiverged&) {  // the guess diverges: the later segments start from the initial state
  }
  for (size_t k = 0; k < starts.size(); ++k) ReplaceByData(starts[k], &guess[k].q, &guess[k].v);
  return guess;
}

void ShootingProblem::ReplaceByData(double t, VecX<double>* q, VecX<double>* v) const {
  using ColumnKind = TrajectoryColumn::Kind;
  for (const Observations& r : recordings_) {
    size_t nearest = 0;
    for (size_t row = 1; row < r.times.size(); ++row) {
      if (std::abs(r.times[row] - t) < std::abs(r.times[nearest] - t)) nearest = row;
    }
    for (size_t c = 0; c < r.columns.size(); ++c) {
      const double value = r.values[nearest][c];
      if (std::isnan(value)) continue;
      const TrajectoryColumn& column = r.columns[c];
      if (column.kind == ColumnKind::kVelocity) (*v)[column.index] = value;
      if (column.kind != ColumnKind::kConfiguration) continue;
      const int velocity = VelocityIndexOf(model_, column.index);
      if (velocity < 0) continue;  // a quaternion component: the run's orientation is kept
      (*q)[column.index] = value;
      // a coordinate observed without its velocity: central difference of the neighbouring rows
      if (nearest > 0 && nearest + 1 < r.times.size() && !std::isnan(r.values[nearest - 1][c]) &&
          !std::isnan(r.values[nearest + 1][c])) {
        (*v)[velocity] = (r.values[nearest + 1][c] - r.values[nearest - 1][c]) /
                         (r.times[nearest + 1] - r.times[nearest - 1]);
      }
    }
  }
}

}  // namespace tether
