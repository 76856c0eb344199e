#include "tether/tuning/identification.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <type_traits>

#include "tether/autodiff/adjoint.h"
#include "tether/autodiff/residuals.h"
#include "tether/dynamics/configuration_space.h"
#include "tether/dynamics/errors.h"
#include "tether/dynamics/simulator.h"
#include "tether/dynamics/trajectory.h"
#include "fit_judgement.h"

namespace tether {
namespace {

using Kind = FieldRef::Kind;
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

// Everything Identify needs to turn unknowns into residuals.
class ShootingProblem {
 public:
  ShootingProblem(const Model<double>& model, const ParameterSet& parameters, const std::vector<Observations>& recordings,
                  const IdentifySettings& settings)
      : model_(model), parameters_(parameters), recordings_(recordings), settings_(settings) {
    const std::vector<double> values = parameters.Values(model);
    for (int i = 0; i < parameters.size(); ++i) {
      const bool lower_positive = settings.bounds.empty() || settings.bounds[i].first > 0 ||
                                  settings.bounds[i].first == -kUnbounded;
      log_space_.push_back(PositiveKind(parameters.field(i).kind) && values[i] > 0 && lower_positive);
    }
    double end = 0.0;
    for (const Observations& r : recordings) end = std::max(end, r.times.back());
    if (!(end > 0.0)) throw InputError("the data has no observation after t = 0: there is nothing to fit");
    const int segments = std::max(1, settings.segments);
    for (int k = 0; k <= segments; ++k) boundaries_.push_back(end * k / segments);
    state_size_ = 2 * model.NumVelocities();
    if (segments > 1) references_ = SegmentStarts();
    // the smoothing pairs: consecutive values of one schedule component
    for (int a = 0; a < parameters.size(); ++a) {
      for (int b = 0; b < parameters.size(); ++b) {
        const FieldRef &fa = parameters.field(a), &fb = parameters.field(b);
        const bool schedule = fa.kind == Kind::kForceSchedule || fa.kind == Kind::kTorqueSchedule ||
                              fa.kind == Kind::kJointTorqueSchedule;
        if (schedule && fb.kind == fa.kind && fb.index == fa.index && fb.component == fa.component &&
            fb.slot == fa.slot + 1) {
          smooth_pairs_.push_back({a, b});
        }
      }
    }
  }

  int Unknowns() const { return parameters_.size() + (Segments() - 1) * state_size_; }
  int Segments() const { return static_cast<int>(boundaries_.size()) - 1; }
  bool LogSpace(int i) const { return log_space_[i]; }

  // unknowns <-> parameters (in their own units)
  double ToUnknown(int i, double p) const { return log_space_[i] ? std::log(p) : p; }
  double ToParameter(int i, double x) const { return log_space_[i] ? std::exp(x) : x; }

  // The starting unknowns: the scene's parameters and, for multiple shooting, the segments' start states as
  // offsets from their references (zero) and velocities.
  std::vector<double> Start() const {
    std::vector<double> x;
    const std::vector<double> values = parameters_.Values(model_);
    for (int i = 0; i < parameters_.size(); ++i) x.push_back(ToUnknown(i, values[i]));
    for (const State<double>& reference : references_) {
      for (int i = 0; i < reference.v.size(); ++i) x.push_back(0.0);
      for (int i = 0; i < reference.v.size(); ++i) x.push_back(reference.v[i]);
    }
    return x;
  }

  // Residuals at unknowns x, and their Jacobian when asked (Jets in chunks of kJetStride unknowns).
  bool Evaluate(const std::vector<double>& x, Eigen::VectorXd* r, Eigen::MatrixXd* jacobian) const {
    Model<double> guess = model_;
    for (int i = 0; i < parameters_.size(); ++i) parameters_.Field(&guess, i) = ToParameter(i, x[i]);
    parameters_.ApplyTies(&guess);
    try {
      if (!jacobian) {
        const std::vector<double> values = Residuals<double>(CastModel<double>(guess), x, -1);
        *r = Eigen::Map<const Eigen::VectorXd>(values.data(), values.size());
        return true;
      }
      const int n = Unknowns();
      for (int first = 0; first < n; first += kJetStride) {
        const std::vector<Jet> values = Residuals<Jet>(CastModel<Jet>(guess), x, first);
        if (first == 0) {
          r->resize(values.size());
          jacobian->setZero(values.size(), n);
          for (size_t i = 0; i < values.size(); ++i) (*r)[i] = values[i].a;
        }
        for (int k = 0; k < kJetStride && first + k < n; ++k) {
          for (size_t i = 0; i < values.size(); ++i) (*jacobian)(i, first + k) = values[i].v[k];
        }
      }
      return true;
    } catch (const SimulationDiverged&) {
      return false;
    } catch (const InputError&) {  // a trial start state that cannot be assembled onto the constraints
      return false;
    }
  }

