// The stepping API in C++ (docs/stepping.md): a Stepper whose controls are set between steps (controls.h) makes the
// run of the scene with those values, bit for bit; controls are found by joint or pointer, with clear errors.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "test_scenes.h"
#include "tether/dynamics/integration/controls.h"
#include "tether/dynamics/integration/stepper.h"

namespace tether {
namespace {

using nlohmann::json;

json CartPole() {
  Scene scene = ReadSceneFile(TETHER_SOURCE_DIR "/scenes/cart_pole.json");
  scene.document["simulation"]["duration"] = 1.0;
  return scene.document;
}

TEST(Stepping, AControlHeldFromTheStartIsTheSceneWithThatValue) {
  json document = CartPole();
  Model<double> model = ParseScene(document, "cart_pole.json").model;
  std::vector<VecX<double>> stepped;
  Stepper<double> stepper(model, RunOptions{}, [&](const Sample<double>& s) { stepped.push_back(s.q); });
  const Control rail = FindControl(model, "rail");
  SetControl(rail, 2.0, &model);
  stepper.Start();
  while (stepper.Step()) {
  }
  document["effects"][1] = {{"type", "joint_torque"}, {"joint", "rail"}, {"value", 2.0}};
  std::vector<VecX<double>> simulated;
  Simulate<double>(ParseScene(document, "constant.json").model, RunOptions{},
                   [&](const Sample<double>& s) { simulated.push_back(s.q); });
  ASSERT_EQ(stepped.size(), simulated.size());
  for (size_t i = 0; i < stepped.size(); ++i) EXPECT_EQ(stepped[i], simulated[i]) << i;
  EXPECT_EQ(ControlValue(rail, model, 0.3), 2.0);
  EXPECT_EQ(stepper.time(), 1.0);
  EXPECT_EQ(stepper.steps_left(), 0);
}

TEST(Stepping, AControlChangedBetweenStepsActsFromTheNextStepOn) {
  // run A holds 2 N to t = 0.5 s and -1 N after; run B holds -1 N throughout but starts at A's state at 0.5 s
  Model<double> a = ParseScene(CartPole(), "cart_pole.json").model, b = a;
  VecX<double> end_a, end_b;
  Stepper<double> run_a(a, RunOptions{}, [&](const Sample<double>& s) { end_a = s.q; });
  Stepper<double> run_b(b, RunOptions{}, [&](const Sample<double>& s) { end_b = s.q; });
  SetControl(FindControl(a, "rail"), 2.0, &a);
  SetControl(FindControl(b, "rail"), -1.0, &b);
  run_a.Start();
  while (run_a.time() < 0.5 - 1e-9) run_a.Step();
  run_b.Restore(run_a.Save());
  SetControl(FindControl(a, "rail"), -1.0, &a);
  while (run_a.Step()) {
  }
  while (run_b.Step()) {
  }
  EXPECT_EQ(end_a, end_b);
  EXPECT_GT(std::abs(end_a[0]), 0.1);  // the cart moved
}

TEST(Stepping, TheLoopOfDocsSteppingRuns) {  // docs/stepping.md's C++ example, as written there
  tether::Model<double> model = tether::ReadSceneFile(TETHER_SOURCE_DIR "/scenes/cart_pole.json").model;
  double angle = 0.0;
  tether::Stepper<double> stepper(model, tether::RunOptions{}, [&](const tether::Sample<double>& s) {
    angle = s.coordinates[1];  // the samples as simulate's observer sees them: q, v, the joint coordinates...
  });
  const tether::Control rail = tether::FindControl(model, "rail");  // InputError naming the controls there are
  stepper.Start();                                                  // the sample at t = 0
  while (!stepper.done()) {
    tether::SetControl(rail, -5.0 * angle, &model);  // held from the next step on
    stepper.Step();                                  // one step of h; SimulationDiverged if it fails
  }
  EXPECT_EQ(stepper.time(), 3.0);
  EXPECT_NEAR(angle, 0.0, 1e-12);  // the pole hangs at rest, so the loop never pushes it off
  EXPECT_NEAR(ControlValue(rail, model, 3.0), -5.0 * angle, 1e-15);
}

TEST(Stepping, SavedControlsComeBackWithTheirSchedules) {
  Model<double> model = ParseScene(CartPole(), "cart_pole.json").model;
  const ControlSettings saved = SaveControls(model);
  const Control rail = FindControl(model, "/effects/1");
  SetControl(rail, 5.0, &model);
  EXPECT_TRUE(model.joint_torques[0].schedule.empty());
  RestoreControls(saved, &model);
  EXPECT_EQ(model.joint_torques[0].schedule.times.size(), 16u);
  EXPECT_EQ(ControlValue(rail, model, 0.5), 0.0);
}

TEST(Stepping, ControlsAreFoundByJointOrPointerWithClearErrors) {
  const Model<double> model = ParseScene(CartPole(), "cart_pole.json").model;
  const auto message = [&](const std::string& name) {
    try {
      FindControl(model, name);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("found");
  };
  EXPECT_EQ(message("rail"), "found");
  EXPECT_EQ(message("/effects/1"), "found");
  EXPECT_EQ(message("pivot"),
            "no control 'pivot': a control is a joint_torque's value or a joint_servo's target, named by its joint or "
            "/effects/K: /effects/1 (the joint_torque on 'rail')");
  EXPECT_NE(message("/effects/0").find("no control '/effects/0'"), std::string::npos);  // gravity is no control
  Model<double> copy = model;
  EXPECT_THROW(SetControl(FindControl(copy, "rail"), std::numeric_limits<double>::infinity(), &copy), InputError);
  const Model<double> none = testing::Pendulum60();
  EXPECT_THROW(
      {
        try {
          FindControl(none, "rail");
        } catch (const InputError& e) {
          EXPECT_NE(std::string(e.what()).find("and the scene has none"), std::string::npos) << e.what();
          throw;
        }
      },
      InputError);
}

}  // namespace
}  // namespace tether
