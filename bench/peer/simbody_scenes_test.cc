// Simbody builds tether's mechanisms (simbody_models.h against tether_models.h): both run tightly, Simbody's
// Runge-Kutta-Merson at accuracy 1e-10 and tether's rk45 with the projection stabilization at tolerance 1e-10, and
// every body's centre of mass agrees after 1 s to 1e-7 m (measured 5e-11 to 8e-10) and has moved by more than 1 cm.
// The N-four-bar runs 0.7 s, up to just before its first singular pass, which Simbody's integrators do not cross on
// the parallelogram branch (bench/peer/README.md). A wrong axis, frame, inertia, motor or initial velocity moves the
// bodies by millimetres or more in that time.
#include <gtest/gtest.h>

#include <algorithm>
#include <ostream>
#include <string>
#include <vector>

#include "simbody_models.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/model/kinematics.h"
#include "tether_models.h"

namespace tether::bench {
namespace {

constexpr double kAgreement = 1e-7, kMoved = 0.01;  // m

struct Case {
  std::string name;
  Mechanism mechanism;
  int n;
  double duration;  // s
};

void PrintTo(const Case& c, std::ostream* out) { *out << c.name; }

class SimbodyScenes : public ::testing::TestWithParam<Case> {};

TEST_P(SimbodyScenes, MoveAsTetherScenesDo) {
  const Case c = GetParam();
  Model<double> model = TetherPeerScene(c.mechanism, c.n, true, c.duration);
  model.simulation.integrator = Integrator::kRk45;
  model.simulation.step = c.duration;
  model.simulation.tolerance = 1e-10;
  model.stabilization.method = Stabilization::kProjection;
  std::vector<Vec3<double>> start, end;
  Simulate<double>(model, RunOptions{}, [&](const Sample<double>& s) {
    std::vector<Vec3<double>>& centres = s.t == 0.0 ? start : end;
    for (const Body<double>& body : model.bodies) {
      centres.push_back(Translation(model.dimension, s.q.data() + body.q_offset));
    }
  });
  const std::vector<Vec3<double>> simbody =
      SimbodyScene(c.mechanism, c.n).Run({SimbodyIntegrator::kRungeKuttaMerson, 1e-10}, c.duration);
  ASSERT_EQ(simbody.size(), end.size());
  double moved = 0.0;
  for (size_t k = 0; k < end.size(); ++k) {
    EXPECT_LT((simbody[k] - end[k]).norm(), kAgreement) << c.name << ", body " << k;
    moved = std::max(moved, (end[k] - start[k]).norm());
  }
  EXPECT_GT(moved, kMoved) << c.name;
}

INSTANTIATE_TEST_SUITE_P(PeerScenes, SimbodyScenes,
                         ::testing::Values(Case{"hinge_chain10", Mechanism::kHingeChain, 10, 1.0},
                                           Case{"humanoid", Mechanism::kHumanoid, 0, 1.0},
                                           Case{"rssr", Mechanism::kRssr, 0, 1.0},
                                           Case{"four_bar10", Mechanism::kFourBar, 10, 0.7}),
                         [](const ::testing::TestParamInfo<Case>& info) { return info.param.name; });

}  // namespace
}  // namespace tether::bench
