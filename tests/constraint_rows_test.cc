// Constraint rows of the built-in constraints (distance, pin, slider; 2D with particles and planar rigid bodies,
// 3D with particles), at non-degenerate states off the constraints and with non-zero body points:
//   (a) the Jacobian blocks, mapped onto the full q, against central differences of C(q);
//   (b) the bias Jdot q' against central differences of s -> J(q + s v) v at s = 0;
//   (c) values, Jacobians and bias against the same constraint written as a user residual (user_constraint.h),
//       whose derivatives tether derives with dual numbers.
#include "tether/dynamics/constraints/constraint_rows.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <vector>

#include "tether/dynamics/constraints/user_constraint.h"

namespace tether {
namespace {

constexpr double kStep = 1e-6;                 // central-difference step
constexpr double kDifferenceTolerance = 1e-7;  // relative to max(1, |exact|)
constexpr double kAutomaticTolerance = 1e-12;  // built-in vs user residual, relative to max(1, |built-in|)
constexpr int kStates = 6;                     // random states per scene

enum class Kind { kDistance, kPin, kSlider };

struct Point {
  int body = kWorld;
  Vec3<double> local = Vec3<double>::Zero();
};

struct Spec {
  Kind kind;
  Point a, b;
  double length = 1.0;                        // distance only
  Vec3<double> axis = Vec3<double>::UnitX();  // slider only
};

struct Scene {
  int dimension = 2;
  std::vector<BodyKind> bodies;
  std::vector<Spec> constraints;  // listed distances first, then pins, then sliders (the row order)
};

int RowsOf(const Spec& spec, int dimension) {
  switch (spec.kind) {
    case Kind::kDistance:
      return 1;
    case Kind::kPin:
      return dimension;
    case Kind::kSlider:
      return dimension - 1;
  }
  return 0;
}

// World position of a body point from the body's own coordinates q (nullptr for the world).
template <typename S>
void PointPosition(const Point& point, BodyKind kind, int dimension, const S* q, S p[3]) {
  for (int k = 0; k < 3; ++k) p[k] = S(point.local[k]);
  if (point.body == kWorld) return;
  for (int k = 0; k < dimension; ++k) p[k] = q[k] + S(point.local[k]);
  if (kind == BodyKind::kPlanar) {
    using std::cos;
    using std::sin;
    const S c = cos(q[2]), s = sin(q[2]);
    p[0] = q[0] + c * S(point.local[0]) - s * S(point.local[1]);
    p[1] = q[1] + s * S(point.local[0]) + c * S(point.local[1]);
  }
}

// Slider normals in body A's frame, by the convention constraint_rows.h documents: in 2D perp(u); in 3D
// n1 = u x e / |u x e| with e the coordinate axis least aligned with u, and n2 = u x n1.
std::vector<Vec3<double>> SliderNormals(int dimension, const Vec3<double>& axis) {
  const Vec3<double> u = axis.normalized();
  if (dimension == 2) return {Vec3<double>(-u.y(), u.x(), 0.0)};
  int least = 0;
  for (int k = 1; k < 3; ++k) {
    if (std::abs(u[k]) < std::abs(u[least])) least = k;
  }
  const Vec3<double> n1 = u.cross(Vec3<double>::Unit(least)).normalized();
  return {n1, u.cross(n1)};
}

// The same constraint written as a user residual of (q_A, q_B).
template <int kRowCount>
struct AsUserResidual {
  static constexpr int kRows = kRowCount;
  Spec spec;
  int dimension;
  BodyKind kind_a, kind_b;

