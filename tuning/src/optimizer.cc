#include "tether/tuning/optimizer.h"

#include <ceres/ceres.h>
#include <nlopt.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <nlopt.hpp>
#include <stdexcept>

#include "tether/dynamics/integration/interrupts.h"
#include "tether/dynamics/model/errors.h"

namespace tether {

void EvaluateLoss(const RobustLoss& loss, double s, double rho[2]) {
  rho[0] = s;  // no robust loss: rho(s) = s
  rho[1] = 1.0;
  const double b = loss.delta * loss.delta;
  if (loss.kind == RobustLoss::Kind::kHuber && s > b) {
    const double root = std::sqrt(s);
    rho[0] = 2.0 * loss.delta * root - b;
    rho[1] = loss.delta / root;
  } else if (loss.kind == RobustLoss::Kind::kCauchy) {
    rho[0] = b * std::log1p(s / b);
    rho[1] = 1.0 / (1.0 + s / b);
  }
}

namespace {

constexpr unsigned long kNloptSeed = 20261123;  // NLopt's random generator, seeded for repeatable runs

// The residual function as a Ceres cost: one parameter block holding x.
class ResidualCost final : public ceres::CostFunction {
 public:
  ResidualCost(const ResidualFunction& residuals, int num_residuals, int num_parameters, int* evaluations)
      : residuals_(residuals), evaluations_(evaluations) {
    set_num_residuals(num_residuals);
    mutable_parameter_block_sizes()->push_back(num_parameters);
  }

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const int n = parameter_block_sizes()[0];
    const std::vector<double> x(parameters[0], parameters[0] + n);
    Eigen::VectorXd r;
    Eigen::MatrixXd jacobian;
    ++*evaluations_;
    if (!residuals_(x, &r, jacobians && jacobians[0] ? &jacobian : nullptr)) return false;
    if (r.size() != num_residuals()) return false;  // a run that ended early cannot be compared
    Eigen::Map<Eigen::VectorXd>(residuals, r.size()) = r;
    if (jacobians && jacobians[0]) {
      Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(jacobians[0], r.size(), n) =
          jacobian;
    }
    return true;
  }

 private:
  const ResidualFunction& residuals_;
  int* evaluations_;
};

// OptimizerSettings::done as a Ceres callback.
class StopWhenDone final : public ceres::IterationCallback {
 public:
  explicit StopWhenDone(const std::function<bool()>& done) : done_(done) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary&) override {
    return done_() ? ceres::SOLVER_TERMINATE_SUCCESSFULLY : ceres::SOLVER_CONTINUE;
  }

 private:
  const std::function<bool()>& done_;
};

