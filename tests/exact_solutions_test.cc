// Physics against exact solutions: the pendulum's period (complete elliptic integral), the harmonic oscillator
// on a slider (undamped and damped), a constant torque on a pinned wheel, a projectile, piecewise linear force
// and torque schedules against their integrals, and energy conservation of the pendulum and double pendulum.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "test_scenes.h"

namespace tether {
namespace {

using testing::EllipticK;
using testing::Record;
using testing::Recording;
using testing::SceneFromJson;

constexpr double kG = 9.81;  // m/s^2, as in the acceptance checks

// A number written with enough digits to round-trip, for scene text built in a test.
std::string Num(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", x);
  return text;
}

// A bob on a rod of length L from the origin, released at rest at angle theta0 from the downward vertical.
Model<double> Pendulum(double length, double theta0, double duration) {
  return SceneFromJson(R"({
    "bodies": [{"name": "bob", "type": "particle", "mass": 1.0,
                "position": [)" +
                       Num(length * std::sin(theta0)) + ", " + Num(-length * std::cos(theta0)) + R"(]}],
    "constraints": [{"type": "distance", "bodies": ["world", "bob"], "length": )" +
                       Num(length) + R"(}],
    "effects": [{"type": "gravity", "acceleration": [0.0, -9.81]}],
    "simulation": {"integrator": "rk4", "step": 1e-3, "duration": )" +
                       Num(duration) + R"(},
    "stabilization": {"method": "baumgarte", "alpha": 10.0, "beta": 25.0}})");
}

// Times at which coordinate `i` crosses zero, located on the cubic Hermite interpolant through the output
// rows (positions and velocities), whose error is O(h^4), far below the period tolerance.
std::vector<double> ZeroCrossings(const Recording& r, int i) {
  std::vector<double> crossings;
  for (size_t k = 1; k < r.t.size(); ++k) {
    const double x0 = r.q[k - 1][i], x1 = r.q[k][i];
    if ((x0 < 0) == (x1 < 0)) continue;
    const double h = r.t[k] - r.t[k - 1], d0 = h * r.v[k - 1][i], d1 = h * r.v[k][i];
    auto hermite = [&](double s) {
      const double s2 = s * s, s3 = s2 * s;
      return (2 * s3 - 3 * s2 + 1) * x0 + (s3 - 2 * s2 + s) * d0 + (-2 * s3 + 3 * s2) * x1 + (s3 - s2) * d1;
    };
    double lo = 0.0, hi = 1.0;
    for (int it = 0; it < 60; ++it) {
      const double mid = 0.5 * (lo + hi);
      ((hermite(mid) < 0) == (x0 < 0) ? lo : hi) = mid;
    }
    crossings.push_back(r.t[k - 1] + h * 0.5 * (lo + hi));
  }
  return crossings;
}

double RelativeEnergyDrift(const Recording& r) {
  double drift = 0.0;
  for (double e : r.energy) drift = std::max(drift, std::abs(e - r.energy[0]));
  return drift / std::abs(r.energy[0]);
}

TEST(ExactSolutions, EllipticIntegralByAgmMatchesKnownValues) {
  // K(0) = pi/2; K(1/sqrt 2) = Gamma(1/4)^2 / (4 sqrt(pi))
  EXPECT_NEAR(EllipticK(0.0), M_PI / 2, 1e-15);
  EXPECT_NEAR(EllipticK(1.0 / std::sqrt(2.0)), std::pow(std::tgamma(0.25), 2) / (4.0 * std::sqrt(M_PI)), 1e-14);
}

TEST(ExactSolutions, PendulumPeriodAtSixtyDegreesMatchesEllipticIntegral) {
  const double length = 0.7, theta0 = M_PI / 3;
  const Recording r = Record(Pendulum(length, theta0, 8.0));
  const double exact = 4.0 * std::sqrt(length / kG) * EllipticK(std::sin(theta0 / 2));
  // bob.x crosses zero twice per period
  const std::vector<double> crossings = ZeroCrossings(r, 0);
  ASSERT_GE(crossings.size(), 6u);
  const double period = 2.0 * (crossings.back() - crossings.front()) / (crossings.size() - 1);
  EXPECT_NEAR(period / exact - 1.0, 0.0, 1e-6) << "period " << period << ", exact " << exact;
}

// Particle of mass 2 kg on a horizontal slider through the origin, a spring (k = 50 N/m, rest length 1 m) to the
// world point (-2, 0), optional damping c; released at rest at x = -0.7, 0.3 m from its equilibrium x = -1.
Model<double> Oscillator(double damping) {
  const std::string damper =
      damping > 0 ? R"(, {"type": "damping", "coefficient": )" + Num(damping) + R"(, "bodies": ["m"]})" : "";
  return SceneFromJson(R"({
    "bodies": [{"name": "m", "type": "particle", "mass": 2.0, "position": [-0.7, 0.0]}],
    "constraints": [{"type": "slider", "bodies": ["world", "m"], "axis": [1.0, 0.0]}],
    "effects": [{"type": "gravity", "acceleration": [0.0, -9.81]},
                {"type": "spring", "bodies": ["world", "m"], "points": [[-2.0, 0.0], [0.0, 0.0]],
                 "stiffness": 50.0, "rest_length": 1.0})" +
                       damper + R"(],
    "simulation": {"integrator": "rk4", "step": 1e-3, "duration": 3.0},
    "stabilization": {"method": "baumgarte", "alpha": 10.0, "beta": 25.0}})");
}

// x(t) = -1 + 0.3 e^{-zeta w t} (cos(w_d t) + zeta w / w_d sin(w_d t)), w = sqrt(k/m), zeta = c / (2 sqrt(k m)).
double OscillatorX(double t, double damping) {
  const double k = 50.0, m = 2.0, w = std::sqrt(k / m), zeta = damping / (2.0 * std::sqrt(k * m));
  const double wd = w * std::sqrt(1.0 - zeta * zeta);
  return -1.0 + 0.3 * std::exp(-zeta * w * t) * (std::cos(wd * t) + zeta * w / wd * std::sin(wd * t));
}

void ExpectOscillatorMatchesClosedForm(double damping) {
  const Recording r = Record(Oscillator(damping), 10);
  const double m = 2.0, k = 50.0, dt = 1e-6;
  double worst_x = 0.0, worst_y = 0.0, worst_energy = 0.0;
  for (size_t i = 0; i < r.t.size(); ++i) {
    const double t = r.t[i], x = OscillatorX(t, damping);
    const double v = (OscillatorX(t + dt, damping) - OscillatorX(t - dt, damping)) / (2 * dt);
    worst_x = std::max(worst_x, std::abs(r.q[i][0] - x));
    worst_y = std::max(worst_y, std::abs(r.q[i][1]));
    // kinetic + spring energy (the gravity term vanishes on y = 0); the central difference of x(t) is
    // accurate to ~1e-9 here, so the bound is the integrator's
    worst_energy = std::max(worst_energy, std::abs(r.energy[i] - (0.5 * m * v * v + 0.5 * k * (x + 1) * (x + 1))));
  }
  EXPECT_LT(worst_x, 1e-6);
  EXPECT_LT(worst_y, 1e-6);       // the slider holds the particle on y = 0 against gravity
  EXPECT_LT(worst_energy, 1e-7);  // J, of E0 = 2.25 J
  EXPECT_DOUBLE_EQ(r.t.back(), 3.0);
}

TEST(ExactSolutions, UndampedOscillatorOnSliderMatchesClosedForm) { ExpectOscillatorMatchesClosedForm(0.0); }

TEST(ExactSolutions, DampedOscillatorOnSliderMatchesClosedForm) { ExpectOscillatorMatchesClosedForm(0.8); }

TEST(ExactSolutions, ConstantTorqueOnPinnedWheel) {
  // I = 0.5 kg m^2, tau = 0.2 N m: angle = tau t^2 / (2 I), omega = tau t / I; the pin holds the centre against
  // gravity. RK4 integrates this polynomial motion exactly, so only rounding remains.
  const double inertia = 0.5, tau = 0.2;
  const Recording r = Record(SceneFromJson(R"({
    "bodies": [{"name": "wheel", "type": "rigid", "mass": 1.0, "inertia": 0.5, "position": [0.0, 0.0]}],
    "constraints": [{"type": "pin", "bodies": ["world", "wheel"]}],
    "effects": [{"type": "gravity", "acceleration": [0.0, -9.81]}, {"type": "torque", "body": "wheel", "value": 0.2}],
    "simulation": {"duration": 2.0}})"));
  ASSERT_DOUBLE_EQ(r.t.back(), 2.0);
  for (size_t k = 0; k < r.t.size(); ++k) {
    const double t = r.t[k];
    ASSERT_NEAR(r.q[k][2], tau * t * t / (2 * inertia), 1e-8) << "t = " << t;
    ASSERT_NEAR(r.v[k][2], tau * t / inertia, 1e-8) << "t = " << t;
    ASSERT_NEAR(r.q[k][0], 0.0, 1e-8) << "t = " << t;
    ASSERT_NEAR(r.q[k][1], 0.0, 1e-8) << "t = " << t;
    // the energy counts the rotational kinetic energy 1/2 I omega^2 = tau^2 t^2 / (2 I) (the centre does not move)
    ASSERT_NEAR(r.energy[k], tau * tau * t * t / (2 * inertia), 1e-8) << "t = " << t;
  }
}

TEST(ExactSolutions, ProjectileWithoutConstraints) {
  // 3D, so the third axis is exercised too: x = x0 + v0 t + g t^2 / 2 componentwise
  const Recording r = Record(SceneFromJson(R"({
    "dimension": 3,
    "bodies": [{"name": "ball", "type": "particle", "mass": 0.3, "position": [1.0, -2.0, 0.5],
                "velocity": [3.0, 1.5, 12.0]}],
    "effects": [{"type": "gravity", "acceleration": [0.0, 0.0, -9.81]}],
    "simulation": {"integrator": "rk4", "step": 0.01, "duration": 2.5}})"));
  const double x0[3] = {1.0, -2.0, 0.5}, v0[3] = {3.0, 1.5, 12.0}, g[3] = {0.0, 0.0, -kG};
  ASSERT_EQ(r.t.size(), 251u);
  for (size_t k = 0; k < r.t.size(); ++k) {
    const double t = r.t[k];
    for (int i = 0; i < 3; ++i) {
      ASSERT_NEAR(r.q[k][i], x0[i] + v0[i] * t + 0.5 * g[i] * t * t, 1e-11) << "t = " << t << ", axis " << i;
      ASSERT_NEAR(r.v[k][i], v0[i] + g[i] * t, 1e-11) << "t = " << t << ", axis " << i;
    }
    EXPECT_EQ(r.constraint_error[k], 0.0);
  }
  // energy: 1/2 m |v|^2 - m g . x is conserved exactly by the exact solution
  EXPECT_LT(RelativeEnergyDrift(r), 1e-12);
}

TEST(ExactSolutions, ForceScheduleMatchesItsIntegral) {
  // F_x ramps 0 -> 4 N over [0, 1] s and back to 0 over [1, 2] s, then holds 0; m = 2 kg, so a = F / m and
  //   x = t^3/3                    on [0, 1]
  //   x = 2 t^2 - t^3/3 - 2t + 2/3 on [1, 2]
  //   x = 2 + 2 (t - 2)            after 2
  // The kinks lie on the grid, where RK4 is exact for this cubic motion.
  const Recording r = Record(SceneFromJson(R"({
    "bodies": [{"name": "puck", "type": "particle", "mass": 2.0, "position": [0.0, 0.0]}],
    "effects": [{"type": "force", "body": "puck",
                 "schedule": {"times": [0.0, 1.0, 2.0], "values": [[0, 0], [4, 0], [0, 0]]}}],
    "simulation": {"duration": 3.0}, "stabilization": {"method": "none"}})"));
  auto exact_x = [](double t) {
    if (t <= 1.0) return t * t * t / 3;
    if (t <= 2.0) return 2 * t * t - t * t * t / 3 - 2 * t + 2.0 / 3;
    return 2.0 + 2.0 * (t - 2.0);
  };
  auto exact_v = [](double t) { return t <= 1.0 ? t * t : t <= 2.0 ? 4 * t - t * t - 2 : 2.0; };
  for (size_t k = 0; k < r.t.size(); ++k) {
    ASSERT_NEAR(r.q[k][0], exact_x(r.t[k]), 1e-9) << "t = " << r.t[k];
    ASSERT_NEAR(r.v[k][0], exact_v(r.t[k]), 1e-9) << "t = " << r.t[k];
    ASSERT_EQ(r.q[k][1], 0.0);
  }
  EXPECT_NEAR(r.q.back()[0], 4.0, 1e-9);
}

TEST(ExactSolutions, TorqueScheduleIsHeldOutsideItsTimes) {
  // a free wheel, I = 0.5: tau = 1 N m held before t = 0.5, down to 0 at t = 1.5, held at 0 after
  //   alpha = 2 on [0, 0.5];  alpha = 2 (1.5 - t) on [0.5, 1.5];  0 after
  //   omega(0.5) = 1, omega(1.5) = 1 + 1 = 2, angle(0.5) = 0.25,
  //   angle(1.5) = 0.25 + int_0.5^1.5 (1 + 2 (s - 0.5) - (s - 0.5)^2) ds = 0.25 + 1 + 1 - 1/3
  const Recording r = Record(SceneFromJson(R"({
    "bodies": [{"name": "w", "type": "rigid", "mass": 1.0, "inertia": 0.5, "position": [0.0, 0.0]}],
    "effects": [{"type": "torque", "body": "w", "schedule": {"times": [0.5, 1.5], "values": [1.0, 0.0]}}],
    "simulation": {"duration": 2.0}})"));
  auto exact_angle = [](double t) {
    if (t <= 0.5) return t * t;
    const double s = t - 0.5;
    if (t <= 1.5) return 0.25 + s + s * s - s * s * s / 3;
    return 0.25 + 2.0 - 1.0 / 3 + 2.0 * (t - 1.5);
  };
  for (size_t k = 0; k < r.t.size(); ++k) ASSERT_NEAR(r.q[k][2], exact_angle(r.t[k]), 1e-9) << "t = " << r.t[k];
  EXPECT_NEAR(r.v.back()[2], 2.0, 1e-9);
}

TEST(ExactSolutions, PendulumConservesEnergyWithRk4) {
  const Recording r = Record(Pendulum(0.7, M_PI / 3, 8.0));
  EXPECT_LT(RelativeEnergyDrift(r), 1e-6);
}

TEST(ExactSolutions, DoublePendulumConservesEnergyWithRk4) {
  // the acceptance check's double pendulum: rods 0.5 m and 1 m, masses 1 and 2 kg, released at rest at
  // (2.0, 1.0) rad from the downward vertical; chaotic, but its energy is an invariant
  const double a0 = 2.0, a1 = 1.0;
  const double x0 = 0.5 * std::sin(a0), y0 = -0.5 * std::cos(a0);
  const double x1 = x0 + std::sin(a1), y1 = y0 - std::cos(a1);
  const Recording r = Record(SceneFromJson(R"({
    "bodies": [{"name": "p0", "type": "particle", "mass": 1.0, "position": [)" +
                                           Num(x0) + ", " + Num(y0) + R"(]},
               {"name": "p1", "type": "particle", "mass": 2.0, "position": [)" +
                                           Num(x1) + ", " + Num(y1) + R"(]}],
    "constraints": [{"type": "distance", "bodies": ["world", "p0"], "length": 0.5},
                    {"type": "distance", "bodies": ["p0", "p1"], "length": 1.0}],
    "effects": [{"type": "gravity", "acceleration": [0.0, -9.81]}],
    "simulation": {"integrator": "rk4", "step": 1e-3, "duration": 5.0},
    "stabilization": {"method": "baumgarte", "alpha": 10.0, "beta": 25.0}})"));
  // E0 = g (m0 y0 + m1 y1) with the bodies at rest
  EXPECT_NEAR(r.energy[0], kG * (1.0 * y0 + 2.0 * y1), 1e-12);
  EXPECT_LT(RelativeEnergyDrift(r), 1e-6);
}

}  // namespace
}  // namespace tether
