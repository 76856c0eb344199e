// One descriptor per integrator: what the rest of tether knows of a method, in one place (the stepping itself is
// integrators.h). Read by the scene reader (its name), the default gains (default_gains.h: the real stability
// limit and whether the method is of the first order), the tuner's stability bounds (tuning/stability.h: the
// stability function) and the studies' cost estimate (KKT evaluations a step).
//
// The stability function R of a method is its step map on the test equation y' = lambda y, y_{n+1} = R(h lambda)
// y_n. For the explicit Runge-Kutta methods it is a polynomial, held as the divisors d_k of its successive terms,
// R(z) = 1 + z/d_1 + z^2/(d_1 d_2) + ... (R(Z) for a matrix argument Z: the tuner's error dynamics
// C'' + alpha C' + beta C = 0 as a first-order 2 x 2 system):
//   euler   1 + z                                        d = 1
//   rk4     1 + z + z^2/2 + z^3/6 + z^4/24               d = 1, 2, 3, 4
//   rk45    the same to z^5/120, + z^6/600               d = 1, 2, 3, 4, 5, 5
//           (Dormand-Prince's fifth-order solution: seven stages, the last shared with the next step)
// Symplectic Euler is a partitioned method: its step map on (C, C') is not a polynomial in Z but
// [[1 - x^2, x (1 - 2 zeta x)], [-x, 1 - 2 zeta x]] with x = h omega (tuning/stability.cc), so it has no
// coefficients here. The real stability limit r is the largest x with |R(-x)| <= 1: 2 for both Eulers, 2.785 for
// rk4, 3.307 for rk45.
//
// A force F held constant over a step changes the velocity by h M^-1 F and the configuration by w h^2 M^-1 F: w is
// what the method makes of it (Euler's step moves q by the old velocity: 0; symplectic Euler's by the new one: 1;
// the Runge-Kutta methods integrate it exactly: 1/2). The time-stepping contact (unilateral_events.h) moves q by
// w h dv with its impulse's velocity change dv, as the integrator would have moved it under that impulse spread
// over the step.
#pragma once

#include "tether/dynamics/model/model.h"

namespace tether {

struct IntegratorDescriptor {
  Integrator integrator;
  const char* name;              // the scene file's and the flags' name
  int order;                     // of the global error
  double evaluations_per_step;   // stages a step evaluates (rk45: seven, the last shared with the next step)
  double real_stability_limit;   // r above
  int stability_terms;           // how many d_k: 0 for a partitioned method
  double stability_divisors[6];  // d_k above
  double force_position_weight;  // w above
};

// Every integrator, in the order the scene format lists them (a table: nothing is allocated to read it).
inline constexpr IntegratorDescriptor kIntegrators[] = {
    {Integrator::kEuler, "euler", 1, 1.0, 2.0, 1, {1.0}, 0.0},
    {Integrator::kSymplecticEuler, "symplectic_euler", 1, 1.0, 2.0, 0, {}, 1.0},
    {Integrator::kRk4, "rk4", 4, 4.0, 2.785, 4, {1.0, 2.0, 3.0, 4.0}, 0.5},
    {Integrator::kRk45, "rk45", 5, 7.0, 3.307, 6, {1.0, 2.0, 3.0, 4.0, 5.0, 5.0}, 0.5}};

constexpr const IntegratorDescriptor& Describe(Integrator integrator) {
  for (const IntegratorDescriptor& d : kIntegrators) {
    if (d.integrator == integrator) return d;
  }
  return kIntegrators[0];  // unreachable: every Integrator is listed
}

}  // namespace tether
