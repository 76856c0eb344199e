// The scene reader's record of its numbers (io/scene_numbers.h): every bound pointer reaches the model field that
// holds the document's number there, for every scalar; every number a field holds is bound; a product of inertia
// is one field at two pointers; a schedule's values are its knots; and each number has the domain the format
// gives it.
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>

#include "test_scenes.h"
#include "tether/dynamics/io/scene_reader.h"

namespace tether {
namespace {

using nlohmann::json;

// A 3D scene with a tensor inertia, a universal joint's two axes, a limit with its restitution, a marker, every
// 3D effect (a scheduled force), every shape type with its placement and law, the contact defaults, and gains.
const char* kSpatial = R"({"dimension": 3,
  "bodies": [{"name": "a", "type": "rigid", "mass": 2.0, "inertia": [[0.03, 0.001, 0.002], [0.001, 0.04, 0.003],
              [0.002, 0.003, 0.05]], "position": [0.0, 0.0, -1.0], "orientation": [0.6, 0.8, 0.0, 0.0],
              "velocity": [0.1, 0.2, 0.3], "angular_velocity": [0.4, 0.5, 0.6]},
             {"name": "b", "type": "rigid", "mass": 1.0, "inertia": [0.01, 0.02, 0.025], "position": [0.0, 0.0, -1.5]},
             {"name": "p", "type": "particle", "mass": 0.5, "position": [0.5, 0.0, -1.5]}],
  "constraints": [{"type": "hinge", "name": "shoulder", "bodies": ["world", "a"], "points": [[0.0, 0.0, 0.0],
                   [0.0, 0.0, 1.0]], "axis": [0.0, 1.0, 0.0], "angle": 0.1, "range": [-1.0, null], "restitution": 0.5},
                  {"type": "universal", "bodies": ["a", "b"], "points": [[0.0, 0.0, -0.25], [0.0, 0.0, 0.25]],
                   "axes": [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]},
                  {"type": "distance", "bodies": ["b", "p"], "length": 0.5}],
  "effects": [{"type": "gravity", "acceleration": [0.0, 0.0, -9.81]},
              {"type": "damping", "coefficient": 0.1, "angular_coefficient": 0.01},
              {"type": "spring", "bodies": ["world", "p"], "points": [[1.0, 0.0, -0.5], [0.0, 0.0, 0.0]],
               "stiffness": 10.0, "rest_length": 0.4, "damping": 0.2},
              {"type": "force", "body": "b", "point": [0.0, 0.1, 0.0],
               "schedule": {"times": [0.0, 0.5, 1.0], "values": [[0.5, 0.0, 0.0], [0.0, 0.5, 0.0], [0.0, 0.0, 0.5]]}},
              {"type": "torque", "body": "a", "value": [0.0, 1.0, 0.0]},
              {"type": "joint_torque", "joint": "shoulder", "schedule": {"times": [0.0, 1.0], "values": [0.3, -0.3]}},
              {"type": "joint_spring", "joint": "shoulder", "stiffness": 5.0, "rest": 0.3, "damping": 0.1},
              {"type": "joint_servo", "joint": "shoulder", "kp": 8.0, "kd": 0.5, "target": 0.2, "target_rate": 0.1,
               "limit": 2.0},
              {"type": "joint_servo", "joint": "shoulder", "kp": 1.0, "kd": 0.0,
               "schedule": {"times": [0.0, 1.0], "values": [0.0, 0.4]}}],
  "markers": [{"name": "tip", "body": "b", "point": [0.0, 0.0, -0.1]}],
  "shapes": [{"name": "ball", "body": "p", "type": "sphere", "radius": 0.05, "restitution": 0.4},
             {"body": "b", "type": "capsule", "radius": 0.02, "length": 0.3, "position": [0.0, 0.0, 0.05],
              "orientation": [0.6, 0.0, 0.8, 0.0], "friction": 0.3},
             {"body": "a", "type": "box", "size": [0.1, 0.2, 0.3], "contact": false},
             {"name": "floor", "body": "world", "type": "plane", "position": [0.0, 0.0, -3.0],
              "orientation": [1.0, 0.0, 0.0, 0.0]}],
  "contact": {"friction": 0.5, "restitution": 0.1, "exclude": [["b", "world"]]},
  "simulation": {"integrator": "rk4", "step": 0.001, "duration": 0.01, "tolerance": 1e-8},
  "stabilization": {"method": "baumgarte", "alpha": 20.0, "beta": 100.0}})";

