// Spatial linkages and the 3D parameters:
//   - degrees of freedom by rank: the orthogonal Bricard linkage (six hinges in a loop, which Grubler's count calls
//     rigid) moves with one, and simulating it keeps the loop closed; a Cardan joint between two world hinges has
//     three redundant rows and one degree of freedom; an RSSR four-bar has two (one the coupler's idle spin);
//   - a double hinge leaves two degrees of freedom, and Jet gradients through it (its axes, points, the foot's mass
//     and moment) match central differences;
//   - Jet gradients of a loss against central differences for every new kind of parameter (principal moments,
//     products of inertia, orientation components, angular velocities, axes, joint angle keys, marker points,
//     joint springs and motors), with quaternion, encoder and marker columns as data, and Jets against doubles;
//     the discrete adjoint equals the Jets in both gradient tests;
//   - a recorded quaternion of either sign fits the same.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "test_scenes.h"
#include "tether/autodiff/adjoint.h"
#include "tether/autodiff/residuals.h"
#include "tether/dynamics/io/scene_check.h"
#include "tether/dynamics/io/scene_reader.h"

namespace tether {
namespace {

using testing::SceneFromJson;

// The discrete adjoint differentiates the computation the Jets do, in reverse: equal to 1e-8 relative.
void ExpectAdjointEqualsJets(const Model<double>& model, const ParameterSet& parameters,
                             const Observations& observations, const LossGradient& jet) {
  const LossGradient adjoint = AdjointLossGradient(model, parameters, observations);
  EXPECT_NEAR(adjoint.loss, jet.loss, 1e-12 * jet.loss);
  for (int i = 0; i < parameters.size(); ++i) {
    EXPECT_NEAR(adjoint.gradient[i], jet.gradient[i], 1e-8 * std::max(1.0, std::abs(jet.gradient[i])))
        << "adjoint, " << parameters.pointers()[i];
  }
}

// The numbers of one CSV row.
std::vector<double> Cells(const std::string& line) {
  std::vector<double> cells;
  std::stringstream in(line);
  for (std::string cell; std::getline(in, cell, ',');) cells.push_back(std::stod(cell));
  return cells;
}

// The run's own columns at `times`, each shifted by its amount, written as a data file named `file` in the test
// folder: observations off the run, so that the loss and its gradient are not zero. Returns the file's path.
std::string ShiftedData(const Scene& scene, const std::vector<double>& times,
                        const std::vector<std::pair<std::string, double>>& shifts, const std::string& file) {
  const std::string path = ::testing::TempDir() + file;
  std::istringstream in(testing::TrajectoryCsvAt(scene.model, times));
  std::ofstream out(path);
  std::string line;
  std::getline(in, line);
  out << "t";
  for (const auto& [name, shift] : shifts) out << "," << name;
  out << "\n";
  const std::vector<TrajectoryColumn> columns = TrajectoryColumns(scene.model);
  while (std::getline(in, line)) {
    const std::vector<double> cells = Cells(line);
    auto at = [&](const std::string& name) {
      for (size_t i = 0; i < columns.size(); ++i) {
        if (columns[i].name == name) return cells[i];
      }
      return std::numeric_limits<double>::quiet_NaN();
    };
    out << at("t");
    for (const auto& [name, shift] : shifts) out << "," << at(name) + shift;
    out << "\n";
  }
  return path;
}

// The orthogonal Bricard linkage on the edges of a unit cube, (0,0,0) -> (1,0,0) -> (1,1,0) -> (1,1,1) ->
// (0,1,1) -> (0,0,1) -> (0,0,0): six unit links, consecutive hinge axes perpendicular, each link the common
// normal of its two axes (lengths equal, twists 90 degrees, offsets zero). The last link is the world.
std::string Bricard(const std::string& effects) {
  const double p[6][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {0, 1, 1}, {0, 0, 1}};
  const char* axes[6] = {"[0, 1, 0]", "[0, 0, 1]", "[1, 0, 0]", "[0, 1, 0]", "[0, 0, 1]", "[1, 0, 0]"};
  std::string bodies, constraints;
  for (int k = 0; k < 5; ++k) {  // link k from vertex k to vertex k + 1, body axes = world axes
    char body[300];
    std::snprintf(body, sizeof body,
                  R"(%s{"name": "l%d", "type": "rigid", "mass": 1, "inertia": [0.1, 0.1, 0.1], "position": [%g, %g, %g]})",
                  k ? ", " : "", k, 0.5 * (p[k][0] + p[k + 1][0]), 0.5 * (p[k][1] + p[k + 1][1]),
                  0.5 * (p[k][2] + p[k + 1][2]));
    bodies += body;
  }
  for (int k = 0; k < 6; ++k) {  // hinge k at vertex k between link k - 1 (the world for k = 0) and link k
    const std::string a = k == 0 ? "world" : "l" + std::to_string(k - 1);
    const std::string b = k == 5 ? "world" : "l" + std::to_string(k);
    auto local = [&](int link) {  // vertex k in link `link`'s frame (world coordinates for the world)
      char out[100];
      if (link < 0 || link > 4) {
        std::snprintf(out, sizeof out, "[%g, %g, %g]", p[k][0], p[k][1], p[k][2]);
      } else {
        std::snprintf(out, sizeof out, "[%g, %g, %g]", p[k][0] - 0.5 * (p[link][0] + p[link + 1][0]),
                      p[k][1] - 0.5 * (p[link][1] + p[link + 1][1]), p[k][2] - 0.5 * (p[link][2] + p[link + 1][2]));
      }
      return std::string(out);
    };
    constraints += std::string(k ? ", " : "") + R"({"type": "hinge", "name": "h)" + std::to_string(k) +
                   R"(", "bodies": [")" + a + R"(", ")" + b + R"("], "points": [)" + local(k - 1) + ", " +
                   local(k == 5 ? -1 : k) + R"(], "axis": )" + axes[k] + "}";
  }
  return R"({"dimension": 3, "bodies": [)" + bodies + R"(], "constraints": [)" + constraints + R"(], "effects": [)" +
         effects + R"(], "simulation": {"integrator": "rk4", "step": 1e-3, "duration": 2.0}})";
}

TEST(DegreesOfFreedom, BricardLinkageMovesWithOneAlthoughGrublerCallsItRigid) {
  const SceneCheck check = CheckScene(SceneFromJson(Bricard("")));
  EXPECT_EQ(check.coordinates, 30);
  EXPECT_EQ(check.constraint_rows, 30);  // Grubler: 6 (5 links) - 5 (6 hinges) = 0
  EXPECT_EQ(check.rank, 29);
  EXPECT_EQ(check.degrees_of_freedom, 1);
  EXPECT_LT(check.initial_violation, 1e-15);
}

TEST(DegreesOfFreedom, BricardLinkageDrivenByAMotorStaysClosed) {
  const Model<double> model = SceneFromJson(Bricard(R"({"type": "joint_torque", "joint": "h0", "value": 0.5})"));
  double largest = 0.0, final_angle = 0.0;
  const std::vector<TrajectoryColumn> columns = TrajectoryColumns(model);
  int angle = -1;
  for (size_t i = 0; i < columns.size(); ++i) {
    if (columns[i].name == "h0.angle") angle = static_cast<int>(i);
  }
  ASSERT_GE(angle, 0);
  Simulate<double>(model, {}, [&](const Sample<double>& s) {
    largest = std::max(largest, s.constraint_error);
    final_angle = ColumnValue(model, columns[angle], s);
  });
  EXPECT_LT(largest, 1e-8);
  EXPECT_GT(std::abs(final_angle), 0.2) << "the motor did not move the linkage";
}

TEST(DegreesOfFreedom, CardanJointBetweenWorldHingesHasThreeRedundantRows) {
  const Model<double> model = ReadSceneFile(std::string(TETHER_SOURCE_DIR) + "/scenes/cardan.json").model;
  const SceneCheck check = CheckScene(model);
  EXPECT_EQ(check.constraint_rows, 14);
  EXPECT_EQ(check.rank, 11);
  EXPECT_EQ(check.degrees_of_freedom, 1);
}

TEST(DegreesOfFreedom, RssrFourBarHasItsCranksFreedomAndTheCouplersSpin) {
  const Model<double> model = ReadSceneFile(std::string(TETHER_SOURCE_DIR) + "/scenes/rssr.json").model;
  EXPECT_EQ(CheckScene(model).degrees_of_freedom, 2);
}

// A foot on a double hinge below a shin fixed to the world (MuJoCo's humanoid's ankle: two hinges whose axis lines
// do not meet), with gravity, a marker at the toe and a head start.
constexpr char kAnkle[] = R"({"dimension": 3,
  "bodies": [{"name": "foot", "type": "rigid", "mass": 1.1, "inertia": [0.001, 0.006, 0.0065],
              "position": [0.035, -0.01, -0.04], "angular_velocity": [0.5, 1.0, 0.2]}],
  "constraints": [{"type": "double_hinge", "name": "ankle", "bodies": ["world", "foot"],
                   "points": [[0, 0, 0.04], [-0.035, 0.01, 0.04]], "axes": [[0, 1, 0], [0.8944, 0, 0.4472]]}],
  "effects": [{"type": "gravity", "acceleration": [0, 0, -9.81]}],
  "markers": [{"name": "toe", "body": "foot", "point": [0.1, 0, -0.02]}],
  "stabilization": {"method": "baumgarte", "alpha": 20, "beta": 100},
  "simulation": {"integrator": "rk4", "step": 2e-3, "duration": 0.6}})";

