// The residuals of identification and fitting as functions of the unknowns (tuning/src/shooting_problem.h): their
// Jacobian, taken segment by segment by Jets over the unknowns each segment depends on, against central
// differences of the residuals themselves, for the acrobot with multiple shooting (its segment start states among
// the unknowns, held to the constraints by their own rows), an inequality target, smoothing and effort; the
// effort rows against the integral they stand for.
#include "shooting_problem.h"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "tether/dynamics/io/scene_reader.h"

namespace tether {
namespace {

struct Acrobot {
  Scene scene = ReadSceneFile(std::string(TETHER_SOURCE_DIR) + "/scenes/acrobot.json");
  ParameterSet parameters{scene, {"/effects/1/schedule/values/*"}};
  std::vector<Observations> recordings;
  IdentifySettings settings;

  Acrobot() {
    scene.model.simulation.step = 0.01;
    std::mt19937 random(7);
    std::uniform_real_distribution<double> torque(-3.0, 3.0);
    for (double& value : scene.model.joint_torques[0].schedule.values) value = torque(random);
    settings.smooth = 0.5;
    settings.effort = 0.2;
    settings.inequalities = {{"tip.y", 1.0, 4.3, true, "--at-least tip.y=1@4.3"},
                             {"elbow.omega", 0.5, 5.0, false, "--at-most elbow.omega=0.5@5"}};
  }
};

TEST(ShootingProblem, JacobianBySegmentsMatchesCentralDifferences) {
  Acrobot acrobot;
  acrobot.settings.segments = 4;
  const ShootingProblem problem(acrobot.scene.model, acrobot.parameters, acrobot.recordings, acrobot.settings,
                                ShootingProblem::StartRows::kOnTheConstraints);
  ASSERT_EQ(problem.Unknowns(), 41 + 3 * 12);
  ASSERT_EQ(problem.ContinuityCount(), 2 * 3 * 12);  // the gaps, then the starts' distances to the constraints
  std::vector<double> x = problem.Start();
  // segments that do not join, starting off the constraints
  for (size_t i = 41; i < x.size(); ++i) x[i] += 0.01 * std::sin(3.0 * i);
  Eigen::VectorXd r;
  Eigen::MatrixXd jacobian;
  ASSERT_TRUE(problem.Evaluate(x, &r, &jacobian));
  ASSERT_EQ(r.size(), problem.FirstConstraintRow() + 2);
  EXPECT_GT(r.segment(problem.DataCount() + 3 * 12, 3 * 12).lpNorm<Eigen::Infinity>(), 1e-3);  // off the constraints
  const double h = 1e-6;
  double worst = 0.0;
  for (int j = 0; j < problem.Unknowns(); ++j) {
    std::vector<double> plus = x, minus = x;
    plus[j] += h;
    minus[j] -= h;
    Eigen::VectorXd rp, rm;
    ASSERT_TRUE(problem.Evaluate(plus, &rp, nullptr));
    ASSERT_TRUE(problem.Evaluate(minus, &rm, nullptr));
    const Eigen::VectorXd central = (rp - rm) / (2 * h);
    worst = std::max(worst, (central - jacobian.col(j)).lpNorm<Eigen::Infinity>() / (1.0 + central.lpNorm<Eigen::Infinity>()));
  }
  EXPECT_LT(worst, 1e-6);
}

// A segment continues the joint coordinates of the whole run: started from the states of one run, the segments
// give the joint angles that run gives (before the fix, a segment measured them from its own start).
TEST(ShootingProblem, SegmentsContinueTheJointCoordinatesOfTheRun) {
  Acrobot acrobot;
  acrobot.settings.inequalities.clear();
  acrobot.recordings.push_back(MakeObservations("angles", {"t", "shoulder.angle", "elbow.angle"},
                                                {{1.3, 0.0, 0.0}, {2.6, 0.0, 0.0}, {4.9, 0.0, 0.0}},
                                                acrobot.scene.model));
  Eigen::VectorXd whole, pieces;
  acrobot.settings.segments = 1;
  const ShootingProblem one(acrobot.scene.model, acrobot.parameters, acrobot.recordings, acrobot.settings);
  ASSERT_TRUE(one.Evaluate(one.Start(), &whole, nullptr));
  acrobot.settings.segments = 4;
  const ShootingProblem four(acrobot.scene.model, acrobot.parameters, acrobot.recordings, acrobot.settings);
  ASSERT_TRUE(four.Evaluate(four.Start(), &pieces, nullptr));
  ASSERT_EQ(one.DataCount(), 6);
  ASSERT_EQ(four.DataCount(), 6);
  EXPECT_GT(std::abs(whole[4]), 0.1);  // the shoulder has turned: a segment's own zero would show
  // a segment's start is moved onto the constraints (the run's drift, about 1e-8 m, is taken out)
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(pieces[i], whole[i], 1e-6) << i;
  // started from one run, the segments join and start on the constraints: every continuity row vanishes (to the
  // run's own drift off the constraints, about 2e-6 here)
  const ShootingProblem held(acrobot.scene.model, acrobot.parameters, acrobot.recordings, acrobot.settings,
                             ShootingProblem::StartRows::kOnTheConstraints);
  ASSERT_TRUE(held.Evaluate(held.Start(), &pieces, nullptr));
  ASSERT_EQ(held.ContinuityCount(), 2 * 3 * 12);
  EXPECT_LT(pieces.segment(held.DataCount(), held.ContinuityCount()).lpNorm<Eigen::Infinity>(), 1e-5);
}

// With kOnTheConstraints a segment's end is moved onto the constraints before it is compared with the next start
// (shooting_problem.h). Each segment started from the previous one's end so moved, every continuity row and every
// start's distance to the constraints vanish to rounding; compared with the end itself, which a stabilized run
// leaves off the constraints by its drift, the two sets of rows could not both be met (the reach's gaps stalled at
// the drift).
TEST(ShootingProblem, SegmentsStartedFromTheEndsMovedOntoTheConstraintsMeetEveryContinuityRow) {
  Acrobot acrobot;
  acrobot.settings.segments = 4;
  const ShootingProblem problem(acrobot.scene.model, acrobot.parameters, acrobot.recordings, acrobot.settings,
                                ShootingProblem::StartRows::kOnTheConstraints);
  const int first = problem.DataCount(), starts = 3 * 12;
  ASSERT_EQ(problem.Unknowns(), 41 + starts);
  std::vector<double> x = problem.Start();
  Eigen::VectorXd r;
  ASSERT_TRUE(problem.Evaluate(x, &r, nullptr));
  EXPECT_GT(r.segment(first, 2 * starts).lpNorm<Eigen::Infinity>(), 1e-8);  // one run's states: its drift
  // each start moved by its gap (end - start, an offset and a velocity, as the unknowns are), boundary by boundary
  for (int pass = 0; pass < 4; ++pass) {
    for (int i = 0; i < starts; ++i) x[41 + i] += r[first + i];
    ASSERT_TRUE(problem.Evaluate(x, &r, nullptr));
  }
  EXPECT_LT(r.segment(first, 2 * starts).lpNorm<Eigen::Infinity>(), 1e-11);
}

// A 3D hinge's angle is continuous across segments however far their starts are from the first guess: a rotor
// built at rest (the first guess's run never turns), its segments started as if spinning at 8 rad/s, measures 8 rad
// after 1 s. Each segment's angle takes the branch nearest the previous segment's end; taken from the first guess,
// the last segment (starting at 6 rad, past pi from the guess's 0) measured 8 - 2 pi.
TEST(ShootingProblem, AHingeAngleContinuesAcrossSegmentsPastPi) {
  const nlohmann::json document = {
      {"dimension", 3},
      {"bodies", {{{"name", "rotor"}, {"type", "rigid"}, {"mass", 1.0}, {"inertia", {0.5, 0.5, 0.5}},
                   {"position", {0.0, 0.0, 0.0}}}}},
      {"constraints", {{{"type", "hinge"}, {"name", "axle"}, {"bodies", {"world", "rotor"}},
                        {"points", {{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}}}, {"axis", {0.0, 0.0, 1.0}}}}},
      {"effects", {{{"type", "joint_torque"}, {"joint", "axle"}, {"value", 0.0}}}},
      {"simulation", {{"integrator", "rk4"}, {"step", 0.01}, {"duration", 1.0}}}};
  const Scene scene = ParseScene(document, "rotor.json");
  const ParameterSet parameters(scene, {"/effects/0/value"});
  const std::vector<Observations> recordings = {
      MakeObservations("angle", {"t", "axle.angle"}, {{1.0, 0.0}}, scene.model)};
  IdentifySettings settings;
  settings.segments = 4;
  const ShootingProblem problem(scene.model, parameters, recordings, settings);
  std::vector<double> x = problem.Start();
  ASSERT_EQ(x.size(), 1u + 3 * 12);
  const double omega = 8.0;
  for (int k = 1; k < 4; ++k) {  // offset: the turn omega t_k about z; velocity: omega about z
    x[1 + (k - 1) * 12 + 5] = omega * 0.25 * k;
    x[1 + (k - 1) * 12 + 6 + 5] = omega;
  }
  Eigen::VectorXd r;
  ASSERT_TRUE(problem.Evaluate(x, &r, nullptr));
  EXPECT_NEAR(r[0], omega, 1e-9);  // the angle at 1 s minus the observed 0
}

// 1/2 (r1^2 + r2^2) summed over the effort rows is W int_0^D tau^2 dt, here by a fine midpoint rule.
TEST(ShootingProblem, EffortRowsAreTheIntegralOfTheSquaredTorque) {
  Acrobot acrobot;
  acrobot.settings.smooth = 0.0;
  acrobot.settings.segments = 1;
  acrobot.settings.inequalities.resize(1);
  const ShootingProblem problem(acrobot.scene.model, acrobot.parameters, acrobot.recordings, acrobot.settings);
  Eigen::VectorXd r;
  ASSERT_TRUE(problem.Evaluate(problem.Start(), &r, nullptr));
  const Eigen::VectorXd effort = r.segment(problem.DataCount(), problem.PenaltyCount());
  const Schedule<double>& schedule = acrobot.scene.model.joint_torques[0].schedule;
  const int n = 200000;
  double integral = 0.0;
  for (int i = 0; i < n; ++i) {
    const double t = 5.0 * (i + 0.5) / n;
    size_t k = 0;
    while (k + 2 < schedule.times.size() && schedule.times[k + 1] <= t) ++k;
    const double w = (t - schedule.times[k]) / (schedule.times[k + 1] - schedule.times[k]);
    const double tau = (1 - w) * schedule.values[k] + w * schedule.values[k + 1];
    integral += tau * tau * 5.0 / n;
  }
  EXPECT_NEAR(0.5 * effort.squaredNorm(), acrobot.settings.effort * integral, 1e-8 * integral);
}

}  // namespace
}  // namespace tether
