#include "tether/autodiff/residuals.h"

#include <algorithm>
#include <climits>
#include <cmath>

namespace tether {

template <typename T>
VecX<T> ObservationResiduals(const Model<T>& model, const Observations& observations, const RunOptions& options) {
  // where each row's residuals start
  std::vector<int> first(observations.times.size() + 1, 0);
  for (size_t row = 0; row < observations.times.size(); ++row) {
    int count = 0;
    for (double v : observations.values[row]) count += std::isnan(v) ? 0 : 1;
    first[row + 1] = first[row] + count;
  }
  VecX<T> residuals(first.back());
  RunOptions run = options;
  run.every = INT_MAX;  // no output rows are needed, only the stops
  run.stops = observations.times;
  run.energy = ObservesEnergy(observations);
  Simulate<T>(model, run, [&](const Sample<T>& s) {
    if (s.stop < 0) return;
    int cell = first[s.stop];
    ObservedResiduals(model, observations, s.stop, s, [&](size_t, const T& r) { residuals[cell++] = r; });
  });
  return residuals;
}

void EvaluateByJets(const Model<double>& model, const ParameterSet& parameters, const JetResidualFunction& residuals,
                    Eigen::VectorXd* values, Eigen::MatrixXd* jacobian) {
  const int count = parameters.size();
  for (int first = 0; first == 0 || first < count; first += kJetStride) {
    const int chunk = std::min(kJetStride, count - first);
    std::vector<ParameterSet::Seed> seeds;
    for (int k = 0; k < chunk; ++k) seeds.push_back({first + k, k, 1.0});
    const VecX<Jet> r = residuals(parameters.Seeded(model, seeds));
    if (first == 0) {
      values->resize(r.size());
      for (int i = 0; i < r.size(); ++i) (*values)[i] = r[i].a;
      if (jacobian) jacobian->resize(r.size(), count);
    }
    if (!jacobian) break;
    for (int k = 0; k < chunk; ++k) {
      for (int i = 0; i < r.size(); ++i) (*jacobian)(i, first + k) = r[i].v[k];
    }
  }
}

LossGradient JetLossGradient(const Model<double>& model, const ParameterSet& parameters,
                             const Observations& observations, bool factor_jet_matrices) {
  RunOptions options;
  options.factor_jet_matrices = factor_jet_matrices;
  Eigen::VectorXd r;
  Eigen::MatrixXd jacobian;
  EvaluateByJets(
      model, parameters,
      [&](const Model<Jet>& m) { return ObservationResiduals(m, observations, options); }, &r, &jacobian);
  LossGradient result;
  result.loss = 0.5 * r.squaredNorm();
  const Eigen::VectorXd gradient = jacobian.transpose() * r;
  result.gradient.assign(gradient.data(), gradient.data() + gradient.size());
  return result;
}

double CentralDifferenceStep(double value) { return 1e-5 * std::max(std::abs(value), 1e-2); }

LossGradient CentralDifferenceLossGradient(const Model<double>& model, const ParameterSet& parameters,
                                           const Observations& observations) {
  auto loss = [&observations](const Model<double>& m) {
    return 0.5 * ObservationResiduals(m, observations).squaredNorm();
  };
  LossGradient result;
  Model<double> shifted = model;
  parameters.ApplyTies(&shifted);
  result.loss = loss(shifted);
  const std::vector<double> values = parameters.Values(model);
  for (int i = 0; i < parameters.size(); ++i) {
    const double h = CentralDifferenceStep(values[i]);
    double& field = parameters.Field(&shifted, i);
    field = values[i] + h;
    parameters.ApplyTies(&shifted);
    const double up = loss(shifted);
    field = values[i] - h;
    parameters.ApplyTies(&shifted);
    const double down = loss(shifted);
    field = values[i];
    parameters.ApplyTies(&shifted);
    result.gradient.push_back((up - down) / (2 * h));
  }
  return result;
}

template VecX<double> ObservationResiduals<double>(const Model<double>&, const Observations&, const RunOptions&);
template VecX<Jet> ObservationResiduals<Jet>(const Model<Jet>&, const Observations&, const RunOptions&);


}  // namespace tether
