#include "tether/tuning/gain_objective.h"

#include <cmath>
#include <random>

#include "tether/autodiff/seeds.h"
#include "tether/dynamics/constraints/constraint_rows.h"
#include "tether/dynamics/effects/effects.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/model/configuration_space.h"
#include "tether/dynamics/model/errors.h"

namespace tether {
namespace {

// Steps from the start within which two references (the given one, and one whose initial velocities are scaled
// by 1 + kHorizonPerturbation) stay within kHorizonSeparation times the length scale (window rule).
int HorizonSteps(const Model<double>& model, const ReferenceMotion& reference,
                 const std::vector<int>& translational) {
  const State<double> start = InitialState(model);
  const ReferenceMotion other =
      ComputeReference(WithInitialState(model, start.q, VecX<double>((1.0 + kHorizonPerturbation) * start.v)));
  const double separation = kHorizonSeparation * LengthScale(model);
  for (size_t k = 0; k < reference.q.size(); ++k) {
    double squared = 0.0;
    for (int i : translational) squared += std::pow(other.q[k][i] - reference.q[k][i], 2);
    if (std::sqrt(squared) > separation) return std::max<int>(1, static_cast<int>(k) - 1);
  }
  return static_cast<int>(reference.q.size()) - 1;
}

// Initial velocities moved by 5% of the speed scale, deterministically for each sample.
Model<double> Perturbed(const Model<double>& model, int sample) {
  if (sample == 0) return model;
  State<double> start = InitialState(model);
  const double speed = std::max(start.v.lpNorm<Eigen::Infinity>(), std::sqrt(9.81 * LengthScale(model)));
  std::mt19937 random(static_cast<unsigned>(sample));
  std::normal_distribution<double> normal(0.0, 0.05 * speed);
  for (int i = 0; i < start.v.size(); ++i) start.v[i] += normal(random);
  return WithInitialState(model, start.q, start.v);
}

}  // namespace

template <typename T>
Model<T> WithGains(const Model<T>& model, const T& alpha, const T& beta) {
  Model<T> out = model;
  out.stabilization.method = Stabilization::kBaumgarte;
  out.stabilization.gains_from_rule = false;
  out.stabilization.alpha = alpha;
  out.stabilization.beta = beta;
  return out;
}

GainObjective::GainObjective(const Model<double>& model, const GainObjectiveSettings& settings)
    : settings_(settings), length_scale_(LengthScale(model)) {
  for (const Body<double>& body : model.bodies) {
    for (int k = 0; k < model.dimension; ++k) translational_.push_back(body.q_offset + k);
  }
  const double h = model.simulation.step;
  int samples = 0;
  for (int s = 0; s < std::max(1, settings.samples); ++s) {
    const Model<double> start = Perturbed(model, s);
    if (settings.kind == GainObjectiveKind::kDrift) {
      windows_.push_back({start, 0.0, {}, {}});
      samples += static_cast<int>(std::ceil(start.simulation.duration / h - 1e-9));
      continue;
    }
    const ReferenceMotion reference = ComputeReference(start);
    const int last = static_cast<int>(reference.t.size()) - 1;
    if (s == 0) {
      reference_ = reference;
      window_ = reference.t[HorizonSteps(start, reference, translational_)];
    }
    const int per_window = std::max(1, static_cast<int>(std::lround(window_ / h)));
    for (int first = 0; first < last; first += per_window) {
      const int end = std::min(last, first + per_window);
      Window w{WithInitialState(start, reference.q[first], reference.v[first]), reference.t[first], {}, {}};
      w.model.simulation.duration = reference.t[end] - reference.t[first];
      for (int k = first + 1; k <= end; ++k) {
        w.times.push_back(reference.t[k]);
        w.q.push_back(reference.q[k]);
      }
      samples += end - first;
      windows_.push_back(std::move(w));
    }
  }
  normalization_ = 1.0 / std::sqrt(std::max(1, samples));
}

template <typename T>
bool GainObjective::Residuals(const Model<T>& stabilized, const Window& window, std::vector<T>* out) const {
  const bool drift = settings_.kind == GainObjectiveKind::kDrift;
  int sample = -1;
  T energy0(0.0);
  RunOptions options;
  options.start_time = window.start;
  try {
    Simulate<T>(stabilized, options, [&](const Sample<T>& s) {
      if (++sample == 0) {  // the initial state
        energy0 = s.energy;
        return;
      }
      if (!drift) {
        const Eigen::VectorXd& reference = window.q[sample - 1];
        for (int i : translational_) out->push_back(s.q[i] - T(reference[i]));
      }
      for (const ConstraintRow<T>& row : s.rows) out->push_back(row.value);
      if (drift) {
        for (const ConstraintRow<T>& row : s.rows) {
          out->push_back(T(kDriftTime) * (Dot(stabilized, row.a, s.v) + Dot(stabilized, row.b, s.v)));
        }
        const double scale = std::max(std::abs(::tether::Value(energy0)), 1.0);
        out->push_back((s.energy - energy0) * T(length_scale_ / scale));
      }
    });
  } catch (const SimulationDiverged&) {
    return false;
  }
  return true;
}

bool GainObjective::Evaluate(double log_omega, double zeta, Eigen::VectorXd* r, Eigen::MatrixXd* jacobian) const {
  const double omega = std::exp(log_omega);
  const double alpha = 2.0 * zeta * omega, beta = omega * omega;
  if (!jacobian) {
    std::vector<double> values;
    for (const Window& w : windows_) {
      if (!Residuals(WithGains(w.model, alpha, beta), w, &values)) return false;
    }
    *r = Eigen::Map<Eigen::VectorXd>(values.data(), values.size()) * normalization_;
    return true;
  }
  // derivative directions: 0 = log omega, 1 = zeta (alpha = 2 zeta omega, beta = omega^2)
  const ModelField alpha_field([](auto& m) -> auto& { return m.stabilization.alpha; });
  const ModelField beta_field([](auto& m) -> auto& { return m.stabilization.beta; });
  const std::vector<JetSeed> seeds = {
      {alpha_field, 0, 2.0 * zeta * omega}, {alpha_field, 1, 2.0 * omega}, {beta_field, 0, 2.0 * omega * omega}};
  std::vector<Jet> values;
  for (const Window& w : windows_) {
    if (!Residuals(SeededModel(WithGains(w.model, alpha, beta), seeds), w, &values)) return false;
  }
  r->resize(values.size());
  jacobian->resize(values.size(), 2);
  for (size_t i = 0; i < values.size(); ++i) {
    (*r)[i] = values[i].a * normalization_;
    (*jacobian)(i, 0) = values[i].v[0] * normalization_;
    (*jacobian)(i, 1) = values[i].v[1] * normalization_;
  }
  return true;
}

double GainObjective::Value(double log_omega, double zeta) const {
  Eigen::VectorXd r;
  return Evaluate(log_omega, zeta, &r, nullptr) ? r.norm() : INFINITY;
}

template Model<double> WithGains<double>(const Model<double>&, const double&, const double&);

}  // namespace tether
