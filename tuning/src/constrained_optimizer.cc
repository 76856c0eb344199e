// MinimizeConstrained (optimizer.h): NLopt with equality and inequality constraints on rows of one residual
// function. NLopt asks for the objective and each constraint set separately at the same point, so the residuals
// and their Jacobian are evaluated once per point and kept.
#include <nlopt.h>

#include <chrono>
#include <cmath>
#include <nlopt.hpp>
#include <stdexcept>

#include "tether/dynamics/integration/interrupts.h"
#include "tether/dynamics/model/errors.h"
#include "tether/tuning/optimizer.h"

namespace tether {
namespace {

struct ConstrainedContext {
  const ResidualFunction* residuals = nullptr;
  const ConstraintRows* rows = nullptr;
  std::vector<bool> objective_row;
  int* evaluations = nullptr;
  // the residuals at the last point asked for
  std::vector<double> x;
  Eigen::VectorXd r;
  Eigen::MatrixXd jacobian;
  bool feasible_run = false, with_jacobian = false;
  // the best point: least cost among the feasible ones, else least violation
  std::vector<double> best_x;
  double best_value = INFINITY, best_violation = INFINITY;

  // Evaluates at x unless it was the last point; false where the run is infeasible.
  bool At(const std::vector<double>& at, bool need_jacobian) {
    if (at == x && (with_jacobian || !need_jacobian)) return feasible_run;
    x = at;
    with_jacobian = need_jacobian;
    ++*evaluations;
    feasible_run = (*residuals)(at, &r, need_jacobian ? &jacobian : nullptr);
    if (feasible_run) Remember();
    return feasible_run;
  }

