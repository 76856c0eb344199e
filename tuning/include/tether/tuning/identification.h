// Identification and fitting: estimate scene parameters from recorded trajectories.
//
// Unknowns x: the parameters (positive quantities - masses, inertias, lengths, stiffnesses, rest lengths,
// damping coefficients - as log p, the others as p), and with multiple shooting the start states of the
// segments after the first. Minimized: 1/2 sum_i rho(r_i^2) over
//   data residuals        simulated - observed, every observed cell of every recording;
//   continuity residuals  (multiple shooting) end state of segment k - start state of segment k + 1;
//   smoothing residuals   (fit, --smooth W) sqrt(W) (s_{j+1} - s_j) for consecutive schedule values.
// Multiple shooting (segments K > 1): [0, last observation time] is cut into K equal segments, each simulated
// from its own start state; the start states begin at the initial-guess run with the observed coordinates
// replaced by the data, so a chaotic or long recording is followed piece by piece and the fit converges from
// a rough guess where one long run (single shooting) would not.
//
// Uncertainty: with J the Jacobian of the residuals with respect to the unknowns (parameters in their own units)
// at the estimate, m residuals and n unknowns, the noise variance is s^2 = 2 cost / (m - n) and the covariance
// s^2 (J^T J)^-1 comes from ceres::Covariance (dense SVD, dropping directions below a reciprocal condition
// number of 1e-14). Standard deviations and correlations are read off its parameter block. The parameters are
// reported as not identifiable when the columns of J scaled by the parameters' magnitudes have a condition
// number above kIdentifiabilityCondition; the warning names the parameters of the weakest direction, and
// those get no standard deviation (NaN; null in JSON) rather than the small one the pseudo-inverse would give.
// A parameter with no measurable effect at all (kNoEffect; a lone one has condition number 1) is reported and
// treated the same way. Identify judges its own result (fit_judgement.h: residuals far above the noise the data
// implies, multiple-shooting joins left open, an optimizer stopped by its budget) and marks a failed fit.
//
// Derivatives (settings.method, gradient_method.h): Ceres' Levenberg-Marquardt needs the Jacobian of the
// residuals, which is formed by Jets (ceil(n / kJetStride) Jet runs, a column per unknown); the adjoint gives the
// gradient of the cost, not the Jacobian (a Jacobian by reverse mode would cost one sweep per residual), so it
// serves the gradient-based NLopt algorithms (LD_LBFGS, LD_MMA, LD_SLSQP, ...): there `auto` takes the adjoint
// from kAdjointCrossover unknowns on. The adjoint covers single shooting (multiple shooting's start-state
// unknowns take Jets). The uncertainty at the estimate always comes from the Jacobian by Jets, once.
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

// Throws InputError for bad settings (a bound outside which the initial value lies, an unbounded parameter for
// a global optimizer, a segment count that leaves a segment without observations).
IdentifyResult Identify(const Model<double>& model, const ParameterSet& parameters,
                        const std::vector<Observations>& recordings, const IdentifySettings& settings);

// The cost Identify minimizes, 1/2 sum rho(r_i^2) over the data (and smoothing) residuals of single shooting, at
// the model's parameter values, and its gradient with respect to the parameters in their own units, by
// `method` (jet: J^T rho'(r^2) r from the Jacobian by Jets; adjoint; auto by the count). A check of the adjoint
// path, and the gradient a user's own optimizer may take.
LossGradient IdentifyCostGradient(const Model<double>& model, const ParameterSet& parameters,
                                  const std::vector<Observations>& recordings, const IdentifySettings& settings,
                                  GradientMethod method);

}  // namespace tether
