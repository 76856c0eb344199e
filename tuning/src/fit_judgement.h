// Whether an identification or a fit found what it reports: the checks Identify runs on its own result.
//
// Noise the data implies: for each observed column, sigma = min over k = 2..6 of RMS(D^k x) / sqrt(C(2k, k)),
// D^k the k-th difference of consecutive rows. For white noise of deviation sigma, D^k x has deviation
// sigma sqrt(C(2k, k)); a smooth motion adds about x^(k) dt^k, which shrinks with k while dt is short against
// the motion, so the minimum over k is an upper estimate of the noise (columns with fewer than 8 values give
// none). The checks, each a warning:
//   residuals    a column's residual RMS above kNoiseFactor times max(its noise, 1e-6 of its RMS value): the
//                estimate does not reproduce the data (a local minimum, a wrong model);
//   continuity   (multiple shooting) a gap between a segment's end and the next start above kNoiseFactor times
//                the largest residual RMS and 1e-6 of the scene's length scale: the pieces are not one motion;
//   budget       the optimizer stopped at its iteration or evaluation limit rather than converging;
//   no cost      the optimizer ended without a finite cost: the runs it tried failed (diverged), nothing was fitted.
// The first two and the last mean the fit failed: its standard deviations and correlations are not meaningful. Identify
// adds, with multiple shooting, a warning when one run of the estimate from the scene's initial state (what a scene
// written with it does) misses a recording by more than kNoiseFactor times the fit's residual RMS.
#pragma once

#include <string>
#include <vector>

#include "tether/tuning/identification.h"

namespace tether {

inline constexpr double kNoiseFactor = 10.0;

struct FitJudgement {
  std::vector<std::string> warnings;
  bool failed = false;
};

// `continuity`: the position and velocity gaps of multiple shooting's joins (empty with one segment);
// `length_scale` the scene's (simulator.h).
FitJudgement JudgeFit(const std::vector<Observations>& recordings, const std::vector<ResidualStatistics>& residuals,
                      const std::vector<double>& continuity, double length_scale, const OptimizerResult& optimizer);

// The noise estimate above for column `column` of `recording` (NaN when it has too few values).
double NoiseLevel(const Observations& recording, size_t column);

}  // namespace tether
