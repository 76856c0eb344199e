#include "tether/dynamics/integration/simulator.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <type_traits>

#include "tether/dynamics/effects/effects.h"
#include "tether/dynamics/integration/default_gains.h"
#include "tether/dynamics/integration/integrators.h"
#include "tether/dynamics/integration/interrupts.h"
#include "tether/dynamics/integration/projection.h"
#include "tether/dynamics/integration/stepper.h"
#include "tether/dynamics/model/configuration_space.h"
#include "tether/dynamics/model/errors.h"

namespace tether {
namespace {

// Projections stop at this violation, relative to the length scale.
constexpr double kProjectionTolerance = 1e-12;
// An event is located to this fraction of the step (the event function's root, bracketed).
constexpr double kEventTimeTolerance = 1e-13;
// A step that came close to a singular pass is retaken in this many substeps (schur_solver.h, "Singular passes"):
// their stage states are off the constraints by 1/256 of the step's.
constexpr int kSingularPassSubsteps = 16;
// More events than this within one step: a sequence of impacts that the capture rule did not end.
constexpr int kMostEventsPerStep = 10000;
// An initial state off its constraints by more than this (relative) is reported as moved.
constexpr double kAssemblyWarning = 1e-10;
// A run whose constraints drift beyond this (relative to the length scale) is warned of (Stepper::WarnOfDrift).
constexpr double kDriftWarning = 0.01;
// An assembly whose Gauss-Newton iteration stalls (round-off in the constraint values can sit above the
// projection's 1e-12 of the length scale, e.g. far from the origin) is accepted below this (relative): a
// nanometre on a metre, which the run's stabilization then holds.
constexpr double kAssemblyAcceptance = 1e-9;

std::string Seconds(double t) {
  std::ostringstream out;
  out << "t = " << t << " s";
  return out.str();
}

template <typename T>
bool AllFinite(const VecX<T>& x) {
  for (int i = 0; i < x.size(); ++i) {
    if (!std::isfinite(Value(x[i]))) return false;
  }
  return true;
}

template <typename T>
double LargestChange(const VecX<T>& before, const VecX<T>& after) {
  double change = 0.0;
  for (int i = 0; i < before.size(); ++i) change = std::max(change, std::abs(Value(after[i]) - Value(before[i])));
  return change;
}

template <typename T>
void AssembleInitialState(const Model<T>& model, double scale, Workspace<T>* ws, VecX<T>* q, VecX<T>* v,
                          RunReport* report) {
  const VecX<T> q_given = *q, v_given = *v;
  auto assembled = [&](const ProjectionResult& r) {
    return r.converged || r.violation.largest <= kAssemblyAcceptance * scale;
  };
  ProjectionResult result = ProjectPositions(model, kProjectionTolerance * scale, ws, q);
  if (!assembled(result)) {  // far off the constraints: reach them by the robust iteration (a consistent state)
    *q = q_given;
    result = ProjectPositionsRobustly(model, kProjectionTolerance * scale, ws, q);
  }
  if (!assembled(result)) {
    std::ostringstream out;
    out << "the initial state cannot be assembled onto the constraints: "
        << DescribeConstraint(model, result.violation.scene_index) << " is still violated by "
        << result.violation.largest << (model.dimension == 3 ? " (m, or rad for an axis)" : " m") << " after "
        << result.iterations << " Gauss-Newton iterations";
    throw InputError(out.str());
  }
  if (!ProjectVelocities(model, *q, ws, v))
    throw InputError("the initial velocities cannot be projected onto the constraints");
  const double moved = LargestChange(q_given, *q);
  if (moved > kAssemblyWarning * scale) {
    std::ostringstream out;
    out << "the initial positions violated the constraints; moved them onto the constraints (mass-weighted "
           "nearest state) by up to "
        << moved;
    report->warnings.push_back(out.str());
  }
  const double turned = LargestChange(v_given, *v);
  double speed = 0.0;
  for (int i = 0; i < v_given.size(); ++i) speed = std::max(speed, std::abs(Value(v_given[i])));
  if (turned > kAssemblyWarning * (1.0 + speed)) {
    std::ostringstream out;
    out << "the initial velocities violated the constraints; projected them onto the constraints by up to " << turned;
    report->warnings.push_back(out.str());
  }
}

}  // namespace

template <typename T>
State<T> AssembledInitialState(const Model<T>& model, RunReport* report) {
  State<T> start = InitialState(model);
  Workspace<T> ws(model, start.q);
  AssembleInitialState(model, LengthScale(model), &ws, &start.q, &start.v, report);
  return start;
}

template <typename T>
double LengthScale(const Model<T>& model) {
  double scale = 1e-3;
  for (const Body<T>& body : model.bodies) {
    for (int k = 0; k < model.dimension; ++k) scale = std::max(scale, std::abs(Value(body.position[k])));
  }
  for (const Joint<T>& c : model.joints) {
    if (c.type == JointType::kDistance) scale = std::max(scale, Value(c.length));
    for (const BodyPoint<T>* p : {&c.a, &c.b}) {
      for (int k = 0; k < 3; ++k) scale = std::max(scale, std::abs(Value(p->local[k])));
    }
  }
  return scale;
}

template <typename T>
std::string DescribeConstraint(const Model<T>& model, int scene_index) {
  auto name = [&model](int body) { return body == kWorld ? std::string("world") : model.bodies[body].name; };
  auto describe = [&](const char* kind, int a, int b) {
    return "constraint /constraints/" + std::to_string(scene_index) + " (" + kind + " " + name(a) + "-" + name(b) + ")";
  };
  for (const Joint<T>& c : model.joints) {
    if (c.scene_index == scene_index) return describe(JointTypeName(c.type), c.a.body, c.b.body);
  }
  for (const auto& c : model.user_constraints) {
    if (c.scene_index == scene_index) return describe("user-defined", c.body_a, c.body_b);
  }
  if (scene_index >= model.NumConstraints() && !model.shapes.empty()) {  // a contact pair's row
    const std::vector<ContactPair> pairs = BuildContactGeometry(model).pairs;
    const size_t pair = static_cast<size_t>(scene_index - model.NumConstraints());
    if (pair < pairs.size()) return "the contact " + pairs[pair].label;
  }
  return "no constraint";
}

template <typename T>
Stepper<T>::Stepper(const Model<T>& model, const RunOptions& options, Observer observer)
    : model_(model),
      options_(options),
      observer_(std::move(observer)),
      state_(InitialState(model)),
      ws_(model, state_.q, options.factor_jet_matrices),
      integrator_(model),
      scale_(LengthScale(model)),
      h_(model.simulation.step),
      gaps_(model) {
  if (options.every < 1) throw InputError("RunOptions::every must be >= 1, got " + std::to_string(options.every));
  const double duration = model.simulation.duration;
  const double t0 = options.start_time;
  const std::vector<double>& stops = options.stops;
  for (size_t i = 0; i < stops.size(); ++i) {
    if (!(stops[i] >= t0 && stops[i] <= t0 + duration * (1 + 1e-12)) || (i > 0 && !(stops[i] > stops[i - 1]))) {
      throw InputError("RunOptions::stops must increase strictly and lie within the run's interval");
    }
  }
  GainsInUse(model, &ws_.alpha, &ws_.beta);
  CheckStepCount(model.simulation, "the simulation settings");
  steps_ = StepCount(model.simulation);
  time_ = t0;
  AssembleInitialState(model, scale_, &ws_, &state_.q, &state_.v, &report_);
  ws_.coordinates = BuildJointCoordinates(model, state_.q);
  const int num_coordinates = static_cast<int>(ws_.coordinates.references.size());
  coordinates_ = VecX<T>::Zero(num_coordinates);
  rates_ = VecX<T>::Zero(num_coordinates);
  q_projected_ = state_.q;
  v_projected_ = state_.v;
  settle_ = [this](double t, VecX<T>* q, VecX<T>* v) { return Settle(t, q, v); };
  // a limit the run starts on, at rest or moving into it (time stepping: at the first step's end)
  if (!gaps_.empty() && !gaps_.stepping()) gaps_.Resolve(t0, h_, -1, -1, &state_.q, &state_.v, &ws_, &report_);
}

template <typename T>
SimulationDiverged Stepper<T>::Diverged(double t, const std::string& what) const {
  const Violation worst = LargestViolation(ws_.infos, ws_.rows);
  std::string message = "the simulation diverged at " + Seconds(t) + ": " + what;
  if (worst.scene_index >= 0) {
    std::ostringstream out;
    out << "; the worst constraint is " << DescribeConstraint(model_, worst.scene_index) << ", violated by "
        << worst.largest << (model_.dimension == 3 ? " (m, or rad for an axis)" : " m");
    message += out.str();
  }
  return SimulationDiverged(message, t, worst.scene_index);
}

// A violation above the scene's length scale: the run has left its constraints.
template <typename T>
void Stepper<T>::CheckViolation(double t, double largest) const {
  if (largest <= scale_) return;
  std::ostringstream out;
  out << "a constraint ran away (violation above the scene's length scale " << scale_ << " m)";
  throw Diverged(t, out.str());
}

// A run whose constraints drift beyond kDriftWarning of the length scale is not the constrained motion any more:
// said once, at the first sample where it happens, so that no such run ends silently (the run goes on; beyond the
// length scale itself it stops, CheckViolation).
template <typename T>
void Stepper<T>::WarnOfDrift(double t, double largest) {
  if (drift_warned_ || !(largest > kDriftWarning * scale_)) return;
  drift_warned_ = true;
  std::ostringstream out;
  out << "t = " << t << ": the constraints have drifted by " << largest << " m (" << largest / scale_ * 100
      << "% of the scene's length scale " << scale_
      << " m): this is no longer the constrained motion; a smaller step, another integrator or tuned gains "
         "(tether tune) keep it";
  report_.drift = out.str();
  report_.warnings.push_back(report_.drift);
}

// Every sample is checked as it is made, the last one included (the steps' own checks see the rows of their
// last stage, not of the state they end in).
template <typename T>
void Stepper<T>::Emit(double t, bool output, int stop) {
  const VecX<T>& q = state_.q;
  const VecX<T>& v = state_.v;
  UpdateFrames(model_, q, v, true, &ws_.frames);
  EvaluateConstraintRows(model_, ws_.constraints, ws_.frames, q, v, false, &ws_.rows);
  const double error = ws_.rows.empty() ? 0.0 : LargestViolation(ws_.infos, ws_.rows).largest;
  CheckViolation(t, error);
  WarnOfDrift(t, error);
  for (int k = 0; k < coordinates_.size(); ++k) {
    const CoordinateRow<T> row = EvaluateCoordinate(model_, ws_.coordinates, k, ws_.frames, q, v, true);
    coordinates_[k] = row.value;
    rates_[k] = row.rate;
  }
  const T energy =
      options_.energy ? Energy(model_, ws_.coordinates, ws_.frames, q, v) : T(std::numeric_limits<double>::quiet_NaN());
  observer_(Sample<T>{t, q, v, error, energy, coordinates_, rates_, ws_.frames, ws_.rows, output, stop});
}

// After every integrator step (rk45: every internal step): the projection stabilization; or, for Baumgarte,
// when the step's Schur factorizations saw a configuration near a singular one (schur_solver.h), the same
// projection, adopted only when it converges (there it can stall a little above its rounding-level tolerance,
// and the Baumgarte state is then kept as it is).
template <typename T>
bool Stepper<T>::Settle(double t, VecX<T>* q, VecX<T>* v) {
  const Stabilization method = model_.stabilization.method;
  bool changed = false;
  if (method == Stabilization::kProjection) {
    if (!ProjectPositions(model_, kProjectionTolerance * scale_, &ws_, q).converged ||
        !ProjectVelocities(model_, *q, &ws_, v)) {
      throw Diverged(t, "the projection onto the constraints did not converge");
    }
    changed = true;
  } else if (method == Stabilization::kBaumgarte && ws_.solver->saw_near_singular()) {
    q_projected_ = *q;
    v_projected_ = *v;
    if (ProjectPositions(model_, kProjectionTolerance * scale_, &ws_, &q_projected_).converged &&
        ProjectVelocities(model_, q_projected_, &ws_, &v_projected_)) {
      q->swap(q_projected_);
      v->swap(v_projected_);
      changed = true;
    }
  }
  ws_.solver->ForgetConditioning();  // the next step starts afresh (the projection's own solves included)
  return changed;
}

// One step of the plan from t to t + dt, split at the events of the joint limits inside it (stepper.h).
template <typename T>
void Stepper<T>::Advance(double t, double dt) {
  if (gaps_.empty()) return AdvanceSmooth(t, dt);
  if (gaps_.stepping()) {  // impulses at the step's end (unilateral_stepping.cc)
    v_start_ = state_.v;
    AdvanceSmooth(t, dt);
    gaps_.StepContacts(t + dt, dt, v_start_, &state_.q, &state_.v, &ws_, &report_);
    return;
  }
  const double t_end = t + dt;
  gaps_.FollowSlips(t, dt, state_.q, state_.v, &ws_);
  for (int events = 0; events < kMostEventsPerStep; ++events) {
    SaveInto(&before_);
    AdvanceSmooth(t, t_end - t);
    const double tau = FirstEvent(t, t_end - t);  // leaves the state at the event
    if (tau < 0.0) return;
    t += tau;
    gaps_.Resolve(t, h_, capture_, event_, &state_.q, &state_.v, &ws_, &report_);
    if (t_end - t <= kEventTimeTolerance * h_) {  // the event closes the step
      if (t < t_end) AdvanceSmooth(t, t_end - t);
      return;
    }
  }
  throw Diverged(t, "more than " + std::to_string(kMostEventsPerStep) +
                        " joint-limit events within one step (a sequence of impacts that does not end)");
}

// The sides due for an event at time t (the state now): inactive ones overlapping, active ones pulling.
template <typename T>
bool Stepper<T>::CollectDue(double t) {
  due_.clear();
  gaps_.Overlapping(state_.q, &ws_, &due_);
  if (!gaps_.active_order().empty()) {
    const bool solved = gaps_.Multipliers(t, state_.q, state_.v, &ws_, &multipliers_);
    for (size_t j = 0; j < multipliers_.size(); ++j) {
      if (multipliers_[j] < 0.0) due_.push_back(gaps_.active_order()[j]);
    }
    gaps_.FrictionDue(t, state_.q, state_.v, &ws_, &due_, solved);
  }
  return !due_.empty();
}

// After a step from t of dt (the state saved in before_): the time from t of the first event within it, the
// state left there (just past it: a gap closed, or a multiplier turned negative); -1 with the state at t + dt
// when there is none.
template <typename T>
double Stepper<T>::FirstEvent(double t, double dt) {
  if (!CollectDue(t + dt)) return -1.0;
  double first = dt;
  capture_ = -1;
  event_ = -1;
  for (int i : due_) {
    const double tau = Locate(i, t, first);
    if (tau < first) {
      first = tau;
      // a gap closing again at once is captured; a held side at 0 just releases, a friction event just changes
      capture_ = tau == 0.0 && !gaps_.IsFrictionEvent(i) && !gaps_.active(i) ? i : -1;
      event_ = i;
    }
  }
  Restore(before_);
  if (first > 0.0) AdvanceSmooth(t, first);
  return first;
}

// The event time of side i within [0, dt]: the end of the final bracket where its event function is negative;
// dt when the function is not negative there (no event before dt), 0 when a gap that has just opened closes
// again within the first kCaptureFlight of the step (it is then captured) or a held side's multiplier is not
// positive at the start (it releases there).
template <typename T>
double Stepper<T>::Locate(int side, double t, double dt) {
  // a gap left overlapping at the start (a side released or dropped with its drift) is due where it deepens
  const bool gap = !gaps_.IsFrictionEvent(side) && !gaps_.active(side);
  double overlap = 0.0;
  auto value_after = [&](double tau) {
    Restore(before_);
    if (tau > 0.0) AdvanceSmooth(t, tau);
    return gaps_.EventValue(side, t + tau, state_.q, state_.v, &ws_) - overlap;
  };
  if (gap) overlap = std::min(value_after(0.0), 0.0);
  double hi = dt, f_hi = value_after(dt);
  if (!(f_hi < 0.0)) return dt;
  double lo = 0.0, f_lo = value_after(0.0);
  // a gap at zero at the start (it has just opened): bracket from the first probe where it is open
  for (double probe = kCaptureFlight * dt; gap && !(f_lo > 0.0) && probe < dt; probe *= 2.0) {
    const double f = value_after(probe);
    if (f > 0.0) {
      lo = probe;
      f_lo = f;
    }
  }
  if (!(f_lo > 0.0)) return 0.0;  // a gap that closes again at once (captured), or a multiplier already at zero
  int stale = 0;                  // Illinois: halve the value of an end that stays
  while (hi - lo > kEventTimeTolerance * dt) {
    double mid = (f_lo * hi - f_hi * lo) / (f_lo - f_hi);
    if (!(mid > lo && mid < hi) || std::abs(stale) > 2) mid = 0.5 * (lo + hi);
    const double f = value_after(mid);
    if (f > 0.0) {
      lo = mid;
      f_lo = f;
      if (stale < 0) f_hi *= 0.5;
      stale = stale < 0 ? stale - 1 : -1;
    } else {
      hi = mid;
      f_hi = f;
      if (f == 0.0) break;
      if (stale > 0) f_lo *= 0.5;
      stale = stale > 0 ? stale + 1 : 1;
    }
  }
  return hi;
}

// one step of the run, with its stabilization and divergence checks
template <typename T>
void Stepper<T>::AdvanceSmooth(double t, double dt) {
  if (RunsCancelled()) throw RunInterrupted(Interrupted());
  VecX<T>& q = state_.q;
  VecX<T>& v = state_.v;
  ws_.solver->ForgetConditioning();
  const bool baumgarte = model_.stabilization.method == Stabilization::kBaumgarte;
  if (baumgarte) {
    pass_start_.q = q;
    pass_start_.v = v;
    pass_start_.integrator = integrator_.memory();
    pass_start_.solver = ws_.solver->memory();
    ws_.solver->ForgetSingularPass();
  }
  StepStatus status = integrator_.Advance(t, dt, &ws_, &q, &v, settle_);
  if (baumgarte && status == StepStatus::kOk && ws_.solver->saw_singular_pass()) status = RetakeSingularPass(t, dt);
  const double t_next = t + dt;
  if (status == StepStatus::kSolveFailed && ws_.painleve >= 0) {
    throw Diverged(t_next, "Painleve's paradox at " + DescribeConstraint(model_, ws_.infos[ws_.painleve].scene_index) +
                               ": its sliding friction admits no consistent accelerations (the normal force would "
                               "have to pull); a smaller friction coefficient, or the time-stepping mode, avoids it");
  }
  if (status == StepStatus::kSolveFailed) throw Diverged(t_next, "the constraint system became singular or non-finite");
  if (status == StepStatus::kStepSizeUnderflow) throw Diverged(t_next, "rk45's step size collapsed");
  if (!AllFinite(q) || !AllFinite(v)) throw Diverged(t_next, "the state became non-finite (NaN or infinity)");
  CheckViolation(t_next, LargestViolation(ws_.infos, ws_.rows).largest);
  if (coordinates_.size() > 0) {  // the branch of every hinge angle follows the motion step by step
    if constexpr (std::is_same_v<T, double>) {
      UpdateFrames(model_, q, v, false, &ws_.frames);
      TrackCoordinates(model_, ws_.frames, q, v, &ws_.coordinates);
    } else {  // the branches are plain data: from the values alone, with nothing differentiated or recorded
      q_values_ = q.unaryExpr([](const T& x) { return T(Value(x)); });
      v_values_ = v.unaryExpr([](const T& x) { return T(Value(x)); });
      UpdateFrames(model_, q_values_, v_values_, false, &ws_.frames);
      TrackCoordinates(model_, ws_.frames, q_values_, v_values_, &ws_.coordinates);
    }
  }
}

// The step from t of dt again from its start, in kSingularPassSubsteps substeps with the KKT solver's pivot floor
// on (schur_solver.h, "Singular passes").
template <typename T>
StepStatus Stepper<T>::RetakeSingularPass(double t, double dt) {
  state_.q = pass_start_.q;
  state_.v = pass_start_.v;
  integrator_.Restore(pass_start_.integrator);
  ws_.solver->Restore(pass_start_.solver);
  ws_.solver->set_pass_floor(true);
  ++report_.retaken_steps;
  const double substep = dt / kSingularPassSubsteps;
  StepStatus status = StepStatus::kOk;
  for (int k = 0; k < kSingularPassSubsteps && status == StepStatus::kOk; ++k) {
    ws_.solver->ForgetConditioning();
    const double start = t + k * substep;
    status = integrator_.Advance(start, k + 1 == kSingularPassSubsteps ? t + dt - start : substep, &ws_, &state_.q,
                                 &state_.v, settle_);
  }
  ws_.solver->set_pass_floor(false);
  return status;
}

// stops closer than 1e-9 h to a grid time are served by that grid time
template <typename T>
int Stepper<T>::StopAt(double t) {
  const std::vector<double>& stops = options_.stops;
  return next_stop_ < stops.size() && std::abs(stops[next_stop_] - t) <= 1e-9 * h_ ? static_cast<int>(next_stop_++)
                                                                                   : -1;
}

template <typename T>
void Stepper<T>::Start() {
  Emit(time_, true, StopAt(time_));
}

template <typename T>
bool Stepper<T>::Step() {
  if (step_ >= steps_) return false;
  const std::vector<double>& stops = options_.stops;
  const double t0 = options_.start_time;
  const double t = time_;
  const double t_next = t0 + (step_ + 1 == steps_ ? model_.simulation.duration : static_cast<double>(step_ + 1) * h_);
  if (next_stop_ < stops.size() && stops[next_stop_] < t_next - 1e-9 * h_) {  // step onto the stop
    Advance(t, stops[next_stop_] - t);
    time_ = stops[next_stop_];
    Emit(time_, false, static_cast<int>(next_stop_++));
    return true;
  }
  Advance(t, t_next - t);
  report_.steps = ++step_;
  time_ = t_next;
  const bool output = step_ % options_.every == 0 || step_ == steps_;
  const int stop = StopAt(t_next);
  if (output || stop >= 0) Emit(t_next, output, stop);
  // stops past the last grid time by no more than the rounding RunOptions allows are served by the end state
  if (step_ == steps_) {
    while (next_stop_ < stops.size()) Emit(t0 + model_.simulation.duration, false, static_cast<int>(next_stop_++));
  }
  return true;
}

template <typename T>
typename Stepper<T>::Carry Stepper<T>::Save() const {
  Carry carry;
  SaveInto(&carry);
  return carry;
}

template <typename T>
void Stepper<T>::SaveInto(Carry* carry) const {
  carry->q = state_.q;
  carry->v = state_.v;
  Memory& memory = carry->memory;
  memory.step = step_;
  memory.time = time_;
  memory.next_stop = next_stop_;
  memory.integrator = integrator_.memory();
  memory.solver = ws_.solver->memory();
  memory.coordinate_branches = ws_.coordinates.last;
  memory.active_sides = gaps_.active_set();
  memory.held_slips = gaps_.held_slips();
  memory.touching_sides = gaps_.touching();
  memory.contact_impulses = gaps_.last_impulses();
}

template <typename T>
void Stepper<T>::Restore(const Carry& carry) {
  state_.q = carry.q;
  state_.v = carry.v;
  const Memory& memory = carry.memory;
  step_ = memory.step;
  time_ = memory.time;
  next_stop_ = memory.next_stop;
  integrator_.Restore(memory.integrator);
  gaps_.SetActiveSet(memory.active_sides, memory.held_slips,
                     &ws_);  // before the solver's memory: the set picks the solver
  ws_.solver->Restore(memory.solver);
  gaps_.SetTouching(memory.touching_sides, memory.contact_impulses);
  ws_.coordinates.last = memory.coordinate_branches;
}

template <typename T>
RunReport Simulate(const Model<T>& model, const RunOptions& options,
                   const std::function<void(const Sample<T>&)>& observer) {
  Stepper<T> stepper(model, options, observer);
  stepper.Start();
  while (stepper.Step()) {
  }
  return stepper.report();
}

#define TETHER_INSTANTIATE_SIMULATOR(T)                                                                             \
  template RunReport Simulate<T>(const Model<T>&, const RunOptions&, const std::function<void(const Sample<T>&)>&); \
  template double LengthScale<T>(const Model<T>&);                                                                  \
  template State<T> AssembledInitialState<T>(const Model<T>&, RunReport*);                                          \
  template std::string DescribeConstraint<T>(const Model<T>&, int);                                                 \
  template class Stepper<T>;
TETHER_FOR_EACH_SCALAR(TETHER_INSTANTIATE_SIMULATOR)

}  // namespace tether
