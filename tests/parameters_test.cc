// ParameterSet (parameters.h): every differentiable JSON Pointer resolves to the model field it names, checked by
// writing a value through Field() (for double and Jet models) and reading the model field directly; Values(),
// Assign() and WriteInto() round-trip; pointers that are missing, name arrays or non-differentiable leaves, are
// malformed or repeated are refused with an InputError naming the file and the pointer.
#include "tether/autodiff/parameters.h"

#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <vector>

#include "tether/dynamics/io/scene_reader.h"
#include "tether/dynamics/model/errors.h"

namespace tether {
namespace {

using nlohmann::json;

constexpr const char* kPath = "parameters_scene.json";

// A planar scene with one element of every kind. Scene indices differ from positions in the model's per-kind
// lists on purpose (gravity is /effects/1 but gravity[0]; the second force is /effects/4 but forces[1]), so
// that a resolver mixing them up is caught; every built-in constraint is a joint (model.joints, in scene
// order). The initial state is held per body (position, angle, velocity, angular_velocity; a planar body's
// angular velocity and a planar torque are z components). Body s leaves velocity and angular velocity to
// their defaults.
const char* kSceneText = R"({
  "dimension": 2,
  "bodies": [
    {"name": "p", "type": "particle", "mass": 1.25, "position": [1.1, -0.2], "velocity": [0.31, -0.32]},
    {"name": "r", "type": "rigid", "mass": 2.5, "inertia": 0.15, "position": [0.4, 0.6], "angle": 0.35,
     "velocity": [0.41, 0.42], "angular_velocity": 1.7},
    {"name": "s", "type": "rigid", "mass": 0.75, "inertia": 0.05, "position": [0.9, 1.1], "angle": -0.2}
  ],
  "constraints": [
    {"type": "distance", "bodies": ["world", "p"], "points": [[0.1, 0.2], [0.01, 0.02]], "length": 1.05},
    {"type": "pin", "bodies": ["r", "s"], "points": [[0.3, 0.4], [-0.31, -0.41]]},
    {"type": "slider", "bodies": ["world", "s"], "points": [[0.5, 0.6], [0.07, 0.08]], "axis": [1.0, 0.5]},
    {"type": "distance", "bodies": ["p", "s"], "points": [[0.03, 0.04], [0.05, 0.06]], "length": 1.3}
  ],
  "effects": [
    {"type": "damping", "coefficient": 0.3, "angular_coefficient": 0.2},
    {"type": "gravity", "acceleration": [0.5, -9.81]},
    {"type": "spring", "bodies": ["p", "r"], "points": [[0.11, 0.12], [0.13, 0.14]], "stiffness": 40.0,
     "rest_length": 0.9, "damping": 0.6},
    {"type": "force", "body": "r", "point": [0.21, 0.22], "value": [1.5, -2.5]},
    {"type": "force", "body": "p", "point": [0.23, 0.24],
     "schedule": {"times": [0.0, 0.5, 1.0], "values": [[1.0, 2.0], [3.0, 4.0], [5.0, 6.0]]}},
    {"type": "torque", "body": "r", "value": 0.7},
    {"type": "torque", "body": "s", "schedule": {"times": [0.0, 1.0], "values": [0.1, 0.2]}}
  ],
  "simulation": {"integrator": "rk4", "step": 0.001, "duration": 0.5},
  "stabilization": {"method": "baumgarte", "alpha": 12.0, "beta": 36.0}
})";

Scene TestScene() { return ParseScene(ParseJsonText(kSceneText, kPath), kPath); }

// A differentiable pointer and the model field it must name, for both scalars.
struct Expected {
  std::string pointer;
  std::function<double&(Model<double>&)> in_double;
  std::function<Jet&(Model<Jet>&)> in_jet;
};
#define TETHER_EXPECT_FIELD(pointer, expression)                                              \
  Expected {                                                                                  \
    pointer, [](Model<double>& m) -> double& { return expression; },                          \
        [](Model<Jet>& m) -> Jet& { return expression; }                                      \
  }