OptimizerResult MinimizeWithCeres(const ResidualFunction& residuals, const std::vector<double>& start,
                                  const std::vector<double>& lower, const std::vector<double>& upper,
                                  const OptimizerSettings& settings) {
  OptimizerResult result;
  Eigen::VectorXd r;
  ++result.evaluations;
  residuals(start, &r, nullptr);  // Minimize checked that the start is feasible; this sizes the problem
  std::vector<double> x = start;
  ceres::Problem problem;
  // A ceres::LossFunction would apply rho to the block's whole squared norm (one block holds every residual),
  // so the loss goes into the residuals instead: r~_i = sign(r_i) sqrt(rho(r_i^2)) has sum r~_i^2 =
  // sum rho(r_i^2) exactly, and d r~_i = rho'(r_i^2) r_i / r~_i d r_i.
  const RobustLoss loss = settings.loss;
  const ResidualFunction robust = [&residuals, loss](const std::vector<double>& at, Eigen::VectorXd* out,
                                                      Eigen::MatrixXd* jacobian) {
    if (!residuals(at, out, jacobian)) return false;
    if (loss.kind == RobustLoss::Kind::kNone) return true;
    for (int i = 0; i < out->size(); ++i) {
      double rho[2];
      const double ri = (*out)[i];
      EvaluateLoss(loss, ri * ri, rho);
      const double root = std::copysign(std::sqrt(rho[0]), ri);
      if (jacobian) jacobian->row(i) *= root != 0.0 ? rho[1] * ri / root : 1.0;
      (*out)[i] = root;
    }
    return true;
  };
  problem.AddResidualBlock(new ResidualCost(robust, static_cast<int>(r.size()), static_cast<int>(x.size()),
                                            &result.evaluations),
                           nullptr, x.data());
  for (size_t i = 0; i < x.size(); ++i) {
    problem.SetParameterLowerBound(x.data(), static_cast<int>(i), lower[i]);
    problem.SetParameterUpperBound(x.data(), static_cast<int>(i), upper[i]);
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.logging_type = ceres::SILENT;
  options.max_num_iterations = settings.max_evaluations / 2;
  options.function_tolerance = settings.relative_tolerance;
  options.parameter_tolerance = settings.relative_tolerance;
  options.use_nonmonotonic_steps = settings.nonmonotonic_steps;
  StopWhenDone stop(settings.done);
  if (settings.done) options.callbacks.push_back(&stop);
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  result.x = x;
  result.value = summary.final_cost;
  result.message = summary.message;
  result.hit_limit = summary.termination_type == ceres::NO_CONVERGENCE;
  return result;
}

// MLSL and AUGLAG run a local optimizer that NLopt leaves to the caller (AUGLAG without one crashes NLopt 2.7):
// a gradient-based one (LD_LBFGS) for the GD_/LD_ variants and the generic AUGLAG, a derivative-free one
// (LN_BOBYQA) for the GN_/LN_ variants, and for G_MLSL, whose own search is derivative-free.
bool NeedsLocalOptimizer(const std::string& algorithm) {
  return algorithm.find("MLSL") != std::string::npos || algorithm.find("AUGLAG") != std::string::npos;
}
nlopt::algorithm LocalOptimizerFor(const std::string& algorithm) {
  const bool gradient_based = algorithm.compare(0, 3, "GD_") == 0 || algorithm.compare(0, 3, "LD_") == 0 ||
                              algorithm.compare(0, 6, "AUGLAG") == 0;
  return gradient_based ? nlopt::LD_LBFGS : nlopt::LN_BOBYQA;
}

// What NLopt's objective works from, and the best point it has seen (some algorithms, COBYLA in NLopt 2.7, return
// their last point instead).
struct NloptContext {
  const ResidualFunction* residuals;
  const CostGradientFunction* cost_gradient;
  double cost_scale;  // of the scaled residuals' cost to the cost_gradient's
  const RobustLoss* loss;
  int* evaluations;
  std::vector<double> best_x;
  double best_value;
};

// f = 1/2 sum rho(r_i^2) and, when asked, df/dx = sum rho'(r_i^2) r_i dr_i/dx from the residuals' Jacobian.
bool CostFromResiduals(const NloptContext& c, const std::vector<double>& x, double* value,
                       std::vector<double>* gradient) {
  Eigen::VectorXd r;
  Eigen::MatrixXd jacobian;
  if (!(*c.residuals)(x, &r, gradient ? &jacobian : nullptr)) return false;
  Eigen::VectorXd weight(r.size());
  for (int i = 0; i < r.size(); ++i) {
    double rho[2];
    EvaluateLoss(*c.loss, r[i] * r[i], rho);
    *value += 0.5 * rho[0];
    weight[i] = rho[1] * r[i];
  }
  if (gradient) {
    const Eigen::VectorXd g = jacobian.transpose() * weight;
    for (size_t i = 0; i < gradient->size(); ++i) (*gradient)[i] = g[static_cast<int>(i)];
  }
  return true;
}

// f and df/dx from the cost-gradient function (the adjoint), scaled as the residuals are.
bool CostFromGradientFunction(const NloptContext& c, const std::vector<double>& x, double* value,
                              std::vector<double>* gradient) {
  if (!(*c.cost_gradient)(x, value, gradient)) return false;
  *value *= c.cost_scale;
  for (double& g : *gradient) g *= c.cost_scale;
  return true;
}

OptimizerResult MinimizeWithNlopt(const ResidualFunction& residuals, const CostGradientFunction& cost_gradient,
                                  double cost_scale, const std::string& algorithm_name,
                                  const std::vector<double>& start, const std::vector<double>& lower,
                                  const std::vector<double>& upper, const OptimizerSettings& settings) {
  const nlopt_algorithm algorithm = nlopt_algorithm_from_string(algorithm_name.c_str());
  OptimizerResult result;
  nlopt::opt opt(static_cast<nlopt::algorithm>(algorithm), static_cast<unsigned>(start.size()));
  NloptContext context{&residuals, &cost_gradient, cost_scale, &settings.loss, &result.evaluations, start, INFINITY};
  auto objective = [](const std::vector<double>& x, std::vector<double>& gradient, void* data) -> double {
    NloptContext& c = *static_cast<NloptContext*>(data);
    ++*c.evaluations;
    const bool want_gradient = !gradient.empty();
    double value = 0.0;
    if (!(want_gradient && *c.cost_gradient ? CostFromGradientFunction(c, x, &value, &gradient)
                                             : CostFromResiduals(c, x, &value, want_gradient ? &gradient : nullptr))) {
      std::fill(gradient.begin(), gradient.end(), 0.0);
      return kInfeasibleValue;
    }
    if (value < c.best_value) {
      c.best_value = value;
      c.best_x = x;
    }
    return value;
  };
  opt.set_min_objective(objective, &context);
  opt.set_lower_bounds(NloptBounds(lower));
  opt.set_upper_bounds(NloptBounds(upper));
  opt.set_xtol_rel(settings.relative_tolerance);
  opt.set_ftol_rel(settings.relative_tolerance);
  opt.set_maxeval(settings.max_evaluations);
  if (NeedsLocalOptimizer(algorithm_name)) {
    nlopt::opt local(LocalOptimizerFor(algorithm_name), static_cast<unsigned>(start.size()));
    local.set_xtol_rel(settings.relative_tolerance);
    local.set_ftol_rel(settings.relative_tolerance);
    opt.set_local_optimizer(local);
  }
  nlopt::srand(kNloptSeed);  // randomized algorithms (CRS2, MLSL, ...) repeat their runs
  std::vector<double> x = start;
  double value = 0.0;
  try {
    const nlopt::result code = opt.optimize(x, value);
    result.message = "nlopt result code " + std::to_string(static_cast<int>(code));
    result.hit_limit = code == nlopt::MAXEVAL_REACHED || code == nlopt::MAXTIME_REACHED;
  } catch (const std::invalid_argument&) {  // NLOPT_INVALID_ARGS: nothing was optimized
    throw InputError("--optimizer: NLopt cannot run nlopt:" + algorithm_name + " on this problem (" +
                     std::to_string(start.size()) + " parameters): it is missing from this NLopt build, or needs "
                     "finite bounds on every parameter or more parameters; choose another, e.g. nlopt:LN_BOBYQA");
  } catch (const nlopt::roundoff_limited&) {
    value = opt.last_optimum_value();
    result.message = "nlopt stopped: roundoff limited";
  } catch (const std::runtime_error& e) {  // nlopt's failure codes arrive as exceptions
    // an exception in the objective arrives as nlopt's forced stop; a cancelled run (interrupts.h) stays one
    if (RunsCancelled()) throw RunInterrupted(Interrupted());
    value = opt.last_optimum_value();
    result.message = std::string("nlopt stopped: ") + e.what();
  }
  if (context.best_value < value) {
    x = context.best_x;
    value = context.best_value;
  }
  result.x = x;
  result.value = value;
  return result;
}

}  // namespace

