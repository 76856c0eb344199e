#include "tether/tuning/optimizer.h"

#include <ceres/ceres.h>
#include <nlopt.h>

#include <chrono>
#include <nlopt.hpp>

#include "tether/dynamics/errors.h"

namespace tether {
namespace {

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

OptimizerResult MinimizeWithCeres(const ResidualFunction& residuals, const std::vector<double>& start,
                                  const std::vector<double>& lower, const std::vector<double>& upper,
                                  const OptimizerSettings& settings) {
  OptimizerResult result;
  Eigen::VectorXd r;
  ++result.evaluations;
  residuals(start, &r, nullptr);  // Minimize checked that the start is feasible; this sizes the problem
  std::vector<double> x = start;
  ceres::Problem problem;
  problem.AddResidualBlock(new ResidualCost(residuals, static_cast<int>(r.size()), static_cast<int>(x.size()),
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
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  result.x = x;
  result.value = summary.final_cost;
  result.message = summary.message;
  return result;
}

bool IsMultiLevelSingleLinkage(const std::string& algorithm) { return algorithm.find("MLSL") != std::string::npos; }

OptimizerResult MinimizeWithNlopt(const ResidualFunction& residuals, const std::string& algorithm_name,
                                  const std::vector<double>& start, const std::vector<double>& lower,
                                  const std::vector<double>& upper, const OptimizerSettings& settings) {
  const nlopt_algorithm algorithm = nlopt_algorithm_from_string(algorithm_name.c_str());
  OptimizerResult result;
  nlopt::opt opt(static_cast<nlopt::algorithm>(algorithm), static_cast<unsigned>(start.size()));
  struct Context {
    const ResidualFunction* residuals;
    int* evaluations;
  } context{&residuals, &result.evaluations};
  auto objective = [](const std::vector<double>& x, std::vector<double>& gradient, void* data) -> double {
    const Context& c = *static_cast<Context*>(data);
    Eigen::VectorXd r;
    Eigen::MatrixXd jacobian;
    ++*c.evaluations;
    const bool want_gradient = !gradient.empty();
    if (!(*c.residuals)(x, &r, want_gradient ? &jacobian : nullptr)) {
      std::fill(gradient.begin(), gradient.end(), 0.0);
      return kInfeasibleValue;
    }
    if (want_gradient) {
      const Eigen::VectorXd g = jacobian.transpose() * r;
      for (size_t i = 0; i < gradient.size(); ++i) gradient[i] = g[static_cast<int>(i)];
    }
    return 0.5 * r.squaredNorm();
  };
  opt.set_min_objective(objective, &context);
  opt.set_lower_bounds(lower);
  opt.set_upper_bounds(upper);
  opt.set_xtol_rel(settings.relative_tolerance);
  opt.set_ftol_rel(settings.relative_tolerance);
  opt.set_maxeval(settings.max_evaluations);
  if (IsMultiLevelSingleLinkage(algorithm_name)) {
    nlopt::opt local(algorithm_name[0] == 'G' && algorithm_name[1] == '_' ? nlopt::LD_LBFGS : nlopt::LN_BOBYQA,
                     static_cast<unsigned>(start.size()));
    local.set_xtol_rel(settings.relative_tolerance);
    local.set_ftol_rel(settings.relative_tolerance);
    opt.set_local_optimizer(local);
  }
  std::vector<double> x = start;
  double value = 0.0;
  try {
    const nlopt::result code = opt.optimize(x, value);
    result.message = "nlopt result code " + std::to_string(static_cast<int>(code));
  } catch (const nlopt::roundoff_limited&) {
    value = opt.last_optimum_value();
    result.message = "nlopt stopped: roundoff limited";
  } catch (const std::runtime_error& e) {  // nlopt's failure codes arrive as exceptions
    value = opt.last_optimum_value();
    result.message = std::string("nlopt stopped: ") + e.what();
  }
  result.x = x;
  result.value = value;
  return result;
}

}  // namespace

void CheckOptimizerName(const std::string& name) {
  if (name == "ceres") return;
  const std::string prefix = "nlopt:";
  if (name.compare(0, prefix.size(), prefix) != 0) {
    throw InputError("--optimizer: unknown optimizer '" + name + "' (expected ceres or nlopt:ALGORITHM, e.g. nlopt:LD_LBFGS)");
  }
  const std::string algorithm = name.substr(prefix.size());
  if (static_cast<int>(nlopt_algorithm_from_string(algorithm.c_str())) < 0) {
    throw InputError("--optimizer: unknown NLopt algorithm '" + algorithm + "' (NLopt's own names: LD_LBFGS, LN_BOBYQA, GN_DIRECT_L, ...)");
  }
}

OptimizerResult Minimize(const ResidualFunction& residuals, const std::vector<double>& start,
                         const std::vector<double>& lower, const std::vector<double>& upper,
                         const OptimizerSettings& settings) {
  CheckOptimizerName(settings.name);
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
  OptimizerResult result = settings.name == "ceres"
                               ? MinimizeWithCeres(scaled, start, lower, upper, settings)
                               : MinimizeWithNlopt(scaled, settings.name.substr(6), start, lower, upper, settings);
  result.value /= scale * scale;
  result.evaluations += 1;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  return result;
}

}  // namespace tether