std::vector<Expected> AllKinds() {
  return {
      // bodies
      TETHER_EXPECT_FIELD("/bodies/0/mass", m.bodies[0].mass),
      TETHER_EXPECT_FIELD("/bodies/1/mass", m.bodies[1].mass),
      TETHER_EXPECT_FIELD("/bodies/1/inertia", m.bodies[1].inertia),
      TETHER_EXPECT_FIELD("/bodies/2/inertia", m.bodies[2].inertia),
      TETHER_EXPECT_FIELD("/bodies/0/position/1", m.bodies[0].position[1]),
      TETHER_EXPECT_FIELD("/bodies/1/position/0", m.bodies[1].position[0]),
      TETHER_EXPECT_FIELD("/bodies/2/position/1", m.bodies[2].position[1]),
      TETHER_EXPECT_FIELD("/bodies/1/angle", m.bodies[1].angle),
      TETHER_EXPECT_FIELD("/bodies/2/angle", m.bodies[2].angle),
      TETHER_EXPECT_FIELD("/bodies/0/velocity/0", m.bodies[0].velocity[0]),
      TETHER_EXPECT_FIELD("/bodies/1/velocity/1", m.bodies[1].velocity[1]),
      TETHER_EXPECT_FIELD("/bodies/1/angular_velocity", m.bodies[1].angular_velocity[2]),
      // constraints
      TETHER_EXPECT_FIELD("/constraints/0/length", m.joints[0].length),
      TETHER_EXPECT_FIELD("/constraints/3/length", m.joints[3].length),
      TETHER_EXPECT_FIELD("/constraints/0/points/0/1", m.joints[0].a.local[1]),
      TETHER_EXPECT_FIELD("/constraints/3/points/1/0", m.joints[3].b.local[0]),
      TETHER_EXPECT_FIELD("/constraints/1/points/0/0", m.joints[1].a.local[0]),
      TETHER_EXPECT_FIELD("/constraints/1/points/1/1", m.joints[1].b.local[1]),
      TETHER_EXPECT_FIELD("/constraints/2/points/0/1", m.joints[2].a.local[1]),
      TETHER_EXPECT_FIELD("/constraints/2/points/1/0", m.joints[2].b.local[0]),
      TETHER_EXPECT_FIELD("/constraints/2/axis/0", m.joints[2].axis[0]),
      TETHER_EXPECT_FIELD("/constraints/2/axis/1", m.joints[2].axis[1]),
      // effects
      TETHER_EXPECT_FIELD("/effects/1/acceleration/0", m.gravity[0].acceleration[0]),
      TETHER_EXPECT_FIELD("/effects/1/acceleration/1", m.gravity[0].acceleration[1]),
      TETHER_EXPECT_FIELD("/effects/0/coefficient", m.damping[0].coefficient),
      TETHER_EXPECT_FIELD("/effects/0/angular_coefficient", m.damping[0].angular_coefficient),
      TETHER_EXPECT_FIELD("/effects/2/stiffness", m.springs[0].stiffness),
      TETHER_EXPECT_FIELD("/effects/2/rest_length", m.springs[0].rest_length),
      TETHER_EXPECT_FIELD("/effects/2/damping", m.springs[0].damping),
      TETHER_EXPECT_FIELD("/effects/2/points/0/1", m.springs[0].a.local[1]),
      TETHER_EXPECT_FIELD("/effects/2/points/1/0", m.springs[0].b.local[0]),
      TETHER_EXPECT_FIELD("/effects/3/value/0", m.forces[0].value[0]),
      TETHER_EXPECT_FIELD("/effects/3/value/1", m.forces[0].value[1]),
      TETHER_EXPECT_FIELD("/effects/3/point/1", m.forces[0].point[1]),
      TETHER_EXPECT_FIELD("/effects/4/point/0", m.forces[1].point[0]),
      TETHER_EXPECT_FIELD("/effects/4/schedule/values/1/0", m.forces[1].schedule.values[1][0]),
      TETHER_EXPECT_FIELD("/effects/4/schedule/values/2/1", m.forces[1].schedule.values[2][1]),
      TETHER_EXPECT_FIELD("/effects/5/value", m.torques[0].value[2]),
      TETHER_EXPECT_FIELD("/effects/6/schedule/values/1", m.torques[1].schedule.values[1][2]),
      // stabilization
      TETHER_EXPECT_FIELD("/stabilization/alpha", m.stabilization.alpha),
      TETHER_EXPECT_FIELD("/stabilization/beta", m.stabilization.beta),
  };
}

std::vector<std::string> Pointers(const std::vector<Expected>& expected) {
  std::vector<std::string> pointers;
  for (const Expected& e : expected) pointers.push_back(e.pointer);
  return pointers;
}