  void Remember() {
    double value = 0.0, violation = 0.0;
    for (int i = 0; i < r.size(); ++i) value += objective_row[i] ? 0.5 * r[i] * r[i] : 0.0;
    for (size_t e = 0; e < rows->equality.size(); ++e) {
      violation = std::max(violation, std::abs(r[rows->equality[e]]) / rows->equality_tolerance[e]);
    }
    for (size_t c = 0; c < rows->inequality.size(); ++c) {
      violation = std::max(violation, rows->inequality_sign[c] * r[rows->inequality[c]] / rows->inequality_tolerance[c]);
    }
    const bool feasible = violation <= 1.0;
    const bool better = feasible ? best_violation > 1.0 || value < best_value
                                 : best_violation > 1.0 && violation < best_violation;
    if (!better) return;
    best_x = x;
    best_value = value;
    best_violation = std::max(violation, 0.0);
  }
};

double Objective(const std::vector<double>& x, std::vector<double>& gradient, void* data) {
  ConstrainedContext& c = *static_cast<ConstrainedContext*>(data);
  if (RunsCancelled()) throw nlopt::forced_stop();
  if (!c.At(x, !gradient.empty())) {
    std::fill(gradient.begin(), gradient.end(), 0.0);
    return kInfeasibleValue;
  }
  double value = 0.0;
  std::fill(gradient.begin(), gradient.end(), 0.0);
  for (int i = 0; i < c.r.size(); ++i) {
    if (!c.objective_row[i]) continue;
    value += 0.5 * c.r[i] * c.r[i];
    for (size_t j = 0; j < gradient.size(); ++j) gradient[j] += c.r[i] * c.jacobian(i, static_cast<int>(j));
  }
  return value;
}

// result[i] = sign_i r_{row_i}, grad[i n + j] = sign_i d r_{row_i} / d x_j
void RowConstraints(ConstrainedContext& c, const std::vector<int>& rows, const std::vector<double>* signs, unsigned m,
                    double* result, unsigned n, const double* x, double* grad) {
  const std::vector<double> at(x, x + n);
  if (!c.At(at, grad != nullptr)) {
    for (unsigned i = 0; i < m; ++i) result[i] = kInfeasibleValue;
    if (grad) std::fill(grad, grad + m * n, 0.0);
    return;
  }
  for (unsigned i = 0; i < m; ++i) {
    const double sign = signs ? (*signs)[i] : 1.0;
    result[i] = sign * c.r[rows[i]];
    for (unsigned j = 0; grad && j < n; ++j) grad[i * n + j] = sign * c.jacobian(rows[i], static_cast<int>(j));
  }
}

void Equalities(unsigned m, double* result, unsigned n, const double* x, double* grad, void* data) {
  ConstrainedContext& c = *static_cast<ConstrainedContext*>(data);
  RowConstraints(c, c.rows->equality, nullptr, m, result, n, x, grad);
}

void Inequalities(unsigned m, double* result, unsigned n, const double* x, double* grad, void* data) {
  ConstrainedContext& c = *static_cast<ConstrainedContext*>(data);
  RowConstraints(c, c.rows->inequality, &c.rows->inequality_sign, m, result, n, x, grad);
}

}  // namespace

void CheckConstrainedOptimizer(const std::string& name) {
  if (name.rfind("nlopt:", 0) != 0) {
    throw InputError("--optimizer " + name + ": constraints need an NLopt algorithm made for them (nlopt:LD_SLSQP, "
                     "the default with constraints; nlopt:LN_COBYLA, nlopt:AUGLAG)");
  }
}

OptimizerResult MinimizeConstrained(const ResidualFunction& unobserved, const ConstraintRows& rows,
                                    const std::vector<double>& start, const std::vector<double>& lower,
                                    const std::vector<double>& upper, const OptimizerSettings& settings) {
  CheckOptimizerName(settings.name, "optimizer");
  if (rows.equality.empty() && rows.inequality.empty() && settings.name == "ceres") {
    return Minimize(unobserved, start, lower, upper, settings);
  }
  const ResidualFunction residuals = Observed(unobserved, settings);
  const auto begin = std::chrono::steady_clock::now();
  CheckConstrainedOptimizer(settings.name);
  const std::string algorithm = settings.name.substr(6);
  OptimizerResult result;
  Eigen::VectorXd r0;
  if (!residuals(start, &r0, nullptr)) {
    throw InputError("the optimization cannot start: the simulation diverges at the starting point");
  }
  ConstrainedContext context;
  context.residuals = &residuals;
  context.rows = &rows;
  context.objective_row.assign(r0.size(), true);
  context.evaluations = &result.evaluations;
  for (int row : rows.equality) context.objective_row[row] = false;
  for (int row : rows.inequality) context.objective_row[row] = false;
  const unsigned n = static_cast<unsigned>(start.size());
  nlopt::opt opt(static_cast<nlopt::algorithm>(nlopt_algorithm_from_string(algorithm.c_str())), n);
  std::vector<double> x = start;
  double value = 0.0;
  try {
    opt.set_lower_bounds(NloptBounds(lower));
    opt.set_upper_bounds(NloptBounds(upper));
    opt.set_min_objective(Objective, &context);
    if (!rows.equality.empty()) opt.add_equality_mconstraint(Equalities, &context, rows.equality_tolerance);
    if (!rows.inequality.empty()) opt.add_inequality_mconstraint(Inequalities, &context, rows.inequality_tolerance);
    if (algorithm.find("AUGLAG") != std::string::npos) {
      nlopt::opt local(nlopt::LD_LBFGS, n);
      local.set_xtol_rel(settings.relative_tolerance);
      opt.set_local_optimizer(local);
    }
    // no test on the cost's change: NLopt 2.7's SLSQP applies it before the constraints are met
    opt.set_xtol_rel(settings.relative_tolerance);
    opt.set_maxeval(settings.max_evaluations);
    const nlopt::result code = opt.optimize(x, value);
    result.message = "nlopt result code " + std::to_string(static_cast<int>(code));
    result.hit_limit = code == nlopt::MAXEVAL_REACHED || code == nlopt::MAXTIME_REACHED;
  } catch (const std::invalid_argument&) {
    throw InputError("--optimizer: NLopt's " + algorithm + " does not take " +
                     (rows.equality.empty() ? "inequality" : "equality") +
                     " constraints; use nlopt:LD_SLSQP (the default), nlopt:LN_COBYLA or nlopt:AUGLAG");
  } catch (const nlopt::roundoff_limited&) {
    result.message = "nlopt stopped: roundoff limited";
  } catch (const std::runtime_error& e) {
    if (RunsCancelled()) throw RunInterrupted(Interrupted());
    result.message = std::string("nlopt stopped: ") + e.what();
  }
  if (context.best_x.empty()) {  // no point could be run but the start
    context.x.clear();
    context.At(start, false);
  }
  result.x = context.best_x;
  result.value = context.best_value;
  result.violation = context.best_violation;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  return result;
}

}  // namespace tether
