// The default Baumgarte gains, used when a scene names none.
//
// The constraint error obeys C'' + alpha C' + beta C = 0, a damped oscillator with alpha = 2 zeta omega,
// beta = omega^2. The rule takes it critically damped (zeta = 1: a double root at -omega, no overshoot) with
//   omega = min(kDefaultStabilityFraction * r / h, cap),
// where r is the integrator's stability limit on the negative real axis for y' = lambda y (|R(h lambda)| <= 1):
// r = 2 for explicit and symplectic Euler, 2.785 for RK4, 3.307 for Dormand-Prince, so h omega stays a tenth of
// the way to the edge. The cap depends on the order of the method, as measured on the pendulum, the double
// pendulum and the one- and ten-parallelogram four-bars (docs/numerics.md has the table):
//   first order (euler, symplectic_euler): the drift per step is O(h^2) and a firmer pull always helps, up to
//     the stability margin: cap kFirstOrderMaxOmega;
//   high order (rk4, rk45): the drift is tiny and the constraint error grows about linearly with omega above
//     10 rad/s, while below 10 rad/s the 21-bar four-bar leaves its branch at a singular pass: cap
//     kHighOrderMaxOmega = 10 rad/s (alpha = 20, beta = 100, RBDL's critically damped T = 0.1 s).
#pragma once

#include "tether/dynamics/model/model.h"

namespace tether {

inline constexpr double kDefaultStabilityFraction = 0.1;
inline constexpr double kFirstOrderMaxOmega = 1000.0;  // rad/s
inline constexpr double kHighOrderMaxOmega = 10.0;     // rad/s

// r above: the stability limit of the integrator on the negative real axis.
double RealStabilityLimit(Integrator integrator);

struct Gains {
  double alpha = 0.0;
  double beta = 0.0;
};

Gains DefaultGains(Integrator integrator, double step);

// The gains a run uses: the scene's for baumgarte (or the rule's when the scene names none), zero otherwise.
template <typename T>
void GainsInUse(const Model<T>& model, T* alpha, T* beta);

}  // namespace tether
