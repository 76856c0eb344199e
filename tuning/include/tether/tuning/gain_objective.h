// What the gain tuner minimizes: residual vectors r(log omega, zeta), objective = |r| (metres).
//
// Gains: alpha = 2 zeta omega, beta = omega^2 (Baumgarte with natural frequency omega, damping ratio zeta).
//
// `reference` (default): how far the stabilized run (the scene's integrator and step) strays from the true
//   constrained motion, computed by tether itself (reference.h), sampled on the scene's step grid. r stacks (q - q_ref) over every translational coordinate and every
//   sample, then the constraint rows C(q) (metres, weight 1), all divided by sqrt(number of samples x
//   coordinates): |r| is the RMS position error combined with the RMS violation.
//   Window rule: the run is cut into windows as long as the reference's own predictability horizon, each
//   restarted from the reference state at its start. The horizon is the first time at which a second reference,
//   started with its initial velocities scaled by 1 + kHorizonPerturbation, parts from the first by more than
//   kHorizonSeparation times the scene's length scale (the whole run if it never does). A regular mechanism's
//   runs part only linearly in time, so it gets one window: the objective sees the whole run, including any
//   slow blow-up. A chaotic one's (the double pendulum) part exponentially, so it gets windows of a few
//   seconds: the objective measures how the gains hold the constraints, not how chaos amplifies differences.
// `drift`: no reference; r stacks the constraint rows C (m), kDriftTime * C' (m) and the energy drift
//   (E - E0) / max(|E0|, 1 J) times the scene's length scale (m), over every sample, divided likewise.
// --samples N: N initial states, the scene's own and N - 1 perturbed ones (initial velocities moved by 5% of
//   the scene's speed scale, seeded deterministically, then assembled), so that the gains do not fit one motion.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "tether/dynamics/model/model.h"
#include "tether/tuning/reference.h"

namespace tether {

enum class GainObjectiveKind { kReference, kDrift };

inline constexpr double kHorizonPerturbation = 1e-8;
inline constexpr double kHorizonSeparation = 1e-4;
inline constexpr double kDriftTime = 0.1;  // s, the time scale that turns C' into metres

struct GainObjectiveSettings {
  GainObjectiveKind kind = GainObjectiveKind::kReference;
  int samples = 1;
};

class GainObjective {
 public:
  // Computes the reference motions (reference objective). Throws SimulationDiverged if a reference diverges.
  GainObjective(const Model<double>& model, const GainObjectiveSettings& settings);

  // r at the gains; the 2-column Jacobian d r / d(log omega, zeta) too when jacobian is not null.
  // Returns false when the stabilized run diverges (an infeasible point for the optimizer).
  bool Evaluate(double log_omega, double zeta, Eigen::VectorXd* r, Eigen::MatrixXd* jacobian) const;

  // The objective |r| at the gains, or +infinity if the run diverges.
  double Value(double log_omega, double zeta) const;

  // The reference motion of the scene's own initial state on the step grid (empty for the drift objective).
  const ReferenceMotion& reference() const { return reference_; }
  // The window length in use (s): the predictability horizon of the scene's own initial state.
  double window() const { return window_; }

 private:
  // One stretch of the run: a model starting from a reference state, and the reference at its samples.
  struct Window {
    Model<double> model;
    double start = 0.0;
    std::vector<double> times;         // sample times (the step grid within the window)
    std::vector<Eigen::VectorXd> q;    // reference coordinates at those times (reference objective)
  };

  template <typename T>
  bool Residuals(const Model<T>& stabilized, const Window& window, std::vector<T>* out) const;

  GainObjectiveSettings settings_;
  ReferenceMotion reference_;
  std::vector<Window> windows_;
  std::vector<int> translational_;  // indices of translational coordinates in q
  double length_scale_ = 1.0;
  double normalization_ = 1.0;      // 1 / sqrt(number of samples)
  double window_ = 0.0;
};

// The model with Baumgarte gains (alpha, beta) = (2 zeta omega, omega^2).
template <typename T>
Model<T> WithGains(const Model<T>& model, const T& alpha, const T& beta);

}  // namespace tether