TEST(DegreesOfFreedom, ADoubleHingeLeavesTwo) {
  const SceneCheck check = CheckScene(ParseScene(ParseJsonText(kAnkle, "ankle.json"), "ankle.json").model);
  EXPECT_EQ(check.constraint_rows, 4);
  EXPECT_EQ(check.rank, 4);
  EXPECT_EQ(check.degrees_of_freedom, 2);
}

TEST(Gradients, JetsMatchCentralDifferencesThroughADoubleHinge) {
  const Scene scene = ParseScene(ParseJsonText(kAnkle, "ankle.json"), "ankle.json");
  const std::string path = ShiftedData(scene, {0.3, 0.6}, {{"toe.x", 0.01}, {"toe.z", 0.01}}, "ankle_data.csv");
  const Observations observations = ReadObservations(path, scene.model);
  const ParameterSet parameters(scene, {"/constraints/0/axes/0/2", "/constraints/0/axes/1/1",
                                        "/constraints/0/points/0/0", "/constraints/0/points/1/2", "/bodies/0/mass",
                                        "/bodies/0/inertia/1"});
  const LossGradient jet = JetLossGradient(scene.model, parameters, observations);
  const LossGradient fd = CentralDifferenceLossGradient(scene.model, parameters, observations);
  EXPECT_NEAR(jet.loss, fd.loss, 1e-13 * fd.loss);
  ASSERT_GT(jet.loss, 0.0);
  for (int i = 0; i < parameters.size(); ++i) {
    EXPECT_NEAR(jet.gradient[i], fd.gradient[i], 1e-6 * std::max(1.0, std::abs(fd.gradient[i])))
        << parameters.pointers()[i];
    EXPECT_GT(std::abs(fd.gradient[i]), 1e-6) << parameters.pointers()[i];  // every parameter matters
  }
  ExpectAdjointEqualsJets(scene.model, parameters, observations, jet);
}

