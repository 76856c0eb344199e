// The IFToMM A02 N-four-bar on its parallelogram branch, the reference of tests/singular_mechanisms_test.cc and of
// the Simbody comparison (bench/peer/simbody_bench.cc). N parallelograms of uniform 1 m, 1 kg bars: N + 1 cranks
// pinned to the ground at x = 0, 1, ..., N and N couplers joining their tips. On the branch every crank turns by
// the same angle theta and every coupler translates with the crank tips, so the mechanism has one degree of
// freedom:
//   I theta'' = -G cos theta,   I = (N + 1) / 3 + N,   G = g ((N + 1) / 2 + N),
// from theta(0) = pi/2, theta'(0) = -1 (the cranks vertical, turning clockwise), integrated by classical RK4 at
// h = 1e-5 s, independently of tether. Crank i's centre is (i + cos(theta) / 2, sin(theta) / 2), coupler i's
// (i + 1/2 + cos theta, sin theta).
#pragma once

#include <cmath>
#include <vector>

namespace tether {

inline double NFourBarInertia(int n) { return (n + 1) / 3.0 + n; }
inline double NFourBarLoad(int n, double gravity) { return gravity * ((n + 1) / 2.0 + n); }

// theta at t = every, 2 every, ... up to `duration` from I theta'' = -G cos theta (any I and G: a redundant
// parallelogram has its own), theta(0) = pi/2, theta'(0) = -1, by classical RK4 at h = 1e-5 s.
inline std::vector<double> ReducedCrankAngles(double inertia, double load, double every, double duration) {
  auto accel = [&](double theta) { return -load / inertia * std::cos(theta); };
  double theta = M_PI / 2, omega = -1.0;
  const double h = 1e-5;
  const long per_sample = std::lround(every / h), steps = std::lround(duration / h);
  std::vector<double> angles;
  for (long k = 1; k <= steps; ++k) {
    const double k1t = omega, k1w = accel(theta);
    const double k2t = omega + 0.5 * h * k1w, k2w = accel(theta + 0.5 * h * k1t);
    const double k3t = omega + 0.5 * h * k2w, k3w = accel(theta + 0.5 * h * k2t);
    const double k4t = omega + h * k3w, k4w = accel(theta + h * k3t);
    theta += h / 6.0 * (k1t + 2 * k2t + 2 * k3t + k4t);
    omega += h / 6.0 * (k1w + 2 * k2w + 2 * k3w + k4w);
    if (k % per_sample == 0) angles.push_back(theta);
  }
  return angles;
}

}  // namespace tether
