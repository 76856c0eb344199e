// Quadratic drag (effects/drag.h) against closed forms, and its numbers as parameters against central differences.
//   falling from rest (gravity g, k = 1/2 rho C_d A):  v(t) = v_t tanh(g t / v_t),
//                                                      fallen(t) = v_t^2 / g ln cosh(g t / v_t),  v_t = sqrt(m g / k)
//   coasting (no gravity):                             |v|(t) = v0 / (1 + k v0 t / m), along the initial direction
#include <gtest/gtest.h>

#include <cmath>

#include "gradient_checks.h"
#include "test_scenes.h"

namespace tether {
namespace {

using nlohmann::json;

constexpr double kRho = 1.2, kCd = 0.47, kArea = 0.02, kMass = 0.5, kG = 9.81;
constexpr double kK = 0.5 * kRho * kCd * kArea;

json Ball(const json& velocity, const json& gravity) {
  return {{"dimension", 3},
          {"bodies",
           {{{"name", "ball"},
             {"type", "particle"},
             {"mass", kMass},
             {"position", {0.0, 0.0, 100.0}},
             {"velocity", velocity}}}},
          {"effects",
           {{{"type", "gravity"}, {"acceleration", gravity}},
            {{"type", "drag"}, {"body", "ball"}, {"density", kRho}, {"drag_coefficient", kCd}, {"area", kArea}}}},
          {"simulation", {{"integrator", "rk4"}, {"step", 1e-3}, {"duration", 4.0}}}};
}

TEST(Drag, AFallingBallApproachesItsTerminalSpeedAsTanh) {
  const Model<double> model = ParseScene(Ball({0.0, 0.0, 0.0}, {0.0, 0.0, -kG}), "fall.json").model;
  const testing::Recording run = testing::Record(model, 100);
  const double terminal = std::sqrt(kMass * kG / kK);
  ASSERT_GT(run.size(), 30u);
  for (size_t i = 0; i < run.size(); ++i) {
    const double t = run.t[i], x = kG * t / terminal;
    EXPECT_NEAR(run.v[i][2], -terminal * std::tanh(x), 1e-9 * terminal) << t;
    EXPECT_NEAR(100.0 - run.q[i][2], terminal * terminal / kG * std::log(std::cosh(x)), 1e-9 * terminal) << t;
    EXPECT_EQ(run.v[i][0], 0.0);
  }
  EXPECT_GT(-run.v.back()[2], 0.6 * terminal);  // well on the way: tanh(g t / v_t) at 4 s
}

TEST(Drag, ACoastingBallSlowsAsOneOverTimeAlongItsLine) {
  const double v0 = 13.0;
  const Model<double> model = ParseScene(Ball({3.0, -4.0, 12.0}, {0.0, 0.0, 0.0}), "coast.json").model;
  const testing::Recording run = testing::Record(model, 100);
  for (size_t i = 0; i < run.size(); ++i) {
    const double speed = v0 / (1.0 + kK * v0 * run.t[i] / kMass);
    EXPECT_NEAR(run.v[i].norm(), speed, 1e-9 * v0) << run.t[i];
    EXPECT_NEAR(run.v[i].normalized().dot(Eigen::Vector3d(3.0, -4.0, 12.0) / v0), 1.0, 1e-12);
  }
}

// A rod pinned at one end, swinging with drag at a point off its axis: every number of the drag is a parameter,
// and the loss gradient by Jets, by the adjoint and by central differences agree.
TEST(Drag, EveryNumberIsAParameter_JetsAndTheAdjointMatchCentralDifferences) {
  const json scene = {
      {"dimension", 2},
      {"bodies",
       {{{"name", "rod"},
         {"type", "rigid"},
         {"mass", 1.0},
         {"inertia", 0.08},
         {"position", {0.5, 0.0}},
         {"velocity", {0.0, -1.0}},
         {"angular_velocity", -2.0}}}},
      {"constraints", {{{"type", "pin"}, {"bodies", {"world", "rod"}}, {"points", {{0.0, 0.0}, {-0.5, 0.0}}}}}},
      {"effects",
       {{{"type", "gravity"}, {"acceleration", {0.0, -9.81}}},
        {{"type", "drag"},
         {"body", "rod"},
         {"point", {0.3, 0.05}},
         {"density", 1.2},
         {"drag_coefficient", 1.1},
         {"area", 0.05}}}},
      {"simulation", {{"integrator", "rk4"}, {"step", 1e-3}, {"duration", 1.0}}}};
  const Scene parsed = ParseScene(scene, "swing.json");
  const std::vector<std::string> pointers = {"/effects/1/density", "/effects/1/drag_coefficient", "/effects/1/area",
                                             "/effects/1/point/0", "/effects/1/point/1"};
  const ParameterSet parameters(parsed, pointers);
  const Observations data = MakeObservations("swing data", {"t", "rod.x", "rod.y", "rod.angle"},
                                             {{0.5, 0.2, -0.4, -1.2}, {1.0, -0.3, -0.4, -2.0}}, parsed.model);
  testing::ExpectGradientsAgree(parsed.model, parameters, data);
}

TEST(Drag, ItsNumbersAreCheckedAndItAddsNoEnergy) {
  json scene = Ball({1.0, 0.0, 0.0}, {0.0, 0.0, -kG});
  scene["effects"][1]["area"] = -0.1;
  EXPECT_THROW(
      {
        try {
          ParseScene(scene, "bad.json");
        } catch (const InputError& e) {
          EXPECT_NE(std::string(e.what()).find("bad.json: /effects/1/area: must be >= 0"), std::string::npos)
              << e.what();
          throw;
        }
      },
      InputError);
  scene["effects"][1].erase("area");
  EXPECT_THROW(ParseScene(scene, "bad.json"), InputError);
  const Model<double> model = ParseScene(Ball({1.0, 0.0, 0.0}, {0.0, 0.0, 0.0}), "coast.json").model;
  EXPECT_FALSE(ConservesEnergy(model));
  const testing::Recording run = testing::Record(model, 100);
  for (size_t i = 1; i < run.size(); ++i) EXPECT_LT(run.energy[i], run.energy[i - 1]);  // kinetic energy only falls
}

}  // namespace
}  // namespace tether
