#include "trajectory_fit.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <limits>
#include <random>
#include <sstream>
#include <thread>

#include "fit_judgement.h"
#include "shooting_problem.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/model/errors.h"
#include "tether/tuning/task_threads.h"

namespace tether {
namespace {

constexpr double kUnbounded = std::numeric_limits<double>::max();
constexpr double kMargin = 10.0;  // MinimizeViolation aims this many tolerances inside an inequality
// Random starts lie within this fraction of each bounded box's half-width about its middle (or of |value| + 1
// about the value): full-width random torques jerk a motion about and start on the bounds (on the acrobot, no
// start of eight reached the target with full-width starts, one to three with 0.3).
constexpr double kStartSpread = 0.3;
// The polish minimizes the cost from a feasible point with this fraction of the budget.
constexpr int kPolishShare = 4;
// How far outside its box an unknown may lie, relative to the bound, for the reach to count as met.
constexpr double kBoxTolerance = 1e-8;

// What one start reached: single shooting's result from the scene's initial state.
struct Attempt {
  std::vector<double> estimate;  // parameters in their own units
  OptimizerResult optimizer;     // of the last (single-shooting) solve; evaluations and seconds of all
  int segments = 1;
};

bool Better(const Attempt& a, const Attempt& b) {  // a before b
  const bool feasible_a = a.optimizer.violation <= 1.0, feasible_b = b.optimizer.violation <= 1.0;
  if (feasible_a != feasible_b) return feasible_a;
  return feasible_a ? a.optimizer.value < b.optimizer.value : a.optimizer.violation < b.optimizer.violation;
}

// The constraint rows of a problem: its continuity rows (equalities) and its inequality targets.
ConstraintRows RowsOf(const ShootingProblem& problem, const IdentifySettings& settings) {
  ConstraintRows rows;
  for (int i = 0; i < problem.ContinuityCount(); ++i) {
    rows.equality.push_back(problem.DataCount() + i);
    rows.equality_tolerance.push_back(kContinuityTolerance);
  }
  for (int c = 0; c < problem.ConstraintCount(); ++c) {
    rows.inequality.push_back(problem.FirstConstraintRow() + c);
    rows.inequality_sign.push_back(problem.ConstraintSign(c));
    rows.inequality_tolerance.push_back(kConstraintTolerance * std::max(1.0, std::abs(settings.inequalities[c].value)));
  }
  return rows;
}

// Whether the violations v of MinimizeViolation (below) are all met: every equality within its tolerance, every
// inequality within its bound (not yet kMargin tolerances inside it), every unknown within 1e-8 of its box
// (relative; the result is clamped into it).
bool Met(const ConstraintRows& rows, const std::vector<double>& lower, const std::vector<double>& upper,
         const std::vector<int>& bounded, const Eigen::VectorXd& v) {
  const size_t equalities = rows.equality.size(), inequalities = rows.inequality.size();
  for (size_t e = 0; e < equalities; ++e) {
    if (std::abs(v[e]) > rows.equality_tolerance[e]) return false;
  }
  for (size_t c = 0; c < inequalities; ++c) {
    if (v[equalities + c] > kMargin * rows.inequality_tolerance[c]) return false;
  }
  for (size_t b = 0; b < bounded.size(); ++b) {
    const int i = bounded[b];
    const double bound = v[equalities + inequalities + b] > 0.0 ? upper[i] : lower[i];
    if (std::abs(v[equalities + inequalities + b]) > kBoxTolerance * std::max(1.0, std::abs(bound))) return false;
  }
  return true;
}

// Minimizes 1/2 sum of the squared violations by Levenberg-Marquardt: the equality rows, the inequality rows
// where they come within kMargin tolerances of their bound (so that the result meets them with room rather than
// on the kink of max(0, g)), and how far each unknown lies outside its bound (rows rather than Ceres' bounds, whose
// steps projected onto the box stall where many unknowns sit on their bounds, as a swing-up's torques do; the
// result is clamped into the box). It stops at the first point that meets every row (Met): minimizing on to zero
// cost only pushes the inequalities deeper inside their bounds, which the polish does not need (on the acrobot
// swing-up the single-shooting reach after the multiple-shooting one took up to 1000 evaluations; with the stop,
// 10 to 52 on seven of the eight starts). Its steps may raise the cost for a while (non-monotonic steps): with
// monotonic ones, 5 of the acrobot's 8 starts reached the upright, with them all 8.
OptimizerResult MinimizeViolation(const ResidualFunction& residuals, const ConstraintRows& rows,
                                  const std::vector<double>& start, const std::vector<double>& lower,
                                  const std::vector<double>& upper, const OptimizerSettings& settings) {
  const size_t n = start.size();
  std::vector<int> bounded;  // the unknowns with a finite bound, each a row
  for (size_t i = 0; i < n; ++i) {
    if (lower[i] != -kUnbounded || upper[i] != kUnbounded) bounded.push_back(static_cast<int>(i));
  }
  const size_t m = rows.equality.size() + rows.inequality.size() + bounded.size();
  std::vector<double> met;  // the first point seen that meets every row
  const ResidualFunction violations = [&](const std::vector<double>& x, Eigen::VectorXd* v, Eigen::MatrixXd* jacobian) {
    Eigen::VectorXd r;
    Eigen::MatrixXd j;
    if (!residuals(x, &r, jacobian ? &j : nullptr)) return false;
    v->setZero(m);
    if (jacobian) jacobian->setZero(m, n);
    for (size_t e = 0; e < rows.equality.size(); ++e) {
      (*v)[e] = r[rows.equality[e]];
      if (jacobian) jacobian->row(e) = j.row(rows.equality[e]);
    }
    for (size_t c = 0; c < rows.inequality.size(); ++c) {
      const size_t row = rows.equality.size() + c;
      const double sign = rows.inequality_sign[c], g = sign * r[rows.inequality[c]] + kMargin * rows.inequality_tolerance[c];
      if (!(g > 0.0)) continue;
      (*v)[row] = g;
      if (jacobian) jacobian->row(row) = sign * j.row(rows.inequality[c]);
    }
    for (size_t b = 0; b < bounded.size(); ++b) {  // how far an unknown lies outside its bound
      const size_t row = rows.equality.size() + rows.inequality.size() + b;
      const int i = bounded[b];
      const double below = lower[i] - x[i], above = x[i] - upper[i];
      if (below > 0.0) (*v)[row] = -below;
      if (above > 0.0) (*v)[row] = above;
      if (jacobian && (below > 0.0 || above > 0.0)) (*jacobian)(row, i) = 1.0;
    }
    if (met.empty() && Met(rows, lower, upper, bounded, *v)) met = x;
    return true;
  };
  OptimizerSettings lm = settings;
  lm.name = "ceres";
  lm.loss = RobustLoss{};
  // single shooting of a sensitive motion needs steps far below 1e-8 of the unknowns to close the last gap
  lm.relative_tolerance = 1e-15;
  lm.nonmonotonic_steps = true;
  lm.done = [&met] { return !met.empty(); };
  const std::vector<double> unbounded_lo(n, -kUnbounded), unbounded_hi(n, kUnbounded);
  OptimizerResult result = Minimize(violations, start, unbounded_lo, unbounded_hi, lm);
  if (!met.empty()) result.x = met;
  for (size_t i = 0; i < n; ++i) result.x[i] = std::clamp(result.x[i], lower[i], upper[i]);
  return result;
}

// A shooting problem with `segments` segments at `model`'s values, with its box and its residual function.
struct Shooting {
  Shooting(const Model<double>& model, const ParameterSet& parameters, const std::vector<Observations>& recordings,
           const IdentifySettings& settings, int segments, ShootingProblem::StartRows start_rows, IdleCores* idle)
      : with_segments(WithSegments(settings, segments)),
        problem(model, parameters, recordings, with_segments, start_rows, idle) {
    problem.Box(&lower, &upper);
  }
  Shooting(const Shooting&) = delete;
  Shooting& operator=(const Shooting&) = delete;