// A value no field of the scene holds, distinct per parameter.
double Sentinel(int i) { return 100.0 + 0.25 * i; }

TEST(Parameters, ValuesAreTheSceneFileNumbers) {
  const Scene scene = TestScene();
  const std::vector<Expected> expected = AllKinds();
  const ParameterSet parameters(scene, Pointers(expected));
  ASSERT_EQ(parameters.size(), static_cast<int>(expected.size()));
  EXPECT_EQ(parameters.pointers(), Pointers(expected));
  const std::vector<double> values = parameters.Values(scene.model);
  ASSERT_EQ(values.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    // exact: the model holds the file's number unchanged
    EXPECT_EQ(values[i], scene.document.at(json::json_pointer(expected[i].pointer)).get<double>()) << expected[i].pointer;
  }
}

TEST(Parameters, FieldWritesTheNamedModelFieldOnly) {
  const Scene scene = TestScene();
  const std::vector<Expected> expected = AllKinds();
  const ParameterSet parameters(scene, Pointers(expected));
  for (int i = 0; i < parameters.size(); ++i) {
    Model<double> model = scene.model;
    parameters.Field(&model, i) = Sentinel(i);
    EXPECT_EQ(expected[i].in_double(model), Sentinel(i)) << expected[i].pointer;
    // no other parameter's field moved
    const std::vector<double> before = parameters.Values(scene.model), after = parameters.Values(model);
    for (int k = 0; k < parameters.size(); ++k) {
      if (k != i) EXPECT_EQ(after[k], before[k]) << expected[i].pointer << " changed " << expected[k].pointer;
    }
  }
}

TEST(Parameters, FieldOfAJetModelSeedsTheNamedField) {
  const Scene scene = TestScene();
  const std::vector<Expected> expected = AllKinds();
  const ParameterSet parameters(scene, Pointers(expected));
  const std::vector<double> values = parameters.Values(scene.model);
  for (int i = 0; i < parameters.size(); ++i) {
    Model<Jet> model = CastModel<Jet>(scene.model);
    Jet& field = parameters.Field(&model, i);
    EXPECT_EQ(field.a, values[i]) << expected[i].pointer;
    field.v[i % kJetStride] = 1.0;
    const Jet& named = expected[i].in_jet(model);
    EXPECT_EQ(&named, &field) << expected[i].pointer;  // the very same field
    EXPECT_EQ(named.v[i % kJetStride], 1.0) << expected[i].pointer;
  }
}

TEST(Parameters, AssignAndValuesRoundTrip) {
  const Scene scene = TestScene();
  const std::vector<Expected> expected = AllKinds();
  const ParameterSet parameters(scene, Pointers(expected));
  std::vector<double> values;
  for (int i = 0; i < parameters.size(); ++i) values.push_back(Sentinel(i));
  Model<double> model = scene.model;
  parameters.Assign(values, &model);
  EXPECT_EQ(parameters.Values(model), values);
  for (int i = 0; i < parameters.size(); ++i) EXPECT_EQ(expected[i].in_double(model), values[i]) << expected[i].pointer;
}

TEST(Parameters, WriteIntoPutsTheValuesAtTheirPointers) {
  const Scene scene = TestScene();
  const std::vector<Expected> expected = AllKinds();
  const ParameterSet parameters(scene, Pointers(expected));
  // small changes that keep the scene valid
  std::vector<double> values = parameters.Values(scene.model);
  for (double& v : values) v += 0.125;
  json document = scene.document;
  parameters.WriteInto(values, &document);
  for (int i = 0; i < parameters.size(); ++i) {
    EXPECT_EQ(document.at(json::json_pointer(expected[i].pointer)).get<double>(), values[i]) << expected[i].pointer;
  }
  // everything else is untouched
  EXPECT_EQ(document.at("/bodies/2/name"_json_pointer), "s");
  EXPECT_EQ(document.at("/constraints/0/points/0/0"_json_pointer).get<double>(), 0.1);
  EXPECT_EQ(document.at("/effects/4/schedule/times/1"_json_pointer).get<double>(), 0.5);
  EXPECT_EQ(document.at("/simulation/step"_json_pointer).get<double>(), 0.001);
  // the written document reads back to the same values
  const Scene written = ParseScene(document, kPath);
  EXPECT_EQ(ParameterSet(written, parameters.pointers()).Values(written.model), values);
}

