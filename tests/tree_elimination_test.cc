// The tree elimination (tree_elimination.h) against the Schur path it stands in for: on a tree that joins 3D bodies
// by every kind of joint (the closed form's hinge, ball, universal and weld, each way round; prismatic, cylindrical,
// double hinge, distance and slider from their rows as they are), hung from the world and from one another, with a
// free body beside them, v' agrees with the sparse Schur solve's to 1e-11 relative at a state where every velocity
// term is non-zero, and its run stays as close to the sparse path's as the dense path's does. Loops, particles, a
// pair with more than six rows and a solver asked for by name keep the Schur path.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "test_scenes.h"
#include "tether/dynamics/integration/default_gains.h"
#include "tether/dynamics/integration/integrators.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/integration/trajectory.h"
#include "tether/dynamics/solvers/constrained_dynamics.h"

namespace tether {
namespace {

using testing::SceneFromJson;

// A rigid body named `name` at `position`, turning and moving so that every velocity product is non-zero.
std::string Body(const std::string& name, const std::string& position, const std::string& spin) {
  return R"({"name": ")" + name + R"(", "type": "rigid", "mass": 0.7, "inertia": [0.01, 0.02, 0.025],
             "position": )" +
         position + R"(, "angular_velocity": )" + spin + "}";
}

// Every joint kind between 3D bodies, in one tree: base hangs from the world by a hinge whose child is the rows' first
// body; the others hang from it and from one another, but for one no row touches.
std::string TreeScene(const std::string& solver) {
  return R"({"dimension": 3, "bodies": [)" + Body("base", "[0, 0, -0.2]", "[0.3, 0.1, 0.2]") + "," +
         Body("ball", "[0.2, 0, -0.4]", "[0.5, -0.2, 0.1]") + "," + Body("cross", "[0.4, 0.1, -0.5]", "[0.1, 0.4, 0]") +
         "," + Body("welded", "[0.6, 0.1, -0.5]", "[0, 0.1, 0.3]") + "," +
         Body("slide", "[0, 0.3, -0.2]", "[0.2, 0, 0.1]") + "," + Body("tube", "[0, -0.3, -0.3]", "[0.1, 0.2, 0.3]") +
         "," + Body("foot", "[0.2, 0.2, -0.7]", "[0.5, 1.0, 0.2]") + "," +
         Body("rod", "[0.4, -0.2, -0.6]", "[0.3, 0.3, 0.1]") + "," + Body("rail", "[-0.3, 0, -0.4]", "[0.2, 0.1, 0]") +
         "," + Body("arm", "[0, 0.3, -0.5]", "[0.2, 0, 0.1]") + "," + Body("loose", "[1, 1, 0]", "[0.4, 0.3, 2]") +
         R"(],
  "constraints": [
    {"type": "hinge", "bodies": ["base", "world"], "points": [[0, 0, 0.2], [0, 0, 0]], "axis": [0, 1, 0]},
    {"type": "pin", "bodies": ["base", "ball"], "points": [[0.1, 0, -0.1], [-0.1, 0, 0.1]]},
    {"type": "universal", "bodies": ["ball", "cross"], "points": [[0.1, 0.05, -0.05], [-0.1, -0.05, 0.05]],
     "axes": [[0, 0, 1], [0, 1, 0]]},
    {"type": "weld", "bodies": ["welded", "cross"], "points": [[-0.1, 0, 0], [0.1, 0, 0]]},
    {"type": "prismatic", "bodies": ["base", "slide"], "points": [[0, 0.15, 0], [0, -0.15, 0]], "axis": [0, 1, 0]},
    {"type": "cylindrical", "bodies": ["base", "tube"], "points": [[0, -0.15, -0.05], [0, 0.15, 0.05]],
     "axis": [0, 1, 0]},
    {"type": "double_hinge", "bodies": ["ball", "foot"], "points": [[0, 0.1, -0.15], [0, -0.1, 0.15]],
     "axes": [[0, 1, 0], [0.8944, 0, 0.4472]]},
    {"type": "distance", "bodies": ["cross", "rod"], "points": [[0, -0.1, 0], [0, 0.1, 0.1]]},
    {"type": "slider", "bodies": ["rail", "base"], "points": [[0.15, 0, 0.1], [-0.15, 0, -0.1]], "axis": [1, 0, 0]},
    {"type": "hinge", "bodies": ["slide", "arm"], "points": [[0, 0, -0.15], [0, 0, 0.15]], "axis": [0.6, 0, 0.8]}],
  "effects": [{"type": "gravity", "acceleration": [0, 0, -9.81]}],
  "stabilization": {"method": "baumgarte", "alpha": 20, "beta": 100},
  "simulation": {"integrator": "rk4", "step": 1e-3, "duration": 0.3, "solver": ")" +
         solver + R"("}})";
}

