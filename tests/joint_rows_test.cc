// Constraint rows of every joint type between 3D rigid bodies (and the world, and particles where the joint allows
// them), at random states away from the state the joint's fixed quantities were taken at:
//   (a) J v against the central difference of C(q (+) s v) at s = 0 (configuration_space.h);
//   (b) the velocity product Jdot v against the second central difference of C(q (+) s v): with v constant
//       (body-frame angular velocity included) q (+) s v is the motion itself, so C'' = Jdot v there;
//   (c) the joint coordinates' rates and gradients against differences of their values (for angles at states on
//       the joint, where the relative angular velocity is along the axis: elsewhere the angle is not defined).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "tether/dynamics/configuration_space.h"
#include "tether/dynamics/constraint_rows.h"
#include "tether/dynamics/joint_coordinates.h"
#include "tether/dynamics/rotation.h"

namespace tether {
namespace {

constexpr double kStep = 1e-5;
constexpr double kFirstTolerance = 1e-8;   // relative to max(1, |exact|)
constexpr double kSecondTolerance = 1e-5;  // second differences lose more digits

Vec4<double> RandomQuaternion(std::mt19937* random) {
  std::normal_distribution<double> normal;
  Vec4<double> q(normal(*random), normal(*random), normal(*random), normal(*random));
  return q / q.norm();
}

Vec3<double> RandomVector(std::mt19937* random, double scale) {
  std::uniform_real_distribution<double> uniform(-scale, scale);
  return Vec3<double>(uniform(*random), uniform(*random), uniform(*random));
}

// Two 3D rigid bodies (the second with a full inertia tensor, so that its principal axes differ from its body
// axes), a particle, and one joint of `type` between `a` and `b`.
Model<double> TwoBodies(JointType type, int a, int b, std::mt19937* random) {
  Model<double> model;
  model.dimension = 3;
  Mat3<double> tensor;
  tensor << 0.3, 0.02, -0.01, 0.02, 0.4, 0.03, -0.01, 0.03, 0.5;
  AddRigidBody3d<double>(&model, "a", 1.0, Vec3<double>(0.1, 0.2, 0.3).asDiagonal(), RandomVector(random, 1.0),
                         RandomQuaternion(random), Vec3<double>::Zero(), Vec3<double>::Zero());
  AddRigidBody3d<double>(&model, "b", 2.0, tensor, RandomVector(random, 1.0), RandomQuaternion(random),
                         Vec3<double>::Zero(), Vec3<double>::Zero());
  AddBody<double>(&model, "p", BodyKind::kParticle, 0.5, 0.0, RandomVector(random, 1.0), 0.0, Vec3<double>::Zero(),
                  0.0);
  Joint<double> joint;
  joint.type = type;
  joint.name = "j";
  joint.a = {a, RandomVector(random, 0.5)};
  joint.b = {b, RandomVector(random, 0.5)};
  joint.axis = RandomVector(random, 1.0);
  joint.axis_b = RandomVector(random, 1.0);
  joint.length = 0.7;
  joint.angle = 0.3;
  AddJoint(&model, joint);
  return model;
}

State<double> RandomState(const Model<double>& model, std::mt19937* random) {
  State<double> s = InitialState(model);
  for (const Body<double>& body : model.bodies) {
    s.q.segment<3>(body.q_offset) = RandomVector(random, 1.0);
    if (body.kind == BodyKind::kRigid3d) s.q.segment<4>(body.q_offset + 3) = RandomQuaternion(random);
    s.v.segment(body.v_offset, body.v_size) = VecX<double>::Random(body.v_size) * 2.0;
  }
  return s;
}

std::vector<ConstraintRow<double>> Rows(const Model<double>& model, const ConstraintSet<double>& set,
                                        const VecX<double>& q, const VecX<double>& v) {
  BodyFrames<double> frames;
  UpdateFrames(model, q, v, true, &frames);
  std::vector<ConstraintRow<double>> rows(DescribeRows(model, set).size());
  EvaluateConstraintRows(model, set, frames, q, v, true, &rows);
  return rows;
}

VecX<double> Along(const Model<double>& model, const VecX<double>& q, const VecX<double>& v, double s) {
  VecX<double> out(q.size());
  Integrate(model, q, v, s, &out);
  return out;
}

void ExpectNear(double exact, double approximate, double tolerance, const std::string& what) {
  EXPECT_NEAR(exact, approximate, tolerance * std::max(1.0, std::abs(exact))) << what;
}

struct Case {
  JointType type;
  int a, b;
};

class JointRowsTest : public ::testing::TestWithParam<Case> {};

TEST_P(JointRowsTest, JacobianAndVelocityProductMatchDifferences) {
  const Case c = GetParam();
  std::mt19937 random(17);
  for (int trial = 0; trial < 5; ++trial) {
    const Model<double> model = TwoBodies(c.type, c.a, c.b, &random);
    const State<double> start = RandomState(model, &random);
    const ConstraintSet<double> set = BuildConstraintSet(model, start.q);
    const State<double> s = RandomState(model, &random);
    const std::vector<ConstraintRow<double>> rows = Rows(model, set, s.q, s.v);
    const auto plus = Rows(model, set, Along(model, s.q, s.v, kStep), s.v);
    const auto minus = Rows(model, set, Along(model, s.q, s.v, -kStep), s.v);
    const auto plus2 = Rows(model, set, Along(model, s.q, s.v, 1e-3), s.v);
    const auto minus2 = Rows(model, set, Along(model, s.q, s.v, -1e-3), s.v);
    ASSERT_FALSE(rows.empty());
    for (size_t i = 0; i < rows.size(); ++i) {
      const std::string what = std::string(JointTypeName(c.type)) + " row " + std::to_string(i);
      const double rate = Dot(model, rows[i].a, s.v) + Dot(model, rows[i].b, s.v);
      ExpectNear(rate, (plus[i].value - minus[i].value) / (2 * kStep), kFirstTolerance, what + " J v");
      // fourth-order second difference: (-f(2h) + 16 f(h) - 30 f(0) + 16 f(-h) - f(-2h)) / (12 h^2), h = 5e-4
      const auto far_plus = Rows(model, set, Along(model, s.q, s.v, 2e-3), s.v);
      const auto far_minus = Rows(model, set, Along(model, s.q, s.v, -2e-3), s.v);
      const double h = 1e-3;
      const double second = (-far_plus[i].value + 16 * plus2[i].value - 30 * rows[i].value + 16 * minus2[i].value -
                             far_minus[i].value) / (12 * h * h);
      ExpectNear(rows[i].bias, second, kSecondTolerance, what + " Jdot v");
    }
  }
}

TEST_P(JointRowsTest, CoordinateRatesMatchDifferences) {
  const Case c = GetParam();
  std::mt19937 random(23);
  for (int trial = 0; trial < 5; ++trial) {
    const Model<double> model = TwoBodies(c.type, c.a, c.b, &random);
    const State<double> start = RandomState(model, &random);
    const JointCoordinates<double> coordinates = BuildJointCoordinates(model, start.q);
    State<double> s = RandomState(model, &random);
    if (c.type == JointType::kHinge || c.type == JointType::kCylindrical) {
      // the start configuration, where the axes are common, with B turning relative to A about the axis only
      s.q = start.q;
      const Joint<double>& joint = model.joints[0];
      BodyFrames<double> frames;
      UpdateFrames(model, s.q, s.v, true, &frames);
      const Mat3<double> R_WA = c.a == kWorld ? Mat3<double>::Identity() : frames[c.a].R_WB;
      const Vec3<double> w_A = c.a == kWorld ? Vec3<double>::Zero() : frames[c.a].w_W;
      const Vec3<double> w_B = w_A + 1.7 * R_WA * joint.axis.normalized();
      if (c.b != kWorld) s.v.segment<3>(model.bodies[c.b].v_offset + 3) = frames[c.b].R_WP.transpose() * w_B;
      if (c.b == kWorld) s.v.segment<3>(model.bodies[c.a].v_offset + 3).setZero();
    }
    for (size_t k = 0; k < coordinates.references.size(); ++k) {
      auto value = [&](double step) {
        const VecX<double> q = Along(model, s.q, s.v, step);
        BodyFrames<double> frames;
        UpdateFrames(model, q, s.v, true, &frames);
        JointCoordinates<double> near = coordinates;
        TrackCoordinates(model, frames, q, s.v, &near);
        return EvaluateCoordinate(model, near, static_cast<int>(k), frames, q, s.v, true);
      };
      const CoordinateRow<double> row = value(0.0);
      const double difference = (value(kStep).value - value(-kStep).value) / (2 * kStep);
      ExpectNear(row.rate, difference, kFirstTolerance, "coordinate rate");
      ExpectNear(Dot(model, row.a, s.v) + Dot(model, row.b, s.v), row.rate, 1e-12, "coordinate gradient");
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    Joints, JointRowsTest,
    ::testing::Values(Case{JointType::kDistance, 0, 1}, Case{JointType::kPin, 0, 1}, Case{JointType::kSlider, 0, 1},
                      Case{JointType::kHinge, 0, 1}, Case{JointType::kUniversal, 0, 1},
                      Case{JointType::kPrismatic, 0, 1}, Case{JointType::kCylindrical, 0, 1},
                      Case{JointType::kWeld, 0, 1}, Case{JointType::kHinge, kWorld, 1},
                      Case{JointType::kHinge, 1, kWorld}, Case{JointType::kPrismatic, kWorld, 0},
                      Case{JointType::kSlider, 1, 2}, Case{JointType::kPin, 2, 0}, Case{JointType::kDistance, 2, 1}),
    [](const ::testing::TestParamInfo<Case>& info) {
      auto name = [](int body) { return body == kWorld ? std::string("world") : std::string(1, "abp"[body]); };
      return std::string(JointTypeName(info.param.type)) + "_" + name(info.param.a) + "_" + name(info.param.b);
    });

}  // namespace
}  // namespace tether
