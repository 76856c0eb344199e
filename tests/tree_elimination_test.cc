// The tree elimination (tree_elimination.h) against the Schur path it stands in for: on a tree that joins 3D bodies
// by every kind of joint it takes (hinge, ball, universal, weld, double hinge with crossed and with parallel axes),
// each way round (the child as the rows' first body or their second), hung from the world and from one another, with
// a free body beside them, v' agrees with the sparse Schur solve's to 1e-11 relative at a state where every velocity
// term is non-zero, and at one where every joint is violated by centimetres and degrees, and the two runs stay within
// 1e-9 of each other; it leaves the rows' values the Schur path evaluates; Jets through it give central differences'
// loss gradient. Loops, particles, joints of other rows
// (prismatic joints) and a solver asked for by name keep the Schur path.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "test_files.h"
#include "test_scenes.h"
#include "tether/autodiff/observations.h"
#include "tether/autodiff/parameters.h"
#include "tether/autodiff/residuals.h"
#include "tether/dynamics/integration/default_gains.h"
#include "tether/dynamics/integration/integrators.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/integration/trajectory.h"
#include "tether/dynamics/io/scene_reader.h"
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

// Every joint kind the elimination takes, in one tree: base hangs from the world by a hinge whose child is the
// rows' first body; the others hang from it and from one another, but for one no row touches.
std::string TreeScene(const std::string& solver) {
  return R"({"dimension": 3, "bodies": [)" + Body("base", "[0, 0, -0.2]", "[0.3, 0.1, 0.2]") + "," +
         Body("ball", "[0.2, 0, -0.4]", "[0.5, -0.2, 0.1]") + "," + Body("cross", "[0.4, 0.1, -0.5]", "[0.1, 0.4, 0]") +
         "," + Body("welded", "[0.6, 0.1, -0.5]", "[0, 0.1, 0.3]") + "," +
         Body("arm", "[0, 0.3, -0.2]", "[0.2, 0, 0.1]") + "," + Body("loose", "[1, 1, 0]", "[0.4, 0.3, 2]") + "," +
         Body("foot", "[0.05, 0.44, -0.24]", "[0.3, -0.4, 0.2]") + "," +
         Body("toe", "[0.1, 0.5, -0.3]", "[-0.2, 0.1, 0.5]") + "," +
         Body("flap", "[-0.2, 0.3, -0.2]", "[0.1, 0.6, -0.3]") + R"(],
  "constraints": [
    {"type": "hinge", "bodies": ["base", "world"], "points": [[0, 0, 0.2], [0, 0, 0]], "axis": [0, 1, 0]},
    {"type": "pin", "bodies": ["base", "ball"], "points": [[0.1, 0, -0.1], [-0.1, 0, 0.1]]},
    {"type": "universal", "bodies": ["ball", "cross"], "points": [[0.1, 0.05, -0.05], [-0.1, -0.05, 0.05]],
     "axes": [[0, 0, 1], [0, 1, 0]]},
    {"type": "weld", "bodies": ["welded", "cross"], "points": [[-0.1, 0, 0], [0.1, 0, 0]]},
    {"type": "hinge", "bodies": ["base", "arm"], "points": [[0, 0.15, 0], [0, -0.15, 0]], "axis": [0.6, 0, 0.8]},
    {"type": "double_hinge", "bodies": ["arm", "foot"], "points": [[0, 0.1, 0], [0, 0.04, 0.1]],
     "axes": [[0, 1, 0], [0.8944, 0, 0.4472]]},
    {"type": "double_hinge", "bodies": ["toe", "foot"], "points": [[-0.03, -0.03, 0.06], [0.04, 0.03, -0.03]],
     "axes": [[1, 0, 0], [0, 0.6, 0.8]]},
    {"type": "double_hinge", "bodies": ["arm", "flap"], "points": [[-0.1, 0, 0], [0.05, 0, 0.05]],
     "axes": [[0, 0, 1], [0, 0, 1]]}],
  "effects": [{"type": "gravity", "acceleration": [0, 0, -9.81]}],
  "stabilization": {"method": "baumgarte", "alpha": 20, "beta": 100},
  "simulation": {"integrator": "rk4", "step": 1e-3, "duration": 0.3, "solver": ")" +
         solver + R"("}})";
}