// A two-link arm with a full inertia tensor, a motor, a joint spring and a marker, observed through a quaternion
// component, an encoder, a marker and a world angular velocity.
constexpr char kArm[] = R"({"dimension": 3,
  "bodies": [
    {"name": "upper", "type": "rigid", "mass": 1.2, "inertia": [0.01, 0.04, 0.045], "position": [0.25, 0, 0],
     "orientation": [1, 0, 0, 0], "angular_velocity": [0, 0, 0.8]},
    {"name": "lower", "type": "rigid", "mass": 0.8,
     "inertia": [[0.004, 0.0005, 0.0002], [0.0005, 0.03, 0.001], [0.0002, 0.001, 0.031]],
     "position": [0.75, 0, 0], "orientation": [0.99, 0.1, 0.05, 0.0], "velocity": [0, 0, 0],
     "angular_velocity": [0.1, 0.2, 0.3]}],
  "constraints": [
    {"type": "hinge", "name": "shoulder", "bodies": ["world", "upper"], "points": [[0, 0, 0], [-0.25, 0, 0]],
     "axis": [0, 0.1, 1], "angle": 0.2},
    {"type": "hinge", "name": "elbow", "bodies": ["upper", "lower"], "points": [[0.25, 0, 0], [-0.25, 0, 0]],
     "axis": [0, 1, 0]}],
  "effects": [
    {"type": "gravity", "acceleration": [0, 0, -9.81]},
    {"type": "joint_spring", "joint": "elbow", "stiffness": 2.0, "rest": 0.1, "damping": 0.05},
    {"type": "joint_torque", "joint": "shoulder", "value": 0.3}],
  "markers": [{"name": "hand", "body": "lower", "point": [0.25, 0.01, 0]}],
  "stabilization": {"method": "baumgarte", "alpha": 20, "beta": 100},
  "simulation": {"integrator": "rk4", "step": 2e-3, "duration": 0.6}})";

