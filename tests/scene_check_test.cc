// CheckScene and `tether check`: rank, degrees of freedom, redundant constraints, initial violation and
// conditioning, on scenes whose answers are known by hand.
#include "tether/dynamics/io/scene_check.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "test_files.h"
#include "test_scenes.h"

namespace tether {
namespace {

using testing::SceneFromJson;

// The IFToMM A02 parallelogram (three 1 m, 1 kg bars on four pins) with its cranks at `angle` from the ground.
std::string Parallelogram(double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  auto bar = [](const std::string& name, double x, double y, double a) {
    return R"({"name": ")" + name + R"(", "type": "rigid", "mass": 1.0, "inertia": 0.0833333, "position": [)" +
           std::to_string(x) + ", " + std::to_string(y) + R"(], "angle": )" + std::to_string(a) + "}";
  };
  return R"({"bodies": [)" + bar("crank0", 0.5 * c, 0.5 * s, angle) + ", " + bar("crank1", 1 + 0.5 * c, 0.5 * s, angle) +
         ", " + bar("coupler", 0.5 + c, s, 0.0) + R"(],
    "constraints": [
      {"type": "pin", "bodies": ["world", "crank0"], "points": [[0.0, 0.0], [-0.5, 0.0]]},
      {"type": "pin", "bodies": ["world", "crank1"], "points": [[1.0, 0.0], [-0.5, 0.0]]},
      {"type": "pin", "bodies": ["coupler", "crank0"], "points": [[-0.5, 0.0], [0.5, 0.0]]},
      {"type": "pin", "bodies": ["coupler", "crank1"], "points": [[0.5, 0.0], [0.5, 0.0]]}]})";
}

TEST(SceneCheck, PendulumHasOneDegreeOfFreedom) {
  const Model<double> model = testing::Pendulum60();
  const SceneCheck c = CheckScene(model);
  EXPECT_EQ(c.coordinates, 2);
  EXPECT_EQ(c.constraint_rows, 1);
  EXPECT_EQ(c.rank, 1);
  EXPECT_EQ(c.degrees_of_freedom, 1);
  EXPECT_TRUE(c.redundant_constraints.empty());
  EXPECT_NEAR(c.condition_number, 1.0, 1e-12);  // one row: a single singular value
  // the helper writes the bob's position with six decimals: the violation is exactly |position| - 0.7
  const Vec3<double>& bob = model.bodies[0].position;
  EXPECT_NEAR(c.initial_violation, std::abs(std::hypot(bob[0], bob[1]) - 0.7), 1e-15);
  EXPECT_EQ(c.solver, "sparse");  // what "auto" takes at every size
}

TEST(SceneCheck, NamesTheTreeEliminationWhereAutoTakesIt) {
  const std::string scene = R"({"dimension": 3,
      "bodies": [{"name": "rod", "type": "rigid", "mass": 1, "inertia": [0.1, 0.1, 0.01], "position": [0, 0, -0.5]}],
      "constraints": [{"type": "hinge", "bodies": ["world", "rod"], "points": [[0, 0, 0], [0, 0, 0.5]],
                       "axis": [0, 1, 0]}]SOLVER})";
  const auto solver_of = [&scene](const std::string& simulation) {
    std::string text = scene;
    text.replace(text.find("SOLVER"), 6, simulation);
    return CheckScene(SceneFromJson(text)).solver;
  };
  EXPECT_EQ(solver_of(""), "tree");
  EXPECT_EQ(solver_of(R"(, "simulation": {"solver": "sparse"})"), "sparse");
  EXPECT_EQ(solver_of(R"(, "simulation": {"solver": "dense"})"), "dense");
}

TEST(SceneCheck, DuplicatedRodIsRedundant) {
  const SceneCheck c = CheckScene(SceneFromJson(R"({
    "bodies": [{"name": "bob", "type": "particle", "mass": 1.0, "position": [0.6, -0.8]}],
    "constraints": [{"type": "distance", "bodies": ["world", "bob"], "length": 1.0},
                    {"type": "distance", "bodies": ["world", "bob"], "length": 1.0}]})"));
  EXPECT_EQ(c.rank, 1);
  EXPECT_EQ(c.degrees_of_freedom, 1);
  ASSERT_EQ(c.redundant_constraints.size(), 1u);  // either copy may be named; exactly one of them
  EXPECT_TRUE(c.redundant_constraints[0] == 0 || c.redundant_constraints[0] == 1);
}

// A straight chain of n unit particles on 1 m links from the origin along x, its first link doubled when
// `duplicate` (rows n + 1, rank n).
std::string StraightChain(int n, bool duplicate) {
  std::string bodies, constraints;
  for (int k = 0; k < n; ++k) {
    const std::string name = "p" + std::to_string(k), previous = k ? "p" + std::to_string(k - 1) : "world";
    bodies += std::string(k ? ", " : "") + R"({"name": ")" + name + R"(", "type": "particle", "mass": 1.0, "position": [)" +
              std::to_string(k + 1) + ", 0.0]}";
    const std::string link = R"({"type": "distance", "bodies": [")" + previous + R"(", ")" + name + R"("], "length": 1.0})";
    constraints += std::string(k ? ", " : "") + link + (k == 0 && duplicate ? ", " + link : "");
  }
  return R"({"bodies": [)" + bodies + R"(], "constraints": [)" + constraints + "]}";
}