// The state of TreeScene's run after 0.1 s.
State<double> StateAfterARun() {
  const Model<double> model = SceneFromJson(TreeScene("auto"));
  RunReport report;
  State<double> state = AssembledInitialState(model, &report);
  Workspace<double> ws(model, state.q);
  GainsInUse(model, &ws.alpha, &ws.beta);
  TimeIntegrator<double> integrator(model);
  for (int i = 0; i < 100; ++i) integrator.Advance(i * 1e-3, 1e-3, &ws, &state.q, &state.v);
  return state;
}

// v' of TreeScene at (q, v) by the tree path against the sparse Schur path's, to 1e-11 relative; and the rows' values
// the tree path leaves (what a step's runaway check reads) against those the Schur path evaluates.
void ExpectTheSchurPathsAcceleration(const VecX<double>& q, const VecX<double>& v) {
  const auto acceleration = [&q, &v](const std::string& solver, bool* tree, std::vector<double>* values) {
    const Model<double> model = SceneFromJson(TreeScene(solver));
    Workspace<double> ws(model, q);
    GainsInUse(model, &ws.alpha, &ws.beta);
    for (ConstraintRow<double>& row : ws.rows) row.value = std::nan("");
    VecX<double> a = VecX<double>::Zero(v.size());
    EXPECT_TRUE(ComputeAcceleration(model, 0.0, q, v, &ws, &a));
    *tree = ws.tree != nullptr;
    for (const ConstraintRow<double>& row : ws.rows) values->push_back(row.value);
    return a;
  };
  bool tree = false, schur_tree = true;
  std::vector<double> values, schur_values;
  const VecX<double> a = acceleration("auto", &tree, &values);
  const VecX<double> schur = acceleration("sparse", &schur_tree, &schur_values);
  ASSERT_TRUE(tree);
  ASSERT_FALSE(schur_tree);
  EXPECT_GT(schur.norm(), 1.0);
  for (Eigen::Index i = 0; i < a.size(); ++i) EXPECT_NEAR(a[i], schur[i], 1e-11 * schur.norm()) << i;
  ASSERT_EQ(values.size(), schur_values.size());
  for (size_t i = 0; i < values.size(); ++i) EXPECT_NEAR(values[i], schur_values[i], 1e-15) << "row " << i;
}

TEST(TreeElimination, GivesTheSchurPathsAccelerationForEveryJointKindItTakes) {
  const State<double> state = StateAfterARun();
  ExpectTheSchurPathsAcceleration(state.q, state.v);
}

TEST(TreeElimination, GivesTheSchurPathsAccelerationWhereTheRowsAreViolated) {
  // every body moved off its joints by a few centimetres and turned by a few degrees: the transports must keep the
  // rows as they are evaluated there, not as they would be if the joints held
  const Model<double> model = SceneFromJson(TreeScene("auto"));
  RunReport report;
  const State<double> start = AssembledInitialState(model, &report);
  VecX<double> q = start.q;
  for (size_t k = 1; k <= model.bodies.size(); ++k) {
    const int o = model.bodies[k - 1].q_offset;
    q.segment<3>(o) += Vec3<double>(0.02, -0.03, 0.01) * std::sin(static_cast<double>(k));
    q.segment<4>(o + 3) =
        (q.segment<4>(o + 3) + Vec4<double>(0, 0.03, -0.02, 0.04) * std::cos(static_cast<double>(k))).normalized();
  }
  ExpectTheSchurPathsAcceleration(q, start.v);
}

