// The integrators: observed orders of convergence on the 60-degree pendulum against a tight rk45 reference,
// rk45's error control and output grid, and the stated stability limits on the negative real axis checked on
// the linear test equation y' = lambda y, realised as a damped free particle (m v' = -c v, lambda = -c/m).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>

#include "test_scenes.h"
#include "tether/dynamics/integration/default_gains.h"

namespace tether {
namespace {

using testing::Pendulum60;
using testing::Record;
using testing::Recording;

// Position of the bob at t = 1 s.
VecX<double> BobAtOneSecond(const std::string& integrator, double step, double tolerance = 1e-8) {
  Model<double> model = Pendulum60(integrator, step, 1.0);
  model.simulation.tolerance = tolerance;
  const Recording r = Record(model, 1000000);  // first and last rows only
  EXPECT_DOUBLE_EQ(r.t.back(), 1.0);
  return r.q.back();
}

const VecX<double>& Reference() {
  static const VecX<double> reference = BobAtOneSecond("rk45", 1e-2, 1e-12);
  return reference;
}

double ErrorAtOneSecond(const std::string& integrator, double step) {
  return (BobAtOneSecond(integrator, step) - Reference()).norm();
}

// log2 of the error ratio when h is halved.
double ObservedOrder(const std::string& integrator, double step) {
  return std::log2(ErrorAtOneSecond(integrator, step) / ErrorAtOneSecond(integrator, step / 2));
}

TEST(Integrators, ReferenceIsFarMoreAccurateThanTheMethodsUnderTest) {
  // rk45 at tolerance 1e-12 against rk45 at 1e-13: the reference error is at the 1e-11 level or below, well under
  // the smallest error measured below (rk4 at h = 5e-3, about 6e-9)
  EXPECT_LT((BobAtOneSecond("rk45", 1e-2, 1e-13) - Reference()).norm(), 1e-10);
}

TEST(Integrators, EulerIsFirstOrder) {
  const double order = ObservedOrder("euler", 2e-4);
  EXPECT_NEAR(order, 1.0, 0.1) << "observed order " << order;
}

TEST(Integrators, SymplecticEulerIsFirstOrder) {
  const double order = ObservedOrder("symplectic_euler", 2e-4);
  EXPECT_NEAR(order, 1.0, 0.1) << "observed order " << order;
}

TEST(Integrators, Rk4IsFourthOrder) {
  const double order = ObservedOrder("rk4", 1e-2);
  EXPECT_NEAR(order, 4.0, 0.25) << "observed order " << order;
}

TEST(Integrators, Rk45MeetsItsTolerance) {
  // the output step (0.1 s) is far coarser than the internal steps: accuracy comes from the error control.
  // The global error after 1 s is a modest multiple of the local tolerance.
  for (double tolerance : {1e-6, 1e-8, 1e-10}) {
    const double error = (BobAtOneSecond("rk45", 0.1, tolerance) - Reference()).norm();
    EXPECT_LT(error, 10 * tolerance) << "tolerance " << tolerance;
  }
  // and a tighter tolerance is more accurate
  EXPECT_LT((BobAtOneSecond("rk45", 0.1, 1e-10) - Reference()).norm(),
            (BobAtOneSecond("rk45", 0.1, 1e-6) - Reference()).norm());
}

TEST(Integrators, Rk45LandsOnTheOutputGrid) {
  Model<double> model = Pendulum60("rk45", 0.05, 1.02);
  model.simulation.tolerance = 1e-9;
  const Recording r = Record(model);
  ASSERT_EQ(r.t.size(), 22u);  // 0, 0.05, ..., 1.0 and the shortened last step to 1.02
  for (size_t k = 0; k + 1 < r.t.size(); ++k) EXPECT_DOUBLE_EQ(r.t[k], k * 0.05);
  EXPECT_DOUBLE_EQ(r.t.back(), 1.02);
  // the rows are states at those times, not at the internal steps: compare with rk4 at a fine step
  Model<double> fine = Pendulum60("rk4", 1e-3, 1.02);
  const Recording f = Record(fine, 50);
  ASSERT_EQ(f.t.size(), r.t.size());
  for (size_t k = 0; k < r.t.size(); ++k) EXPECT_LT((r.q[k] - f.q[k]).norm(), 1e-7) << "t = " << r.t[k];
}

// The amplification factor R(h lambda) of one step on y' = lambda y, measured on the library's integrator: a free
// particle of unit mass with damping c has v' = -c v, so one step of h = 1 maps v0 = 1 to R(-c).
double Amplification(const std::string& integrator, double z) {
  Model<double> model = testing::SceneFromJson(R"({
    "bodies": [{"name": "p", "type": "particle", "mass": 1.0, "position": [0.0, 0.0], "velocity": [1.0, 0.0]}],
    "effects": [{"type": "damping", "coefficient": 1.0}],
    "simulation": {"integrator": ")" + integrator +
                                               R"(", "step": 1.0, "duration": 1.0}})");
  model.damping[0].coefficient = -z;
  model.simulation.tolerance = 1e300;  // rk45: accept the first trial step, a single Dormand-Prince step of h
  const Recording r = Record(model);
  EXPECT_EQ(r.t.size(), 2u);
  return r.v.back()[0];
}

// Where |R(z)| crosses 1 on the negative real axis near -limit, by bisection on [-1.5 limit, -0.5 limit].
double MeasuredStabilityLimit(const std::string& integrator, double limit) {
  double inside = -0.5 * limit, outside = -1.5 * limit;
  EXPECT_LT(std::abs(Amplification(integrator, inside)), 1.0);
  EXPECT_GT(std::abs(Amplification(integrator, outside)), 1.0);
  for (int i = 0; i < 50; ++i) {
    const double mid = 0.5 * (inside + outside);
    (std::abs(Amplification(integrator, mid)) <= 1.0 ? inside : outside) = mid;
  }
  return -0.5 * (inside + outside);
}

TEST(Integrators, AmplificationFactorsAreTheMethodsPolynomials) {
  // a spot check that the damped particle realises the test equation: R(z) = 1 + z for euler, the degree-4
  // Taylor polynomial of e^z for rk4
  const double z = -0.7;
  EXPECT_NEAR(Amplification("euler", z), 1 + z, 1e-15);
  EXPECT_NEAR(Amplification("symplectic_euler", z), 1 + z, 1e-15);
  EXPECT_NEAR(Amplification("rk4", z), 1 + z + z * z / 2 + z * z * z / 6 + z * z * z * z / 24, 1e-15);
}

TEST(Integrators, RealStabilityLimitsMatchTheTestEquation) {
  // the header states r to three or four digits (RK4: 2.7853, Dormand-Prince: 3.3066), hence 2e-4 relative
  for (const auto& [name, integrator] : {std::pair<std::string, Integrator>{"euler", Integrator::kEuler},
                                         {"symplectic_euler", Integrator::kSymplecticEuler},
                                         {"rk4", Integrator::kRk4},
                                         {"rk45", Integrator::kRk45}}) {
    const double stated = RealStabilityLimit(integrator);
    const double measured = MeasuredStabilityLimit(name, stated);
    EXPECT_NEAR(measured / stated, 1.0, 2e-4) << name << ": stated " << stated << ", measured " << measured;
  }
}

}  // namespace
}  // namespace tether
