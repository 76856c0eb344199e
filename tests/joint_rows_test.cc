// Constraint rows of every joint type between 3D rigid bodies (and the world, and particles where the joint allows
// them), at random states away from the state the joint's fixed quantities were taken at:
//   (a) J v against the (fourth-order) central difference of C(q (+) s v) at s = 0 (configuration_space.h);
//   (b) the velocity product Jdot v against the second central difference of C(q (+) s v): with v constant
//       (body-frame angular velocity included) q (+) s v is the motion itself, so C'' = Jdot v there;
//   (c) the joint coordinates' rates and gradients against differences of their values (for angles at states on
//       the joint, where the relative angular velocity is along the axis: elsewhere the angle is not defined);
// (d) the translations the rows announce before evaluation, and S assembled with them, bit for bit;
// and the joint kinds (joint_kinds.h): each type listed once under its scene name, its rows exactly its parts'
// rows, its coordinates as HasCoordinate reports them, and a range refused on a kind that takes none.
#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "tether/dynamics/constraints/constraint_rows.h"
#include "tether/dynamics/constraints/joint_coordinates.h"
#include "tether/dynamics/integration/unilateral_events.h"
#include "tether/dynamics/model/configuration_space.h"
#include "tether/dynamics/model/errors.h"
#include "tether/dynamics/model/rotation.h"
#include "tether/dynamics/solvers/schur_system.h"
#include "tether/dynamics/solvers/workspace.h"

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
    std::uniform_real_distribution<double> uniform(-2.0, 2.0);  // not Eigen's Random: std::rand's state is shared
    for (int k = 0; k < body.v_size; ++k) s.v[body.v_offset + k] = uniform(*random);
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
    const auto plus_twice = Rows(model, set, Along(model, s.q, s.v, 2 * kStep), s.v);
    const auto minus_twice = Rows(model, set, Along(model, s.q, s.v, -2 * kStep), s.v);
    const auto plus2 = Rows(model, set, Along(model, s.q, s.v, 1e-3), s.v);
    const auto minus2 = Rows(model, set, Along(model, s.q, s.v, -1e-3), s.v);
    ASSERT_FALSE(rows.empty());
    for (size_t i = 0; i < rows.size(); ++i) {
      const std::string what = std::string(JointTypeName(c.type)) + " row " + std::to_string(i);
      const double rate = Dot(model, rows[i].a, s.v) + Dot(model, rows[i].b, s.v);
      // fourth-order first difference: (8 (f(h) - f(-h)) - (f(2h) - f(-2h))) / (12 h)
      const double first =
          (8 * (plus[i].value - minus[i].value) - (plus_twice[i].value - minus_twice[i].value)) / (12 * kStep);
      ExpectNear(rate, first, kFirstTolerance, what + " J v");
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

// The translations DescribeRows announces (RowTranslation) are the evaluated rows' own; the point rows' blocks,
// which skip the zeros of their directions (AxisGradient), are PointGradient's bit for bit; and S assembled with
// the announced translations (schur_system.h) is S assembled from the evaluated ones, bit for bit.
TEST_P(JointRowsTest, KnownTranslationsAreTheRowsOwnAndAssembleTheSameSchurComplement) {
  const Case c = GetParam();
  std::mt19937 random(23);
  Model<double> model = TwoBodies(c.type, c.a, c.b, &random);
  Joint<double> pin;  // body b then holds blocks as a row's first body and as its second, as in a chain
  pin.type = JointType::kPin;
  pin.name = "pin";
  pin.a = {1, RandomVector(&random, 0.5)};
  pin.b = {kWorld, RandomVector(&random, 0.5)};
  AddJoint(&model, pin);
  const ConstraintSet<double> set = BuildConstraintSet(model, RandomState(model, &random).q);
  const State<double> s = RandomState(model, &random);
  const std::vector<RowInfo> infos = DescribeRows(model, set);
  const std::vector<ConstraintRow<double>> rows = Rows(model, set, s.q, s.v);
  for (size_t i = 0; i < rows.size(); ++i) {
    if (infos[i].translation == RowTranslation::kEvaluated) continue;
    const Vec3<double> t = infos[i].translation == RowTranslation::kZero
                               ? Vec3<double>(Vec3<double>::Zero())
                               : Vec3<double>(Vec3<double>::Unit(TranslationAxis(infos[i].translation)));
    const std::string what = std::string(JointTypeName(c.type)) + " row " + std::to_string(i);
    if (rows[i].a.body != kWorld) EXPECT_TRUE(rows[i].a.translation == -t) << what;
    if (rows[i].b.body != kWorld) EXPECT_TRUE(rows[i].b.translation == t) << what;
  }
  BodyFrames<double> frames;
  UpdateFrames(model, s.q, s.v, true, &frames);
  size_t row = set.distances.size();
  for (const PointPrimitive<double>& point : set.points) {
    const PointMotion<double> pa = MovePoint(model, frames, point.a, s.q, s.v, true);
    const PointMotion<double> pb = MovePoint(model, frames, point.b, s.q, s.v, true);
    for (int k = 0; k < 3; ++k, ++row) {
      const Vec3<double> e = Vec3<double>::Unit(k);
      EXPECT_TRUE(rows[row].a.rotation == PointGradient(model, frames, point.a.body, Vec3<double>(-e), pa).rotation);
      EXPECT_TRUE(rows[row].b.rotation == PointGradient(model, frames, point.b.body, e, pb).rotation);
    }
  }
  const std::vector<BodyLayout> layout = LayoutOf(model);
  const InverseMass<double> inverse = BuildInverseMass(model);
  auto assemble = [&](const std::vector<RowInfo>& described, bool* known) {
    const SchurPattern pattern(described, layout);
    for (const SchurPattern::DenseBody& dense : pattern.dense_bodies()) {
      *known = *known || (dense.count > 0 && dense.known_translations);
    }
    std::vector<double> scratch, values(pattern.nonzeros());
    AssembleSchur(layout, pattern, rows, inverse.diagonal, inverse.rotational, &scratch, &values);
    return values;
  };
  std::vector<RowInfo> evaluated = infos;
  for (RowInfo& info : evaluated) info.translation = RowTranslation::kEvaluated;
  bool known = false, known_anyway = false;
  EXPECT_EQ(assemble(infos, &known), assemble(evaluated, &known_anyway));
  EXPECT_FALSE(known_anyway);
  const bool all_known = std::all_of(
      infos.begin(), infos.end(), [](const RowInfo& info) { return info.translation != RowTranslation::kEvaluated; });
  if (all_known) EXPECT_TRUE(known) << "the known translations' path was not taken";
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

// A double hinge's rows vanish on the whole two-parameter family of its massless link (B turned about a_2
// through o_2, then with the link about a_1 through o_1) and are independent (rank 4) there, for skew axes and
// for parallel ones (the parallel form of the rows).
TEST(DoubleHingeRows, VanishOnTheLinksMotionsAndHaveRankFour) {
  std::mt19937 random(31);
  for (const bool parallel : {false, true}) {
    for (int trial = 0; trial < 5; ++trial) {
      Model<double> model = TwoBodies(JointType::kDoubleHinge, 0, 1, &random);
      Joint<double>& joint = model.joints[0];
      const State<double> start = InitialState(model);
      const Vec4<double> q_WA = model.bodies[0].orientation, q_WB = model.bodies[1].orientation;
      const Vec3<double> a_1W = Rotate(q_WA, Vec3<double>(joint.axis.normalized()));
      if (parallel) joint.axis_b = Rotate(Vec4<double>(q_WB[0], -q_WB[1], -q_WB[2], -q_WB[3]), a_1W);
      const Vec3<double> a_2W = Rotate(q_WB, Vec3<double>(joint.axis_b.normalized()));
      const Vec3<double> o_1W = model.bodies[0].position + Rotate(q_WA, joint.a.local);
      const Vec3<double> o_2W = model.bodies[1].position + Rotate(q_WB, joint.b.local);
      const ConstraintSet<double> set = BuildConstraintSet(model, start.q);
      ASSERT_EQ(DescribeRows(model, set).size(), 4u);
      for (const double theta_1 : {0.0, 0.4, -1.3}) {
        for (const double theta_2 : {0.0, 0.7, 2.9}) {
          // B's pose after turning about joint 2's line, then about joint 1's line (world rotations)
          const Vec4<double> turn_1 = Exp(Vec3<double>(theta_1 * a_1W)), turn_2 = Exp(Vec3<double>(theta_2 * a_2W));
          const Vec3<double> p_2 = o_2W + Rotate(turn_2, Vec3<double>(model.bodies[1].position - o_2W));
          const Vec3<double> p_WB = o_1W + Rotate(turn_1, Vec3<double>(p_2 - o_1W));
          VecX<double> q = start.q;
          q.segment<3>(model.bodies[1].q_offset) = p_WB;
          q.segment<4>(model.bodies[1].q_offset + 3) = QuaternionProduct(turn_1, QuaternionProduct(turn_2, q_WB));
          const std::vector<ConstraintRow<double>> rows = Rows(model, set, q, start.v);
          Eigen::MatrixXd jacobian(4, 12);
          for (int i = 0; i < 4; ++i) {
            EXPECT_NEAR(rows[i].value, 0.0, 1e-14) << "row " << i << " at " << theta_1 << ", " << theta_2;
            for (const BodyVector<double>& g : {rows[i].a, rows[i].b}) {
              jacobian.block<1, 3>(i, 6 * g.body) = g.translation.transpose();
              jacobian.block<1, 3>(i, 6 * g.body + 3) = g.rotation.transpose();
            }
          }
          Eigen::JacobiSVD<Eigen::MatrixXd> svd(jacobian);
          EXPECT_GT(svd.singularValues()[3], 1e-3 * svd.singularValues()[0]) << "rank below 4";
        }
      }
    }
  }
}

// Rows of one part in 3D (joint_kinds.h's table).
int PartRows(JointPart part) {
  switch (part) {
    case JointPart::kNone:
      return 0;
    case JointPart::kDistance:
      return 1;
    case JointPart::kPoint:
      return 3;
    case JointPart::kLine:
      return 2;
    case JointPart::kCommonAxis:
      return 2;
    case JointPart::kCrossedAxes:
      return 1;
    case JointPart::kFrozenOrientation:
      return 3;
    case JointPart::kDoubleHinge:
      return 4;
  }
  return -1;
}

TEST(JointKinds, EachTypeIsOneRowWhoseRowsAndCoordinatesAreItsParts) {
  std::mt19937 random(7);
  for (int t = 0; t <= static_cast<int>(JointType::kDoubleHinge); ++t) {
    const JointType type = static_cast<JointType>(t);
    const JointKind& kind = JointKindOf(type);
    EXPECT_EQ(kind.type, type);
    const JointKind* found = FindJointKind(kind.name);
    ASSERT_NE(found, nullptr) << kind.name;
    EXPECT_EQ(found->type, type) << kind.name;
    const Model<double> model = TwoBodies(type, 0, 1, &random);
    const ConstraintSet<double> set = BuildConstraintSet(model, InitialState(model).q);
    EXPECT_EQ(static_cast<int>(DescribeRows(model, set).size()), PartRows(kind.parts[0]) + PartRows(kind.parts[1]))
        << kind.name;
    const bool angle = HasAngle(kind) && kind.coordinates != CoordinateSet::kPlanarAngle;  // a pin's is 2D's only
    EXPECT_EQ(HasCoordinate(model, model.joints[0], JointCoordinate::kAngle), angle) << kind.name;
    EXPECT_EQ(HasCoordinate(model, model.joints[0], JointCoordinate::kDisplacement), HasDisplacement(kind))
        << kind.name;
    Model<double> limited = model;
    limited.joints[0].range.has_low = true;
    limited.joints[0].range.low = -10.0;
    if (kind.limitable && (angle || HasDisplacement(kind))) {
      EXPECT_EQ(UnilateralEvents<double>(limited).size(), 1) << kind.name;  // its low side
    } else {
      EXPECT_THROW(UnilateralEvents<double>{limited}, InputError) << kind.name;
    }
  }
  EXPECT_EQ(FindJointKind("ball"), nullptr);
  EXPECT_EQ(JointTypeList(), "distance, pin, slider, hinge, universal, prismatic, cylindrical, weld or double_hinge");
}

INSTANTIATE_TEST_SUITE_P(
    Joints, JointRowsTest,
    ::testing::Values(Case{JointType::kDistance, 0, 1}, Case{JointType::kPin, 0, 1}, Case{JointType::kSlider, 0, 1},
                      Case{JointType::kHinge, 0, 1}, Case{JointType::kUniversal, 0, 1},
                      Case{JointType::kPrismatic, 0, 1}, Case{JointType::kCylindrical, 0, 1},
                      Case{JointType::kWeld, 0, 1}, Case{JointType::kHinge, kWorld, 1},
                      Case{JointType::kHinge, 1, kWorld}, Case{JointType::kPrismatic, kWorld, 0},
                      Case{JointType::kSlider, 1, 2}, Case{JointType::kPin, 2, 0}, Case{JointType::kDistance, 2, 1},
                      Case{JointType::kDoubleHinge, 0, 1}, Case{JointType::kDoubleHinge, kWorld, 1},
                      Case{JointType::kDoubleHinge, 1, kWorld}),
    [](const ::testing::TestParamInfo<Case>& info) {
      auto name = [](int body) { return body == kWorld ? std::string("world") : std::string(1, "abp"[body]); };
      return std::string(JointTypeName(info.param.type)) + "_" + name(info.param.a) + "_" + name(info.param.b);
    });

}  // namespace
}  // namespace tether