// v' at the model's state after 0.1 s of its own run.
VecX<double> AccelerationAfterARun(const Model<double>& model, bool* tree) {
  RunReport report;
  const State<double> start = AssembledInitialState(model, &report);
  VecX<double> q = start.q, v = start.v;
  Workspace<double> ws(model, q);
  GainsInUse(model, &ws.alpha, &ws.beta);
  TimeIntegrator<double> integrator(model);
  for (int i = 0; i < 100; ++i) integrator.Advance(i * 1e-3, 1e-3, &ws, &q, &v);
  *tree = ws.tree != nullptr;
  VecX<double> a = VecX<double>::Zero(v.size());
  EXPECT_TRUE(ComputeAcceleration(model, 0.1, q, v, &ws, &a));
  return a;
}

TEST(TreeElimination, GivesTheSchurPathsAccelerationForEveryJointKind) {
  bool tree = false, schur_tree = true;
  const VecX<double> a = AccelerationAfterARun(SceneFromJson(TreeScene("auto")), &tree);
  const VecX<double> schur = AccelerationAfterARun(SceneFromJson(TreeScene("sparse")), &schur_tree);
  ASSERT_TRUE(tree);
  ASSERT_FALSE(schur_tree);
  EXPECT_GT(schur.norm(), 1.0);
  for (Eigen::Index i = 0; i < a.size(); ++i) EXPECT_NEAR(a[i], schur[i], 1e-11 * schur.norm()) << i;
}

// The double hinge passes close to its singular pose (axis lines that meet) at t = 0.26 s, where the sparse and the
// dense Schur paths themselves part by some 1e-8: the tree's run stays as close to the sparse path's as the dense
// path's does.
TEST(TreeElimination, RunsAsTheSchurPathsRun) {
  const Trajectory<double> tree = Record(SceneFromJson(TreeScene("auto")));
  const Trajectory<double> sparse = Record(SceneFromJson(TreeScene("sparse")));
  const Trajectory<double> dense = Record(SceneFromJson(TreeScene("dense")));
  ASSERT_EQ(tree.size(), sparse.size());
  ASSERT_GT(tree.size(), 100u);
  const auto apart = [&sparse](const Trajectory<double>& run) {
    double largest = 0.0;
    for (size_t i = 0; i < run.size(); ++i) {
      largest = std::max(largest, (run.q[i] - sparse.q[i]).cwiseAbs().maxCoeff());
      largest = std::max(largest, (run.v[i] - sparse.v[i]).cwiseAbs().maxCoeff());
    }
    return largest;
  };
  EXPECT_LT(apart(tree), 10.0 * apart(dense) + 1e-12);
  EXPECT_LT(apart(tree), 1e-6);
  EXPECT_LT(tree.LargestViolation(), 1e-6);
}

TEST(TreeElimination, KeepsTheSchurPathWhereTheRowsAreNotATree) {
  const auto plan_of = [](const std::string& json) {
    const Model<double> model = SceneFromJson(json);
    RunReport report;
    const Workspace<double> ws(model, AssembledInitialState(model, &report).q);
    return ws.tree != nullptr;
  };
  const std::string rigid = R"({"name": "a", "type": "rigid", "mass": 1, "inertia": [1, 1, 1], "position": [1, 0, 0]},
                               {"name": "b", "type": "rigid", "mass": 1, "inertia": [1, 1, 1], "position": [2, 0, 0]})";
  const std::string hinges = R"({"type": "hinge", "bodies": ["world", "a"], "points": [[0, 0, 0], [-1, 0, 0]],
                                 "axis": [0, 0, 1]},
                                {"type": "hinge", "bodies": ["a", "b"], "points": [[0.5, 0, 0], [-0.5, 0, 0]],
                                 "axis": [0, 0, 1]})";
  const auto scene = [](const std::string& bodies, const std::string& constraints, const std::string& extra) {
    return R"({"dimension": 3, "bodies": [)" + bodies + R"(], "constraints": [)" + constraints + "]" + extra + "}";
  };
  EXPECT_TRUE(plan_of(scene(rigid, hinges, "")));
  EXPECT_FALSE(plan_of(scene(rigid, hinges, R"(, "simulation": {"solver": "dense"})")));
  EXPECT_FALSE(plan_of(scene(rigid, hinges + R"(, {"type": "distance", "bodies": ["world", "b"],
                                                   "points": [[2, 1, 0], [0, 0, 0]]})",
                             "")));  // a loop through the world
  EXPECT_FALSE(
      plan_of(scene(rigid + R"(, {"name": "p", "type": "particle", "mass": 1, "position": [3, 0, 0]})",
                    hinges + R"(, {"type": "distance", "bodies": ["b", "p"], "points": [[0.5, 0, 0], [0, 0, 0]]})",
                    "")));  // a particle
}

}  // namespace
}  // namespace tether