TEST(TreeElimination, RunsAsTheSchurPathRuns) {
  const Trajectory<double> tree = Record(SceneFromJson(TreeScene("auto")));
  const Trajectory<double> sparse = Record(SceneFromJson(TreeScene("sparse")));
  ASSERT_EQ(tree.size(), sparse.size());
  ASSERT_GT(tree.size(), 100u);
  for (size_t i = 0; i < tree.size(); ++i) {
    EXPECT_LT((tree.q[i] - sparse.q[i]).cwiseAbs().maxCoeff(), 1e-9) << tree.t[i];
    EXPECT_LT((tree.v[i] - sparse.v[i]).cwiseAbs().maxCoeff(), 1e-9) << tree.t[i];
  }
  EXPECT_LT(tree.LargestViolation(), 1e-6);
}

// Jets take the tree path too: the loss gradient with respect to a mass, an inertia and a double hinge's axis, on
// observations of a truth whose foot is heavier, agrees with central differences.
TEST(TreeElimination, JetGradientsAgreeWithCentralDifferences) {
  const nlohmann::json document = nlohmann::json::parse(TreeScene("auto"));
  nlohmann::json truth = document;
  truth["bodies"][6]["mass"] = 0.75;
  const Model<double> truth_model = ParseScene(truth, "truth.json").model;
  const Trajectory<double> run = Record(truth_model);
  const int foot_x = truth_model.bodies[6].q_offset, toe_z = truth_model.bodies[7].q_offset + 2;
  std::string csv = "t,foot.x,toe.z\n";
  for (double t : {0.05, 0.1, 0.2}) {
    const size_t i = std::lower_bound(run.t.begin(), run.t.end(), t - 1e-9) - run.t.begin();
    ASSERT_LT(i, run.size());
    csv += std::to_string(run.t[i]) + "," + std::to_string(run.q[i][foot_x]) + "," + std::to_string(run.q[i][toe_z]) +
           "\n";
  }
  const testing::TempFolder folder;
  const Scene scene = ParseScene(document, "tree.json");
  const Model<Jet> jets = CastModel<Jet>(scene.model);
  ASSERT_NE(Workspace<Jet>(jets, VecX<Jet>(run.q[0].cast<Jet>())).tree, nullptr);  // the path under test
  const ParameterSet parameters(scene, {"/bodies/6/mass", "/bodies/0/inertia/1", "/constraints/5/axes/1/0"});
  const Observations observations = ReadObservations(folder.Write("observations.csv", csv), scene.model);
  const LossGradient jet = JetLossGradient(scene.model, parameters, observations);
  const LossGradient reference = CentralDifferenceLossGradient(scene.model, parameters, observations);
  EXPECT_GT(jet.loss, 1e-12);
  ASSERT_EQ(jet.gradient.size(), 3u);
  for (size_t k = 0; k < 3; ++k) {
    EXPECT_GT(std::abs(reference.gradient[k]), 0.0) << k;
    EXPECT_NEAR(jet.gradient[k], reference.gradient[k], 1e-5 * std::abs(reference.gradient[k])) << k;
  }
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
  const std::string first_hinge = hinges.substr(0, hinges.find("},") + 2);
  EXPECT_FALSE(plan_of(scene(rigid, first_hinge + R"({"type": "prismatic", "bodies": ["a", "b"],
                                   "points": [[0.5, 0, 0], [-0.5, 0, 0]], "axis": [1, 0, 0]})",
                             "")));  // a line and angles
  EXPECT_FALSE(plan_of(scene(rigid, hinges + R"(, {"type": "distance", "bodies": ["a", "b"],
                                                   "points": [[0, 0, 0.1], [0, 0, 0.1]]})",
                             "")));  // two constraints on one pair
  EXPECT_FALSE(
      plan_of(scene(rigid + R"(, {"name": "p", "type": "particle", "mass": 1, "position": [3, 0, 0]})",
                    hinges + R"(, {"type": "distance", "bodies": ["b", "p"], "points": [[0.5, 0, 0], [0, 0, 0]]})",
                    "")));  // a particle
}

}  // namespace
}  // namespace tether
