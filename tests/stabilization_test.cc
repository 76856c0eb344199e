// Constraint stabilization: projection holds the constraints to rounding, Baumgarte gains reduce drift, and the
// default gain rule (critically damped, omega = 0.1 r / h capped by the method's order) keeps a rigid four-bar on
// its branch through its singular configurations.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "test_scenes.h"
#include "tether/dynamics/integration/default_gains.h"

namespace tether {
namespace {

using testing::Pendulum60;
using testing::Record;
using testing::Recording;

double LargestConstraintError(const Recording& r) {
  return *std::max_element(r.constraint_error.begin(), r.constraint_error.end());
}

TEST(Stabilization, ProjectionHoldsTheConstraintsAtACoarseStep) {
  Model<double> model = Pendulum60("rk4", 1e-2, 20.0);
  model.stabilization.method = Stabilization::kProjection;
  const Recording r = Record(model);
  EXPECT_LT(LargestConstraintError(r), 1e-10);
  // the velocities are projected too: for a rod from the origin, v is orthogonal to q
  for (size_t k = 0; k < r.t.size(); ++k) ASSERT_NEAR(r.q[k].dot(r.v[k]), 0.0, 1e-10) << "t = " << r.t[k];
}

TEST(Stabilization, BaumgarteReducesDriftAgainstNone) {
  Model<double> free = Pendulum60("rk4", 1e-2, 20.0);
  free.stabilization.method = Stabilization::kNone;
  Model<double> held = Pendulum60("rk4", 1e-2, 20.0);
  held.stabilization.alpha = 20.0;
  held.stabilization.beta = 100.0;
  const double drift_free = LargestConstraintError(Record(free));
  const double drift_held = LargestConstraintError(Record(held));
  EXPECT_GT(drift_free, 0.0);
  // the unstabilized drift grows secularly; the gains bound it: expect at least a tenfold reduction
  EXPECT_LT(drift_held, 0.1 * drift_free) << "none " << drift_free << ", baumgarte " << drift_held;
}

// The IFToMM A02 four-bar with one parallelogram, as fourbar(1) in the acceptance checks, but with no
// "stabilization" key so that the default gain rule applies: uniform 1 m, 1 kg bars; crank0's tip is B0.
Model<double> FourBar() {
  return testing::SceneFromJson(R"({
    "bodies": [
      {"name": "crank0", "type": "rigid", "mass": 1.0, "inertia": 0.08333333333333333, "position": [0.0, 0.5],
       "angle": 1.5707963267948966, "velocity": [0.5, 0.0], "angular_velocity": -1.0},
      {"name": "crank1", "type": "rigid", "mass": 1.0, "inertia": 0.08333333333333333, "position": [1.0, 0.5],
       "angle": 1.5707963267948966, "velocity": [0.5, 0.0], "angular_velocity": -1.0},
      {"name": "coupler0", "type": "rigid", "mass": 1.0, "inertia": 0.08333333333333333, "position": [0.5, 1.0],
       "angle": 0.0, "velocity": [1.0, 0.0], "angular_velocity": 0.0}],
    "constraints": [
      {"type": "pin", "bodies": ["world", "crank0"], "points": [[0.0, 0.0], [-0.5, 0.0]]},
      {"type": "pin", "bodies": ["world", "crank1"], "points": [[1.0, 0.0], [-0.5, 0.0]]},
      {"type": "pin", "bodies": ["coupler0", "crank0"], "points": [[-0.5, 0.0], [0.5, 0.0]]},
      {"type": "pin", "bodies": ["coupler0", "crank1"], "points": [[0.5, 0.0], [0.5, 0.0]]}],
    "effects": [{"type": "gravity", "acceleration": [0.0, -9.81]}],
    "simulation": {"integrator": "rk4", "step": 1e-3, "duration": 5.0}})");
}

TEST(Stabilization, DefaultRuleKeepsTheFourBarOnItsBranchThroughSingularPasses) {
  const Model<double> model = FourBar();
  ASSERT_TRUE(model.stabilization.gains_from_rule);
  // B0 at t = 0.5, 1.0, ..., 5.0: FOURBAR1 of the acceptance checks (reduced equation I th'' = -g cos th)
  const double kReference[10][2] = {{0.701512678911, 0.712656973114}, {-0.260712675184, -0.965416439159},
                                    {-0.554074591943, 0.83246702431}, {0.077085471793, 0.997024488184},
                                    {0.849932751197, 0.526891182734}, {-0.69893952728, -0.715180772397},
                                    {-0.421439410668, 0.9068565615},  {0.158955504256, 0.987285747728},
                                    {0.966763945034, 0.255670636919}, {-0.944908186042, -0.327335485323}};
  const Recording r = Record(model, 500);  // rows every 0.5 s
  ASSERT_EQ(r.t.size(), 11u);
  const int crank0 = model.bodies[0].q_offset;
  for (int i = 0; i < 10; ++i) {
    const VecX<double>& q = r.q[i + 1];
    ASSERT_DOUBLE_EQ(r.t[i + 1], 0.5 * (i + 1));
    const double angle = q[crank0 + 2];
    const double bx = q[crank0] + 0.5 * std::cos(angle), by = q[crank0 + 1] + 0.5 * std::sin(angle);
    // 1e-3: the IFToMM high-precision bound used by the acceptance check
    EXPECT_LT(std::hypot(bx - kReference[i][0], by - kReference[i][1]), 1e-3) << "t = " << r.t[i + 1];
  }
}

TEST(Stabilization, DefaultGainsAreCriticallyDampedWithinATenthOfTheStabilityLimit) {
  for (Integrator integrator :
       {Integrator::kEuler, Integrator::kSymplecticEuler, Integrator::kRk4, Integrator::kRk45}) {
    const bool first_order = integrator == Integrator::kEuler || integrator == Integrator::kSymplecticEuler;
    const double cap = first_order ? kFirstOrderMaxOmega : kHighOrderMaxOmega;
    const double r = RealStabilityLimit(integrator);
    for (double h : {0.5, 1e-1, 1e-2, 1e-3, 1e-5}) {
      const Gains g = DefaultGains(integrator, h);
      const double omega = std::sqrt(g.beta);
      EXPECT_NEAR(g.alpha * g.alpha, 4.0 * g.beta, 1e-12 * g.beta) << "h = " << h;  // zeta = 1
      // omega = min(0.1 r / h, cap): h omega never beyond a tenth of the way to the stability edge
      EXPECT_NEAR(omega, std::min(cap, kDefaultStabilityFraction * r / h), 1e-12 * omega) << "h = " << h;
      EXPECT_LE(h * omega, kDefaultStabilityFraction * r * (1 + 1e-12)) << "h = " << h;
    }
  }
}

TEST(Stabilization, DefaultGainsStatedValues) {
  // the header's rule worked by hand: omega = min(0.1 r / h, cap), alpha = 2 omega, beta = omega^2, with r = 2
  // (Euler), 2.785 (RK4), 3.307 (Dormand-Prince) and caps 1000 rad/s (first order), 10 rad/s (rk4, rk45)
  struct Case {
    Integrator integrator;
    double h, omega;
  };
  const Case cases[] = {{Integrator::kEuler, 1e-2, 20.0},   {Integrator::kSymplecticEuler, 1e-3, 200.0},
                        {Integrator::kEuler, 1e-5, 1000.0}, {Integrator::kSymplecticEuler, 1e-6, 1000.0},
                        {Integrator::kRk4, 0.1, 2.785},     {Integrator::kRk45, 0.1, 3.307},
                        {Integrator::kRk4, 1e-3, 10.0},     {Integrator::kRk45, 1e-2, 10.0}};
  for (const Case& c : cases) {
    const Gains g = DefaultGains(c.integrator, c.h);
    EXPECT_NEAR(g.alpha, 2 * c.omega, 1e-12 * c.omega) << "h = " << c.h;
    EXPECT_NEAR(g.beta, c.omega * c.omega, 1e-12 * c.omega * c.omega) << "h = " << c.h;
  }
}

TEST(Stabilization, GainsInUseFollowTheSceneOrTheRule) {
  Model<double> model = FourBar();  // no "stabilization": the rule at rk4, h = 1e-3
  double alpha = -1, beta = -1;
  GainsInUse(model, &alpha, &beta);
  EXPECT_DOUBLE_EQ(alpha, DefaultGains(Integrator::kRk4, 1e-3).alpha);
  EXPECT_DOUBLE_EQ(beta, DefaultGains(Integrator::kRk4, 1e-3).beta);
  // the rule follows the integrator and step of the run
  model.simulation.integrator = Integrator::kEuler;
  model.simulation.step = 2e-3;
  GainsInUse(model, &alpha, &beta);
  EXPECT_DOUBLE_EQ(alpha, DefaultGains(Integrator::kEuler, 2e-3).alpha);
  // gains named by the scene
  model.stabilization.gains_from_rule = false;
  model.stabilization.alpha = 3.0;
  model.stabilization.beta = 7.0;
  GainsInUse(model, &alpha, &beta);
  EXPECT_EQ(alpha, 3.0);
  EXPECT_EQ(beta, 7.0);
  // none and projection use no gains
  for (Stabilization method : {Stabilization::kNone, Stabilization::kProjection}) {
    model.stabilization.method = method;
    GainsInUse(model, &alpha, &beta);
    EXPECT_EQ(alpha, 0.0);
    EXPECT_EQ(beta, 0.0);
  }
}

}  // namespace
}  // namespace tether
