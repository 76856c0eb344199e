// Minimizing f(x) = 1/2 sum rho(r_i(x)^2) (rho: a robust loss, the identity by default) over a box with Ceres or
// NLopt, for gain tuning and identification.
//
// The residual function returns false at an infeasible point (the simulation diverges). Ceres then rejects the
// step (the cost function returns false); NLopt gets a large finite value, kInfeasibleValue, and a zero
// gradient, never NaN.
//
// Optimizer names (docs/contract.md): "ceres" (Levenberg-Marquardt with the Jacobian, box bounds), or
// "nlopt:ALGORITHM" with any NLopt algorithm name: gradient based (LD_LBFGS, LD_MMA, LD_SLSQP, ...) get
// g = J^T r; derivative free (LN_BOBYQA, LN_COBYLA, LN_SBPLX, LN_NELDERMEAD, ...) and global ones (GN_DIRECT_L,
// GN_CRS2_LM, ...) only f. The multi-level single-linkage methods (GN_MLSL, GN_MLSL_LDS, G_MLSL, G_MLSL_LDS) run
// LN_BOBYQA as their local optimizer, or LD_LBFGS when their name asks for derivatives (G_...).
#pragma once

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

namespace tether {

inline constexpr double kInfeasibleValue = 1e10;

// r at x; the Jacobian (rows of r by entries of x) too when jacobian is not null. False: infeasible.
using ResidualFunction = std::function<bool(const std::vector<double>& x, Eigen::VectorXd* r, Eigen::MatrixXd* jacobian)>;

// The cost 1/2 sum rho(r_i(x)^2) and its gradient at x computed at once (by the adjoint, adjoint.h), which the
// gradient-based NLopt algorithms then take instead of J^T rho'(r^2) r. False: infeasible.
using CostGradientFunction = std::function<bool(const std::vector<double>& x, double* cost, std::vector<double>* gradient)>;

// A robust loss rho(s) of the squared residual s = r_i^2 (Ceres' convention): the cost is 1/2 sum rho(r_i^2).
//   none    rho(s) = s
//   huber   rho(s) = s for s <= d^2, 2 d sqrt(s) - d^2 beyond       (linear growth past |r| = d)
//   cauchy  rho(s) = d^2 log(1 + s / d^2)                            (logarithmic growth)
struct RobustLoss {
  enum class Kind { kNone, kHuber, kCauchy };
  Kind kind = Kind::kNone;
  double delta = 1.0;
};

// rho(s) and rho'(s) of a robust loss (the same functions as Ceres' HuberLoss and CauchyLoss).
void EvaluateLoss(const RobustLoss& loss, double s, double rho[2]);

// rho(s) in any scalar (the adjoint records the loss in Rev arithmetic).
template <typename T>
T RobustRho(const RobustLoss& loss, const T& s) {
  using std::log;
  using std::sqrt;
  const double b = loss.delta * loss.delta;
  if (loss.kind == RobustLoss::Kind::kHuber && s > b) return 2.0 * loss.delta * sqrt(s) - b;
  if (loss.kind == RobustLoss::Kind::kCauchy) return b * log(1.0 + s / b);
  return s;
}

// Parses "huber:DELTA" or "cauchy:DELTA" (DELTA > 0); throws InputError naming `flag`.
RobustLoss ParseRobustLoss(const std::string& text, const std::string& flag);

// Told of every evaluation of the cost, with its value (NaN where the point is infeasible), from the thread that
// made it: a progress display's hook (the command line's, cli/progress_line.h).
using EvaluationObserver = std::function<void(double cost)>;

struct OptimizerSettings {
  std::string name = "ceres";
  RobustLoss loss;
  int max_evaluations = 200;  // NLopt's budget of evaluations; Ceres gets max_evaluations / 2 iterations
  double relative_tolerance = 1e-8;  // on x (NLopt) and on the cost decrease (Ceres)
  EvaluationObserver observer;       // none by default
  // Ceres only: accept a step that raises the cost where the last few steps have lowered it more than this one
  // raises it (Ceres' non-monotonic steps), which crosses the narrow valleys of a swing-up's shooting problem
  bool nonmonotonic_steps = false;
  // Ceres only: the caller's own test, asked after every iteration; true stops the minimizer
  std::function<bool()> done;
};

// `residuals` telling `settings`' observer of each evaluation (the cost 1/2 sum rho(r_i^2)), or `residuals`
// itself when there is no observer.
ResidualFunction Observed(const ResidualFunction& residuals, const OptimizerSettings& settings);

struct OptimizerResult {
  std::vector<double> x;
  double value = 0.0;    // 1/2 sum rho(r_i^2) at x (1/2 |r|^2 without a robust loss)
  int evaluations = 0;   // residual evaluations, with or without Jacobian
  double seconds = 0.0;
  std::string message;   // the back end's own summary of why it stopped
  bool hit_limit = false;  // stopped by its budget (Ceres' iterations, NLopt's evaluations), not by converging
  double violation = 0.0;  // MinimizeConstrained: the largest constraint violation at x over its tolerance
};

// Throws InputError ("optimizer: ...") for an unknown optimizer name. With `cost_gradient`, a gradient-based
// NLopt algorithm takes its gradients (and the costs that come with them) from it; the others ignore it.
OptimizerResult Minimize(const ResidualFunction& residuals, const std::vector<double>& start,
                         const std::vector<double>& lower, const std::vector<double>& upper,
                         const OptimizerSettings& settings, const CostGradientFunction& cost_gradient = nullptr);

// Constrained minimization (trajectory optimisation): minimize 1/2 sum r_i^2 over the rows of the residual
// function that are neither equality nor inequality rows, subject to r_e = 0 (equality rows) and sign_c r_c <= 0
// (inequality rows), each within its tolerance, and the box, with an NLopt algorithm made for constraints
// (nlopt:LD_SLSQP: sequential quadratic programming with a BFGS Hessian, which takes the rows' Jacobian). The
// result is the best feasible point seen (the least cost among those meeting every constraint), or, where none
// was feasible, the one with the least violation; `violation` is its largest violation relative to the row's
// tolerance (at most 1: feasible).
struct ConstraintRows {
  std::vector<int> equality, inequality;  // row indices
  std::vector<double> equality_tolerance, inequality_tolerance, inequality_sign;
};
// The bounds as NLopt takes them: +-the largest double (tether's "unbounded") as true infinities, since with the
// largest double NLopt's first step would be ~1e308.
std::vector<double> NloptBounds(std::vector<double> bounds);

// Throws InputError naming --optimizer unless `name` is an NLopt algorithm (constraints need one).
void CheckConstrainedOptimizer(const std::string& name);
OptimizerResult MinimizeConstrained(const ResidualFunction& residuals, const ConstraintRows& rows,
                                    const std::vector<double>& start, const std::vector<double>& lower,
                                    const std::vector<double>& upper, const OptimizerSettings& settings);

// True for the NLopt algorithms that use gradients (LD_, GD_, and the MLSL and AUGLAG variants that run LD_LBFGS).
bool UsesGradients(const std::string& optimizer_name);

// Checks an optimizer name without running anything; throws InputError naming `where` (the command line's
// "--optimizer", the Python module's "optimizer").
void CheckOptimizerName(const std::string& name, const std::string& where);

// 1/2 sum rho(r_i^2).
double RobustCost(const RobustLoss& loss, const Eigen::VectorXd& r);

// (J^T J)^-1 at x from ceres::Covariance (dense SVD; directions whose reciprocal condition number is below
// 1e-14 are dropped, as a pseudo-inverse does). False if the residuals cannot be evaluated there.
bool UnscaledCovariance(const ResidualFunction& residuals, const std::vector<double>& x, Eigen::MatrixXd* covariance);

}  // namespace tether