  // The cost 1/2 sum rho(r_i^2) at x over the data and smoothing residuals, and its gradient with respect to x,
  // by the adjoint: single shooting, whose unknowns are the parameters. False where the run diverges.
  bool CostGradient(const std::vector<double>& x, const RobustLoss& loss, double* cost,
                    std::vector<double>* gradient) const {
    Model<double> guess = TruncatedModel(model_, 0);
    for (int i = 0; i < parameters_.size(); ++i) parameters_.Field(&guess, i) = ToParameter(i, x[i]);
    parameters_.ApplyTies(&guess);
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
    std::vector<double>& g = data.gradient;
    const double weight = std::sqrt(settings_.smooth);
    for (const auto& [a, b] : smooth_pairs_) {  // r = w (p_b - p_a)
      const double pa = parameters_.Field(&guess, a), pb = parameters_.Field(&guess, b);
      const double r = weight * (pb - pa);
      double rho[2];
      EvaluateLoss(loss, r * r, rho);
      *cost += 0.5 * rho[0];
      g[b] += rho[1] * r * weight;
      g[a] -= rho[1] * r * weight;
    }
    gradient->resize(x.size());
    for (int i = 0; i < parameters_.size(); ++i) {  // d p / d x: p for log p, 1 otherwise
      (*gradient)[i] = g[i] * (log_space_[i] ? ToParameter(i, x[i]) : 1.0);
    }
    return true;
  }

  // The data residuals at x grouped per recording and column, for the report.
  std::vector<ResidualStatistics> Statistics(const std::vector<double>& x) const {
    Model<double> guess = model_;
    for (int i = 0; i < parameters_.size(); ++i) parameters_.Field(&guess, i) = ToParameter(i, x[i]);
    parameters_.ApplyTies(&guess);
    std::vector<ResidualStatistics> stats;
    for (const Observations& r : recordings_) {
      for (const TrajectoryColumn& c : r.columns) stats.push_back({r.path, c.name});
    }
    DataResiduals<double>(guess, x, -1, [&stats](size_t group, double residual) {
      ResidualStatistics& s = stats[group];
      ++s.count;
      s.rms += residual * residual;
      s.largest = std::max(s.largest, std::abs(residual));
    });
    for (ResidualStatistics& s : stats) s.rms = s.count ? std::sqrt(s.rms / s.count) : 0.0;
    return stats;
  }

 private:
  // The model covering segment k: its duration ends at the next boundary.
  template <typename T>
  Model<T> TruncatedModel(const Model<T>& model, int k) const {
    Model<T> out = model;
    out.simulation.duration = boundaries_[k + 1] - boundaries_[k];
    return out;
  }

  // Segment start states (references) from the initial-guess run, with the observed coordinates replaced by the
  // data nearest in time; a start state's unknowns are its offset d from the reference, q = q_ref (+) d, and v.
  std::vector<State<double>> SegmentStarts() const {
    const std::vector<double> starts(boundaries_.begin() + 1, boundaries_.end() - 1);
    Model<double> whole = model_;
    whole.simulation.duration = boundaries_.back();
    std::vector<State<double>> guess(starts.size(), InitialState(model_));
    RunOptions options;
    options.every = std::numeric_limits<int>::max();
    options.stops = starts;
    try {
      const Trajectory<double> run = Record(whole, options, RecordWhat::kStops);
      for (size_t k = 0; k < starts.size(); ++k) guess[k] = {run.q[k], run.v[k]};
    } catch (const SimulationDiverged&) {  // the guess diverges: start every segment from the initial state
    }
    for (size_t k = 0; k < starts.size(); ++k) ReplaceByData(starts[k], &guess[k].q, &guess[k].v);
    return guess;
  }