TEST(Gradients, JetsMatchCentralDifferencesForEveryThreeDimensionalParameter) {
  std::string text = kArm;
  // the quaternion as written is within 1e-2 of unit: the reader wants 1e-6, so normalise it here
  const Vec4<double> q = Vec4<double>(0.99, 0.1, 0.05, 0.0).normalized();
  char orientation[200];
  std::snprintf(orientation, sizeof orientation, "[%.17g, %.17g, %.17g, %.17g]", q[0], q[1], q[2], q[3]);
  text.replace(text.find("[0.99, 0.1, 0.05, 0.0]"), std::string("[0.99, 0.1, 0.05, 0.0]").size(), orientation);
  const Scene scene = ParseScene(ParseJsonText(text, "arm.json"), "arm.json");
  const std::string path = ShiftedData(scene, {0.2, 0.4, 0.6},
                                       {{"lower.qx", 0.01}, {"elbow.angle", -0.02}, {"hand.x", 0.01},
                                        {"hand.z", -0.01}, {"upper.wz", 0.05}, {"energy", 0.1}},
                                       "arm_data.csv");
  const Observations observations = ReadObservations(path, scene.model);
  const ParameterSet parameters(
      scene, {"/bodies/0/inertia/1", "/bodies/1/inertia/0/1", "/bodies/1/inertia/2/2", "/bodies/1/orientation/1",
              "/bodies/0/angular_velocity/2", "/bodies/1/angular_velocity/0", "/constraints/0/axis/1",
              "/constraints/1/axis/2", "/constraints/0/angle", "/constraints/1/points/1/1", "/markers/0/point/1",
              "/effects/1/stiffness", "/effects/1/rest", "/effects/2/value", "/bodies/1/mass"});
  const LossGradient jet = JetLossGradient(scene.model, parameters, observations);
  const LossGradient fd = CentralDifferenceLossGradient(scene.model, parameters, observations);
  EXPECT_NEAR(jet.loss, fd.loss, 1e-13 * fd.loss);  // the Jets' value part is the double run
  ASSERT_GT(jet.loss, 0.0);
  for (int i = 0; i < parameters.size(); ++i) {
    EXPECT_NEAR(jet.gradient[i], fd.gradient[i], 1e-6 * std::max(1.0, std::abs(fd.gradient[i])))
        << parameters.pointers()[i];
  }
  ExpectAdjointEqualsJets(scene.model, parameters, observations, jet);
}

TEST(Observations, ARecordedQuaternionOfEitherSignFitsTheSame) {
  // a free tumbling body recorded with its quaternion negated on every other row: q and -q are one rotation, so
  // the residuals against its own run are zero either way
  const Model<double> model = SceneFromJson(R"({"dimension": 3,
    "bodies": [{"name": "b", "type": "rigid", "mass": 1, "inertia": [0.2, 0.3, 0.4], "position": [0, 0, 0],
                "angular_velocity": [1, 2, 3]}],
    "simulation": {"integrator": "rk4", "step": 1e-3, "duration": 1.0}})");
  const std::vector<double> times = {0.2, 0.4, 0.6, 0.8};
  const std::string run = testing::TrajectoryCsvAt(model, times);
  const std::vector<TrajectoryColumn> columns = TrajectoryColumns(model);
  const std::string path = ::testing::TempDir() + "flipped_quaternions.csv";
  {
    std::istringstream in(run);
    std::ofstream out(path);
    std::string line;
    std::getline(in, line);
    out << "t,b.qw,b.qx,b.qy,b.qz\n";
    for (int row = 0; std::getline(in, line); ++row) {
      const std::vector<double> cells = Cells(line);
      const double sign = row % 2 == 0 ? -1.0 : 1.0;
      out.precision(17);
      out << cells[0];
      for (int k = 4; k < 8; ++k) out << "," << sign * cells[k];  // columns b.qw .. b.qz follow t, b.x, b.y, b.z
      out << "\n";
    }
  }
  ASSERT_EQ(columns[4].name, "b.qw");
  const Observations observations = ReadObservations(path, model);
  const VecX<double> residuals = ObservationResiduals(model, observations);
  ASSERT_EQ(residuals.size(), 16);
  EXPECT_LT(residuals.lpNorm<Eigen::Infinity>(), 1e-15);
}

