// The Schur-complement KKT solve (schur_system.h, schur_solver.h) through ComputeAcceleration:
//   - kDense and kSparse agree with each other and with a dense LU solve of the full KKT matrix [M J^T; J 0]
//     assembled here from EvaluateConstraintRows, on a chain and on a four-bar loop;
//   - a duplicated row (a redundant constraint) gives finite multipliers split equally between the copies (the
//     least-norm choice) and the acceleration of the model without the copy;
//   - the Jet path (implicit function theorem, one factorization of the value part) matches an oracle that
//     builds the Schur matrix as a dense matrix of Jets and factors it with Eigen;
//   - half solves (F^-1 b, S = F F^T) multiply as full solves do, b^T S^-1 b'.
#include "tether/dynamics/solvers/schur_solver.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "test_scenes.h"
#include "tether/dynamics/effects/effects.h"
#include "tether/dynamics/model/configuration_space.h"
#include "tether/dynamics/solvers/constrained_dynamics.h"

namespace tether {
namespace {

constexpr double kSolverAgreement = 1e-12;   // dense vs sparse factorization, relative to the largest entry
constexpr double kKktAgreement = 1e-9;       // vs the unregularized KKT solve (regularization moves lambda ~1e-12)
constexpr double kJetAgreement = 1e-12;      // Jet path vs factoring the Jet matrix, relative
constexpr double kAlpha = 3.0, kBeta = 5.0;  // Baumgarte gains, so that every term of the right-hand side counts

int AddBar(Model<double>* model, double x, double y, double angle) {
  const int index = static_cast<int>(model->bodies.size());
  return AddBody<double>(model, "bar" + std::to_string(index), BodyKind::kPlanar, 1.0 + 0.2 * index, 0.02 + 0.01 * index,
                         Vec3<double>(x, y, 0.0), angle, Vec3<double>::Zero(), 0.0);
}

void AddPin(Model<double>* model, int a, const Vec3<double>& local_a, int b, const Vec3<double>& local_b) {
  Joint<double> joint;
  joint.scene_index = model->NumConstraints();
  joint.type = JointType::kPin;
  joint.a = {a, local_a};
  joint.b = {b, local_b};
  AddJoint(model, joint);
}

void AddRod(Model<double>* model, int a, const Vec3<double>& local_a, int b, const Vec3<double>& local_b,
            double length) {
  Joint<double> joint;
  joint.scene_index = model->NumConstraints();
  joint.type = JointType::kDistance;
  joint.a = {a, local_a};
  joint.b = {b, local_b};
  joint.length = length;
  AddJoint(model, joint);
}

Model<double> WithGravity() {
  Model<double> model;
  model.dimension = 2;
  model.gravity.push_back({0, Vec3<double>(0.0, -9.81, 0.0)});
  return model;
}

// Five rigid bars of length 0.5 pinned end to end from the world, and a particle on a rod from the last one:
// 11 rows, a banded Schur matrix.
Model<double> Chain() {
  Model<double> model = WithGravity();
  const Vec3<double> head(-0.25, 0.0, 0.0), tail(0.25, 0.0, 0.0);
  int previous = kWorld;
  Vec3<double> joint = Vec3<double>::Zero();
  for (int k = 0; k < 5; ++k) {
    const double angle = -0.3 - 0.25 * k;
    const Vec3<double> centre = joint + RotatePlanar(angle, tail);
    const int bar = AddBar(&model, centre.x(), centre.y(), angle);
    AddPin(&model, previous, previous == kWorld ? joint : tail, bar, head);
    previous = bar;
    joint = centre + RotatePlanar(angle, tail);
  }
  const int bob = AddBody<double>(&model, "bob", BodyKind::kParticle, 0.7, 0.0, joint + Vec3<double>(0.1, -0.28, 0.0),
                                  0.0, Vec3<double>::Zero(), 0.0);
  AddRod(&model, previous, tail, bob, Vec3<double>::Zero(), 0.3);
  return model;
}

// A four-bar loop: crank, coupler and rocker pinned to each other and, at both ends, to the world. The state is
// only near the loop's assembly: the KKT solve does not need C = 0.
Model<double> FourBar() {
  Model<double> model = WithGravity();
  const int crank = AddBar(&model, 0.1, 0.17, 1.05);    // length 0.4
  const int coupler = AddBar(&model, 0.6, 0.45, 0.25);  // length 1.1
  const int rocker = AddBar(&model, 1.05, 0.2, 1.5);    // length 0.8
  AddPin(&model, kWorld, Vec3<double>::Zero(), crank, Vec3<double>(-0.2, 0.0, 0.0));
  AddPin(&model, crank, Vec3<double>(0.2, 0.0, 0.0), coupler, Vec3<double>(-0.55, 0.0, 0.0));
  AddPin(&model, coupler, Vec3<double>(0.55, 0.0, 0.0), rocker, Vec3<double>(0.4, 0.0, 0.0));
  AddPin(&model, rocker, Vec3<double>(-0.4, 0.0, 0.0), kWorld, Vec3<double>(1.0, 0.0, 0.0));
  return model;
}

// A velocity with every component O(1), fixed by the seed.
Eigen::VectorXd SomeVelocity(int n, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> unit(-1.5, 1.5);
  Eigen::VectorXd v(n);
  for (int i = 0; i < n; ++i) v[i] = unit(random);
  return v;
}

struct Solution {
  Eigen::VectorXd acceleration, lambda;
};

// The library's solve with the given factorization.
template <typename T>
Solution LibrarySolve(Model<T> model, KktSolver kind, const VecX<T>& q, const VecX<T>& v, VecX<T>* a_out = nullptr,
                      VecX<T>* lambda_out = nullptr) {
  model.simulation.solver = kind;
  Workspace<T> ws(model, q);  // pins and rods fix nothing at the start
  EXPECT_EQ(ws.solver->kind(), kind);
  ws.alpha = T(kAlpha);
  ws.beta = T(kBeta);
  VecX<T> a(model.NumVelocities());
  EXPECT_TRUE(ComputeAcceleration(model, 0.0, q, v, &ws, &a));
  if (a_out != nullptr) *a_out = a;
  if (lambda_out != nullptr) *lambda_out = ws.kkt.lambda;
  Solution s{Eigen::VectorXd(a.size()), Eigen::VectorXd(ws.kkt.lambda.size())};
  for (int i = 0; i < a.size(); ++i) s.acceleration[i] = Value(a[i]);
  for (int i = 0; i < ws.kkt.lambda.size(); ++i) s.lambda[i] = Value(ws.kkt.lambda[i]);
  return s;
}

// The pieces of the KKT system at (q, v), over any scalar: J, M^-1's diagonal, f and the Schur right-hand side
// b = J M^-1 f + Jdot q' + alpha J q' + beta C (so that J q'' = -(Jdot q' + alpha J q' + beta C)).
template <typename T>
struct KktPieces {
  Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> jacobian;
  VecX<T> inverse_mass, force, gamma;  // gamma = -(Jdot q' + alpha J q' + beta C)
};

// (Particles and planar rigid bodies: q and v share their layout, M is diagonal.)
template <typename T>
KktPieces<T> Pieces(const Model<T>& model, const VecX<T>& q, const VecX<T>& v) {
  const int n = model.NumVelocities();
  EXPECT_EQ(n, model.NumCoordinates());
  const ConstraintSet<T> set = BuildConstraintSet(model, q);
  BodyFrames<T> frames;
  UpdateFrames(model, q, v, true, &frames);
  std::vector<ConstraintRow<T>> rows(DescribeRows(model, set).size());
  EvaluateConstraintRows(model, set, frames, q, v, true, &rows);
  const int m = static_cast<int>(rows.size());
  KktPieces<T> p;
  p.jacobian.setZero(m, n);
  for (int i = 0; i < m; ++i) {
    VecX<T> row = VecX<T>::Zero(n);
    AddScaled(model, rows[i].a, T(1.0), &row);
    AddScaled(model, rows[i].b, T(1.0), &row);
    p.jacobian.row(i) = row.transpose();
  }
  p.inverse_mass.resize(n);
  for (const Body<T>& body : model.bodies) {
    for (int k = 0; k < model.dimension; ++k) p.inverse_mass[body.v_offset + k] = T(1.0) / body.mass;
    if (body.kind == BodyKind::kPlanar) p.inverse_mass[body.v_offset + 2] = T(1.0) / body.inertia;
  }
  p.force = VecX<T>::Zero(n);
  AccumulateForces(model, JointCoordinates<T>{}, PrincipalInertias(model), frames, 0.0, q, v, &p.force);
  const VecX<T> velocity = p.jacobian * v;
  p.gamma.resize(m);
  for (int i = 0; i < m; ++i) p.gamma[i] = -(rows[i].bias + T(kAlpha) * velocity[i] + T(kBeta) * rows[i].value);
  return p;
}

// The oracle: LU of the full KKT matrix [M J^T; J 0] [q''; lambda] = [f; gamma].
Solution KktSolve(const Model<double>& model, const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
  const KktPieces<double> p = Pieces(model, q, v);
  const int n = static_cast<int>(p.force.size()), m = static_cast<int>(p.gamma.size());
  Eigen::MatrixXd kkt = Eigen::MatrixXd::Zero(n + m, n + m);
  kkt.topLeftCorner(n, n) = p.inverse_mass.cwiseInverse().asDiagonal();
  kkt.topRightCorner(n, m) = p.jacobian.transpose();
  kkt.bottomLeftCorner(m, n) = p.jacobian;
  Eigen::VectorXd rhs(n + m);
  rhs << p.force, p.gamma;
  const Eigen::VectorXd x = kkt.fullPivLu().solve(rhs);
  return {x.head(n), x.tail(m)};
}

void ExpectVectorNear(const Eigen::VectorXd& actual, const Eigen::VectorXd& expected, double relative,
                      const char* what) {
  ASSERT_EQ(actual.size(), expected.size()) << what;
  const double scale = std::max(1.0, expected.cwiseAbs().maxCoeff());
  for (int i = 0; i < expected.size(); ++i) {
    ASSERT_TRUE(std::isfinite(actual[i])) << what << " [" << i << "]";
    EXPECT_NEAR(actual[i], expected[i], relative * scale) << what << " [" << i << "]";
  }
}

void ExpectDenseSparseAndKktAgree(const Model<double>& model, unsigned seed) {
  const Eigen::VectorXd q = InitialState(model).q;
  const Eigen::VectorXd v = SomeVelocity(model.NumVelocities(), seed);
  const Solution dense = LibrarySolve(model, KktSolver::kDense, q, v);
  const Solution sparse = LibrarySolve(model, KktSolver::kSparse, q, v);
  const Solution kkt = KktSolve(model, q, v);
  ExpectVectorNear(sparse.acceleration, dense.acceleration, kSolverAgreement, "sparse vs dense q''");
  ExpectVectorNear(sparse.lambda, dense.lambda, kSolverAgreement, "sparse vs dense lambda");
  ExpectVectorNear(dense.acceleration, kkt.acceleration, kKktAgreement, "dense vs KKT q''");
  ExpectVectorNear(dense.lambda, kkt.lambda, kKktAgreement, "dense vs KKT lambda");
  // the solution satisfies J q'' = gamma
  const KktPieces<double> p = Pieces(model, q, v);
  ExpectVectorNear(p.jacobian * dense.acceleration, p.gamma, kKktAgreement, "J q'' = gamma");
}

TEST(SchurSolver, DenseSparseAndKktAgreeOnAChain) { ExpectDenseSparseAndKktAgree(Chain(), 11); }

TEST(SchurSolver, DenseSparseAndKktAgreeOnAFourBarLoop) { ExpectDenseSparseAndKktAgree(FourBar(), 12); }

// A pendulum whose rod is declared twice: S is singular, the regularization picks the least-norm multipliers.
TEST(SchurSolver, HalfSolvesGiveTheProductsOfAFullSolve) {
  // y = F^-1 b with S = F F^T: y . y' = b^T S^-1 b', for the dense Cholesky and the sparse LDL^T, and a right-hand
  // side with one nonzero (the sparse path skips the zero columns) as well as a full one
  const Model<double> four_bar = FourBar();
  for (const KktSolver kind : {KktSolver::kDense, KktSolver::kSparse}) {
    Model<double> model = four_bar;
    model.simulation.solver = kind;
    const Eigen::VectorXd q = InitialState(model).q;
    Workspace<double> ws(model, q);
    ws.alpha = kAlpha;
    ws.beta = kBeta;
    Eigen::VectorXd a(model.NumVelocities());
    ASSERT_TRUE(ComputeAcceleration(model, 0.0, q, SomeVelocity(model.NumVelocities(), 5), &ws, &a));
    const Eigen::Index m = ws.kkt.rhs.size();
    std::mt19937 random(7);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    Eigen::VectorXd b(m), c = Eigen::VectorXd::Zero(m), x;
    for (Eigen::Index i = 0; i < m; ++i) b[i] = uniform(random);
    c[m / 2] = 1.5;
    ASSERT_TRUE(ws.solver->SolveAgain(ws.kkt.schur, c, &x, SchurSourceOf(ws)));  // S^-1 c
    Eigen::VectorXd y = b, z = c;
    ASSERT_TRUE(ws.solver->HalfSolveInPlace(&y));
    ASSERT_TRUE(ws.solver->HalfSolveInPlace(&z));
    EXPECT_NEAR(y.dot(z), b.dot(x), kSolverAgreement * b.norm() * x.norm()) << static_cast<int>(kind);
    EXPECT_NEAR(z.dot(z), c.dot(x), kSolverAgreement * c.norm() * x.norm()) << static_cast<int>(kind);
  }
}

TEST(SchurSolver, DuplicatedRowGivesEqualSplitAndTheRightAcceleration) {
  Model<double> single = WithGravity();
  const int bob = AddBody<double>(&single, "bob", BodyKind::kParticle, 1.3, 0.0, Vec3<double>(0.4, -0.5, 0.0), 0.0,
                                  Vec3<double>::Zero(), 0.0);
  AddRod(&single, kWorld, Vec3<double>::Zero(), bob, Vec3<double>::Zero(), 0.6);
  Model<double> doubled = single;
  AddRod(&doubled, kWorld, Vec3<double>::Zero(), bob, Vec3<double>::Zero(), 0.6);

  const Eigen::VectorXd q = InitialState(single).q;
  const Eigen::VectorXd v(Eigen::Vector2d(0.8, 0.64));  // tangent to the rod
  const Solution reference = KktSolve(single, q, v);
  ASSERT_GT(std::abs(reference.lambda[0]), 1.0);  // the rod carries a real load
  for (KktSolver kind : {KktSolver::kDense, KktSolver::kSparse}) {
    SCOPED_TRACE(kind == KktSolver::kDense ? "dense" : "sparse");
    const Solution s = LibrarySolve(doubled, kind, q, v);
    ExpectVectorNear(s.acceleration, reference.acceleration, kKktAgreement, "q''");
    ASSERT_EQ(s.lambda.size(), 2);
    EXPECT_NEAR(s.lambda[0] + s.lambda[1], reference.lambda[0], kKktAgreement * std::abs(reference.lambda[0]));
    // equal split: the least-norm multipliers. The null-space component is resolved only to round-off over the
    // regularization (1e-16 / 1e-12), hence the looser tolerance.
    EXPECT_NEAR(s.lambda[0], 0.5 * reference.lambda[0], 1e-3 * std::abs(reference.lambda[0]));
    EXPECT_NEAR(s.lambda[1], 0.5 * reference.lambda[0], 1e-3 * std::abs(reference.lambda[0]));
  }
}

// The conditioning the factorization reveals (schur_solver.h): a particle held by two rods from anchors on
// either side, their lines at `angle` radians: the rows' pivot ratio is sin^2(angle); at 0 the particle could
// move across both rods (a singular configuration).
bool SawNearSingular(double angle, bool duplicate_first_rod, KktSolver kind) {
  Model<double> model = WithGravity();
  model.simulation.solver = kind;
  const int p = AddBody<double>(&model, "p", BodyKind::kParticle, 1.0, 0.0, Vec3<double>::Zero(), 0.0,
                                Vec3<double>::Zero(), 0.0);
  const Vec3<double> left(-1.0, 0.0, 0.0), right(std::cos(angle), std::sin(angle), 0.0);
  AddRod(&model, kWorld, left, p, Vec3<double>::Zero(), 1.0);
  AddRod(&model, kWorld, right, p, Vec3<double>::Zero(), 1.0);
  if (duplicate_first_rod) AddRod(&model, kWorld, left, p, Vec3<double>::Zero(), 1.0);
  const State<double> initial = InitialState(model);
  Workspace<double> ws(model, initial.q);
  Eigen::VectorXd acceleration(model.NumVelocities());
  EXPECT_TRUE(ComputeAcceleration(model, 0.0, initial.q, initial.v, &ws, &acceleration));
  return ws.solver->saw_near_singular();
}

TEST(SchurSolver, FlagsRowsNearDependenceButNotRedundantOrWellConditionedOnes) {
  for (KktSolver kind : {KktSolver::kDense, KktSolver::kSparse}) {
    SCOPED_TRACE(kind == KktSolver::kDense ? "dense" : "sparse");
    EXPECT_FALSE(SawNearSingular(1.5, false, kind));   // rods nearly at right angles
    EXPECT_FALSE(SawNearSingular(0.02, false, kind));  // ratio 4e-4: above the 1e-4 mark
    EXPECT_TRUE(SawNearSingular(5e-3, false, kind));   // 2.5e-5: near the singular configuration
    EXPECT_TRUE(SawNearSingular(1e-4, false, kind));   // 1e-8
    // a third rod duplicating the first is exactly redundant (ratio at the regularization's 1e-12): not flagged
    EXPECT_FALSE(SawNearSingular(1.5, true, kind));
  }
}

// A straight chain of 50 thin rods on hinges is far from any singular configuration, but the minimum-degree
// order of its rows ends in the chain's middle, where the last pivot ratio is 1e-6 (1.6e-8 at 200 rods): the
// breadth-first order from its base (sparse_ldlt.h) is what keeps the flag quiet, on both paths.
TEST(SchurSolver, DoesNotFlagALongStraightChainOfRods) {
  std::string bodies, constraints;
  for (int k = 0; k < 50; ++k) {
    const std::string name = "\"l" + std::to_string(k) + "\"";
    bodies += std::string(k ? ", " : "") + "{\"name\": " + name + ", \"type\": \"rigid\", \"mass\": 1, " +
              "\"inertia\": [2e-4, 0.0834, 0.0834], \"position\": [" + std::to_string(k + 0.5) + ", 0, 0]}";
    constraints += std::string(k ? ", " : "") + "{\"type\": \"hinge\", \"bodies\": [" +
                   (k ? "\"l" + std::to_string(k - 1) + "\"" : std::string("\"world\"")) + ", " + name +
                   "], \"points\": [[" + (k ? "0.5" : "0") + ", 0, 0], [-0.5, 0, 0]], \"axis\": [0, 1, 0]}";
  }
  for (KktSolver kind : {KktSolver::kDense, KktSolver::kSparse}) {
    Model<double> model = testing::SceneFromJson("{\"dimension\": 3, \"bodies\": [" + bodies + "], \"constraints\": [" +
                                                 constraints + "], \"effects\": [{\"type\": \"gravity\", " +
                                                 "\"acceleration\": [0, 0, -9.81]}]}");
    model.simulation.solver = kind;
    const State<double> initial = InitialState(model);
    Workspace<double> ws(model, initial.q);
    Eigen::VectorXd acceleration(model.NumVelocities());
    ASSERT_TRUE(ComputeAcceleration(model, 0.0, initial.q, initial.v, &ws, &acceleration));
    EXPECT_FALSE(ws.solver->saw_near_singular()) << (kind == KktSolver::kDense ? "dense" : "sparse");
  }
}

// The Jet oracle: lambda from the Schur matrix (schur_system.h) held as a dense matrix of Jets and
// factored with Eigen's LDLT over Jets, then q'' = M^-1 (f - J^T lambda).
void JetOracle(const Model<Jet>& model, const VecX<Jet>& q, const VecX<Jet>& v, VecX<Jet>* a, VecX<Jet>* lambda) {
  const KktPieces<Jet> p = Pieces(model, q, v);
  using JetMatrix = Eigen::Matrix<Jet, Eigen::Dynamic, Eigen::Dynamic>;
  // the scenes' rows are well conditioned, so the library solves S itself (schur_solver.h), and so does the oracle
  const JetMatrix schur = p.jacobian * p.inverse_mass.asDiagonal() * p.jacobian.transpose();
  const VecX<Jet> b = p.jacobian * p.inverse_mass.cwiseProduct(p.force) - p.gamma;
  *lambda = schur.ldlt().solve(b);
  *a = p.inverse_mass.cwiseProduct(p.force - p.jacobian.transpose() * *lambda);
}

void ExpectJetsNear(const VecX<Jet>& actual, const VecX<Jet>& expected, const char* what) {
  ASSERT_EQ(actual.size(), expected.size());
  double value_scale = 1.0, derivative_scale = 1.0;
  for (int i = 0; i < expected.size(); ++i) {
    value_scale = std::max(value_scale, std::abs(expected[i].a));
    derivative_scale = std::max(derivative_scale, expected[i].v.cwiseAbs().maxCoeff());
  }
  for (int i = 0; i < expected.size(); ++i) {
    EXPECT_NEAR(actual[i].a, expected[i].a, kJetAgreement * value_scale) << what << " [" << i << "]";
    for (int k = 0; k < kJetStride; ++k) {
      EXPECT_NEAR(actual[i].v[k], expected[i].v[k], kJetAgreement * derivative_scale)
          << what << " [" << i << "] direction " << k;
    }
  }
}

TEST(SchurSolver, JetPathMatchesFactoringTheJetMatrix) {
  const std::vector<std::pair<std::string, Model<double>>> scenes = {{"chain", Chain()}, {"four-bar", FourBar()}};
  for (const auto& [name, base] : scenes) {
    // derivative directions: a mass, gravity, a coordinate (moves J and S) and a velocity (moves the bias)
    Model<Jet> model = CastModel<Jet>(base);
    model.bodies[1].mass.v[0] = 1.0;
    model.gravity[0].acceleration[1].v[1] = 1.0;
    VecX<Jet> q = InitialState(model).q, v = SomeVelocity(base.NumVelocities(), 13).cast<Jet>();
    q[model.bodies[1].q_offset + 2].v[2] = 1.0;
    v[model.bodies[2].v_offset].v[3] = 1.0;

    VecX<Jet> expected_a, expected_lambda;
    JetOracle(model, q, v, &expected_a, &expected_lambda);
    // the derivative parts are not trivially zero
    double largest_derivative = 0.0;
    for (int i = 0; i < expected_a.size(); ++i) {
      largest_derivative = std::max(largest_derivative, expected_a[i].v.cwiseAbs().maxCoeff());
    }
    ASSERT_GT(largest_derivative, 0.1);
    for (KktSolver kind : {KktSolver::kDense, KktSolver::kSparse}) {
      SCOPED_TRACE(name + (kind == KktSolver::kDense ? ", dense" : ", sparse"));
      VecX<Jet> a, lambda;
      LibrarySolve(model, kind, q, v, &a, &lambda);
      ExpectJetsNear(a, expected_a, "q''");
      ExpectJetsNear(lambda, expected_lambda, "lambda");
    }
  }
}

}  // namespace
}  // namespace tether
