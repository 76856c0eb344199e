#include "fit_judgement.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace tether {

double NoiseLevel(const Observations& recording, size_t column) {
  std::vector<double> x;
  for (const std::vector<double>& row : recording.values) {
    if (!std::isnan(row[column])) x.push_back(row[column]);
  }
  if (x.size() < 8) return NAN;
  double noise = INFINITY, binomial = 2.0;  // C(2k, k), from k = 1
  for (int k = 1; k <= 6 && x.size() > static_cast<size_t>(k) + 1; ++k) {
    for (size_t i = 0; i + 1 < x.size() - (k - 1); ++i) x[i] = x[i + 1] - x[i];  // x holds D^k now
    if (k > 1) binomial *= 2.0 * (2 * k - 1) / k;
    if (k < 2) continue;
    const size_t count = x.size() - k;
    double sum = 0.0;
    for (size_t i = 0; i < count; ++i) sum += x[i] * x[i];
    noise = std::min(noise, std::sqrt(sum / count / binomial));
  }
  return noise;
}

FitJudgement JudgeFit(const std::vector<Observations>& recordings, const std::vector<ResidualStatistics>& residuals,
                      const std::vector<double>& continuity, double length_scale, const OptimizerResult& optimizer) {
  FitJudgement judgement;
  double largest_rms = 0.0;
  size_t group = 0;
  for (const Observations& recording : recordings) {
    for (size_t c = 0; c < recording.columns.size(); ++c, ++group) {
      const ResidualStatistics& s = residuals[group];
      largest_rms = std::max(largest_rms, s.rms);
      const double noise = NoiseLevel(recording, c);
      if (std::isnan(noise) || s.count == 0) continue;
      double magnitude = 0.0;
      int count = 0;
      for (const std::vector<double>& row : recording.values) {
        if (std::isnan(row[c])) continue;
        magnitude += row[c] * row[c];
        ++count;
      }
      magnitude = std::sqrt(magnitude / std::max(count, 1));
      if (s.rms > kNoiseFactor * std::max(noise, 1e-6 * magnitude)) {
        std::ostringstream message;
        message << s.file << ", column " << s.column << ": the residuals (RMS " << s.rms << ") are far above the "
                << "noise the data implies (about " << noise << " from its roughness): the estimate does not "
                << "reproduce the data (a local minimum? more --segments may help)";
        judgement.warnings.push_back(message.str());
        judgement.failed = true;
      }
    }
  }
  double gap = 0.0;
  for (double g : continuity) gap = std::max(gap, std::abs(g));
  if (gap > kNoiseFactor * largest_rms && gap > 1e-6 * length_scale) {
    std::ostringstream message;
    message << "multiple shooting left its segments apart (a gap of up to " << gap << " between a segment's end "
            << "and the next one's start, against residuals of RMS " << largest_rms << "): the pieces do not "
            << "join into one motion";
    judgement.warnings.push_back(message.str());
    judgement.failed = true;
  }
  if (!std::isfinite(optimizer.value)) {  // its evaluations failed (runs diverged): nothing was fitted
    judgement.warnings.push_back("the optimizer ended without a finite cost (" + optimizer.message +
                                 "): the runs it tried failed, so nothing was fitted");
    judgement.failed = true;
  }
  if (optimizer.hit_limit) {
    judgement.warnings.push_back("the optimizer stopped at its limit (" + optimizer.message +
                                 ") rather than converging; raise --max-evaluations");
  }
  if (judgement.failed) {
    judgement.warnings.push_back("the fit failed: no standard deviations or correlations are reported for it");
  }
  return judgement;
}

}  // namespace tether
