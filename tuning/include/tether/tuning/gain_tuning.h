// Tuning the Baumgarte gains of a scene: minimize the gain objective (gain_objective.h) over
// x = (log omega, zeta), alpha = 2 zeta omega, beta = omega^2, inside the box
//   zeta in [kMinZeta, kMaxZeta],   omega in [kMinOmega, kStabilityMargin * min_zeta B(zeta) / h],
// where B is the integrator's stability bound on h omega (stability.h): every point of the box keeps the
// discrete error dynamics stable with a margin, so the tuner never returns gains that blow up. The search
// starts from the best of the presets inside the box (the default rule's gains, default_gains.h; 10 and 50
// rad/s critically damped), so the result is never worse than those on the objective. The tuned gains are then compared with presets on
// the whole run: none (0, 0); RBDL-style (20, 100); MuJoCo-style (100, 2500); the default rule.
#pragma once

#include <string>
#include <vector>

#include "tether/tuning/gain_objective.h"
#include "tether/tuning/optimizer.h"

namespace tether {

inline constexpr double kMinZeta = 0.3;
inline constexpr double kMaxZeta = 1.5;
inline constexpr double kMinOmega = 0.1;         // rad/s
inline constexpr double kStabilityMargin = 0.9;  // fraction of the stability bound the box may use

struct TuneSettings {
  GainObjectiveSettings objective;
  OptimizerSettings optimizer;
};

// How a pair of gains does over the whole run.
struct GainMetrics {
  std::string name;
  double alpha = 0.0, beta = 0.0;
  double objective = NAN;             // the tuning objective at these gains (NaN for beta = 0: not a point of it)
  bool diverged = false;
  std::string divergence;             // the simulator's message when diverged
  double rms_position_error = NAN;    // against the reference, m (NaN without a reference: drift objective)
  double max_constraint_error = NAN;  // m
  double energy_drift = NAN;          // max |E - E0| / max(|E0|, 1 J)
  double seconds = NAN;               // wall time of the run
};

struct TuneResult {
  double alpha = 0.0, beta = 0.0, omega = 0.0, zeta = 0.0;
  double objective = 0.0;        // |r| at the tuned gains, m
  double window = 0.0;           // the objective's window length, s (gain_objective.h)
  double bound = 0.0;            // B(zeta) at the tuned zeta: h omega must stay below it
  double margin = 0.0;           // 1 - h omega / B(zeta)
  double omega_upper = 0.0;      // the box's upper omega
  OptimizerResult optimizer;
  std::vector<GainMetrics> comparison;  // the tuned gains first, then the presets
};

TuneResult TuneGains(const Model<double>& model, const TuneSettings& settings);

// The gains the tuned ones are compared with: none (0, 0); RBDL-style (20, 100); MuJoCo-style (100, 2500); the
// default rule's for the integrator and step (default_gains.h).
struct NamedGains {
  std::string name;
  double alpha = 0.0, beta = 0.0;
};
std::vector<NamedGains> GainPresets(Integrator integrator, double step);

// Runs the model with the gains over its whole duration and measures it (reference may be empty).
GainMetrics MeasureGains(const Model<double>& model, const std::string& name, double alpha, double beta,
                         const GainObjective& objective);

}  // namespace tether
