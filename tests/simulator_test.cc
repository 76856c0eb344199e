// The simulator's contract: output grid, first and last rows, assembly of an inconsistent initial state,
// divergence reports.
#include "tether/dynamics/integration/simulator.h"

#include <gtest/gtest.h>

#include "test_scenes.h"
#include "tether/dynamics/model/errors.h"

namespace tether {
namespace {

using testing::Pendulum60;
using testing::Record;

TEST(Simulator, OutputsTheGridWithFirstAndLastRows) {
  const testing::Recording r = Record(Pendulum60("rk4", 1e-3, 0.0105), 4);
  // 11 steps (the last one shortened to land on 0.0105), rows at steps 0, 4, 8 and 11
  ASSERT_EQ(r.t.size(), 4u);
  EXPECT_DOUBLE_EQ(r.t[0], 0.0);
  EXPECT_DOUBLE_EQ(r.t[1], 0.004);
  EXPECT_DOUBLE_EQ(r.t[2], 0.008);
  EXPECT_DOUBLE_EQ(r.t[3], 0.0105);
}

TEST(Simulator, AssemblesAnInitialStateOffItsConstraints) {
  Model<double> model = Pendulum60();
  model.bodies[0].position[0] += 0.01;  // 1 cm off the rod
  model.bodies[0].velocity << 0.3, 0.3, 0.0;  // and moving across it
  std::vector<std::string> warnings;
  testing::Recording r;
  const RunReport report = Simulate<double>(model, {}, [&r](const Sample<double>& s) {
    r.constraint_error.push_back(s.constraint_error);
    r.v.push_back(s.v);
    r.q.push_back(s.q);
  });
  EXPECT_EQ(report.warnings.size(), 2u);
  EXPECT_LT(r.constraint_error[0], 1e-12);
  // the assembled velocity is tangent to the circle: v . q = 0
  EXPECT_NEAR(r.v[0].dot(r.q[0]), 0.0, 1e-12);
}

TEST(Simulator, RefusesAStateThatCannotBeAssembled) {
  // two rods from the origin of lengths 1 and 3 to the same particle cannot both hold
  Model<double> model = testing::SceneFromJson(R"({
    "bodies": [{"name": "p", "type": "particle", "mass": 1.0, "position": [1.0, 0.0]}],
    "constraints": [{"type": "distance", "bodies": ["world", "p"], "length": 1.0},
                    {"type": "distance", "bodies": ["world", "p"], "length": 3.0}]})");
  EXPECT_THROW(Record(model), InputError);
}

TEST(Simulator, ReportsDivergenceWithTimeAndConstraint) {
  Model<double> model = Pendulum60("euler", 1e-2, 10.0);
  model.stabilization.beta = 1e8;
  try {
    Record(model);
    FAIL() << "the run should have diverged";
  } catch (const SimulationDiverged& e) {
    EXPECT_GT(e.time(), 0.0);
    EXPECT_EQ(e.constraint(), 0);
    EXPECT_NE(std::string(e.what()).find("diverged"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tether
