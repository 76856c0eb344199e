// The default Baumgarte gains, used when a scene names none.
//
// The constraint error obeys C'' + alpha C' + beta C = 0, a damped oscillator with alpha = 2 zeta omega,
// beta = omega^2. The rule takes it critically damped (zeta = 1, a double root at -omega, no overshoot) and as
// firm as the integrator allows with a wide margin:
//   omega = kDefaultStabilityFraction * r / h,
// where r is the integrator's stability limit on the negative real axis for y' = lambda y (|R(h lambda)| <= 1):
// r = 2 for explicit and symplectic Euler, 2.785 for RK4, 3.307 for Dormand-Prince. A firm correction is what
// keeps a mechanism on its branch through singular configurations (a four-bar's collinear passes): soft gains
// let the error grow there until a rounding-level difference picks the other branch. The fraction keeps h omega
// far from the edge, where the discrete error dynamics would ring; omega is also capped at kDefaultMaxOmega so
// that a tiny step does not turn the constraint forces into a stiff spring.
#pragma once

#include "tether/dynamics/model.h"

namespace tether {

inline constexpr double kDefaultStabilityFraction = 0.1;
inline constexpr double kDefaultMaxOmega = 1000.0;  // rad/s

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
