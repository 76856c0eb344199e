// Identification and fitting: estimate scene parameters from recorded trajectories (the vocabulary is
// identification.h).
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

#include <vector>

#include "tether/autodiff/observations.h"
#include "tether/autodiff/parameters.h"
#include "tether/tuning/identification.h"

namespace tether {

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
