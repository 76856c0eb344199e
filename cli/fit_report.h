// The report of an identification or a fit (`--report REPORT.html`, docs/reports.md): one self-contained page with
// the run of the estimates against every observed column (and every constrained one) and its scheduled forces
// and torques through their knots, the residuals against time
// and their histogram beside the normal density of the noise they imply, the parameters with their standard
// deviations and correlations, the warnings, and the viewer's page of the estimate's motion with the recording
// beside it.
//
// The estimate is run once from the scene's initial state, as a scene written with it runs (with multiple
// shooting the fit's own residuals, per segment, can be smaller: the JSON's RMS are listed beside). For each
// column with residuals r_i = simulated - observed (n of them):
//   bias  mean(r);   RMS  sqrt(mean(r^2));   sigma  the RMS, the noise's standard deviation the data imply;
//   lag-one autocorrelation  sum (r_i - bias)(r_{i+1} - bias) / sum (r_i - bias)^2: near 0 for white noise, near
//   1 where the model misses the motion itself (a residual that follows a curve);
//   the histogram: 2 sqrt(n) bins at most over [-4 sigma, 4 sigma] (and the range of r), drawn as a density beside
//   the normal density N(0, sigma^2).
#pragma once

#include <string>
#include <vector>

#include "tether/autodiff/observations.h"
#include "tether/tuning/identification.h"

namespace tether::cli {

struct FitReportInput {
  bool fit = false;  // tether fit (else identify)
  std::string scene_path, optimizer;
  const Model<double>* fitted = nullptr;  // the scene's model with the estimates in place
  const ParameterSet* parameters = nullptr;
  const IdentifyResult* result = nullptr;
  const std::vector<Observations>* recordings = nullptr;
  const std::vector<InequalityTarget>* constraints = nullptr;
};

// The page's text. Throws InputError when the page would be too large for a browser (the viewer's limit); an
// estimate whose run diverges is drawn as far as it went, and the page says so.
std::string FitReportHtml(const FitReportInput& input);

}  // namespace tether::cli