// Point and angle rows of every kind of side (the world, a particle, 3D bodies with and without principal axes
// along their body axes) and every angle primitive (a universal's angle, a weld's frozen orientation, a
// hinge's common axis), and a motor between two 3D bodies, through their recorded operations: the adjoint equals
// the Jets.
constexpr char kJointZoo[] = R"({"dimension": 3,
  "bodies": [
    {"name": "cross", "type": "rigid", "mass": 0.9, "inertia": [0.02, 0.03, 0.025], "position": [0, 0, -0.2],
     "angular_velocity": [0.4, -0.3, 0.2]},
    {"name": "block", "type": "rigid", "mass": 0.6,
     "inertia": [[0.006, 0.0004, 0.0001], [0.0004, 0.008, 0.0003], [0.0001, 0.0003, 0.009]],
     "position": [0, 0, -0.5]},
    {"name": "flap", "type": "rigid", "mass": 0.3, "inertia": [0.002, 0.003, 0.004], "position": [0.2, 0, -0.5],
     "angular_velocity": [0, 0, 0.5]},
    {"name": "bob", "type": "particle", "mass": 0.4, "position": [0, 0.1, -0.8], "velocity": [0.2, 0, 0]}],
  "constraints": [
    {"type": "universal", "bodies": ["world", "cross"], "points": [[0, 0, 0], [0, 0, 0.2]],
     "axes": [[1, 0, 0], [0, 1, 0]]},
    {"type": "weld", "bodies": ["cross", "block"], "points": [[0, 0, -0.15], [0, 0, 0.15]]},
    {"type": "hinge", "name": "flap_hinge", "bodies": ["block", "flap"], "points": [[0.1, 0, 0], [-0.1, 0, 0]],
     "axis": [0, 0.2, 1]},
    {"type": "pin", "bodies": ["block", "bob"], "points": [[0, 0.1, -0.3], [0, 0, 0]]}],
  "effects": [{"type": "gravity", "acceleration": [0, 0, -9.81]},
              {"type": "joint_torque", "joint": "flap_hinge", "value": 0.05}],
  "stabilization": {"method": "baumgarte", "alpha": 20, "beta": 100},
  "simulation": {"integrator": "rk4", "step": 2e-3, "duration": 0.3}})";

TEST(Gradients, AdjointMatchesJetsThroughPointAndAngleRowsOfEveryKind) {
  const Scene scene = ParseScene(ParseJsonText(kJointZoo, "zoo.json"), "zoo.json");
  const std::string path =
      ShiftedData(scene, {0.1, 0.2, 0.3}, {{"bob.x", 0.01}, {"bob.y", -0.01}, {"flap.qz", 0.02}, {"cross.wx", -0.05}},
                  "zoo_data.csv");
  const Observations observations = ReadObservations(path, scene.model);
  const ParameterSet parameters(
      scene, {"/bodies/0/inertia/1", "/bodies/1/inertia/0/1", "/bodies/3/mass", "/bodies/0/angular_velocity/0",
              "/bodies/3/velocity/0", "/constraints/0/axes/0/1", "/constraints/0/points/1/2",
              "/constraints/1/points/0/2", "/constraints/2/axis/1", "/constraints/2/points/1/0",
              "/constraints/3/points/0/1", "/constraints/3/points/1/0", "/effects/1/value"});
  const LossGradient jet = JetLossGradient(scene.model, parameters, observations);
  ASSERT_GT(jet.loss, 0.0);
  for (int i = 0; i < parameters.size(); ++i) EXPECT_TRUE(std::isfinite(jet.gradient[i])) << parameters.pointers()[i];
  ExpectAdjointEqualsJets(scene.model, parameters, observations, jet);
}

}  // namespace
}  // namespace tether