std::vector<double> NloptBounds(std::vector<double> bounds) {
  for (double& b : bounds) {
    if (std::abs(b) == std::numeric_limits<double>::max()) b = std::copysign(HUGE_VAL, b);
  }
  return bounds;
}

RobustLoss ParseRobustLoss(const std::string& text, const std::string& flag) {
  const size_t colon = text.find(':');
  const std::string kind = text.substr(0, colon);
  RobustLoss loss;
  if (kind == "huber") {
    loss.kind = RobustLoss::Kind::kHuber;
  } else if (kind == "cauchy") {
    loss.kind = RobustLoss::Kind::kCauchy;
  } else {
    throw InputError(flag + ": unknown loss '" + text + "' (expected huber:DELTA or cauchy:DELTA)");
  }
  char* end = nullptr;
  const std::string number = colon == std::string::npos ? "" : text.substr(colon + 1);
  loss.delta = std::strtod(number.c_str(), &end);
  if (number.empty() || end != number.c_str() + number.size() || !(loss.delta > 0) || !std::isfinite(loss.delta)) {
    throw InputError(flag + ": '" + text + "' needs a scale DELTA > 0, e.g. " + kind + ":0.01");
  }
  return loss;
}

double RobustCost(const RobustLoss& loss, const Eigen::VectorXd& r) {
  double cost = 0.0;
  for (int i = 0; i < r.size(); ++i) {
    double rho[2];
    EvaluateLoss(loss, r[i] * r[i], rho);
    cost += 0.5 * rho[0];
  }
  return cost;
}