  static IdentifySettings WithSegments(IdentifySettings settings, int segments) {
    settings.segments = segments;
    return settings;
  }
  const IdentifySettings with_segments;  // the problem refers to it
  const ShootingProblem problem;
  std::vector<double> lower, upper;
  const ResidualFunction residuals = [this](const std::vector<double>& x, Eigen::VectorXd* r,
                                            Eigen::MatrixXd* jacobian) { return problem.Evaluate(x, r, jacobian); };
};

// Shooting with `segments` segments (1: one run) from `model`'s values: the constraints alone (continuity and the
// inequality targets) met by Levenberg-Marquardt. The parameters found.
std::vector<double> Reach(const Model<double>& model, const ParameterSet& parameters,
                          const std::vector<Observations>& recordings, const IdentifySettings& settings, int segments,
                          IdleCores* idle, int* evaluations) {
  const Shooting s(model, parameters, recordings, settings, segments, ShootingProblem::StartRows::kOnTheConstraints,
                   idle);
  const OptimizerResult reached =
      MinimizeViolation(s.residuals, RowsOf(s.problem, settings), s.problem.Start(), s.lower, s.upper,
                        settings.optimizer);
  *evaluations += reached.evaluations;
  return s.problem.Parameters(reached.x);
}

// Single shooting from `model`'s values: the cost minimized subject to the inequality targets (SLSQP).
OptimizerResult Polish(const Model<double>& model, const ParameterSet& parameters,
                       const std::vector<Observations>& recordings, const IdentifySettings& settings, IdleCores* idle,
                       std::vector<double>* estimate) {
  const Shooting s(model, parameters, recordings, settings, 1, ShootingProblem::StartRows::kContinuityOnly, idle);
  OptimizerSettings polish = settings.optimizer;
  polish.max_evaluations = std::max(50, settings.optimizer.max_evaluations / kPolishShare);
  OptimizerResult result =
      MinimizeConstrained(s.residuals, RowsOf(s.problem, settings), s.problem.Start(), s.lower, s.upper, polish);
  *estimate = s.problem.Parameters(result.x);
  return result;
}

// One start: reach by multiple shooting with `segments` (when > 1), reach by single shooting, polish.
Attempt Run(const Model<double>& start, const ParameterSet& parameters, const std::vector<Observations>& recordings,
            const IdentifySettings& settings, int segments, IdleCores* idle) {
  Attempt attempt;
  attempt.segments = segments;
  Model<double> model = start;
  int evaluations = 0;
  const auto begin = std::chrono::steady_clock::now();
  // the constraints first by multiple shooting, then by single shooting from there (one run from the scene's
  // initial state can part from the joined segments by their gaps grown along the motion)
  std::vector<int> reaches = {1};
  if (segments > 1) reaches.insert(reaches.begin(), segments);
  for (const int k : reaches) {
    if (k == 1 && settings.inequalities.empty()) break;  // nothing to reach: the polish fits the targets
    try {
      parameters.Assign(Reach(model, parameters, recordings, settings, k, idle, &evaluations), &model);
    } catch (const InputError&) {  // the start diverges: the polish says so below
    }
  }
  try {
    attempt.optimizer = Polish(model, parameters, recordings, settings, idle, &attempt.estimate);
  } catch (const InputError& e) {  // single shooting cannot start from what multiple shooting found
    attempt.estimate = parameters.Values(model);
    attempt.optimizer.violation = INFINITY;
    attempt.optimizer.value = INFINITY;
    attempt.optimizer.message = e.what();
  }
  attempt.optimizer.evaluations += evaluations;
  attempt.optimizer.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  return attempt;
}

// Start s: the scene's values (s = 0) or a random point (trajectory_fit.h).
std::vector<std::vector<double>> StartValues(const Model<double>& model, const ParameterSet& parameters,
                                             const IdentifySettings& settings) {
  const std::vector<double> values = parameters.Values(model);
  std::vector<std::vector<double>> starts = {values};
  std::mt19937_64 random(settings.seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int s = 1; s < settings.starts; ++s) {
    std::vector<double> x(values.size());
    for (size_t i = 0; i < values.size(); ++i) {
      const double lo = settings.bounds.empty() ? -kUnbounded : settings.bounds[i].first;
      const double hi = settings.bounds.empty() ? kUnbounded : settings.bounds[i].second;
      const bool positive = FittedInLogSpace(parameters, static_cast<int>(i), values[i], settings);
      const double u = kStartSpread * unit(random);
      if (lo != -kUnbounded && hi != kUnbounded) {
        x[i] = positive ? std::exp(0.5 * (std::log(lo) + std::log(hi)) + 0.5 * u * (std::log(hi) - std::log(lo)))
                        : 0.5 * (lo + hi) + 0.5 * u * (hi - lo);
      } else {
        x[i] = positive ? values[i] * std::exp(u) : values[i] + u * (std::abs(values[i]) + 1.0);
      }
      x[i] = std::clamp(x[i], lo, hi);
    }
    starts.push_back(x);
  }
  return starts;
}

}  // namespace

std::vector<InequalityTarget> AtEveryStep(const std::vector<InequalityTarget>& targets, double step,
                                          double duration, std::vector<int>* origin) {
  std::vector<InequalityTarget> out;
  origin->clear();
  for (size_t i = 0; i < targets.size(); ++i) {
    const InequalityTarget& target = targets[i];
    if (target.from == target.time) {
      out.push_back(target);
      origin->push_back(static_cast<int>(i));
      continue;
    }
    if (target.from < 0.0 || target.time > duration) {
      std::ostringstream message;
      message << target.text << ": the interval must lie within the run [0, " << duration << "] s";
      throw InputError(message.str());
    }
    const size_t before = out.size();
    // the step times within [from, time], to a rounding of 1e-9 steps (as the simulator's stops)
    for (long k = std::lround(std::ceil(target.from / step - 1e-9)); k * step <= target.time + 1e-9 * step; ++k) {
      InequalityTarget at = target;
      at.time = at.from = k * step;
      out.push_back(at);
      origin->push_back(static_cast<int>(i));
    }
    if (out.size() == before) {
      std::ostringstream message;
      message << target.text << ": no integrator step (of " << step << " s) lies within the interval";
      throw InputError(message.str());
    }
  }
  return out;
}

int AutomaticSegments(const ParameterSet& parameters, const std::vector<Observations>& recordings,
                      const IdentifySettings& settings) {
  double end = 0.0;
  for (const Observations& r : recordings) end = std::max(end, r.times.back());
  for (const InequalityTarget& target : settings.inequalities) end = std::max(end, target.time);
  double knot = INFINITY;
  for (int i = 0; i < parameters.size(); ++i) {
    const std::optional<ScheduleKnot>& of = parameters.number(i).knot;
    for (size_t j = 0; of && j + 1 < of->times.size(); ++j) knot = std::min(knot, of->times[j + 1] - of->times[j]);
  }
  if (!std::isfinite(knot) || !(end > 0.0)) return 10;
  return std::clamp(static_cast<int>(std::lround(end / (4.0 * knot))), 2, 20);
}

IdentifyResult FitTrajectory(const Model<double>& model, const ParameterSet& parameters,
                             const std::vector<Observations>& recordings, const IdentifySettings& given) {
  const auto begin = std::chrono::steady_clock::now();
  std::vector<int> origin;  // the path constraints as a constraint at every step
  IdentifySettings settings = given;
  settings.inequalities = AtEveryStep(given.inequalities, model.simulation.step, model.simulation.duration, &origin);
  IdentifyResult result;
  result.initial = parameters.Values(model);
  CheckStartWithinBounds(parameters, result.initial, settings);
  if (!settings.inequalities.empty()) CheckConstrainedOptimizer(settings.optimizer.name);
  IdentifySettings single = settings;
  single.segments = 1;
  const ShootingProblem at_scene(model, parameters, recordings, single);  // checks the targets before any run

  const std::vector<std::vector<double>> starts = StartValues(model, parameters, settings);
  const int automatic = settings.segments == 0 ? AutomaticSegments(parameters, recordings, settings) : 0;
  IdentifySettings trial = settings;  // where fit chooses: single shooting first, on an eighth of the budget
  trial.optimizer.max_evaluations = std::max(50, settings.optimizer.max_evaluations / 8);
  std::vector<Attempt> attempts(starts.size());
  // each start a task; a core its thread leaves idle takes part in the Jacobians of the starts still running
  IdleCores idle;
  std::vector<std::function<void()>> tasks;
  for (size_t s = 0; s < starts.size(); ++s) {
    tasks.push_back([&, s] {
      Model<double> start = model;
      parameters.Assign(starts[s], &start);
      if (settings.segments > 0) {
        attempts[s] = Run(start, parameters, recordings, settings, settings.segments, &idle);
        return;
      }
      attempts[s] = Run(start, parameters, recordings, trial, 1, &idle);
      // met: polished on the whole budget from there; not met: multiple shooting from the start
      const bool met = attempts[s].optimizer.violation <= 1.0;
      Model<double> from = start;
      if (met) parameters.Assign(attempts[s].estimate, &from);
      Attempt next = Run(from, parameters, recordings, settings, met ? 1 : automatic, &idle);
      next.optimizer.evaluations += attempts[s].optimizer.evaluations;
      next.optimizer.seconds += attempts[s].optimizer.seconds;
      if (Better(next, attempts[s])) attempts[s] = next;
    });
  }
  RunTasks(tasks, std::min<int>(static_cast<int>(starts.size()), std::max(1u, std::thread::hardware_concurrency())),
           &idle);

  int best = 0;
  for (int s = 1; s < static_cast<int>(attempts.size()); ++s) {
    if (Better(attempts[s], attempts[best])) best = s;
  }
  const Attempt& kept = attempts[best];
  result.estimate = kept.estimate;
  result.optimizer = kept.optimizer;
  result.optimizer.evaluations = 0;
  for (const Attempt& a : attempts) result.optimizer.evaluations += a.optimizer.evaluations;
  result.optimizer.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  result.gradient_method = "jet";
  result.segments = kept.segments;
  result.starts = static_cast<int>(attempts.size());
  result.best_start = best;
  result.feasible_starts = static_cast<int>(
      std::count_if(attempts.begin(), attempts.end(), [](const Attempt& a) { return a.optimizer.violation <= 1.0; }));

  // the report: one run of the estimate from the scene's initial state, as a written scene runs
  const int p = parameters.size();
  std::vector<double> x(p);
  for (int i = 0; i < p; ++i) x[i] = at_scene.ToUnknown(i, result.initial[i]);
  Eigen::VectorXd r;
  const auto objective = [&](const Eigen::VectorXd& rows) {
    double cost = 0.0;
    for (int i = 0; i < at_scene.FirstConstraintRow(); ++i) cost += 0.5 * rows[i] * rows[i];
    return cost;
  };
  result.initial_cost = at_scene.Evaluate(x, &r, nullptr) ? objective(r) : INFINITY;
  Model<double> estimated = model;
  parameters.Assign(result.estimate, &estimated);
  const ShootingProblem at_estimate(estimated, parameters, recordings, single);
  for (int i = 0; i < p; ++i) x[i] = at_estimate.ToUnknown(i, result.estimate[i]);
  result.standard_deviation.assign(p, NAN);
  result.correlation = Eigen::MatrixXd::Constant(p, p, NAN);
  result.condition_number = NAN;
  result.residual_count = at_estimate.FirstConstraintRow();
  if (!at_estimate.Evaluate(x, &r, nullptr)) {
    result.failed = true;
    result.feasible = false;
    result.stopping_reason = "infeasible";
    result.final_cost = INFINITY;
    result.warnings.push_back("the best estimate diverges when run from the scene's initial state");
    return result;
  }
  result.final_cost = objective(r);
  result.residuals = at_estimate.Statistics(x);
  double worst = 0.0;
  std::string worst_text;
  // each target as given, at its step closest to (or furthest past) its bound where it is an interval
  std::vector<double> closest(given.inequalities.size(), -INFINITY);
  result.constraints.resize(given.inequalities.size());
  for (int c = 0; c < at_estimate.ConstraintCount(); ++c) {
    const InequalityTarget& target = settings.inequalities[c];
    const double residual = r[at_estimate.FirstConstraintRow() + c];
    const double violation = at_estimate.ConstraintSign(c) * residual /
                             (kConstraintTolerance * std::max(1.0, std::abs(target.value)));
    if (violation > closest[origin[c]]) {
      closest[origin[c]] = violation;
      result.constraints[origin[c]] = {given.inequalities[origin[c]], target.value + residual, target.time,
                                       violation <= 1.0};
    }
    if (violation > worst) {
      worst = violation;
      std::ostringstream text;
      text << target.text << " (simulated " << target.value + residual << " at t = " << target.time << ")";
      worst_text = text.str();
    }
  }
  result.feasible = worst <= 1.0;
  result.stopping_reason = !result.feasible ? "infeasible" : kept.optimizer.hit_limit ? "iteration limit" : "converged";
  if (!result.feasible) {
    std::ostringstream message;
    message << "the constraints are not met: of " << result.starts << " start" << (result.starts > 1 ? "s" : "")
            << ", none reached them; the closest result misses " << worst_text << " (optimizer: "
            << kept.optimizer.message << ")";
    result.warnings.push_back(message.str());
  }
  const FitJudgement judgement = JudgeFit(recordings, result.residuals, {}, LengthScale(model), kept.optimizer);
  result.warnings.insert(result.warnings.end(), judgement.warnings.begin(), judgement.warnings.end());
  result.failed = !result.feasible || judgement.failed;
  return result;
}

}  // namespace tether
