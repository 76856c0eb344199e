// The peer benchmark compares like with like: tether_models.h and mujoco_models.h build the same mechanisms.
// Both engines start from the same state (to 1e-12 m) and, with MuJoCo's constraints made nearly rigid (h = 1e-4,
// solref at its floor of two steps, solimp 0.9999) and rk4 / RK4, move alike: after 2 s crank0's angle agrees to
// 1e-7 rad (measured 7.5e-9), after 0.5 s of falling every mass of a 10-particle chain to 4e-6 m (measured
// 4.2e-7) in either MuJoCo formulation. A wrong axis, sign, inertia or initial velocity in either scene moves
// these by centimetres or radians; with MuJoCo's default softness the motions part by 2 cm and 0.02 rad.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "mujoco_models.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether_models.h"

namespace tether::bench {
namespace {

constexpr double kFourBarSeconds = 2.0, kFourBarAngleAgreement = 1e-7;  // rad (measured 7.5e-9)
constexpr double kChainSeconds = 0.5, kChainAgreement = 4e-6;           // m (measured 4.2e-7)
constexpr int kChainMasses = 10;
// MuJoCo with nearly rigid constraints: h = 1e-4, solref at its floor of two steps, solimp (0.9999, 1)
constexpr MujocoSettings kRigid{1e-4, 2e-4, 0.9999};

// tether's final coordinates after `seconds` with rk4
VecX<double> TetherAfter(Mechanism mechanism, int n, double seconds) {
  const Model<double> model = TetherPeerScene(mechanism, n, true, seconds);
  VecX<double> q;
  Simulate<double>(model, RunOptions{}, [&q](const Sample<double>& s) { q = s.q; });
  return q;
}

// MuJoCo's state after `seconds` with RK4, positions computed
MjDataPtr MujocoAfter(const mjModel& model, MujocoScene scene, double seconds) {
  MjDataPtr data = InitialMujocoState(model, scene);
  for (int k = 0; k < std::lround(seconds / model.opt.timestep); ++k) mj_step(&model, data.get());
  mj_forward(&model, data.get());
  return data;
}

TEST(PeerScenes, FourBarsTurnAlike) {
  const MjModelPtr model = LoadMujoco(MujocoXml(MujocoScene::kFourBar, 1, true, kRigid));
  const MjDataPtr data = MujocoAfter(*model, MujocoScene::kFourBar, kFourBarSeconds);
  EXPECT_EQ(MujocoWarnings(*data), "");
  // tether's crank0 angle is measured from +x in the x-y plane; MuJoCo's hinge turns crank0 from +z towards +x
  const double tether_angle = TetherAfter(Mechanism::kFourBar, 1, kFourBarSeconds)[2];
  EXPECT_NEAR(tether_angle, M_PI / 2 - data->qpos[0], kFourBarAngleAgreement);
  EXPECT_GT(std::abs(tether_angle - M_PI / 2), 0.5);  // it has moved: the comparison means something
}

void ExpectChainsFallAlike(MujocoScene scene) {
  const MjModelPtr model = LoadMujoco(MujocoXml(scene, kChainMasses, true, kRigid));
  const MujocoProbe probe(*model, scene);
  const MjDataPtr start = InitialMujocoState(*model, scene);
  const MjDataPtr end = MujocoAfter(*model, scene, kChainSeconds);
  EXPECT_EQ(MujocoWarnings(*end), "");
  const Model<double> tether = TetherPeerScene(Mechanism::kChain, kChainMasses, true, kChainSeconds);
  const VecX<double> q = TetherAfter(Mechanism::kChain, kChainMasses, kChainSeconds);
  for (int i = 0; i < kChainMasses; ++i) {
    EXPECT_LT((probe.Mass(*start, i) - tether.bodies[i].position).norm(), 1e-12) << "mass " << i << " at t = 0";
    EXPECT_LT((probe.Mass(*end, i) - q.segment<3>(3 * i)).norm(), kChainAgreement) << "mass " << i;
  }
  EXPECT_LT(q[3 * kChainMasses - 1], -0.5);  // the tip has fallen
}

TEST(PeerScenes, ChainsOfSlidesFallAsTetherChainsDo) { ExpectChainsFallAlike(MujocoScene::kChainOfSlides); }

TEST(PeerScenes, ChainsOfFreeBodiesFallAsTetherChainsDo) { ExpectChainsFallAlike(MujocoScene::kChainOfFreeBodies); }

}  // namespace
}  // namespace tether::bench
