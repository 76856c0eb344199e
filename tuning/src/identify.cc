#include "tether/tuning/identify.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "fit_judgement.h"
#include "shooting_problem.h"
#include "tether/autodiff/adjoint.h"
#include "tether/autodiff/residuals.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/model/errors.h"
#include "trajectory_fit.h"

namespace tether {
namespace {

constexpr double kUnbounded = std::numeric_limits<double>::max();

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
    throw InputError(
        "--method adjoint: the adjoint gives the cost's gradient, which only a gradient-based NLopt "
        "algorithm takes (nlopt:LD_LBFGS, nlopt:LD_MMA, ...); --optimizer " +
        optimizer + (optimizer == "ceres" ? " needs the residuals' Jacobian (Jets)" : " uses no derivatives"));
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

IdentifyResult Identify(const Model<double>& model, const ParameterSet& parameters,
                        const std::vector<Observations>& recordings, const IdentifySettings& settings) {
  if (!settings.inequalities.empty() || settings.starts > 1)
    return FitTrajectory(model, parameters, recordings, settings);
  if (settings.segments == 0) {  // fit's choice: single shooting, and multiple shooting where it fails
    IdentifySettings single = settings, multiple = settings;
    single.segments = 1;
    IdentifyResult result = Identify(model, parameters, recordings, single);
    if (!result.failed) return result;
    multiple.segments = AutomaticSegments(parameters, recordings, settings);
    IdentifyResult retried = Identify(model, parameters, recordings, multiple);
    if (!retried.failed || retried.final_cost < result.final_cost) return retried;
    return result;
  }
  const ShootingProblem problem(model, parameters, recordings, settings);
  const int n = problem.Unknowns(), p = parameters.size();
  IdentifyResult result;
  result.initial = parameters.Values(model);

  CheckStartWithinBounds(parameters, result.initial, settings);
  std::vector<double> lower, upper;
  problem.Box(&lower, &upper);
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
    throw InputError(
        "the simulation diverges at the initial parameters; give a better initial guess or use --segments");
  }
  result.initial_cost = RobustCost(settings.optimizer.loss, r0);
  result.optimizer = Minimize(residuals, start, lower, upper, settings.optimizer,
                              CostGradientOf(problem, settings, &result.gradient_method));
  const std::vector<double>& x = result.optimizer.x;
  result.estimate = problem.Parameters(x);
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
    Eigen::VectorXd weakest = Eigen::VectorXd::Ones(p);  // the weakest direction (every one when unseen)
    if (scaled.rows() < p) {  // fewer residuals than parameters: some direction is not seen at all
      result.condition_number = INFINITY;
      result.warnings.push_back("the parameters are not identifiable from this data: " + std::to_string(scaled.rows()) +
                                " residuals for " + std::to_string(p) + " parameters");
    } else {
      const Eigen::JacobiSVD<Eigen::MatrixXd> svd(scaled, Eigen::ComputeThinV);
      const Eigen::VectorXd sigma = svd.singularValues();
      weakest = svd.matrixV().col(p - 1);
      result.condition_number = sigma[p - 1] > 0 ? sigma[0] / sigma[p - 1] : INFINITY;
      if (!(result.condition_number <= kIdentifiabilityCondition)) {
        std::ostringstream message;
        message << "the parameters are not identifiable from this data (condition number " << result.condition_number
                << "); the weakest direction involves " << Names(parameters, weakest);
        result.warnings.push_back(message.str());
      }
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
        if (std::abs(weakest[i]) > 0.3) result.standard_deviation[i] = NAN;
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
    result.warnings.push_back(
        "as many unknowns as residuals: the fit is exact and no standard deviation can be estimated");
  }
  // continuity residuals follow the data residuals in r (ShootingProblem::Residuals)
  int data_count = 0;
  for (const ResidualStatistics& s : result.residuals) data_count += s.count;
  const std::vector<double> continuity(r.data() + data_count, r.data() + data_count + problem.ContinuityCount());
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
  result.segments = problem.Segments();
  result.stopping_reason = result.optimizer.hit_limit ? "iteration limit" : "converged";
  if (judgement.failed) {
    result.standard_deviation.assign(p, NAN);
    result.correlation.setConstant(NAN);
  }
  return result;
}

}  // namespace tether