// A planar scene: a rigid body's inertia, angle and spin, a pin with its angle limit, a planar torque scheduled,
// a box and a line with their angles.
const char* kPlanar = R"({"dimension": 2,
  "bodies": [{"name": "rod", "type": "rigid", "mass": 1.0, "inertia": 0.08, "position": [0.5, 0.0], "angle": 0.2,
              "velocity": [0.0, 0.1], "angular_velocity": 0.3}],
  "constraints": [{"type": "pin", "bodies": ["world", "rod"], "points": [[0.0, 0.0], [-0.5, 0.0]], "angle": 0.0,
                   "range": [-0.5, 0.5]}],
  "effects": [{"type": "torque", "body": "rod", "schedule": {"times": [0.0, 1.0], "values": [1.0, 2.0]}},
              {"type": "torque", "body": "rod", "value": 0.5}],
  "shapes": [{"body": "rod", "type": "box", "size": [1.0, 0.1], "angle": 0.1, "position": [0.0, 0.01]},
             {"body": "world", "type": "plane", "angle": -0.2, "position": [0.0, -2.0]}]})";

std::vector<Scene> ScenesToRead() {
  std::vector<Scene> scenes = {ParseScene(json::parse(kSpatial), "spatial.json"),
                               ParseScene(json::parse(kPlanar), "planar.json")};
  for (const auto& entry : std::filesystem::directory_iterator(TETHER_SOURCE_DIR "/scenes")) {
    if (entry.path().extension() == ".json") scenes.push_back(ReadSceneFile(entry.path().string()));
  }
  return scenes;
}

TEST(SceneNumbers, EveryBoundPointerReachesTheFieldHoldingItsNumber_ForEveryScalar) {
  for (const Scene& scene : ScenesToRead()) {
    const Model<Jet> jets = CastModel<Jet>(scene.model);
    const Model<Rev> revs = CastModel<Rev>(scene.model);
    ASSERT_FALSE(scene.numbers.all().empty()) << scene.path;
    for (const auto& [pointer, number] : scene.numbers.all()) {
      const json& leaf = scene.document.at(json::json_pointer(pointer));
      ASSERT_TRUE(leaf.is_number()) << scene.path << pointer;
      const double written = leaf.get<double>(), held = number.access(scene.model);
      // a quaternion is normalised as it is read; every other number is held as written
      const double tolerance = pointer.find("/orientation/") != std::string::npos ? 1e-6 : 0.0;
      EXPECT_NEAR(held, written, tolerance) << scene.path << pointer;
      EXPECT_EQ(number.access(jets).a, held) << scene.path << pointer;
      EXPECT_EQ(number.access(revs).a, held) << scene.path << pointer;
    }
  }
}

TEST(SceneNumbers, EveryNumberAModelFieldHoldsIsBound_TheRestAreSettingsAndTimes) {
  const std::regex unbound("^/dimension$|^/simulation/|/schedule/times/");
  for (const Scene& scene : ScenesToRead()) {
    for (const std::string& pointer : testing::NumberPointers(scene.document)) {
      const bool bound = scene.numbers.Find(pointer) != nullptr;
      EXPECT_NE(bound, std::regex_search(pointer, unbound)) << scene.path << pointer;
    }
  }
}

TEST(SceneNumbers, AProductOfInertiaIsOneFieldAtItsTwoPointers) {
  const Scene scene = ParseScene(json::parse(kSpatial), "spatial.json");
  const SceneNumber* upper = scene.numbers.Find("/bodies/0/inertia/1/2");
  const SceneNumber* lower = scene.numbers.Find("/bodies/0/inertia/2/1");
  ASSERT_TRUE(upper && lower);
  EXPECT_EQ(upper->field, lower->field);
  EXPECT_EQ(scene.numbers.PointersOf(upper->field),
            (std::vector<std::string>{"/bodies/0/inertia/1/2", "/bodies/0/inertia/2/1"}));
  Model<double> model = scene.model;
  upper->access(model) = 0.004;
  EXPECT_EQ(lower->access(model), 0.004);
  EXPECT_NE(scene.numbers.Find("/bodies/0/inertia/1/1")->field, upper->field);
}

