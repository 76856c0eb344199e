// User-defined constraints (user_constraint.h) simulate like the built-in constraints they restate: the
// documented bead on a circle, a constraint between two bodies (a particle and a rigid bar), and a multi-row
// constraint (a hinge of a rigid bar to the world written as two rows).
#include "tether/dynamics/constraints/user_constraint.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "test_scenes.h"
#include "tether/dynamics/model/configuration_space.h"

namespace tether {
namespace {

constexpr double kTrajectoryTolerance = 1e-10;  // m, over 1 s of rk4 at h = 1 ms

// The example of user_constraint.h, as documented.
struct OnCircle {
  static constexpr int kRows = 1;
  double radius;
  template <typename S>
  void operator()(const S*, const S* q, S* c) const {
    using std::sqrt;
    c[0] = sqrt(q[0] * q[0] + q[1] * q[1]) - S(radius);
  }
};

// |p_B - p_A| = length for a particle A (its position) and a point at `local` on a planar rigid bar B.
struct ParticleToBarPoint {
  static constexpr int kRows = 1;
  double local_x, local_y, length;
  template <typename S>
  void operator()(const S* particle, const S* bar, S* c) const {
    using std::cos;
    using std::sin;
    using std::sqrt;
    const S px = bar[0] + cos(bar[2]) * S(local_x) - sin(bar[2]) * S(local_y);
    const S py = bar[1] + sin(bar[2]) * S(local_x) + cos(bar[2]) * S(local_y);
    const S dx = px - particle[0], dy = py - particle[1];
    c[0] = sqrt(dx * dx + dy * dy) - S(length);
  }
};

// A hinge: the bar's point at `local` sits at the world point `pivot`, two rows.
struct HingeToWorld {
  static constexpr int kRows = 2;
  double local_x, local_y, pivot_x, pivot_y;
  template <typename S>
  void operator()(const S*, const S* bar, S* c) const {
    using std::cos;
    using std::sin;
    c[0] = bar[0] + cos(bar[2]) * S(local_x) - sin(bar[2]) * S(local_y) - S(pivot_x);
    c[1] = bar[1] + sin(bar[2]) * S(local_x) + cos(bar[2]) * S(local_y) - S(pivot_y);
  }
};

// A built-in distance or pin (model.joints) with the next scene index.
void AddBuiltIn(Model<double>* model, JointType type, const BodyPoint<double>& a, const BodyPoint<double>& b,
                double length = 1.0) {
  Joint<double> joint;
  joint.scene_index = model->NumConstraints();
  joint.type = type;
  joint.a = a;
  joint.b = b;
  joint.length = length;
  AddJoint(model, joint);
}

// The rows of a model's constraints (distances and pins fix nothing at the start).
std::vector<RowInfo> Rows(const Model<double>& model) {
  return DescribeRows(model, BuildConstraintSet(model, InitialState(model).q));
}

Model<double> PlanarModelWithGravity() {
  Model<double> model;
  model.dimension = 2;
  model.gravity.push_back({0, Vec3<double>(0.0, -9.81, 0.0)});
  model.simulation.integrator = Integrator::kRk4;
  model.simulation.step = 1e-3;
  model.simulation.duration = 1.0;
  return model;
}

int AddParticle(Model<double>* model, double mass, double x, double y, double vx = 0.0, double vy = 0.0) {
  return AddBody<double>(model, "p" + std::to_string(model->bodies.size()), BodyKind::kParticle, mass, 0.0,
                         Vec3<double>(x, y, 0.0), 0.0, Vec3<double>(vx, vy, 0.0), 0.0);
}

int AddBar(Model<double>* model, double mass, double inertia, double x, double y, double angle, double omega) {
  return AddBody<double>(model, "bar" + std::to_string(model->bodies.size()), BodyKind::kPlanar, mass, inertia,
                         Vec3<double>(x, y, 0.0), angle, Vec3<double>::Zero(), omega);
}

// Runs both models and checks that every output position agrees; returns the user model's recording.
testing::Recording ExpectSameTrajectory(const Model<double>& user, const Model<double>& builtin) {
  const testing::Recording a = testing::Record(user), b = testing::Record(builtin);
  EXPECT_EQ(a.t.size(), b.t.size());
  double largest = 0.0;
  for (size_t k = 0; k < std::min(a.q.size(), b.q.size()); ++k) {
    largest = std::max(largest, (a.q[k] - b.q[k]).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(largest, kTrajectoryTolerance);
  return a;
}

TEST(UserConstraint, BeadOnCircleMatchesBuiltInDistance) {
  const double r = 0.5, start = M_PI / 3;
  Model<double> user = PlanarModelWithGravity();
  const int bead = AddParticle(&user, 0.2, r * std::sin(start), -r * std::cos(start));
  Model<double> builtin = user;
  AddUserConstraint(&user, kWorld, bead, OnCircle{0.5});
  AddBuiltIn(&builtin, JointType::kDistance, {kWorld, Vec3<double>::Zero()}, {bead, Vec3<double>::Zero()}, r);

  const testing::Recording run = ExpectSameTrajectory(user, builtin);
  // the bead swung through the bottom to the other side and stayed on the circle
  double least_x = 0.0;
  for (size_t k = 0; k < run.q.size(); ++k) {
    least_x = std::min(least_x, run.q[k][0]);
    EXPECT_NEAR(run.q[k].norm(), r, 1e-6);  // Baumgarte keeps rk4's drift below a micrometre
  }
  EXPECT_LT(least_x, -0.3);
}

TEST(UserConstraint, BetweenTwoBodiesMatchesBuiltInDistance) {
  // a particle on a rod from the world, and a rigid bar whose end point is held 0.4 m from the particle
  const double rod = 0.6, link = 0.4, half = 0.3, start = 40.0 * M_PI / 180.0;
  Model<double> user = PlanarModelWithGravity();
  const double px = rod * std::sin(start), py = -rod * std::cos(start);
  const int particle = AddParticle(&user, 1.0, px, py, 0.5, 0.6);
  const int bar = AddBar(&user, 2.0, 0.06, px + link + half, py, 0.0, 1.5);
  AddBuiltIn(&user, JointType::kDistance, {kWorld, Vec3<double>::Zero()}, {particle, Vec3<double>::Zero()}, rod);
  Model<double> builtin = user;
  AddUserConstraint(&user, particle, bar, ParticleToBarPoint{-half, 0.0, link});
  AddBuiltIn(&builtin, JointType::kDistance, {particle, Vec3<double>::Zero()}, {bar, Vec3<double>(-half, 0.0, 0.0)},
             link);

  ASSERT_EQ(Rows(user).size(), 2u);
  EXPECT_EQ(Rows(user)[1].body_a, particle);
  EXPECT_EQ(Rows(user)[1].body_b, bar);
  const testing::Recording run = ExpectSameTrajectory(user, builtin);
  // the bar turned
  const int angle = user.bodies[bar].q_offset + 2;
  EXPECT_GT(std::abs(run.q.back()[angle] - run.q.front()[angle]), 0.1);
}

TEST(UserConstraint, MultiRowMatchesBuiltInPin) {
  // a rigid bar hinged to the world at one end (local (-0.35, 0.05)), released spinning
  const double lx = -0.35, ly = 0.05;
  Model<double> user = PlanarModelWithGravity();
  const int bar = AddBar(&user, 1.5, 0.08, 0.35, -0.05, 0.0, 2.0);  // hinge point at the origin
  Model<double> builtin = user;
  AddUserConstraint(&user, kWorld, bar, HingeToWorld{lx, ly, 0.0, 0.0});
  AddBuiltIn(&builtin, JointType::kPin, {kWorld, Vec3<double>::Zero()}, {bar, Vec3<double>(lx, ly, 0.0)});

  // two rows of one constraint
  const std::vector<RowInfo> infos = Rows(user);
  ASSERT_EQ(infos.size(), 2u);
  EXPECT_EQ(infos[0].scene_index, infos[1].scene_index);
  EXPECT_EQ(infos[0].part, infos[1].part);  // one primitive: its violation is the norm of both rows
  const testing::Recording run = ExpectSameTrajectory(user, builtin);
  // the bar swung far from its start, with the hinge held
  EXPECT_GT(std::abs(run.q.back()[2]), 0.5);
  for (double error : run.constraint_error) EXPECT_LT(error, 1e-6);
}

}  // namespace
}  // namespace tether