// Above kDenseCheckRows rows the sparse path (SuiteSparseQR, power and inverse iteration) gives the rank and
// the redundant rows exactly, and the condition number of the path graph's incidence matrix: for a chain of n
// unit links fixed at one end, S = J J^T is the tridiagonal (2, -1) with a last diagonal entry 1, whose
// eigenvalues are 2 - 2 cos((2j - 1) pi / (2 n + 1)), j = 1..n.
TEST(SceneCheck, LargeSystemsTakeTheSparsePathWithTheSameAnswers) {
  const int n = kDenseCheckRows + 100;
  const SceneCheck plain = CheckScene(SceneFromJson(StraightChain(n, false)));
  EXPECT_TRUE(plain.condition_estimated);
  EXPECT_EQ(plain.rank, n);
  EXPECT_EQ(plain.degrees_of_freedom, n);
  EXPECT_TRUE(plain.redundant_constraints.empty());
  const double pi = std::acos(-1.0);
  auto eigenvalue = [&](int j) { return 2.0 - 2.0 * std::cos((2.0 * j - 1.0) * pi / (2.0 * n + 1.0)); };
  const double exact = std::sqrt(eigenvalue(n) / eigenvalue(1));
  EXPECT_LE(plain.condition_number, exact * (1 + 1e-12));  // a lower bound
  EXPECT_NEAR(plain.condition_number, exact, 1e-2 * exact);  // 0.4% low here

  const SceneCheck doubled = CheckScene(SceneFromJson(StraightChain(n, true)));
  EXPECT_EQ(doubled.constraint_rows, n + 1);
  EXPECT_EQ(doubled.rank, n);
  EXPECT_EQ(doubled.degrees_of_freedom, n);
  ASSERT_EQ(doubled.redundant_constraints.size(), 1u);
  EXPECT_TRUE(doubled.redundant_constraints[0] == 0 || doubled.redundant_constraints[0] == 1);
}

TEST(SceneCheck, ParallelogramGainsAFreedomWhenCollinear) {
  // generic position: 9 coordinates, 8 independent rows, 1 degree of freedom
  const SceneCheck generic = CheckScene(SceneFromJson(Parallelogram(1.0)));
  EXPECT_EQ(generic.rank, 8);
  EXPECT_EQ(generic.degrees_of_freedom, 1);
  EXPECT_TRUE(generic.redundant_constraints.empty());
  // cranks along the ground: all bars collinear, one row becomes dependent and a second freedom appears
  const SceneCheck collinear = CheckScene(SceneFromJson(Parallelogram(0.0)));
  EXPECT_EQ(collinear.rank, 7);
  EXPECT_EQ(collinear.degrees_of_freedom, 2);
  EXPECT_EQ(collinear.redundant_constraints.size(), 1u);
}

TEST(SceneCheck, NoConstraintsLeaveEveryCoordinateFree) {
  const SceneCheck c = CheckScene(SceneFromJson(R"({"dimension": 3,
    "bodies": [{"name": "a", "type": "particle", "mass": 1.0, "position": [0, 0, 0]}]})"));
  EXPECT_EQ(c.coordinates, 3);
  EXPECT_EQ(c.rank, 0);
  EXPECT_EQ(c.degrees_of_freedom, 3);
  EXPECT_EQ(c.worst_constraint, -1);
}

TEST(SceneCheck, ReportsTheInitialViolation) {
  Model<double> model = testing::Pendulum60();
  model.bodies[0].position[0] += 0.01;  // 1 cm along x, off a 0.7 m rod
  const SceneCheck c = CheckScene(model);
  const double moved = std::hypot(model.bodies[0].position[0], model.bodies[0].position[1]) - 0.7;
  EXPECT_NEAR(c.initial_violation, std::abs(moved), 1e-12);
  EXPECT_EQ(c.worst_constraint, 0);
}

TEST(SceneCheck, CommandLinePrintsJsonAndText) {
  const testing::TempFolder folder("tether_check");
  const std::string scene = folder.Write("parallelogram.json", Parallelogram(0.0));
  const testing::Outcome json = testing::RunTether("check '" + scene + "' --json", folder);
  ASSERT_EQ(json.status, 0) << json.err;
  const nlohmann::json out = nlohmann::json::parse(json.out);
  EXPECT_EQ(out["degrees_of_freedom"], 2);
  EXPECT_EQ(out["rank"], 7);
  EXPECT_EQ(out["redundant_constraints"].size(), 1u);
  const testing::Outcome text = testing::RunTether("check '" + scene + "'", folder);
  ASSERT_EQ(text.status, 0) << text.err;
  EXPECT_NE(text.out.find("2 degrees of freedom"), std::string::npos) << text.out;
  const testing::Outcome missing = testing::RunTether("check '" + folder.Path("absent.json") + "'", folder);
  EXPECT_EQ(missing.status, 2);
  EXPECT_NE(missing.err.find("absent.json"), std::string::npos) << missing.err;
}

}  // namespace
}  // namespace tether