  template <typename S>
  void operator()(const S* q_a, const S* q_b, S* c) const {
    using std::sqrt;
    S pa[3], pb[3], d[3];
    PointPosition(spec.a, kind_a, dimension, q_a, pa);
    PointPosition(spec.b, kind_b, dimension, q_b, pb);
    for (int k = 0; k < 3; ++k) d[k] = pb[k] - pa[k];
    if (spec.kind == Kind::kDistance) {
      S squared = S(0.0);
      for (int k = 0; k < dimension; ++k) squared += d[k] * d[k];
      c[0] = sqrt(squared) - S(spec.length);
    } else if (spec.kind == Kind::kPin) {
      for (int k = 0; k < dimension; ++k) c[k] = d[k];
    } else {
      const std::vector<Vec3<double>> normals = SliderNormals(dimension, spec.axis);
      for (int r = 0; r < kRows; ++r) {
        const Vec3<double>& n = normals[r];
        S n_x = S(n.x()), n_y = S(n.y());
        if (spec.a.body != kWorld && kind_a == BodyKind::kPlanar) {  // the normal turns with A (2D)
          using std::cos;
          using std::sin;
          const S cs = cos(q_a[2]), sn = sin(q_a[2]);
          n_x = cs * S(n.x()) - sn * S(n.y());
          n_y = sn * S(n.x()) + cs * S(n.y());
        }
        c[r] = n_x * d[0] + n_y * d[1];
        if (dimension == 3) c[r] += S(n.z()) * d[2];
      }
    }
  }
};

template <int kRows>
void AddAsUser(Model<double>* model, const Scene& scene, const Spec& spec) {
  auto kind = [&scene](int body) { return body == kWorld ? BodyKind::kParticle : scene.bodies[body]; };
  AddUserConstraint(model, spec.a.body, spec.b.body,
                    AsUserResidual<kRows>{spec, scene.dimension, kind(spec.a.body), kind(spec.b.body)});
}

// The scene with built-in constraints (user == false) or with the same constraints as user residuals.
Model<double> BuildModel(const Scene& scene, bool user) {
  Model<double> model;
  model.dimension = scene.dimension;
  for (size_t i = 0; i < scene.bodies.size(); ++i) {
    AddBody<double>(&model, "body" + std::to_string(i), scene.bodies[i], 1.0 + i, 0.3 + 0.1 * i, Vec3<double>::Zero(),
                    0.0, Vec3<double>::Zero(), 0.0);
  }
  for (const Spec& spec : scene.constraints) {
    const BodyPoint<double> a{spec.a.body, spec.a.local}, b{spec.b.body, spec.b.local};
    const int index = model.NumConstraints();
    if (user) {
      switch (RowsOf(spec, scene.dimension)) {
        case 1:
          AddAsUser<1>(&model, scene, spec);
          break;
        case 2:
          AddAsUser<2>(&model, scene, spec);
          break;
        default:
          AddAsUser<3>(&model, scene, spec);
          break;
      }
    } else {
      Joint<double> joint;
      joint.scene_index = index;
      joint.type = spec.kind == Kind::kDistance ? JointType::kDistance
                   : spec.kind == Kind::kPin    ? JointType::kPin
                                                : JointType::kSlider;
      joint.a = a;
      joint.b = b;
      joint.axis = spec.axis;
      joint.length = spec.length;
      AddJoint(&model, joint);
    }
  }
  return model;
}

// Rows at (q, v) as dense pieces: values, bias and the Jacobian mapped onto the full coordinate vector.
struct DenseRows {
  Eigen::VectorXd value, bias;
  Eigen::MatrixXd jacobian;
};

// (Particles and planar rigid bodies only: q and v have the same layout, so J over v is J over q.)
DenseRows Evaluate(const Model<double>& model, const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
  // distance, pin and slider fix nothing at the start: the set is the same at any configuration
  const ConstraintSet<double> set = BuildConstraintSet(model, InitialState(model).q);
  BodyFrames<double> frames;
  UpdateFrames(model, q, v, true, &frames);
  std::vector<ConstraintRow<double>> rows(DescribeRows(model, set).size());
  EvaluateConstraintRows(model, set, frames, q, v, true, &rows);
  const int m = static_cast<int>(rows.size()), n = model.NumVelocities();
  EXPECT_EQ(n, model.NumCoordinates());
  DenseRows out{Eigen::VectorXd(m), Eigen::VectorXd(m), Eigen::MatrixXd::Zero(m, n)};
  for (int i = 0; i < m; ++i) {
    out.value[i] = rows[i].value;
    out.bias[i] = rows[i].bias;
    VecX<double> row = VecX<double>::Zero(n);
    AddScaled(model, rows[i].a, 1.0, &row);
    AddScaled(model, rows[i].b, 1.0, &row);
    out.jacobian.row(i) = row.transpose();
  }
  return out;
}

void ExpectMatrixNear(const Eigen::MatrixXd& actual, const Eigen::MatrixXd& expected, double tolerance,
                      const char* what) {
  ASSERT_EQ(actual.rows(), expected.rows()) << what;
  ASSERT_EQ(actual.cols(), expected.cols()) << what;
  for (int i = 0; i < expected.rows(); ++i) {
    for (int j = 0; j < expected.cols(); ++j) {
      EXPECT_NEAR(actual(i, j), expected(i, j), tolerance * std::max(1.0, std::abs(expected(i, j))))
          << what << " (" << i << ", " << j << ")";
    }
  }
}

// A random-ish state: body k near (k, 0.5 k, 0.3 k) so that no two points coincide, angles anywhere, speeds O(1).
void RandomState(const Model<double>& model, std::mt19937* random, Eigen::VectorXd* q, Eigen::VectorXd* v) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const Vec3<double> spacing(1.0, 0.5, 0.3);
  q->resize(model.NumCoordinates());
  v->resize(model.NumVelocities());
  for (size_t k = 0; k < model.bodies.size(); ++k) {
    const Body<double>& body = model.bodies[k];
    for (int i = 0; i < model.dimension; ++i) (*q)[body.q_offset + i] = (k + 1.0) * spacing[i] + 0.3 * unit(*random);
    if (body.kind == BodyKind::kPlanar) (*q)[body.q_offset + 2] = M_PI * unit(*random);
    for (int i = 0; i < body.v_size; ++i) (*v)[body.v_offset + i] = 2.0 * unit(*random);
  }
}

// Checks (a), (b) and (c) of the file comment at kStates random states.
void CheckRows(const Scene& scene) {
  const Model<double> builtin = BuildModel(scene, false);
  const Model<double> user = BuildModel(scene, true);
  ASSERT_EQ(DescribeRows(builtin, BuildConstraintSet(builtin, InitialState(builtin).q)).size(),
            DescribeRows(user, BuildConstraintSet(user, InitialState(user).q)).size());
  std::mt19937 random(20240601);
  for (int s = 0; s < kStates; ++s) {
    SCOPED_TRACE("state " + std::to_string(s));
    Eigen::VectorXd q, v;
    RandomState(builtin, &random, &q, &v);
    const DenseRows exact = Evaluate(builtin, q, v);
    const int n = builtin.NumCoordinates();

    // (a) J against central differences of C(q)
    Eigen::MatrixXd jacobian(exact.value.size(), n);
    for (int j = 0; j < n; ++j) {
      const Eigen::VectorXd e = kStep * Eigen::VectorXd::Unit(n, j);
      jacobian.col(j) = (Evaluate(builtin, q + e, v).value - Evaluate(builtin, q - e, v).value) / (2 * kStep);
    }
    ExpectMatrixNear(jacobian, exact.jacobian, kDifferenceTolerance, "Jacobian vs differences");

    // (b) Jdot q' = d/ds [J(q + s v) v] at s = 0
    const Eigen::VectorXd bias =
        (Evaluate(builtin, q + kStep * v, v).jacobian * v - Evaluate(builtin, q - kStep * v, v).jacobian * v) /
        (2 * kStep);
    ExpectMatrixNear(bias, exact.bias, kDifferenceTolerance, "bias vs differences");

    // (c) the automatic derivation of the same residual
    const DenseRows automatic = Evaluate(user, q, v);
    ExpectMatrixNear(automatic.value, exact.value, kAutomaticTolerance, "value vs user residual");
    ExpectMatrixNear(automatic.jacobian, exact.jacobian, kAutomaticTolerance, "Jacobian vs user residual");
    ExpectMatrixNear(automatic.bias, exact.bias, kAutomaticTolerance, "bias vs user residual");
  }
}

// 2D bodies: 0 a particle, 1 and 2 planar rigid bodies.
const std::vector<BodyKind> kPlanarBodies = {BodyKind::kParticle, BodyKind::kPlanar, BodyKind::kPlanar};
// 3D bodies: particles only.
const std::vector<BodyKind> kSpatialBodies = {BodyKind::kParticle, BodyKind::kParticle};

Point At(int body, double x, double y, double z = 0.0) { return {body, Vec3<double>(x, y, z)}; }

TEST(ConstraintRows, Distance2D) {
  CheckRows({2,
             kPlanarBodies,
             {{Kind::kDistance, At(kWorld, -0.5, 0.3), At(0, 0.1, -0.2), 0.9},
              {Kind::kDistance, At(0, 0.2, 0.1), At(1, 0.4, -0.15), 1.2},
              {Kind::kDistance, At(1, -0.3, 0.25), At(2, 0.35, 0.2), 0.8},
              {Kind::kDistance, At(kWorld, 0.7, -0.4), At(2, -0.2, 0.3), 2.0}}});
}

TEST(ConstraintRows, Pin2D) {
  CheckRows({2,
             kPlanarBodies,
             {{Kind::kPin, At(kWorld, -0.5, 0.3), At(1, 0.4, -0.1)},
              {Kind::kPin, At(0, 0.15, -0.1), At(1, -0.3, 0.2)},
              {Kind::kPin, At(1, 0.25, 0.35), At(2, -0.45, 0.1)}}});
}

TEST(ConstraintRows, Slider2D) {
  CheckRows({2,
             kPlanarBodies,
             {{Kind::kSlider, At(kWorld, -0.5, 0.3), At(0, 0.1, 0.2), {}, Vec3<double>(1.0, 0.4, 0.0)},
              {Kind::kSlider, At(0, 0.2, -0.1), At(1, 0.3, 0.15), {}, Vec3<double>(-0.3, 2.0, 0.0)},
              {Kind::kSlider, At(kWorld, 0.4, 0.2), At(2, -0.25, 0.3), {}, Vec3<double>(0.0, 1.0, 0.0)}}});
}

// The slider whose first body is a rotating rigid body: its normal turns with the body, which adds the
// Jacobian entry perp(n) . d on A's angle and the -w^2 n . d + 2 w perp(n) . d' terms to the bias.
TEST(ConstraintRows, SliderOnRotatingRigidBody) {
  const Scene scene{2,
                    kPlanarBodies,
                    {{Kind::kSlider, At(1, 0.3, -0.2), At(0, 0.1, 0.25), {}, Vec3<double>(0.8, 0.6, 0.0)},
                     {Kind::kSlider, At(1, -0.2, 0.1), At(2, 0.4, -0.3), {}, Vec3<double>(1.0, -0.5, 0.0)}}};
  CheckRows(scene);

  // the turning terms matter in this check: with only A spinning, a normal fixed in the world would give the
  // bias n . (c_B - c_A) = w^2 n . (R r_A) and the angle entry -n . perp(R r_A); the turning normal adds
  // -w^2 n . d + 2 w perp(n) . d' and perp(n) . d
  const Model<double> model = BuildModel(scene, false);
  const Spec& spec = scene.constraints[0];
  Eigen::VectorXd q, v;
  std::mt19937 random(7);
  RandomState(model, &random, &q, &v);
  const int angle = model.bodies[1].q_offset + 2;  // = v_offset + 2 for a planar body
  const double w = 3.0;
  v.setZero();
  v[angle] = w;
  const DenseRows rows = Evaluate(model, q, v);
  const Vec3<double> n = RotatePlanar(q[angle], Perp(Vec3<double>(spec.axis.normalized())));
  const Vec3<double> arm = RotatePlanar(q[angle], spec.a.local);
  EXPECT_GT(std::abs(rows.bias[0] - w * w * n.dot(arm)), 0.1);
  EXPECT_GT(std::abs(rows.jacobian(0, angle) + n.dot(Perp(arm))), 0.1);
}

TEST(ConstraintRows, Distance3D) {
  CheckRows({3,
             kSpatialBodies,
             {{Kind::kDistance, At(kWorld, -0.5, 0.3, 0.2), At(0, 0.1, -0.2, 0.3), 0.9},
              {Kind::kDistance, At(0, 0.2, 0.1, -0.3), At(1, 0.4, -0.15, 0.1), 1.2}}});
}

TEST(ConstraintRows, Pin3D) {
  CheckRows({3,
             kSpatialBodies,
             {{Kind::kPin, At(kWorld, -0.5, 0.3, 0.2), At(0, 0.2, 0.1, -0.3)},
              {Kind::kPin, At(0, 0.15, -0.1, 0.25), At(1, -0.3, 0.2, 0.1)}}});
}

TEST(ConstraintRows, Slider3D) {
  CheckRows({3,
             kSpatialBodies,
             {{Kind::kSlider, At(kWorld, -0.5, 0.3, 0.2), At(0, 0.1, 0.2, -0.1), {}, Vec3<double>(1.0, 0.4, -0.7)},
              {Kind::kSlider, At(0, 0.2, -0.1, 0.3), At(1, 0.3, 0.15, -0.2), {}, Vec3<double>(0.1, -0.3, 2.0)}}});
}

}  // namespace
}  // namespace tether
