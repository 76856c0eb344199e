#include "tether/dynamics/simulator.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "tether/dynamics/configuration_space.h"
#include "tether/dynamics/default_gains.h"
#include "tether/dynamics/effects.h"
#include "tether/dynamics/errors.h"
#include "tether/dynamics/interrupts.h"
#include "tether/dynamics/integrators.h"
#include "tether/dynamics/projection.h"

namespace tether {
namespace {

// Projections stop at this violation, relative to the length scale.
constexpr double kProjectionTolerance = 1e-12;
// An initial state off its constraints by more than this (relative) is reported as moved.
constexpr double kAssemblyWarning = 1e-10;
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
  if (!ProjectVelocities(model, *q, ws, v)) throw InputError("the initial velocities cannot be projected onto the constraints");
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
    out << "the initial velocities violated the constraints; projected them onto the constraints by up to "
        << turned;
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
  return "no constraint";
}

template <typename T>
RunReport Simulate(const Model<T>& model, const RunOptions& options,
                   const std::function<void(const Sample<T>&)>& observer) {
  if (options.every < 1) throw InputError("RunOptions::every must be >= 1, got " + std::to_string(options.every));
  const double duration = model.simulation.duration;
  const double t0 = options.start_time;
  for (size_t i = 0; i < options.stops.size(); ++i) {
    if (!(options.stops[i] >= t0 && options.stops[i] <= t0 + duration * (1 + 1e-12)) ||
        (i > 0 && !(options.stops[i] > options.stops[i - 1]))) {
      throw InputError("RunOptions::stops must increase strictly and lie within the run's interval");
    }
  }
  RunReport report;
  State<T> start = InitialState(model);
  VecX<T>& q = start.q;
  VecX<T>& v = start.v;
  Workspace<T> ws(model, q, options.factor_jet_matrices);
  GainsInUse(model, &ws.alpha, &ws.beta);
  const double scale = LengthScale(model);
  const double h = model.simulation.step;
  CheckStepCount(model.simulation, "the simulation settings");
  const std::int64_t steps = StepCount(model.simulation);
  const bool project = model.stabilization.method == Stabilization::kProjection;
  const bool guard_singular = model.stabilization.method == Stabilization::kBaumgarte;

  AssembleInitialState(model, scale, &ws, &q, &v, &report);
  ws.coordinates = BuildJointCoordinates(model, q);

  const int num_coordinates = static_cast<int>(ws.coordinates.references.size());
  VecX<T> coordinates = VecX<T>::Zero(num_coordinates), rates = VecX<T>::Zero(num_coordinates);
  auto diverged = [&](double t, const std::string& what) {
    const Violation worst = LargestViolation(ws.infos, ws.rows);
    std::string message = "the simulation diverged at " + Seconds(t) + ": " + what;
    if (worst.scene_index >= 0) {
      std::ostringstream out;
      out << "; the worst constraint is " << DescribeConstraint(model, worst.scene_index) << ", violated by "
          << worst.largest << (model.dimension == 3 ? " (m, or rad for an axis)" : " m");
      message += out.str();
    }
    return SimulationDiverged(message, t, worst.scene_index);
  };
  // A violation above the scene's length scale: the run has left its constraints.
  auto check_violation = [&](double t, double largest) {
    if (largest <= scale) return;
    std::ostringstream out;
    out << "a constraint ran away (violation above the scene's length scale " << scale << " m)";
    throw diverged(t, out.str());
  };
  // Every sample is checked as it is made, the last one included (the steps' own checks see the rows of their
  // last stage, not of the state they end in).
  auto emit = [&](double t, bool output, int stop) {
    UpdateFrames(model, q, v, true, &ws.frames);
    EvaluateConstraintRows(model, ws.constraints, ws.frames, q, v, false, &ws.rows);
    const double error = ws.rows.empty() ? 0.0 : LargestViolation(ws.infos, ws.rows).largest;
    check_violation(t, error);
    for (int k = 0; k < num_coordinates; ++k) {
      const CoordinateRow<T> row = EvaluateCoordinate(model, ws.coordinates, k, ws.frames, q, v, true);
      coordinates[k] = row.value;
      rates[k] = row.rate;
    }
    observer(Sample<T>{t, q, v, error, Energy(model, ws.coordinates, ws.frames, q, v), coordinates, rates, ws.frames,
                       ws.rows, output, stop});
  };

  // After every integrator step (rk45: every internal step): the projection stabilization; or, for Baumgarte,
  // when the step's Schur factorizations saw a configuration near a singular one (schur_solver.h), the same
  // projection, adopted only when it converges (there it can stall a little above its rounding-level tolerance,
  // and the Baumgarte state is then kept as it is).
  VecX<T> q_projected = q, v_projected = v;
  const SettleState<T> settle = [&](double t, VecX<T>* q_now, VecX<T>* v_now) {
    bool changed = false;
    if (project) {
      if (!ProjectPositions(model, kProjectionTolerance * scale, &ws, q_now).converged ||
          !ProjectVelocities(model, *q_now, &ws, v_now)) {
        throw diverged(t, "the projection onto the constraints did not converge");
      }
      changed = true;
    } else if (guard_singular && ws.solver.saw_near_singular()) {
      q_projected = *q_now;
      v_projected = *v_now;
      if (ProjectPositions(model, kProjectionTolerance * scale, &ws, &q_projected).converged &&
          ProjectVelocities(model, q_projected, &ws, &v_projected)) {
        q_now->swap(q_projected);
        v_now->swap(v_projected);
        changed = true;
      }
    }
    ws.solver.ForgetConditioning();  // the next step starts afresh (the projection's own solves included)
    return changed;
  };

  // one step of the run, with its stabilization and divergence checks
  auto advance = [&](double t, double dt) {
    if (RunsCancelled()) throw RunInterrupted(Interrupted());
    ws.solver.ForgetConditioning();
    const StepStatus status = Advance(model, t, dt, &ws, &q, &v, settle);
    const double t_next = t + dt;
    if (status == StepStatus::kSolveFailed) throw diverged(t_next, "the constraint system became singular or non-finite");
    if (status == StepStatus::kStepSizeUnderflow) throw diverged(t_next, "rk45's step size collapsed");
    if (!AllFinite(q) || !AllFinite(v)) throw diverged(t_next, "the state became non-finite (NaN or infinity)");
    check_violation(t_next, LargestViolation(ws.infos, ws.rows).largest);
    if (num_coordinates > 0) {  // the branch of every hinge angle follows the motion step by step
      UpdateFrames(model, q, v, false, &ws.frames);
      TrackCoordinates(model, ws.frames, q, v, &ws.coordinates);
    }
  };

  // stops closer than this to a grid time are served by that grid time
  const double same_time = 1e-9 * h;
  const std::vector<double>& stops = options.stops;
  size_t next_stop = 0;
  auto stop_at = [&](double t) {
    return next_stop < stops.size() && std::abs(stops[next_stop] - t) <= same_time ? static_cast<int>(next_stop++) : -1;
  };

  emit(t0, true, stop_at(t0));
  for (std::int64_t k = 0; k < steps; ++k) {
    double t = t0 + static_cast<double>(k) * h;
    const double t_next = t0 + (k + 1 == steps ? duration : static_cast<double>(k + 1) * h);
    while (next_stop < stops.size() && stops[next_stop] < t_next - same_time) {  // step onto the stop
      advance(t, stops[next_stop] - t);
      t = stops[next_stop];
      emit(t, false, static_cast<int>(next_stop++));
    }
    advance(t, t_next - t);
    report.steps = k + 1;
    const bool output = (k + 1) % options.every == 0 || k + 1 == steps;
    const int stop = stop_at(t_next);
    if (output || stop >= 0) emit(t_next, output, stop);
  }
  // stops past the last grid time by no more than the rounding allowed above are served by the end state
  while (next_stop < stops.size()) emit(t0 + duration, false, static_cast<int>(next_stop++));
  return report;
}

#define TETHER_INSTANTIATE_SIMULATOR(T)                                                                       \
  template RunReport Simulate<T>(const Model<T>&, const RunOptions&, const std::function<void(const Sample<T>&)>&); \
  template double LengthScale<T>(const Model<T>&);                                                            \
  template State<T> AssembledInitialState<T>(const Model<T>&, RunReport*);                                    \
  template std::string DescribeConstraint<T>(const Model<T>&, int);
TETHER_FOR_EACH_SCALAR(TETHER_INSTANTIATE_SIMULATOR)

}  // namespace tether
