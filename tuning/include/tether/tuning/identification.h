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
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "tether/autodiff/observations.h"
#include "tether/autodiff/parameters.h"
#include "tether/tuning/optimizer.h"

namespace tether {

inline constexpr double kIdentifiabilityCondition = 1e8;
// A parameter whose scaled Jacobian column (the change of the residuals for a 100% change of the parameter) is
// below this fraction of the data's norm has no measurable effect on the data.
inline constexpr double kNoEffect = 1e-9;

struct IdentifySettings {
  OptimizerSettings optimizer;
  std::vector<std::pair<double, double>> bounds;  // per parameter, in its own units; empty: unbounded
  int segments = 1;                               // multiple shooting when > 1
  double smooth = 0.0;                            // weight W of the schedule smoothing residuals
};

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
  std::vector<std::string> warnings;
  std::vector<ResidualStatistics> residuals;
  bool failed = false;  // the estimate does not reproduce the data (fit_judgement.h): no uncertainty for it
};

// Throws InputError for bad settings (a bound outside which the initial value lies, an unbounded parameter for
// a global optimizer, a segment count that leaves a segment without observations).
IdentifyResult Identify(const Model<double>& model, const ParameterSet& parameters,
                        const std::vector<Observations>& recordings, const IdentifySettings& settings);

// True for the kinds optimized in log space.
bool PositiveKind(FieldRef::Kind kind);

}  // namespace tether
