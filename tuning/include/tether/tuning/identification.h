// The vocabulary of identification and fitting (identify.h, the driver; trajectory_fit.h, fitting with
// constraints): the settings, the inequality targets of trajectory optimisation, bounds on parameters, and the
// result with its uncertainty and the fit's own judgement of it.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "tether/autodiff/gradient_method.h"
#include "tether/autodiff/observations.h"
#include "tether/autodiff/parameters.h"
#include "tether/tuning/optimizer.h"

namespace tether {

inline constexpr double kIdentifiabilityCondition = 1e8;
// A parameter whose scaled Jacobian column (the change of the residuals for a 100% change of the parameter) is
// below this fraction of the data's norm has no measurable effect on the data.
inline constexpr double kNoEffect = 1e-9;

// An inequality target of fit (--at-least / --at-most COLUMN=VALUE@T): a trajectory column above or below a value
// at a time, a constraint met to kConstraintTolerance of max(1, |value|) rather than a penalty.
struct InequalityTarget {
  std::string column;
  double value = 0.0, time = 0.0;
  bool at_least = true;
  std::string text;  // as the user wrote it ("--at-least tip.y=1.99@5"), for messages
  // A path constraint over [from, time] (from < time): met at every integrator step within it; from == time: a
  // constraint at that time.
  double from = 0.0;
};
inline constexpr double kConstraintTolerance = 1e-6;

// "COLUMN=VALUE@T" or "COLUMN=VALUE@T0:T1" (over an interval) -> the target (the column is checked against the
// scene later); InputError naming `flag`.
InequalityTarget ParseInequality(const std::string& text, bool at_least, const std::string& flag);

// Trajectory optimisation's defaults (fit with constraints or several starts: trajectory_fit.h), for the command
// line and Python alike: a solver made for constraints, and a budget at which SLSQP meets them (200 often stops it
// just short).
inline constexpr const char* kTrajectoryOptimizer = "nlopt:LD_SLSQP";
inline constexpr int kTrajectoryMaxEvaluations = 1000;

struct IdentifySettings {
  OptimizerSettings optimizer;
  GradientMethod method = GradientMethod::kAuto;  // how a gradient-based NLopt algorithm gets its gradients
  std::vector<std::pair<double, double>> bounds;  // per parameter, in its own units; empty: unbounded
  int segments = 1;  // multiple shooting when > 1; 0: fit chooses (trajectory_fit.h)
  double smooth = 0.0;  // weight W of the schedule smoothing residuals
  double effort = 0.0;  // weight W of the joint motors' effort, W int tau^2 dt
  std::vector<InequalityTarget> inequalities;
  int starts = 1;          // the scene's values and starts - 1 random ones (trajectory_fit.h)
  unsigned seed = 1;       // of the random starts
};

// A bound on one parameter, or, for a pointer ending in "/*", on every parameter of that array.
struct ParameterBound {
  std::string pointer;
  double lower, upper;  // lower < upper
};

// IdentifySettings::bounds for `parameters`: unbounded, then each wildcard bound on its array's parameters, then
// each parameter's own bound (an element's own bound wins over its array's). `where` names the flag or argument
// in the InputError thrown for a bound that matches no parameter.
std::vector<std::pair<double, double>> BoundsFor(const ParameterSet& parameters,
                                                 const std::vector<ParameterBound>& bounds, const std::string& where);

struct ResidualStatistics {
  std::string file, column;
  int count = 0;
  double rms = 0.0, largest = 0.0;  // of simulated - observed at the estimate
};

struct IdentifyResult {
  std::vector<double> initial, estimate, standard_deviation;  // per parameter (NaN where unavailable)
  Eigen::MatrixXd correlation;                                // parameters x parameters
  double initial_cost = 0.0, final_cost = 0.0;                // 1/2 sum rho(r_i^2)
  double condition_number = 0.0;                              // of the scaled Jacobian (parameters)
  int residual_count = 0;
  OptimizerResult optimizer;
  std::string gradient_method;  // "jet" or "adjoint": how the optimizer's derivatives were taken; "none" if none
  std::vector<std::string> warnings;
  std::vector<ResidualStatistics> residuals;
  bool failed = false;  // the estimate does not reproduce the data (fit_judgement.h): no uncertainty for it
  // Trajectory optimisation (trajectory_fit.h): the inequality targets at the estimate, one run of it from the
  // scene's initial state, and how the starts went.
  struct Constraint {
    InequalityTarget target;
    double simulated = 0.0;  // over an interval: at the step where it comes closest to (or furthest past) its bound
    double at = 0.0;         // that step's time (the target's time for a point)
    bool met = true;
  };
  std::vector<Constraint> constraints;
  bool feasible = true;
  std::string stopping_reason;  // "converged", "iteration limit" or "infeasible"
  int segments = 1;             // multiple shooting's segments on the way to the estimate (1: single shooting)
  int starts = 1, feasible_starts = 1, best_start = 0;
};

}  // namespace tether