TEST(SceneNumbers, AScheduleValueIsAKnotOfItsSchedule_ItsTimesAreNotParameters) {
  const Scene spatial = ParseScene(json::parse(kSpatial), "spatial.json");
  const SceneNumber* force = spatial.numbers.Find("/effects/3/schedule/values/1/1");
  ASSERT_TRUE(force && force->knot);
  EXPECT_EQ(force->knot->schedule, "/effects/3/schedule");
  EXPECT_EQ(force->knot->knot, 1);
  EXPECT_EQ(force->knot->component, 1);
  EXPECT_EQ(force->knot->times, (std::vector<double>{0.0, 0.5, 1.0}));
  EXPECT_EQ(spatial.numbers.Find("/effects/3/schedule/times/1"), nullptr);
  EXPECT_FALSE(spatial.numbers.Find("/effects/3/point/1")->knot);
  const Scene planar = ParseScene(json::parse(kPlanar), "planar.json");
  const SceneNumber* torque = planar.numbers.Find("/effects/0/schedule/values/1");
  ASSERT_TRUE(torque && torque->knot);
  EXPECT_EQ(torque->knot->component, 2);  // a planar torque is about z
  EXPECT_EQ(torque->access(planar.model), 2.0);
}

TEST(SceneNumbers, EachNumberHasTheDomainTheFormatGivesIt) {
  const Scene scene = ParseScene(json::parse(kSpatial), "spatial.json");
  const auto domain = [&scene](const std::string& pointer) { return scene.numbers.Find(pointer)->domain; };
  EXPECT_EQ(domain("/bodies/0/mass"), NumberDomain::kPositive);
  EXPECT_EQ(domain("/bodies/0/inertia/0/0"), NumberDomain::kPositive);
  EXPECT_EQ(domain("/bodies/0/inertia/0/1"), NumberDomain::kAny);
  EXPECT_EQ(domain("/bodies/1/inertia/2"), NumberDomain::kPositive);
  EXPECT_EQ(domain("/constraints/2/length"), NumberDomain::kPositive);
  EXPECT_EQ(domain("/constraints/0/restitution"), NumberDomain::kUnitInterval);
  EXPECT_EQ(domain("/constraints/0/range/0"), NumberDomain::kAny);
  EXPECT_EQ(scene.numbers.Find("/constraints/0/range/1"), nullptr);  // an open side is null, not a number
  EXPECT_EQ(domain("/effects/1/coefficient"), NumberDomain::kNonNegative);
  EXPECT_EQ(domain("/effects/2/rest_length"), NumberDomain::kNonNegative);
  EXPECT_EQ(domain("/effects/6/rest"), NumberDomain::kAny);
  EXPECT_EQ(domain("/effects/7/kp"), NumberDomain::kNonNegative);
  EXPECT_EQ(domain("/effects/7/kd"), NumberDomain::kNonNegative);
  EXPECT_EQ(domain("/effects/7/target"), NumberDomain::kAny);
  EXPECT_EQ(domain("/effects/7/target_rate"), NumberDomain::kAny);
  EXPECT_EQ(domain("/effects/7/limit"), NumberDomain::kPositive);
  EXPECT_EQ(domain("/effects/8/schedule/values/1"), NumberDomain::kAny);
  EXPECT_EQ(domain("/stabilization/beta"), NumberDomain::kNonNegative);
  EXPECT_EQ(domain("/bodies/0/position/2"), NumberDomain::kAny);
  EXPECT_EQ(domain("/shapes/0/radius"), NumberDomain::kPositive);
  EXPECT_EQ(domain("/shapes/0/restitution"), NumberDomain::kUnitInterval);
  EXPECT_EQ(domain("/shapes/1/length"), NumberDomain::kNonNegative);
  EXPECT_EQ(domain("/shapes/1/friction"), NumberDomain::kNonNegative);
  EXPECT_EQ(domain("/shapes/1/orientation/2"), NumberDomain::kAny);
  EXPECT_EQ(domain("/shapes/2/size/1"), NumberDomain::kPositive);
  EXPECT_EQ(domain("/contact/friction"), NumberDomain::kNonNegative);
  EXPECT_EQ(domain("/contact/restitution"), NumberDomain::kUnitInterval);
}

}  // namespace
}  // namespace tether
