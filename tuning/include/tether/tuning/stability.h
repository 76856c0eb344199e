// The stability bound on the Baumgarte gains for an integrator at a step.
//
// The constraint error obeys C'' + 2 zeta omega C' + omega^2 C = 0. An integrator applied to this linear test
// equation, written for y = (C, C' / omega), multiplies y by an amplification matrix M(x, zeta) each step, with
// x = h omega and K = [[0, 1], [-1, -2 zeta]]:
//   euler             M = I + x K
//   symplectic_euler  M = [[1 - x^2, x (1 - 2 zeta x)], [-x, 1 - 2 zeta x]]   (velocity first, then position)
//   rk4               M = sum_{k<=4} (x K)^k / k!
//   rk45              M = sum_{k<=5} (x K)^k / k! + (x K)^6 / 600       (Dormand-Prince's stability polynomial)
// The error dynamics stay stable while the spectral radius of M is at most 1. The bound B(zeta) is the largest
// x such that rho(M(x', zeta)) <= 1 for every x' in (0, x]: h omega must stay below it.
#pragma once

#include "tether/dynamics/model/model.h"

namespace tether {

// Spectral radius of the amplification matrix at x = h omega.
double AmplificationRadius(Integrator integrator, double x, double zeta);

// B(zeta) above, found by scanning x upwards and bisecting the first crossing of 1 (radius slack 1e-12). It is
// good to about 1e-8 relative: near critical damping M has a double eigenvalue, which floating point resolves
// only to the square root of the rounding error, and under light damping rho crosses 1 slowly (slope zeta).
double StabilityBound(Integrator integrator, double zeta);

}  // namespace tether
