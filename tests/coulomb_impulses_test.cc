// Coulomb's impulse problem (coulomb_impulses.h): its solutions meet Coulomb's conditions, the closed forms of one
// contact, the least impulses of a box's four corners, and derivatives equal to central differences.
#include "tether/dynamics/solvers/coulomb_impulses.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace tether {
namespace {

using Blocks = std::vector<ImpulseBlock<double>>;

// The largest departure from the conditions of the header (in rates, m/s; impulses scaled by W's diagonal), with
// the rates after computed from W itself (not the regularized one)
double WorstDeparture(const Eigen::MatrixXd& w, const Eigen::VectorXd& u, const Eigen::VectorXd& b,
                      const Blocks& blocks, const Eigen::VectorXd& p) {
  const Eigen::VectorXd y = u - b + w * p;
  double worst = 0.0;
  for (const ImpulseBlock<double>& block : blocks) {
    const Eigen::Index n = block.first_row;
    const double scale = w(n, n);
    worst = std::max({worst, -p[n] * scale, -y[n], std::abs(p[n] * y[n]) * scale});
    if (block.rows == 1) continue;
    const Eigen::VectorXd tangential = p.segment(n + 1, block.rows - 1), slip = y.segment(n + 1, block.rows - 1);
    const double cone = block.friction * p[n];
    worst = std::max(worst, (tangential.norm() - cone) * scale);
    if (!(p[n] * scale > 1e-12)) continue;  // apart: no friction impulse either (checked just above)
    if (tangential.norm() < cone * (1.0 - 1e-6)) {
      worst = std::max(worst, slip.norm());  // sticking
    } else if (slip.norm() > 0.0) {          // sliding: the impulse against the slip
      worst = std::max(worst, (tangential.normalized() + slip.normalized()).norm() * slip.norm());
    }
  }
  return worst;
}

TEST(CoulombImpulses, OneContactSticksOrSlidesByItsClosedForm) {
  // unit Delassus matrix: the normal impulse cancels the approach, the slip is stopped where mu p_n allows
  const Eigen::MatrixXd w = Eigen::MatrixXd::Identity(3, 3);
  const Blocks blocks = {{0, 3, 0.5}};
  CoulombImpulses<double> solver;
  Eigen::VectorXd p = Eigen::VectorXd::Zero(3);
  ASSERT_TRUE(solver.Solve(w, Eigen::Vector3d(-1.0, 0.3, -0.4), Eigen::Vector3d::Zero(), blocks, 1e-12, &p));
  EXPECT_NEAR(p[0], 1.0, 1e-8);  // sticks: |(-0.3, 0.4)| = 0.5 <= mu p_n
  EXPECT_NEAR(p[1], -0.3, 1e-8);
  EXPECT_NEAR(p[2], 0.4, 1e-8);
  p.setZero();
  ASSERT_TRUE(solver.Solve(w, Eigen::Vector3d(-1.0, 2.0, 0.0), Eigen::Vector3d(0.5, 0.0, 0.0), blocks, 1e-12, &p));
  EXPECT_NEAR(p[0], 1.5, 1e-8);    // to the target rate 0.5
  EXPECT_NEAR(p[1], -0.75, 1e-8);  // slides: mu p_n against the slip
  EXPECT_NEAR(p[2], 0.0, 1e-12);
  p.setZero();
  ASSERT_TRUE(solver.Solve(w, Eigen::Vector3d(1.0, 2.0, 0.0), Eigen::Vector3d::Zero(), blocks, 1e-12, &p));
  EXPECT_EQ(p, Eigen::Vector3d::Zero());  // separating: no impulse
}

TEST(CoulombImpulses, CoupledContactsMeetCoulombsConditionsFromAnyStart) {
  // random articulated-like problems: W = J J^T of rank-full random Jacobians, mixed blocks (limits, 2D and 3D
  // contacts), approaching and separating rates, a cold start and a start far from the solution
  std::mt19937 random(7);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  int solved = 0;
  for (int trial = 0; trial < 200; ++trial) {
    Blocks blocks;
    Eigen::Index rows = 0;
    const int count = 1 + trial % 6;
    for (int c = 0; c < count; ++c) {
      const int kind = (trial + c) % 3;
      blocks.push_back({rows, kind == 0 ? 1 : kind == 1 ? 2 : 3, 0.2 + 0.8 * std::abs(uniform(random))});
      rows += blocks.back().rows;
    }
    const Eigen::MatrixXd jacobian = Eigen::MatrixXd::NullaryExpr(rows, rows + 6, [&] { return uniform(random); });
    const Eigen::MatrixXd w = jacobian * jacobian.transpose();
    Eigen::VectorXd u = Eigen::VectorXd::NullaryExpr(rows, [&] { return uniform(random); });
    const Eigen::VectorXd b = Eigen::VectorXd::Zero(rows);
    Eigen::VectorXd p = trial % 2 == 0
                            ? Eigen::VectorXd::Zero(rows)
                            : Eigen::VectorXd(Eigen::VectorXd::NullaryExpr(rows, [&] { return uniform(random); }));
    CoulombImpulses<double> solver;
    if (!solver.Solve(w, u, b, blocks, 1e-11, &p)) continue;
    ++solved;
    EXPECT_LT(WorstDeparture(w, u, b, blocks, p), 1e-7) << "trial " << trial;
  }
  // Coulomb's problem need not have a solution for every W and mu (Painleve); these random ones nearly always do
  EXPECT_GE(solved, 195);
}

TEST(CoulombImpulses, ABoxsFourCornersShareItsWeightEquallyAndItsMotionIsExact) {
  // a unit box (mass 1, inertia 1/6 about every axis) falling flat at 1 m/s on its four corners (+-1/2, +-1/2): the
  // normal rows' Jacobians [1, y_c, -x_c] on (v_z, w_x, w_y) are 4 rows on 3 unknowns, W singular
  Eigen::MatrixXd jacobian(4, 3);
  const double corners[4][2] = {{0.5, 0.5}, {-0.5, 0.5}, {-0.5, -0.5}, {0.5, -0.5}};
  for (int c = 0; c < 4; ++c) jacobian.row(c) << 1.0, corners[c][1], -corners[c][0];
  const Eigen::Vector3d inverse_mass(1.0, 6.0, 6.0);
  const Eigen::MatrixXd w = jacobian * inverse_mass.asDiagonal() * jacobian.transpose();
  const Blocks blocks = {{0, 1, 0.0}, {1, 1, 0.0}, {2, 1, 0.0}, {3, 1, 0.0}};
  CoulombImpulses<double> solver;
  Eigen::VectorXd p = Eigen::VectorXd::Zero(4);
  ASSERT_TRUE(solver.Solve(w, Eigen::Vector4d::Constant(-1.0), Eigen::Vector4d::Zero(), blocks, 1e-12, &p));
  for (int c = 0; c < 4; ++c) EXPECT_NEAR(p[c], 0.25, 1e-6);  // the least impulses: the weight shared
  const Eigen::Vector3d dv = inverse_mass.asDiagonal() * jacobian.transpose() * p;
  EXPECT_NEAR(dv[0], 1.0, 1e-8);  // the box stops
  EXPECT_NEAR(dv[1], 0.0, 1e-12);
  EXPECT_NEAR(dv[2], 0.0, 1e-12);
  EXPECT_LE(solver.newton_iterations(), 3);
}

TEST(CoulombImpulses, JetDerivativesAreTheImplicitFunctionsAndMatchCentralDifferences) {
  // two coupled 3D contacts, one sticking and one sliding; derivatives along a rate, a target, the friction and a
  // Delassus entry
  Eigen::MatrixXd jacobian(6, 8);
  std::mt19937 random(3);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (Eigen::Index i = 0; i < jacobian.size(); ++i) jacobian.data()[i] = uniform(random);
  const Eigen::MatrixXd w0 = jacobian * jacobian.transpose();
  const Eigen::VectorXd u0 = (Eigen::VectorXd(6) << -1.0, 0.1, -0.05, -0.5, 1.5, 0.4).finished();
  const Eigen::VectorXd b0 = (Eigen::VectorXd(6) << 0.2, 0.0, 0.0, 0.0, 0.0, 0.0).finished();
  const double mu0 = 0.6;
  auto solve_double = [&](const Eigen::VectorXd& u, const Eigen::VectorXd& b, double mu, const Eigen::MatrixXd& w) {
    CoulombImpulses<double> solver;
    Eigen::VectorXd p = Eigen::VectorXd::Zero(6);
    EXPECT_TRUE(solver.Solve(w, u, b, {{0, 3, mu}, {3, 3, mu}}, 1e-13, &p));
    return p;
  };
  const Eigen::VectorXd p0 = solve_double(u0, b0, mu0, w0);
  ASSERT_LT(p0.segment(1, 2).norm(), 0.9 * mu0 * p0[0]);     // the first sticks
  ASSERT_NEAR(p0.segment(4, 2).norm(), mu0 * p0[3], 1e-12);  // the second slides

  VecX<Jet> u = u0.cast<Jet>(), b = b0.cast<Jet>();
  Eigen::Matrix<Jet, Eigen::Dynamic, Eigen::Dynamic> w = w0.cast<Jet>();
  u[0].v[0] = 1.0;
  b[0].v[1] = 1.0;
  const Jet mu(mu0, 2);
  w(1, 4).v[3] = 1.0;  // a symmetric pair of entries
  w(4, 1).v[3] = 1.0;
  CoulombImpulses<Jet> solver;
  VecX<Jet> p = VecX<Jet>::Zero(6);
  ASSERT_TRUE(solver.Solve(w, u, b, {{0, 3, mu}, {3, 3, mu}}, 1e-13, &p));
  const double h = 1e-6;
  Eigen::MatrixXd w_up = w0, w_down = w0;
  w_up(1, 4) += h, w_up(4, 1) += h, w_down(1, 4) -= h, w_down(4, 1) -= h;
  Eigen::VectorXd du = Eigen::VectorXd::Zero(6);
  du[0] = h;
  const Eigen::VectorXd differences[4] = {
      (solve_double(u0 + du, b0, mu0, w0) - solve_double(u0 - du, b0, mu0, w0)) / (2 * h),
      (solve_double(u0, b0 + du, mu0, w0) - solve_double(u0, b0 - du, mu0, w0)) / (2 * h),
      (solve_double(u0, b0, mu0 + h, w0) - solve_double(u0, b0, mu0 - h, w0)) / (2 * h),
      (solve_double(u0, b0, mu0, w_up) - solve_double(u0, b0, mu0, w_down)) / (2 * h)};
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(p[i].a, p0[i], 1e-12);
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(p[i].v[k], differences[k][i], 1e-6) << "row " << i << ", direction " << k;
  }
}

}  // namespace
}  // namespace tether
