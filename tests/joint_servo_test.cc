// The joint servo (effects/joint_servo.h) against an independent integration of its one-coordinate equation
//   I x'' = tau(t, x, x'),   tau = kp (r(t) - x) + kd (r' - x'), or L tanh(that / L) with a limit,
// on a hinge and on a prismatic joint; its potential energy conserved where the servo conserves it; every number a
// parameter, Jets and the adjoint against central differences; and its input checked.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "gradient_checks.h"
#include "test_scenes.h"
#include "tether/dynamics/effects/schedule.h"

namespace tether {
namespace {

using nlohmann::json;

constexpr double kInertia = 0.2;  // the rod's about its centre, where it is pinned

// A planar rod pinned to the world at its centre (no gravity) and a servo on the pin.
json ServoedRod(const json& servo) {
  json s = servo;
  s["type"] = "joint_servo";
  s["joint"] = "pin";
  return {{"dimension", 2},
          {"bodies",
           {{{"name", "rod"}, {"type", "rigid"}, {"mass", 1.0}, {"inertia", kInertia}, {"position", {0.0, 0.0}}}}},
          {"constraints",
           {{{"type", "pin"}, {"name", "pin"}, {"bodies", {"world", "rod"}}, {"points", {{0.0, 0.0}, {0.0, 0.0}}}}}},
          {"effects", {s}},
          {"simulation", {{"integrator", "rk4"}, {"step", 1e-3}, {"duration", 3.0}}}};
}

// x(t) of I x'' = torque(t, x, x') from rest at 0, by rk4 with step h: the reference.
std::vector<double> Integrate1d(const std::function<double(double, double, double)>& torque, double inertia, double h,
                                int steps) {
  std::vector<double> x = {0.0};
  double p = 0.0, w = 0.0, t = 0.0;
  const auto f = [&](double tt, double pp, double ww) { return torque(tt, pp, ww) / inertia; };
  for (int k = 0; k < steps; ++k) {
    const double a1 = f(t, p, w), p1 = w;
    const double a2 = f(t + h / 2, p + h / 2 * p1, w + h / 2 * a1), p2 = w + h / 2 * a1;
    const double a3 = f(t + h / 2, p + h / 2 * p2, w + h / 2 * a2), p3 = w + h / 2 * a2;
    const double a4 = f(t + h, p + h * p3, w + h * a3), p4 = w + h * a3;
    p += h / 6 * (p1 + 2 * p2 + 2 * p3 + p4);
    w += h / 6 * (a1 + 2 * a2 + 2 * a3 + a4);
    t += h;
    x.push_back(p);
  }
  return x;
}

TEST(JointServo, ASaturatedServoWithAScheduledTargetFollowsItsEquation) {
  const Schedule<double> target{{0.0, 1.0, 2.0}, {0.0, 0.8, 0.3}};
  const double kp = 5.0, kd = 0.4, rate = 0.1, limit = 0.9;
  const json servo = {{"kp", kp},
                      {"kd", kd},
                      {"target_rate", rate},
                      {"limit", limit},
                      {"schedule", {{"times", target.times}, {"values", target.values}}}};
  const testing::Recording run = testing::Record(ParseScene(ServoedRod(servo), "servo.json").model, 100);
  const auto torque = [&](double t, double x, double w) {
    return limit * std::tanh((kp * (ScheduleValue(target, t) - x) + kd * (rate - w)) / limit);
  };
  const std::vector<double> reference = Integrate1d(torque, kInertia, 1e-4, 30000);
  ASSERT_EQ(run.size(), 31u);
  double largest = 0.0;
  for (size_t i = 0; i < run.size(); ++i) {
    EXPECT_NEAR(run.q[i][2], reference[1000 * i], 1e-9) << run.t[i];
    largest = std::max(largest, std::abs(run.q[i][2]));
  }
  EXPECT_GT(largest, 0.3);  // it moved: towards 0.8, held back by the limit (a torque of at most 0.9 N m)
  EXPECT_FALSE(ConservesEnergy(ParseScene(ServoedRod(servo), "servo.json").model));
}

TEST(JointServo, OnAPrismaticJointItPushesAlongTheAxis) {
  const double mass = 2.0, kp = 30.0, kd = 3.0, target = 0.25;
  const json scene = {
      {"dimension", 3},
      {"bodies",
       {{{"name", "cart"}, {"type", "rigid"}, {"mass", mass}, {"inertia", {0.1, 0.1, 0.1}}, {"position", {0, 0, 1}}}}},
      {"constraints",
       {{{"type", "prismatic"},
         {"name", "rail"},
         {"bodies", {"world", "cart"}},
         {"points", {{0, 0, 1}, {0, 0, 0}}},
         {"axis", {0.6, 0.8, 0.0}}}}},
      {"effects", {{{"type", "joint_servo"}, {"joint", "rail"}, {"kp", kp}, {"kd", kd}, {"target", target}}}},
      {"simulation", {{"integrator", "rk4"}, {"step", 1e-3}, {"duration", 2.0}}}};
  const testing::Recording run = testing::Record(ParseScene(scene, "rail.json").model, 100);
  // the damped oscillator from rest: x = r (1 - e^(-z w t) (cos(w_d t) + z w / w_d sin(w_d t)))
  const double w = std::sqrt(kp / mass), z = kd / (2 * std::sqrt(kp * mass)), wd = w * std::sqrt(1 - z * z);
  for (size_t i = 0; i < run.size(); ++i) {
    const double t = run.t[i];
    const double x = target * (1 - std::exp(-z * w * t) * (std::cos(wd * t) + z * w / wd * std::sin(wd * t)));
    EXPECT_NEAR(run.q[i][0], 0.6 * x, 1e-10) << t;
    EXPECT_NEAR(run.q[i][1], 0.8 * x, 1e-10) << t;
  }
}

TEST(JointServo, WithoutKdOrATargetRateItConservesItsPotentialEnergy) {
  for (const double limit : {0.0, 0.7}) {
    json servo = {{"kp", 4.0}, {"kd", 0.0}, {"target", 1.2}};
    if (limit > 0.0) servo["limit"] = limit;
    const Model<double> model = ParseScene(ServoedRod(servo), "spring.json").model;
    EXPECT_TRUE(ConservesEnergy(model));
    const testing::Recording run = testing::Record(model, 10);
    EXPECT_GT(run.energy[0], 0.1);
    for (size_t i = 0; i < run.size(); ++i) EXPECT_NEAR(run.energy[i], run.energy[0], 1e-10) << limit;
  }
}

TEST(JointServo, EveryNumberIsAParameter_JetsAndTheAdjointMatchCentralDifferences) {
  const json servo = {{"kp", 5.0},
                      {"kd", 0.4},
                      {"target_rate", 0.1},
                      {"limit", 0.9},
                      {"schedule", {{"times", {0.0, 1.0}}, {"values", {0.2, 0.8}}}}};
  const Scene parsed = ParseScene(ServoedRod(servo), "servo.json");
  const std::vector<std::string> pointers = {"/effects/0/kp", "/effects/0/kd", "/effects/0/target_rate",
                                             "/effects/0/limit", "/effects/0/schedule/values/1"};
  const ParameterSet parameters(parsed, pointers);
  const Observations data =
      MakeObservations("servo data", {"t", "rod.angle"}, {{0.5, 0.1}, {1.0, 0.5}, {1.5, 0.6}}, parsed.model);
  testing::ExpectGradientsAgree(parsed.model, parameters, data);
}

TEST(JointServo, ItsInputIsChecked) {
  const auto message = [](const json& servo) {
    try {
      ParseScene(ServoedRod(servo), "bad.json");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(message({{"kp", -1.0}, {"kd", 0.0}, {"target", 0.0}}), "bad.json: /effects/0/kp: must be >= 0, got -1");
  EXPECT_NE(message({{"kd", 0.0}, {"target", 0.0}}).find("/effects/0: missing required key 'kp'"), std::string::npos);
  EXPECT_NE(message({{"kp", 1.0}, {"kd", 0.0}}).find("give exactly one of 'target' and 'schedule'"), std::string::npos);
  EXPECT_NE(message({{"kp", 1.0}, {"kd", 0.0}, {"target", 0.0}, {"limit", 0.0}}).find("/effects/0/limit: must be > 0"),
            std::string::npos);
  EXPECT_NE(message({{"kp", 1.0}, {"kd", 0.0}, {"target", 0.0}, {"gain", 1.0}}).find("/effects/0/gain"),
            std::string::npos);
}

}  // namespace
}  // namespace tether