bool UnscaledCovariance(const ResidualFunction& residuals, const std::vector<double>& x, Eigen::MatrixXd* covariance) {
  Eigen::VectorXd r;
  if (!residuals(x, &r, nullptr)) return false;
  int evaluations = 0;
  std::vector<double> at = x;
  ceres::Problem problem;
  problem.AddResidualBlock(new ResidualCost(residuals, static_cast<int>(r.size()), static_cast<int>(x.size()), &evaluations),
                           nullptr, at.data());
  ceres::Covariance::Options options;
  options.algorithm_type = ceres::DENSE_SVD;
  options.null_space_rank = -1;
  options.min_reciprocal_condition_number = 1e-14;
  ceres::Covariance estimator(options);
  const std::vector<std::pair<const double*, const double*>> blocks = {{at.data(), at.data()}};
  if (!estimator.Compute(blocks, &problem)) return false;
  covariance->resize(x.size(), x.size());
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rows(x.size(), x.size());
  if (!estimator.GetCovarianceBlock(at.data(), at.data(), rows.data())) return false;
  *covariance = rows;
  return true;
}

void CheckOptimizerName(const std::string& name, const std::string& where) {
  if (name == "ceres") return;
  const std::string prefix = "nlopt:";
  if (name.compare(0, prefix.size(), prefix) != 0) {
    throw InputError(where + ": unknown optimizer '" + name +
                     "' (expected ceres or nlopt:ALGORITHM, e.g. nlopt:LD_LBFGS)");
  }
  const std::string algorithm = name.substr(prefix.size());
  if (static_cast<int>(nlopt_algorithm_from_string(algorithm.c_str())) < 0) {
    throw InputError(where + ": unknown NLopt algorithm '" + algorithm +
                     "' (NLopt's own names: LD_LBFGS, LN_BOBYQA, GN_DIRECT_L, ...)");
  }
}

bool UsesGradients(const std::string& optimizer_name) {
  if (optimizer_name.rfind("nlopt:", 0) != 0) return false;
  const std::string algorithm = optimizer_name.substr(6);
  return algorithm.rfind("LD_", 0) == 0 || algorithm.rfind("GD_", 0) == 0 || algorithm.rfind("AUGLAG", 0) == 0;
}

ResidualFunction Observed(const ResidualFunction& residuals, const OptimizerSettings& settings) {
  if (!settings.observer) return residuals;
  return [residuals, loss = settings.loss, observer = settings.observer](
             const std::vector<double>& x, Eigen::VectorXd* r, Eigen::MatrixXd* jacobian) {
    const bool feasible = residuals(x, r, jacobian);
    observer(feasible ? RobustCost(loss, *r) : NAN);
    return feasible;
  };
}

OptimizerResult Minimize(const ResidualFunction& unobserved, const std::vector<double>& start,
                         const std::vector<double>& lower, const std::vector<double>& upper,
                         const OptimizerSettings& settings, const CostGradientFunction& unobserved_gradient) {
  CheckOptimizerName(settings.name, "optimizer");
  const ResidualFunction residuals = Observed(unobserved, settings);
  CostGradientFunction cost_gradient = unobserved_gradient;
  if (settings.observer && unobserved_gradient) {
    cost_gradient = [&unobserved_gradient, &settings](const std::vector<double>& x, double* cost,
                                                      std::vector<double>* gradient) {
      const bool feasible = unobserved_gradient(x, cost, gradient);
      settings.observer(feasible ? *cost : NAN);
      return feasible;
    };
  }
  const auto begin = std::chrono::steady_clock::now();
  // Both back ends have absolute tolerances somewhere (Ceres' gradient tolerance, NLopt's stopping values), so
  // they see residuals scaled to |r(start)| = 1; the minimizer is the same.
  Eigen::VectorXd r0;
  if (!residuals(start, &r0, nullptr)) {
    throw InputError("the optimization cannot start: the simulation diverges at the starting point");
  }
  const double scale = r0.norm() > 0.0 ? 1.0 / r0.norm() : 1.0;
  const ResidualFunction scaled = [&residuals, scale](const std::vector<double>& x, Eigen::VectorXd* r,
                                                      Eigen::MatrixXd* jacobian) {
    if (!residuals(x, r, jacobian)) return false;
    *r *= scale;
    if (jacobian) *jacobian *= scale;
    return true;
  };
  OptimizerSettings scaled_settings = settings;  // rho is homogeneous of degree 2 in (r, delta)
  scaled_settings.loss.delta *= scale;
  OptimizerResult result =
      settings.name == "ceres"
          ? MinimizeWithCeres(scaled, start, lower, upper, scaled_settings)
          : MinimizeWithNlopt(scaled, cost_gradient, scale * scale, settings.name.substr(6), start, lower, upper,
                              scaled_settings);
  // the value at the returned point (Ceres' final cost can belong to the last trial instead)
  Eigen::VectorXd r;
  result.value = residuals(result.x, &r, nullptr) ? RobustCost(settings.loss, r) : result.value / (scale * scale);
  result.evaluations += 2;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  return result;
}

}  // namespace tether