  void ReplaceByData(double t, VecX<double>* q, VecX<double>* v) const {
    using Kind = TrajectoryColumn::Kind;
    for (const Observations& r : recordings_) {
      size_t nearest = 0;
      for (size_t row = 1; row < r.times.size(); ++row) {
        if (std::abs(r.times[row] - t) < std::abs(r.times[nearest] - t)) nearest = row;
      }
      for (size_t c = 0; c < r.columns.size(); ++c) {
        const double value = r.values[nearest][c];
        if (std::isnan(value)) continue;
        const TrajectoryColumn& column = r.columns[c];
        if (column.kind == Kind::kVelocity) (*v)[column.index] = value;
        if (column.kind != Kind::kConfiguration) continue;
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

  // Calls add(group, residual) for every data residual (group: recording x column, as in Statistics), in a fixed
  // order; returns the end state of every segment but the last (for the continuity residuals).
  template <typename T, typename Add>
  std::vector<State<T>> DataResiduals(const Model<T>& model, const std::vector<double>& x, int first_seeded,
                                      Add add) const {
    std::vector<State<T>> ends;
    const int n_params = parameters_.size();
    for (int k = 0; k < Segments(); ++k) {
      Model<T> segment = TruncatedModel(model, k);
      if (k > 0) {  // this segment's start state is an unknown
        const State<T> start = SegmentStart(model, x, n_params + (k - 1) * state_size_, k - 1, first_seeded);
        segment = WithInitialState(segment, start.q, start.v);
      }
      const double begin = boundaries_[k], end = boundaries_[k + 1];
      auto inside = [&](double t) { return (t > begin || (k == 0 && t == begin)) && t <= end; };
      std::vector<double> times;  // every recording's times in (begin, end] (and t = 0 in the first segment)
      for (const Observations& r : recordings_) {
        for (double t : r.times) {
          if (inside(t)) times.push_back(t);
        }
      }
      times.push_back(end);
      std::sort(times.begin(), times.end());
      times.erase(std::unique(times.begin(), times.end()), times.end());
      // the residuals are added in recording, row, column order: collect them per stop first
      std::vector<std::vector<std::vector<std::pair<size_t, T>>>> cells(recordings_.size());
      for (size_t i = 0; i < recordings_.size(); ++i) cells[i].resize(recordings_[i].times.size());
      RunOptions options;
      options.every = std::numeric_limits<int>::max();
      options.start_time = begin;
      options.stops = times;
      State<T> last;
      Simulate<T>(segment, options, [&](const Sample<T>& s) {
        if (s.stop < 0) return;
        const double t = times[s.stop];
        for (size_t i = 0; i < recordings_.size(); ++i) {
          const Observations& r = recordings_[i];
          const auto row = std::lower_bound(r.times.begin(), r.times.end(), t);
          if (row == r.times.end() || *row != t || !inside(t)) continue;
          const size_t index = row - r.times.begin();
          ObservedResiduals(segment, r, index, s, [&](size_t c, const T& value) { cells[i][index].push_back({c, value}); });
        }
        if (s.stop + 1 == static_cast<int>(times.size())) last = {s.q, s.v};
      });
      size_t group = 0;
      for (size_t i = 0; i < recordings_.size(); ++i) {
        for (const auto& row : cells[i]) {
          for (const auto& [c, value] : row) add(group + c, value);
        }
        group += recordings_[i].columns.size();
      }
      if (k + 1 < Segments()) ends.push_back(last);
    }
    return ends;
  }

  // Segment (reference + 1)'s start state from the unknowns at x[offset ..]: q_ref (+) d and v.
  template <typename T>
  State<T> SegmentStart(const Model<T>& model, const std::vector<double>& x, int offset, int reference,
                        int first_seeded) const {
    const int nv = model.NumVelocities();
    VecX<T> d(nv), v(nv);
    for (int i = 0; i < 2 * nv; ++i) {
      T value(x[offset + i]);
      SeedUnknown(offset + i, first_seeded, &value);
      (i < nv ? d[i] : v[i - nv]) = value;
    }
    State<T> start;
    start.q.resize(model.NumCoordinates());
    Integrate(model, VecX<T>(references_[reference].q.template cast<T>()), d, 1.0, &start.q);
    start.v = v;
    return start;
  }

  // Seeds derivative direction (unknown - first_seeded) when that unknown is in the current chunk.
  template <typename T>
  static void SeedUnknown(int unknown, int first_seeded, T* value) {
    if constexpr (IsJet<T>::value) {
      if (first_seeded >= 0 && unknown >= first_seeded && unknown < first_seeded + kJetStride) {
        value->v[unknown - first_seeded] = 1.0;
      }
    }
  }

  template <typename T>
  std::vector<T> Residuals(Model<T> model, const std::vector<double>& x, int first_seeded) const {
    for (int i = 0; i < parameters_.size(); ++i) {  // d p / d x: p for log p, 1 otherwise
      T& field = parameters_.Field(&model, i);
      if constexpr (IsJet<T>::value) {
        if (first_seeded >= 0 && i >= first_seeded && i < first_seeded + kJetStride) {
          field.v[i - first_seeded] = log_space_[i] ? field.a : 1.0;
        }
      }
    }
    parameters_.ApplyTies(&model);  // the tied fields follow the seeded ones
    std::vector<T> out;
    const auto ends = DataResiduals<T>(model, x, first_seeded, [&out](size_t, const T& r) { out.push_back(r); });
    // continuity: end of segment k (-) start of segment k + 1
    const int nv = model.NumVelocities();
    VecX<T> gap(nv);
    for (size_t k = 0; k < ends.size(); ++k) {
      const State<T> start =
          SegmentStart(model, x, parameters_.size() + static_cast<int>(k) * state_size_, static_cast<int>(k), first_seeded);
      Difference(model, start.q, ends[k].q, &gap);
      for (int i = 0; i < nv; ++i) out.push_back(gap[i]);
      for (int i = 0; i < nv; ++i) out.push_back(ends[k].v[i] - start.v[i]);
    }
    const double weight = std::sqrt(settings_.smooth);
    for (const auto& [a, b] : smooth_pairs_) {
      out.push_back(T(weight) * (parameters_.Field(&model, b) - parameters_.Field(&model, a)));
    }
    return out;
  }

  const Model<double>& model_;
  const ParameterSet& parameters_;
  const std::vector<Observations>& recordings_;
  const IdentifySettings& settings_;
  std::vector<bool> log_space_;
  std::vector<double> boundaries_;
  int state_size_ = 0;                    // unknowns per segment start: an offset d and a velocity (2 nv)
  std::vector<State<double>> references_;  // the start states the offsets are taken from
  std::vector<std::pair<int, int>> smooth_pairs_;
};

std::string Names(const ParameterSet& parameters, const Eigen::VectorXd& direction) {
  std::string names;
  for (int i = 0; i < parameters.size(); ++i) {
    if (std::abs(direction[i]) > 0.3) names += (names.empty() ? "" : ", ") + parameters.pointers()[i];
  }
  return names;
}

// The gradients the optimizer takes (identification.h: Derivatives): the adjoint's, or none (the residual
// function's Jacobian by Jets, or no derivatives at all); *used names the method.
CostGradientFunction CostGradientOf(const ShootingProblem& problem, const IdentifySettings& settings,
                                    std::string* used) {
  const std::string& optimizer = settings.optimizer.name;
  const bool gradient_based = UsesGradients(optimizer);
  if (settings.method == GradientMethod::kCentral) {
    throw InputError("--method fd: identify and fit take derivatives by jet or adjoint (or auto)");
  }
  if (settings.method == GradientMethod::kAdjoint && !gradient_based) {
    throw InputError("--method adjoint: the adjoint gives the cost's gradient, which only a gradient-based NLopt "
                     "algorithm takes (nlopt:LD_LBFGS, nlopt:LD_MMA, ...); --optimizer " + optimizer +
                     (optimizer == "ceres" ? " needs the residuals' Jacobian (Jets)" : " uses no derivatives"));
  }
  if (settings.method == GradientMethod::kAdjoint && problem.Segments() > 1) {
    throw InputError("--method adjoint: multiple shooting (--segments) takes its derivatives by Jets");
  }
  const bool adjoint = gradient_based && problem.Segments() == 1 &&
                       ResolveGradientMethod(settings.method, problem.Unknowns()) == GradientMethod::kAdjoint;
  *used = adjoint ? "adjoint" : gradient_based || optimizer == "ceres" ? "jet" : "none";
  if (!adjoint) return nullptr;
  return [&problem, &settings](const std::vector<double>& x, double* cost, std::vector<double>* gradient) {
    return problem.CostGradient(x, settings.optimizer.loss, cost, gradient);
  };
}

}  // namespace

LossGradient IdentifyCostGradient(const Model<double>& model, const ParameterSet& parameters,
                                  const std::vector<Observations>& recordings, const IdentifySettings& settings,
                                  GradientMethod method) {
  IdentifySettings single = settings;
  single.segments = 1;
  const ShootingProblem problem(model, parameters, recordings, single);
  const std::vector<double> x = problem.Start();
  LossGradient result;
  if (ResolveGradientMethod(method, parameters.size()) == GradientMethod::kAdjoint) {
    if (!problem.CostGradient(x, settings.optimizer.loss, &result.loss, &result.gradient)) {
      throw SimulationDiverged("the simulation diverges at the scene's parameters", 0.0, -1);
    }
  } else {
    Eigen::VectorXd r;
    Eigen::MatrixXd jacobian;
    if (!problem.Evaluate(x, &r, &jacobian)) {
      throw SimulationDiverged("the simulation diverges at the scene's parameters", 0.0, -1);
    }
    Eigen::VectorXd weight(r.size());  // d(1/2 rho(r_i^2))/dr_i = rho'(r_i^2) r_i
    for (int i = 0; i < r.size(); ++i) {
      double rho[2];
      EvaluateLoss(settings.optimizer.loss, r[i] * r[i], rho);
      result.loss += 0.5 * rho[0];
      weight[i] = rho[1] * r[i];
    }
    const Eigen::VectorXd g = jacobian.transpose() * weight;
    result.gradient.assign(g.data(), g.data() + g.size());
  }
  for (int i = 0; i < parameters.size(); ++i) {  // d/dp = d/dx dx/dp: 1/p for log p
    if (problem.LogSpace(i)) result.gradient[i] /= problem.ToParameter(i, x[i]);
  }
  return result;
}

bool PositiveKind(FieldRef::Kind kind) {
  switch (kind) {
    case Kind::kMass:
    case Kind::kInertia:
    case Kind::kInertiaMoment:
    case Kind::kJointLength:
    case Kind::kJointSpringStiffness:
    case Kind::kJointSpringDamping:
    case Kind::kSpringStiffness:
    case Kind::kSpringRestLength:
    case Kind::kSpringDamping:
    case Kind::kDampingCoefficient:
    case Kind::kDampingAngular:
      return true;
    default:
      return false;
  }
}

IdentifyResult Identify(const Model<double>& model, const ParameterSet& parameters,
                        const std::vector<Observations>& recordings, const IdentifySettings& settings) {
  const ShootingProblem problem(model, parameters, recordings, settings);
  const int n = problem.Unknowns(), p = parameters.size();
  IdentifyResult result;
  result.initial = parameters.Values(model);

  std::vector<double> lower(n, -kUnbounded), upper(n, kUnbounded);
  for (int i = 0; i < p && !settings.bounds.empty(); ++i) {
    const auto [lo, hi] = settings.bounds[i];
    if (!(result.initial[i] >= lo && result.initial[i] <= hi)) {
      std::ostringstream message;
      message << "--bound " << parameters.pointers()[i] << ": the scene's value " << result.initial[i]
              << " lies outside [" << lo << ", " << hi << "]";
      throw InputError(message.str());
    }
    if (lo != -kUnbounded) lower[i] = problem.LogSpace(i) ? std::log(lo) : lo;
    if (hi != kUnbounded) upper[i] = problem.ToUnknown(i, hi);
  }
  const bool global = settings.optimizer.name.rfind("nlopt:G", 0) == 0;
  if (global) {
    for (int i = 0; i < n; ++i) {
      if (lower[i] == -kUnbounded || upper[i] == kUnbounded) {
        throw InputError("--optimizer " + settings.optimizer.name +
                         ": a global optimizer needs finite bounds (--bound PTR=LO:HI) on every parameter, and single "
                         "shooting");
      }
    }
  }

  const ResidualFunction residuals = [&problem](const std::vector<double>& x, Eigen::VectorXd* r,
                                                Eigen::MatrixXd* jacobian) { return problem.Evaluate(x, r, jacobian); };
  const std::vector<double> start = problem.Start();
  Eigen::VectorXd r0;
  if (!residuals(start, &r0, nullptr)) {
    throw InputError("the simulation diverges at the initial parameters; give a better initial guess or use --segments");
  }
  result.initial_cost = RobustCost(settings.optimizer.loss, r0);
  result.optimizer = Minimize(residuals, start, lower, upper, settings.optimizer,
                              CostGradientOf(problem, settings, &result.gradient_method));
  const std::vector<double>& x = result.optimizer.x;
  for (int i = 0; i < p; ++i) result.estimate.push_back(problem.ToParameter(i, x[i]));
  Eigen::VectorXd r;
  residuals(x, &r, nullptr);
  result.final_cost = RobustCost(settings.optimizer.loss, r);
  result.residual_count = static_cast<int>(r.size());
  result.residuals = problem.Statistics(x);

  // uncertainty, with the parameters in their own units: J_p = J_x dx/dp
  const ResidualFunction in_own_units = [&](const std::vector<double>& y, Eigen::VectorXd* res, Eigen::MatrixXd* jac) {
    std::vector<double> unknowns = y;
    for (int i = 0; i < p; ++i) unknowns[i] = problem.ToUnknown(i, y[i]);
    if (!residuals(unknowns, res, jac)) return false;
    if (jac) {
      for (int i = 0; i < p; ++i) jac->col(i) /= problem.LogSpace(i) ? y[i] : 1.0;
    }
    return true;
  };
  std::vector<double> y = x;
  for (int i = 0; i < p; ++i) y[i] = result.estimate[i];
  result.standard_deviation.assign(p, NAN);
  result.correlation = Eigen::MatrixXd::Constant(p, p, NAN);
  Eigen::VectorXd unused;
  Eigen::MatrixXd jacobian;
  Eigen::MatrixXd covariance;
  const int dof = result.residual_count - n;
  if (in_own_units(y, &unused, &jacobian)) {
    // identifiability: condition number of the parameters' columns scaled by their magnitudes
    Eigen::MatrixXd scaled = jacobian.leftCols(p);
    for (int i = 0; i < p; ++i) scaled.col(i) *= std::max(std::abs(result.estimate[i]), 1e-12);
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(scaled, Eigen::ComputeThinV);
    const Eigen::VectorXd sigma = svd.singularValues();
    result.condition_number = sigma[p - 1] > 0 ? sigma[0] / sigma[p - 1] : INFINITY;
    if (!(result.condition_number <= kIdentifiabilityCondition)) {
      std::ostringstream message;
      message << "the parameters are not identifiable from this data (condition number " << result.condition_number
              << "); the weakest direction involves " << Names(parameters, svd.matrixV().col(p - 1));
      result.warnings.push_back(message.str());
    }
    if (dof > 0 && UnscaledCovariance(in_own_units, y, &covariance)) {
      const double variance = 2.0 * result.final_cost / dof;
      for (int i = 0; i < p; ++i) result.standard_deviation[i] = std::sqrt(variance * covariance(i, i));
      for (int i = 0; i < p; ++i) {
        for (int j = 0; j < p; ++j) {
          const double c = covariance(i, j) / std::sqrt(covariance(i, i) * covariance(j, j));
          result.correlation(i, j) = std::clamp(c, -1.0, 1.0);
        }
      }
    }
    // the pseudo-inverse drops the weak direction, so its parameters would look precise: they are not
    if (!(result.condition_number <= kIdentifiabilityCondition)) {
      for (int i = 0; i < p; ++i) {
        if (std::abs(svd.matrixV()(i, p - 1)) > 0.3) result.standard_deviation[i] = NAN;
      }
    }
    // a parameter whose doubling would not move the residuals measurably (a lone one has condition number 1)
    double data_norm = 0.0;
    for (const Observations& recording : recordings) {
      for (const auto& row : recording.values) {
        for (double v : row) data_norm += std::isnan(v) ? 0.0 : v * v;
      }
    }
    data_norm = std::sqrt(data_norm);
    for (int i = 0; i < p; ++i) {
      const double effect = scaled.col(i).norm();
      if (effect <= kNoEffect * data_norm) {
        std::ostringstream message;
        message << parameters.pointers()[i] << " has no measurable effect on the data (changing it by 100% moves the "
                << "residuals by " << effect << " against data of norm " << data_norm << "): it cannot be identified";
        result.warnings.push_back(message.str());
        result.standard_deviation[i] = NAN;
      }
    }
  }
  if (dof <= 0) {
    result.warnings.push_back("as many unknowns as residuals: the fit is exact and no standard deviation can be estimated");
  }
  // continuity residuals follow the data residuals in r (ShootingProblem::Residuals)
  int data_count = 0;
  for (const ResidualStatistics& s : result.residuals) data_count += s.count;
  const std::vector<double> continuity(r.data() + data_count, r.data() + data_count + (n - p));
  const FitJudgement judgement =
      JudgeFit(recordings, result.residuals, continuity, LengthScale(model), result.optimizer);
  result.warnings.insert(result.warnings.end(), judgement.warnings.begin(), judgement.warnings.end());
  // what a written scene does: one run of the estimate from the scene's initial state, against the data
  if (problem.Segments() > 1 && !judgement.failed) {
    Model<double> estimated = model;
    parameters.Assign(result.estimate, &estimated);
    size_t group = 0;
    for (const Observations& recording : recordings) {
      double fit_squares = 0.0;
      int fit_count = 0;
      for (size_t c = 0; c < recording.columns.size(); ++c, ++group) {
        fit_squares += result.residuals[group].rms * result.residuals[group].rms * result.residuals[group].count;
        fit_count += result.residuals[group].count;
      }
      const double fit_rms = std::sqrt(fit_squares / std::max(fit_count, 1));
      std::ostringstream message;
      message << recording.path << ": the estimate, run once from the scene's initial state (as a scene written with "
              << "it runs), ";
      try {
        const Eigen::VectorXd once = ObservationResiduals<double>(estimated, recording, RunOptions{});
        const double once_rms = once.size() ? std::sqrt(once.squaredNorm() / once.size()) : 0.0;
        if (!(once_rms > kNoiseFactor * fit_rms)) continue;
        message << "misses the data by RMS " << once_rms << " against the fit's " << fit_rms << ": multiple shooting "
                << "matched the data piece by piece, and one run parts from it (on a chaotic motion any error grows)";
      } catch (const SimulationDiverged& e) {
        message << "diverges: " << e.what();
      }
      result.warnings.push_back(message.str());
    }
  }
  result.failed = judgement.failed;
  if (judgement.failed) {
    result.standard_deviation.assign(p, NAN);
    result.correlation.setConstant(NAN);
  }
  return result;
}

std::vector<std::pair<double, double>> BoundsFor(const ParameterSet& parameters,
                                                 const std::vector<ParameterBound>& bounds, const std::string& where) {
  constexpr double kLargest = std::numeric_limits<double>::max();
  std::vector<std::pair<double, double>> out(parameters.size(), {-kLargest, kLargest});
  const std::vector<std::string>& pointers = parameters.pointers();
  for (const bool wildcards : {true, false}) {
    for (const ParameterBound& b : bounds) {
      const bool wildcard = EndsInWildcard(b.pointer);
      if (wildcard != wildcards) continue;
      const std::string prefix = wildcard ? b.pointer.substr(0, b.pointer.size() - 1) : b.pointer;  // ".../"
      bool matched = false;
      for (size_t i = 0; i < pointers.size(); ++i) {
        const bool match = wildcard ? pointers[i].compare(0, prefix.size(), prefix) == 0 &&
                                          pointers[i].find('/', prefix.size()) == std::string::npos
                                    : pointers[i] == b.pointer;
        if (!match) continue;
        out[i] = {b.lower, b.upper};
        matched = true;
      }
      if (!matched) throw InputError(where + ": '" + b.pointer + "' is not one of the parameters");
    }
  }
  return out;
}

}  // namespace tether