// Expects ParameterSet(scene, pointers) to throw an InputError naming the file and `named`.
void ExpectRefused(const std::vector<std::string>& pointers, const std::string& named, const std::string& why) {
  const Scene scene = TestScene();
  try {
    ParameterSet parameters(scene, pointers);
    ADD_FAILURE() << named << " (" << why << ") was accepted";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(kPath), std::string::npos) << why << ": " << message;
    EXPECT_NE(message.find(named), std::string::npos) << why << ": " << message;
  }
}

TEST(Parameters, PointersNotInTheFileAreRefused) {
  ExpectRefused({"/bodies/2/velocity/0"}, "/bodies/2/velocity/0", "a defaulted velocity");
  ExpectRefused({"/bodies/2/angular_velocity"}, "/bodies/2/angular_velocity", "a defaulted angular velocity");
  ExpectRefused({"/bodies/7/mass"}, "/bodies/7/mass", "no such body");
  ExpectRefused({"/bodies/0/masss"}, "/bodies/0/masss", "a misspelt key");
  ExpectRefused({"/stabilization/gamma"}, "/stabilization/gamma", "no such gain");
}

TEST(Parameters, ArraysAndObjectsAreRefused) {
  ExpectRefused({"/bodies/0/position"}, "/bodies/0/position", "an array");
  ExpectRefused({"/constraints/0/points/1"}, "/constraints/0/points/1", "an array");
  ExpectRefused({"/effects/4/schedule"}, "/effects/4/schedule", "an object");
  ExpectRefused({"/simulation"}, "/simulation", "an object");
}

TEST(Parameters, NonDifferentiableLeavesAreRefused) {
  for (const std::string& pointer :
       {"/bodies/0/name", "/bodies/1/type", "/simulation/step", "/simulation/duration", "/simulation/integrator",
        "/effects/4/schedule/times/1", "/effects/6/schedule/times/0", "/dimension", "/stabilization/method",
        "/constraints/0/bodies/1"}) {
    ExpectRefused({pointer}, pointer, "not differentiable");
  }
}

TEST(Parameters, MalformedPointerIsRefused) {
  ExpectRefused({"bodies/0/mass"}, "bodies/0/mass", "no leading slash");
  ExpectRefused({"/bodies/0/mass", "/bodies/~2/mass"}, "/bodies/~2/mass", "a bad escape");
}

TEST(Parameters, ParameterNamedTwiceIsRefused) {
  ExpectRefused({"/bodies/0/mass", "/effects/2/stiffness", "/bodies/0/mass"}, "/bodies/0/mass", "named twice");
}

TEST(Parameters, AWildcardStandsForEveryElementOfItsArray) {
  const Scene scene = TestScene();
  const ParameterSet parameters(scene, {"/bodies/0/mass", "/effects/6/schedule/values/*", "/effects/4/schedule/values/2/*"});
  EXPECT_EQ(parameters.pointers(),
            (std::vector<std::string>{"/bodies/0/mass", "/effects/6/schedule/values/0", "/effects/6/schedule/values/1",
                                      "/effects/4/schedule/values/2/0", "/effects/4/schedule/values/2/1"}));
  EXPECT_EQ(parameters.Values(scene.model), (std::vector<double>{scene.model.bodies[0].mass, 0.1, 0.2, 5.0, 6.0}));
}

TEST(Parameters, AWildcardOnAnythingButANonEmptyArrayIsRefused) {
  ExpectRefused({"/bodies/0/mass/*"}, "/bodies/0/mass/*", "not a non-empty array");
  ExpectRefused({"/effects/9/schedule/values/*"}, "/effects/9/schedule/values/*", "not a non-empty array");
  ExpectRefused({"/*"}, "/*", "the document is not a non-empty array");
  // an element that is itself an array is named with its own index
  ExpectRefused({"/effects/4/schedule/values/*"}, "/effects/4/schedule/values/0", "names an array, not a number");
  ExpectRefused({"/effects/6/schedule/values/*", "/effects/6/schedule/values/1"}, "/effects/6/schedule/values/1",
                "named twice");
}

TEST(Parameters, EmptySetResolvesNothing) {
  const Scene scene = TestScene();
  const ParameterSet parameters(scene, {});
  EXPECT_EQ(parameters.size(), 0);
  EXPECT_TRUE(parameters.Values(scene.model).empty());
}

}  // namespace
}  // namespace tether
