// Hard cases of conditioning (issue 7): mass ratios up to 1e6 and lengths from 1 mm to 100 m in one scene, a
// chain of 1000 particles.
//
// The double pendulums are checked against the reduced equations in the two angles phi1, phi2 from the downward
// vertical (Lagrange; Delta = phi1 - phi2, D = 2 m1 + m2 - m2 cos 2 Delta):
//   phi1'' = (-g (2 m1 + m2) sin phi1 - m2 g sin(phi1 - 2 phi2) - 2 sin Delta m2 (phi2'^2 l2 + phi1'^2 l1 cos Delta))
//            / (l1 D)
//   phi2'' = 2 sin Delta (phi1'^2 l1 (m1 + m2) + g (m1 + m2) cos phi1 + phi2'^2 l2 m2 cos Delta) / (l2 D)
// integrated by classical RK4 with 100 times tether's step, independently of tether.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/io/scene_reader.h"
#include "tether/dynamics/solvers/constrained_dynamics.h"
#include "tether/dynamics/solvers/workspace.h"

namespace tether {
namespace {

constexpr double kGravity = 9.81;

struct DoublePendulum {
  double m1, m2, l1, l2;
  double phi1, phi2;  // initial angles from the downward vertical, at rest
};

// The second bob's position at time `duration` from the reduced equations.
Eigen::Vector2d ReducedSecondBob(const DoublePendulum& p, double duration, double h) {
  using State = Eigen::Vector4d;  // phi1, phi2, phi1', phi2'
  auto rate = [&](const State& s) {
    const double d = s[0] - s[1], den = 2 * p.m1 + p.m2 - p.m2 * std::cos(2 * d);
    const double a1 = (-kGravity * (2 * p.m1 + p.m2) * std::sin(s[0]) - p.m2 * kGravity * std::sin(s[0] - 2 * s[1]) -
                       2 * std::sin(d) * p.m2 * (s[3] * s[3] * p.l2 + s[2] * s[2] * p.l1 * std::cos(d))) /
                      (p.l1 * den);
    const double a2 = 2 * std::sin(d) *
                      (s[2] * s[2] * p.l1 * (p.m1 + p.m2) + kGravity * (p.m1 + p.m2) * std::cos(s[0]) +
                       s[3] * s[3] * p.l2 * p.m2 * std::cos(d)) /
                      (p.l2 * den);
    return State(s[2], s[3], a1, a2);
  };
  State s(p.phi1, p.phi2, 0.0, 0.0);
  const int steps = static_cast<int>(std::lround(duration / h));
  for (int k = 0; k < steps; ++k) {
    const State k1 = rate(s), k2 = rate(s + 0.5 * h * k1), k3 = rate(s + 0.5 * h * k2), k4 = rate(s + h * k3);
    s += h / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4);
  }
  return {p.l1 * std::sin(s[0]) + p.l2 * std::sin(s[1]), -p.l1 * std::cos(s[0]) - p.l2 * std::cos(s[1])};
}

Model<double> DoublePendulumScene(const DoublePendulum& p, double step, double duration) {
  const Eigen::Vector2d x1(p.l1 * std::sin(p.phi1), -p.l1 * std::cos(p.phi1));
  const Eigen::Vector2d x2 = x1 + Eigen::Vector2d(p.l2 * std::sin(p.phi2), -p.l2 * std::cos(p.phi2));
  const nlohmann::json scene = {
      {"dimension", 2},
      {"bodies", {{{"name", "p1"}, {"type", "particle"}, {"mass", p.m1}, {"position", {x1.x(), x1.y()}}},
                  {{"name", "p2"}, {"type", "particle"}, {"mass", p.m2}, {"position", {x2.x(), x2.y()}}}}},
      {"constraints", {{{"type", "distance"}, {"bodies", {"world", "p1"}}, {"length", p.l1}},
                       {{"type", "distance"}, {"bodies", {"p1", "p2"}}, {"length", p.l2}}}},
      {"effects", {{{"type", "gravity"}, {"acceleration", {0.0, -kGravity}}}}},
      {"simulation", {{"integrator", "rk4"}, {"step", step}, {"duration", duration}}}};
  return ParseScene(scene, "double_pendulum.json").model;
}

struct Case {
  const char* name;
  DoublePendulum pendulum;
  double step, duration, tolerance;  // tolerance on the second bob's position, relative to l1 + l2
};

class DoublePendulumConditioning : public ::testing::TestWithParam<Case> {};

TEST_P(DoublePendulumConditioning, MatchesTheReducedEquations) {
  const Case& c = GetParam();
  const Model<double> model = DoublePendulumScene(c.pendulum, c.step, c.duration);
  Eigen::Vector2d end = Eigen::Vector2d::Zero();
  double worst = 0.0;
  Simulate<double>(model, RunOptions{}, [&](const Sample<double>& s) {
    end = s.q.segment<2>(2);
    worst = std::max(worst, s.constraint_error);
  });
  const Eigen::Vector2d expected = ReducedSecondBob(c.pendulum, c.duration, c.step / 100);
  const double size = c.pendulum.l1 + c.pendulum.l2;
  EXPECT_LT((end - expected).norm() / size, c.tolerance) << c.name << ": " << end.transpose() << " vs "
                                                         << expected.transpose();
  EXPECT_LT(worst / size, c.tolerance) << c.name;
}

INSTANTIATE_TEST_SUITE_P(
    HardCases, DoublePendulumConditioning,
    ::testing::Values(Case{"equal", {1.0, 1.0, 1.0, 1.0, 2.0, 1.0}, 1e-3, 2.0, 1e-8},
                      // a light knee under a heavy bob, released stretched: the rods stay nearly collinear (a
                      // singular configuration) while the knee oscillates across them at about
                      // sqrt(2 g m2 / (m1 l)) = 4.4e3 rad/s, so rk4 needs h omega < 2.8: h = 1e-4. (Released
                      // bent, the knee snaps straight like a whip at t = 0.41 s, which no fixed step follows.)
                      Case{"light_then_heavy_1e6", {1e-3, 1e3, 1.0, 1.0, 1.0, 1.0}, 1e-4, 1.0, 1e-8},
                      Case{"heavy_then_light_1e6", {1e3, 1e-3, 1.0, 1.0, 2.0, 1.0}, 1e-3, 2.0, 1e-8},
                      Case{"long_then_short_1e5", {1.0, 1.0, 100.0, 1e-3, 0.5, 1.0}, 1e-4, 1.0, 1e-8},
                      Case{"short_then_long_1e5", {1.0, 1.0, 1e-3, 100.0, 1.0, 0.5}, 1e-4, 1.0, 1e-8}),
    [](const ::testing::TestParamInfo<Case>& info) { return std::string(info.param.name); });

// 1000 particles on 1 mm links (a 1 m chain) falling from horizontal for 50 ms: the sparse KKT path keeps the
// links to rounding and the energy to the integrator's accuracy.
TEST(LongChain, ThousandParticlesHoldTheirLinksAndEnergy) {
  constexpr int kParticles = 1000;
  const double link = 1e-3;
  nlohmann::json bodies = nlohmann::json::array(), constraints = nlohmann::json::array();
  for (int k = 0; k < kParticles; ++k) {
    bodies.push_back({{"name", "p" + std::to_string(k)}, {"type", "particle"}, {"mass", 1e-3},
                      {"position", {(k + 1) * link, 0.0}}});
    const std::string previous = k == 0 ? std::string("world") : "p" + std::to_string(k - 1);
    constraints.push_back({{"type", "distance"}, {"bodies", {previous, "p" + std::to_string(k)}}, {"length", link}});
  }
  const nlohmann::json scene = {{"dimension", 2}, {"bodies", bodies}, {"constraints", constraints},
                                {"effects", {{{"type", "gravity"}, {"acceleration", {0.0, -kGravity}}}}},
                                {"simulation", {{"integrator", "rk4"}, {"step", 1e-4}, {"duration", 0.05}}}};
  const Model<double> model = ParseScene(scene, "chain1000.json").model;
  double worst = 0.0, energy0 = NAN, drift = 0.0, lowest = 0.0;
  Simulate<double>(model, RunOptions{}, [&](const Sample<double>& s) {
    if (std::isnan(energy0)) energy0 = s.energy;
    worst = std::max(worst, s.constraint_error);
    drift = std::max(drift, std::abs(s.energy - energy0));
    lowest = std::min(lowest, s.q.minCoeff());
  });
  EXPECT_LT(worst, 1e-9 * link * kParticles);
  EXPECT_LT(drift, 1e-6 * kGravity * 1.0);  // against the chain's weight (1 kg) times 1 m
  EXPECT_LT(lowest, -1e-3);                  // it did fall
}

// A rod hanging from a universal joint (its pin and the angle between the world's x axis and the rod's y axis),
// and the same joint split into two hinges through an intermediate body of 1e-6 of the rod's mass and inertia, as
// `tether import --split-joints` makes it. The light body dominates its rows' diagonals of S, and their pivot
// ratios d_i / S_ii fall below kNearSingularPivotRatio, yet nothing is near a singular configuration: read
// against the rows' smallest body shares (schur_solver.h, "Light bodies") the solver sees no near-singular
// configuration and solves S itself, the split run retakes no step, and it moves as the universal joint does.
nlohmann::json HangingRod(bool split) {
  const nlohmann::json rod = {{"name", "rod"},
                              {"type", "rigid"},
                              {"mass", 2.0},
                              {"inertia", {0.17, 0.17, 0.01}},
                              {"position", {0, 0, -0.5}},
                              {"velocity", {-1.0, 1.5, 0.0}},
                              {"angular_velocity", {3.0, 2.0, 0.0}}};
  const nlohmann::json top = {{0, 0, 0}, {0, 0, 0.5}};  // the pivot, in the world and on the rod
  nlohmann::json scene = {
      {"dimension", 3},
      {"effects", nlohmann::json::array({{{"type", "gravity"}, {"acceleration", {0.0, 0.0, -kGravity}}}})},
      {"simulation", {{"integrator", "rk4"}, {"step", 1e-3}, {"duration", 1.0}}}};
  if (!split) {
    scene["bodies"] = nlohmann::json::array({rod});
    scene["constraints"] = nlohmann::json::array(
        {{{"type", "universal"}, {"bodies", {"world", "rod"}}, {"points", top}, {"axes", {{1, 0, 0}, {0, 1, 0}}}}});
    return scene;
  }
  const nlohmann::json link = {{"name", "link"},        {"type", "rigid"},
                               {"mass", 2e-6},          {"inertia", {1.2e-7, 1.2e-7, 1.2e-7}},
                               {"position", {0, 0, 0}}, {"angular_velocity", {3.0, 0.0, 0.0}}};
  // the rod first: its coordinates where the universal scene has them
  scene["bodies"] = nlohmann::json::array({rod, link});
  scene["constraints"] =
      nlohmann::json::array({{{"type", "hinge"}, {"bodies", {"world", "link"}}, {"axis", {1, 0, 0}}},
                             {{"type", "hinge"}, {"bodies", {"link", "rod"}}, {"points", top}, {"axis", {0, 1, 0}}}});
  return scene;
}

TEST(LightBodies, ASplitJointIsNoSingularConfiguration) {
  const Model<double> model = ParseScene(HangingRod(true), "split.json").model;
  RunReport report;
  const State<double> start = AssembledInitialState(model, &report);
  Workspace<double> ws(model, start.q);
  VecX<double> a(start.v.size());
  ASSERT_TRUE(ComputeAcceleration(model, 0.0, start.q, start.v, &ws, &a));
  EXPECT_FALSE(ws.solver->saw_near_singular());
  EXPECT_FALSE(ws.solver->starts_regularized());  // S itself was solved

  VecX<double> universal, split;
  const RunReport whole = Simulate<double>(ParseScene(HangingRod(false), "universal.json").model, RunOptions{},
                                           [&](const Sample<double>& s) { universal = s.q.head<7>(); });
  const RunReport through_link = Simulate<double>(ParseScene(HangingRod(true), "split.json").model, RunOptions{},
                                                  [&](const Sample<double>& s) { split = s.q.head<7>(); });
  EXPECT_EQ(whole.retaken_steps, 0);
  EXPECT_EQ(through_link.retaken_steps, 0);
  EXPECT_GT((universal.head<3>() - Vec3<double>(0, 0, -0.5)).norm(), 0.1);  // it swung
  EXPECT_LT((split - universal).norm(), 1e-6);
}

}  // namespace
}  // namespace tether
