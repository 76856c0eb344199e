// The scene reader: every validation error names the file and the JSON Pointer of the offending value (or the
// line and column of a syntax error), and the documented defaults are filled in.
#include "tether/dynamics/io/scene_reader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <typeinfo>
#include <vector>

#include "tether/dynamics/model/configuration_space.h"
#include "tether/dynamics/model/errors.h"

namespace tether {
namespace {

// Parses scene text as the file "bad.json" would be read.
Model<double> Parse(const std::string& text) { return ParseScene(ParseJsonText(text, "bad.json"), "bad.json").model; }

// The message of the InputError that `text` raises ("" if it parses).
std::string ErrorOf(const std::string& text) {
  try {
    Parse(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// A valid one-particle 2D body list, to build bad scenes around.
const char* kParticle = R"({"name": "a", "type": "particle", "mass": 1.0, "position": [0.0, 0.0]})";
const char* kWheel = R"({"name": "w", "type": "rigid", "mass": 1.0, "inertia": 0.5, "position": [1.0, 0.0]})";

std::string WithBodies(const std::string& rest = "") {
  return std::string(R"({"bodies": [)") + kParticle + ", " + kWheel + "]" + (rest.empty() ? "" : ", " + rest) + "}";
}

struct BadScene {
  const char* name;
  std::string text;
  std::string pointer;  // the message must start with "bad.json: " + pointer + ": "
  std::string word;     // and contain this
};

void PrintTo(const BadScene& s, std::ostream* out) { *out << s.name; }

class SceneReaderRejects : public ::testing::TestWithParam<BadScene> {};

TEST_P(SceneReaderRejects, NamingTheJsonPointer) {
  const BadScene& bad = GetParam();
  const std::string message = ErrorOf(bad.text);
  ASSERT_FALSE(message.empty()) << "the scene was accepted: " << bad.text;
  EXPECT_EQ(message.rfind("bad.json: " + bad.pointer + ": ", 0), 0u) << message;
  EXPECT_NE(message.find(bad.word), std::string::npos) << message;
}

const std::vector<BadScene> kBadScenes = {
    // unknown keys, at every level
    {"unknown_top_level_key", WithBodies(R"("bodys": [])"), "/bodys", "unknown key 'bodys'"},
    {"unknown_body_key",
     R"({"bodies": [{"name": "a", "type": "particle", "mass": 1, "position": [0, 0], "colour": 1}]})",
     "/bodies/0/colour", "unknown key"},
    {"unknown_constraint_key", WithBodies(R"("constraints": [{"type": "pin", "bodies": ["world", "a"], "stiff": 1}])"),
     "/constraints/0/stiff", "unknown key"},
    {"unknown_effect_key", WithBodies(R"("effects": [{"type": "gravity", "acceleration": [0, -1], "g": 1}])"),
     "/effects/0/g", "unknown key"},
    {"unknown_simulation_key", WithBodies(R"("simulation": {"steps": 0.01})"), "/simulation/steps", "unknown key"},
    {"unknown_stabilization_key", WithBodies(R"("stabilization": {"gamma": 1})"), "/stabilization/gamma",
     "unknown key"},
    {"unknown_schedule_key",
     WithBodies(
         R"("effects": [{"type": "torque", "body": "w", "schedule": {"times": [0], "values": [1], "slope": 0}}])"),
     "/effects/0/schedule/slope", "unknown key"},
    {"unknown_key_is_escaped", WithBodies(R"("a/b~c": 1)"), "/a~1b~0c", "unknown key"},
    // wrong types
    {"mass_is_a_string", R"({"bodies": [{"name": "a", "type": "particle", "mass": "heavy", "position": [0, 0]}]})",
     "/bodies/0/mass", "expected a number, got a string"},
    {"bodies_not_an_array", R"({"bodies": {"a": 1}})", "/bodies", "expected an array"},
    {"name_is_a_number", R"({"bodies": [{"name": 3, "type": "particle", "mass": 1, "position": [0, 0]}]})",
     "/bodies/0/name", "expected a string"},
    {"position_component_is_null",
     R"({"bodies": [{"name": "a", "type": "particle", "mass": 1, "position": [0, null]}]})", "/bodies/0/position/1",
     "expected a number, got null"},
    {"integrator_is_a_number", WithBodies(R"("simulation": {"integrator": 4})"), "/simulation/integrator",
     "expected a string"},
    {"effect_is_not_an_object", WithBodies(R"("effects": [true])"), "/effects/0", "expected an object"},
    // numbers out of range
    {"negative_mass", R"({"bodies": [{"name": "a", "type": "particle", "mass": -1, "position": [0, 0]}]})",
     "/bodies/0/mass", "must be > 0"},
    {"zero_inertia", R"({"bodies": [{"name": "w", "type": "rigid", "mass": 1, "inertia": 0, "position": [0, 0]}]})",
     "/bodies/0/inertia", "must be > 0"},
    {"dimension_four", R"({"dimension": 4, "bodies": []})", "/dimension", "must be 2 or 3"},
    {"negative_step", WithBodies(R"("simulation": {"step": -0.01})"), "/simulation/step", "must be > 0"},
    {"zero_duration", WithBodies(R"("simulation": {"duration": 0})"), "/simulation/duration", "must be > 0"},
    {"zero_tolerance", WithBodies(R"("simulation": {"tolerance": 0})"), "/simulation/tolerance", "must be > 0"},
    {"zero_length", WithBodies(R"("constraints": [{"type": "distance", "bodies": ["world", "w"], "length": 0}])"),
     "/constraints/0/length", "must be > 0"},
    {"negative_damping", WithBodies(R"("effects": [{"type": "damping", "coefficient": -0.1}])"),
     "/effects/0/coefficient", "must be >= 0"},
    {"negative_angular_damping",
     WithBodies(R"("effects": [{"type": "damping", "coefficient": 0, "angular_coefficient": -1}])"),
     "/effects/0/angular_coefficient", "must be >= 0"},
    {"negative_stiffness",
     WithBodies(R"("effects": [{"type": "spring", "bodies": ["world", "a"], "points": [[1, 0], [0, 0]],
                               "stiffness": -5, "rest_length": 1}])"),
     "/effects/0/stiffness", "must be >= 0"},
    {"negative_alpha", WithBodies(R"("stabilization": {"method": "baumgarte", "alpha": -1, "beta": 1})"),
     "/stabilization/alpha", "must be >= 0"},
    {"coincident_distance_points",
     WithBodies(R"("constraints": [{"type": "distance", "bodies": ["world", "a"], "length": 1}])"), "/constraints/0",
     "the two points start at the same place"},
    // wrong vector lengths
    {"position_of_three_in_2d", R"({"bodies": [{"name": "a", "type": "particle", "mass": 1, "position": [0, 0, 0]}]})",
     "/bodies/0/position", "expected 2 numbers"},
    {"position_of_two_in_3d",
     R"({"dimension": 3, "bodies": [{"name": "a", "type": "particle", "mass": 1, "position": [0, 0]}]})",
     "/bodies/0/position", "expected 3 numbers"},
    {"velocity_of_one",
     R"({"bodies": [{"name": "a", "type": "particle", "mass": 1, "position": [0, 0], "velocity": [1]}]})",
     "/bodies/0/velocity", "expected 2 numbers"},
    {"gravity_of_three", WithBodies(R"("effects": [{"type": "gravity", "acceleration": [0, 0, -9.81]}])"),
     "/effects/0/acceleration", "expected 2 numbers"},
    {"point_of_three",
     WithBodies(R"("constraints": [{"type": "pin", "bodies": ["world", "a"], "points": [[0, 0], [0, 0, 0]]}])"),
     "/constraints/0/points/1", "expected 2 numbers"},
    {"one_point", WithBodies(R"("constraints": [{"type": "pin", "bodies": ["world", "a"], "points": [[0, 0]]}])"),
     "/constraints/0/points", "expected two points"},
    {"axis_of_one", WithBodies(R"("constraints": [{"type": "slider", "bodies": ["world", "a"], "axis": [1]}])"),
     "/constraints/0/axis", "expected 2 numbers"},
    {"three_bodies", WithBodies(R"("constraints": [{"type": "pin", "bodies": ["world", "a", "w"]}])"),
     "/constraints/0/bodies", "expected two body names"},
    // names
    {"unknown_body_in_constraint", WithBodies(R"("constraints": [{"type": "distance", "bodies": ["a", "ghost"]}])"),
     "/constraints/0/bodies/1", "unknown body 'ghost'"},
    {"unknown_body_in_force", WithBodies(R"("effects": [{"type": "force", "body": "ghost", "value": [1, 0]}])"),
     "/effects/0/body", "unknown body 'ghost'"},
    {"unknown_body_in_damping",
     WithBodies(R"("effects": [{"type": "damping", "coefficient": 1, "bodies": ["a", "ghost"]}])"),
     "/effects/0/bodies/1", "unknown body 'ghost'"},
    // names are unique across bodies, constraints and markers; the message points at the repeated name and at
    // where it was first given
    {"duplicate_name", std::string(R"({"bodies": [)") + kParticle + ", " + kParticle + "]}", "/bodies/1/name",
     "duplicate name 'a' (also /bodies/0)"},
    {"world_is_reserved", R"({"bodies": [{"name": "world", "type": "particle", "mass": 1, "position": [0, 0]}]})",
     "/bodies/0/name", "reserved"},
    {"same_body_twice", WithBodies(R"("constraints": [{"type": "pin", "bodies": ["a", "a"]}])"),
     "/constraints/0/bodies", "must differ"},
    // bodies and effects that do not fit
    // a rigid body in 3D is a 3D rigid body: a planar body's scalar inertia and angle do not fit it, and the
    // joints that hold orientations need dimension 3
    {"planar_inertia_in_3d",
     R"({"dimension": 3, "bodies": [{"name": "w", "type": "rigid", "mass": 1, "inertia": 1, "position": [0, 0, 0]}]})",
     "/bodies/0/inertia", "expected an array"},
    {"planar_angle_in_3d",
     R"({"dimension": 3, "bodies": [{"name": "w", "type": "rigid", "mass": 1, "inertia": [1, 1, 1],
                                    "position": [0, 0, 0], "angle": 0.5}]})",
     "/bodies/0/angle", "unknown key"},
    {"hinge_in_2d", WithBodies(R"("constraints": [{"type": "hinge", "bodies": ["world", "w"], "axis": [1, 0]}])"),
     "/constraints/0/type", "dimension 3"},
    // a double hinge whose axis lines meet is a universal joint; a range is [low, high]
    {"double_hinge_lines_meet",
     R"({"dimension": 3, "bodies": [{"name": "w", "type": "rigid", "mass": 1, "inertia": [1, 1, 1], "position": [0, 0, 0]}],
         "constraints": [{"type": "double_hinge", "bodies": ["world", "w"], "points": [[0, 0, 0.1], [0, 0.2, 0.1]],
                          "axes": [[0, 0, 1], [0, 1, 0]]}]})",
     "/constraints/0", "the two axis lines meet at the start: a double_hinge needs them apart (this is a universal"},
    {"double_hinge_on_one_line",
     R"({"dimension": 3, "bodies": [{"name": "w", "type": "rigid", "mass": 1, "inertia": [1, 1, 1], "position": [0, 0, 0]}],
         "constraints": [{"type": "double_hinge", "bodies": ["world", "w"], "points": [[0, 0, 0.1], [0, 0, 0.3]],
                          "axes": [[0, 0, 1], [0, 0, 2]]}]})",
     "/constraints/0", "the two axis lines coincide at the start"},
    {"range_reversed",
     R"({"dimension": 3, "bodies": [{"name": "w", "type": "rigid", "mass": 1, "inertia": [1, 1, 1], "position": [0, 0, 0]}],
         "constraints": [{"type": "hinge", "bodies": ["world", "w"], "axis": [0, 0, 1], "range": [1, 0]}]})",
     "/constraints/0/range", "low 1 must not exceed high 0"},
    {"range_on_a_universal",
     R"({"dimension": 3, "bodies": [{"name": "w", "type": "rigid", "mass": 1, "inertia": [1, 1, 1], "position": [0, 0, 0]}],
         "constraints": [{"type": "universal", "bodies": ["world", "w"], "axes": [[0, 0, 1], [0, 1, 0]], "range": [0, 1]}]})",
     "/constraints/0/range", "unknown key"},
    {"torque_on_a_particle", WithBodies(R"("effects": [{"type": "torque", "body": "a", "value": 1}])"),
     "/effects/0/body", "particle"},
    {"schedule_times_not_increasing",
     WithBodies(
         R"("effects": [{"type": "torque", "body": "w", "schedule": {"times": [0, 1, 1], "values": [1, 2, 3]}}])"),
     "/effects/0/schedule/times/2", "increase"},
    {"schedule_value_count",
     WithBodies(R"("effects": [{"type": "force", "body": "a", "schedule": {"times": [0, 1], "values": [[1, 0]]}}])"),
     "/effects/0/schedule/values", "expected 2 values"},
    {"schedule_value_length",
     WithBodies(
         R"("effects": [{"type": "force", "body": "a", "schedule": {"times": [0, 1], "values": [[1, 0], [1]]}}])"),
     "/effects/0/schedule/values/1", "expected 2 numbers"},
    {"value_and_schedule",
     WithBodies(
         R"("effects": [{"type": "torque", "body": "w", "value": 1, "schedule": {"times": [0], "values": [1]}}])"),
     "/effects/0", "exactly one of 'value' and 'schedule'"},
    {"neither_value_nor_schedule", WithBodies(R"("effects": [{"type": "force", "body": "a"}])"), "/effects/0",
     "exactly one of 'value' and 'schedule'"},
    // names of methods
    {"bad_integrator", WithBodies(R"("simulation": {"integrator": "rk9"})"), "/simulation/integrator",
     "unknown integrator 'rk9'"},
    {"bad_stabilization", WithBodies(R"("stabilization": {"method": "magic"})"), "/stabilization/method",
     "unknown stabilization method 'magic'"},
    {"bad_solver", WithBodies(R"("simulation": {"solver": "qr"})"), "/simulation/solver", "unknown solver 'qr'"},
    {"bad_body_type", R"({"bodies": [{"name": "a", "type": "blob", "mass": 1, "position": [0, 0]}]})", "/bodies/0/type",
     "unknown body type 'blob'"},
    {"bad_constraint_type", WithBodies(R"("constraints": [{"type": "glue", "bodies": ["world", "a"]}])"),
     "/constraints/0/type", "unknown constraint type 'glue'"},
    {"bad_effect_type", WithBodies(R"("effects": [{"type": "magnetism"}])"), "/effects/0/type",
     "unknown effect type 'magnetism'"},
    // gains
    {"alpha_without_beta", WithBodies(R"("stabilization": {"method": "baumgarte", "alpha": 1})"), "/stabilization",
     "give both 'alpha' and 'beta'"},
    {"beta_without_alpha", WithBodies(R"("stabilization": {"beta": 1})"), "/stabilization",
     "give both 'alpha' and 'beta'"},
    {"gains_with_projection", WithBodies(R"("stabilization": {"method": "projection", "alpha": 1, "beta": 1})"),
     "/stabilization/alpha", "baumgarte"},
    // missing
    {"no_bodies", R"({"dimension": 2})", "(top level)", "missing required key 'bodies'"},
    {"empty_bodies", R"({"bodies": []})", "/bodies", "at least one body"},
    {"missing_mass", R"({"bodies": [{"name": "a", "type": "particle", "position": [0, 0]}]})", "/bodies/0",
     "missing required key 'mass'"},
};

INSTANTIATE_TEST_SUITE_P(SceneReader, SceneReaderRejects, ::testing::ValuesIn(kBadScenes),
                         [](const ::testing::TestParamInfo<BadScene>& info) { return std::string(info.param.name); });

TEST(SceneReader, SyntaxErrorNamesLineAndColumn) {
  // the second comma on line 3 is at column 18
  const std::string message = ErrorOf("{\n  \"bodies\": [\n    {\"name\": \"a\",, }\n  ]\n}\n");
  EXPECT_EQ(message.rfind("bad.json: line 3, column 18: ", 0), 0u) << message;
  // an unfinished document stops at its end
  const std::string unfinished = ErrorOf(R"({"dimension": 2, "bodies": [)");
  EXPECT_EQ(unfinished.rfind("bad.json: line 1, column ", 0), 0u) << unfinished;
}

TEST(SceneReader, NestingDeeperThanTheLimitIsRefusedBeforeParsing) {
  // 100000 brackets would exhaust the stack of a recursive parser (found by fuzz/scene_reader_fuzzer.cc); the
  // object is level 1, so the 256th bracket opens level 257
  const std::string deep = ErrorOf("{\"a\": " + std::string(100000, '['));
  EXPECT_EQ(deep.rfind("bad.json: line 1, column " + std::to_string(6 + kMaxJsonDepth) + ": ", 0), 0u) << deep;
  EXPECT_NE(deep.find("nested deeper than 256 levels"), std::string::npos) << deep;
  // brackets inside strings (escaped quotes included) do not count
  const std::string in_strings = "{\"name\": \"\\\"" + std::string(1000, '[') + "\"}";
  EXPECT_EQ(ErrorOf(in_strings).find("nested deeper"), std::string::npos) << ErrorOf(in_strings);
  // at the limit the JSON is read (and then judged as a scene)
  const std::string at_limit = std::string(kMaxJsonDepth, '[') + std::string(kMaxJsonDepth, ']');
  EXPECT_NE(ErrorOf(at_limit).find("expected an object"), std::string::npos) << ErrorOf(at_limit);
}

TEST(SceneReader, ControlCharactersInTheInputAreEscapedInMessages) {
  // a key holding NUL, ESC (a colour escape sequence) and a line break: the message keeps all of the key after
  // the NUL and carries no control character, so it can neither be cut short nor drive the terminal
  const std::string message = ErrorOf(WithBodies(R"("x\u0000y\u001b[31mz\nw": 1)"));
  EXPECT_NE(message.find("unknown key 'x\\u0000y\\u001b[31mz\\u000aw'"), std::string::npos) << message;
  for (const char c : message) EXPECT_FALSE(static_cast<unsigned char>(c) < 0x20 || c == 0x7f) << message;
  EXPECT_EQ(Printable(std::string("a\0b\x7f\x1b", 5)), "a\\u0000b\\u007f\\u001b");
  EXPECT_EQ(Printable("caf\xc3\xa9 \\ ok"), "caf\xc3\xa9 \\ ok");  // UTF-8 and backslashes pass through
}

TEST(SceneReader, NumberOverflowIsAnInputError) {
  // valid JSON syntax, but 1e400 is no double: an InputError naming the file, like any other bad number
  try {
    ParseJsonText(R"({"bodies": [{"name": "a", "type": "particle", "mass": 1e400, "position": [0, 0]}]})", "bad.json");
    FAIL() << "1e400 was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("bad.json: ", 0), 0u) << e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "threw a " << typeid(e).name() << " instead of an InputError: " << e.what();
  }
}

TEST(SceneReader, MissingFileNamesTheFile) {
  try {
    ReadSceneFile("/nonexistent/folder/scene.json");
    FAIL() << "a missing file was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/folder/scene.json"), std::string::npos) << e.what();
  }
}

TEST(SceneReader, DefaultsOfAMinimalScene) {
  const Model<double> model =
      Parse(R"({"bodies": [{"name": "a", "type": "particle", "mass": 2.0, "position": [1, 2]}]})");
  EXPECT_EQ(model.dimension, 2);
  EXPECT_EQ(model.simulation.integrator, Integrator::kRk4);
  EXPECT_EQ(model.simulation.step, 1e-3);
  EXPECT_EQ(model.simulation.duration, 1.0);
  EXPECT_EQ(model.simulation.tolerance, 1e-8);
  EXPECT_EQ(model.simulation.solver, KktSolver::kAuto);
  // no "stabilization": Baumgarte with gains from the rule
  EXPECT_EQ(model.stabilization.method, Stabilization::kBaumgarte);
  EXPECT_TRUE(model.stabilization.gains_from_rule);
  EXPECT_EQ(model.NumConstraints(), 0);
  EXPECT_TRUE(model.gravity.empty() && model.damping.empty() && model.springs.empty() && model.forces.empty() &&
              model.torques.empty());
  ASSERT_EQ(model.bodies.size(), 1u);
  EXPECT_EQ(model.bodies[0].mass, 2.0);
  EXPECT_EQ(model.bodies[0].position, Vec3<double>(1, 2, 0));
  EXPECT_EQ(model.bodies[0].velocity, Vec3<double>::Zero());  // velocity defaults to 0
  const State<double> initial = InitialState(model);
  EXPECT_EQ(initial.q, (VecX<double>(2) << 1, 2).finished());
  EXPECT_EQ(initial.v, VecX<double>::Zero(2));
}

TEST(SceneReader, LayoutOfCoordinates) {
  const Model<double> model = Parse(WithBodies());
  ASSERT_EQ(model.bodies.size(), 2u);
  EXPECT_EQ(model.bodies[0].kind, BodyKind::kParticle);
  EXPECT_EQ(model.bodies[0].q_offset, 0);
  EXPECT_EQ(model.bodies[0].q_size, 2);
  EXPECT_EQ(model.bodies[0].v_offset, 0);
  EXPECT_EQ(model.bodies[0].v_size, 2);
  EXPECT_EQ(model.bodies[1].kind, BodyKind::kPlanar);
  EXPECT_EQ(model.bodies[1].q_offset, 2);
  EXPECT_EQ(model.bodies[1].q_size, 3);
  EXPECT_EQ(model.bodies[1].v_offset, 2);
  EXPECT_EQ(model.bodies[1].v_size, 3);
  EXPECT_EQ(model.bodies[1].inertia, 0.5);
  EXPECT_EQ(model.NumCoordinates(), 5);
  EXPECT_EQ(model.NumVelocities(), 5);
  // the wheel's angle and angular velocity default to 0
  EXPECT_EQ(model.bodies[1].angle, 0.0);
  EXPECT_EQ(model.bodies[1].angular_velocity, Vec3<double>::Zero());
  const State<double> initial = InitialState(model);
  EXPECT_EQ(initial.q, (VecX<double>(5) << 0, 0, 1, 0, 0).finished());
  EXPECT_EQ(initial.v, VecX<double>::Zero(5));
}

TEST(SceneReader, GivenSettingsAndGains) {
  const Model<double> model = Parse(WithBodies(R"(
    "dimension": 2,
    "simulation": {"integrator": "symplectic_euler", "step": 0.02, "duration": 3.5, "tolerance": 1e-6,
                   "solver": "sparse"},
    "stabilization": {"method": "baumgarte", "alpha": 4.0, "beta": 9.0})"));
  EXPECT_EQ(model.simulation.integrator, Integrator::kSymplecticEuler);
  EXPECT_EQ(model.simulation.step, 0.02);
  EXPECT_EQ(model.simulation.duration, 3.5);
  EXPECT_EQ(model.simulation.tolerance, 1e-6);
  EXPECT_EQ(model.simulation.solver, KktSolver::kSparse);
  EXPECT_FALSE(model.stabilization.gains_from_rule);
  EXPECT_EQ(model.stabilization.alpha, 4.0);
  EXPECT_EQ(model.stabilization.beta, 9.0);
  // a method without gains keeps the rule for baumgarte, and names the method otherwise
  EXPECT_TRUE(Parse(WithBodies(R"("stabilization": {"method": "baumgarte"})")).stabilization.gains_from_rule);
  EXPECT_EQ(Parse(WithBodies(R"("stabilization": {"method": "projection"})")).stabilization.method,
            Stabilization::kProjection);
  EXPECT_EQ(Parse(WithBodies(R"("stabilization": {"method": "none"})")).stabilization.method, Stabilization::kNone);
}

TEST(SceneReader, DistanceLengthDefaultsToTheInitialDistance) {
  // particle a at the origin; wheel w at (1, 0) turned by 90 degrees, so its local point (0, 2) is at (-1, 0)
  const Model<double> model = Parse(R"({"bodies": [
      {"name": "a", "type": "particle", "mass": 1.0, "position": [0.0, 0.0]},
      {"name": "w", "type": "rigid", "mass": 1.0, "inertia": 0.5, "position": [1.0, 0.0], "angle": 1.5707963267948966},
      {"name": "b", "type": "particle", "mass": 1.0, "position": [3.0, 4.0]}],
    "constraints": [{"type": "distance", "bodies": ["a", "b"]},
                    {"type": "distance", "bodies": ["world", "w"], "points": [[-1.0, 3.0], [0.0, 2.0]]},
                    {"type": "distance", "bodies": ["a", "b"], "length": 2.5}]})");
  ASSERT_EQ(model.joints.size(), 3u);
  for (const Joint<double>& joint : model.joints) EXPECT_EQ(joint.type, JointType::kDistance);
  EXPECT_NEAR(model.joints[0].length, 5.0, 1e-15);
  EXPECT_NEAR(model.joints[1].length, 3.0, 1e-15);
  EXPECT_EQ(model.joints[2].length, 2.5);
  EXPECT_EQ(model.joints[1].a.body, kWorld);
  EXPECT_EQ(model.joints[1].b.body, 1);
  EXPECT_EQ(model.joints[1].b.local, Vec3<double>(0.0, 2.0, 0.0));
  EXPECT_EQ(model.joints[2].scene_index, 2);
  // coincident points with no length cannot define one
  const std::string message = ErrorOf(WithBodies(R"("constraints": [{"type": "distance", "bodies": ["world", "a"]}])"));
  EXPECT_EQ(message.rfind("bad.json: /constraints/0: ", 0), 0u) << message;
}

TEST(SceneReader, PointsDefaultToTheOrigin) {
  const Model<double> model = Parse(WithBodies(R"("constraints": [
      {"type": "pin", "bodies": ["world", "w"]},
      {"type": "slider", "bodies": ["w", "a"], "axis": [0.0, 2.0]}],
    "effects": [{"type": "force", "body": "w", "value": [1.0, 2.0]}])"));
  ASSERT_EQ(model.joints.size(), 2u);
  const Joint<double>& pin = model.joints[0];
  const Joint<double>& slider = model.joints[1];
  EXPECT_EQ(pin.type, JointType::kPin);
  EXPECT_EQ(slider.type, JointType::kSlider);
  EXPECT_EQ(pin.a.local, Vec3<double>::Zero());
  EXPECT_EQ(pin.b.local, Vec3<double>::Zero());
  EXPECT_EQ(slider.a.local, Vec3<double>::Zero());
  EXPECT_EQ(slider.b.local, Vec3<double>::Zero());
  EXPECT_EQ(slider.axis, Vec3<double>(0.0, 2.0, 0.0));
  EXPECT_EQ(slider.scene_index, 1);
  ASSERT_EQ(model.forces.size(), 1u);
  EXPECT_EQ(model.forces[0].point, Vec3<double>::Zero());
  EXPECT_EQ(model.forces[0].value, Vec3<double>(1.0, 2.0, 0.0));
  EXPECT_TRUE(model.forces[0].schedule.empty());
}

TEST(SceneReader, EffectDefaults) {
  const Model<double> model = Parse(WithBodies(R"("effects": [
      {"type": "damping", "coefficient": 0.5},
      {"type": "damping", "coefficient": 0.1, "angular_coefficient": 0.2, "bodies": ["w"]},
      {"type": "spring", "bodies": ["a", "w"], "stiffness": 10, "rest_length": 0.5},
      {"type": "torque", "body": "w", "schedule": {"times": [0, 2], "values": [1, 3]}}])"));
  ASSERT_EQ(model.damping.size(), 2u);
  EXPECT_EQ(model.damping[0].bodies, (std::vector<int>{0, 1}));  // all bodies
  EXPECT_EQ(model.damping[0].angular_coefficient, 0.0);
  EXPECT_EQ(model.damping[1].bodies, (std::vector<int>{1}));
  EXPECT_EQ(model.damping[1].angular_coefficient, 0.2);
  EXPECT_EQ(model.damping[1].scene_index, 1);
  ASSERT_EQ(model.springs.size(), 1u);
  EXPECT_EQ(model.springs[0].damping, 0.0);
  EXPECT_EQ(model.springs[0].stiffness, 10.0);
  EXPECT_EQ(model.springs[0].rest_length, 0.5);
  ASSERT_EQ(model.torques.size(), 1u);
  EXPECT_EQ(model.torques[0].schedule.times, (std::vector<double>{0, 2}));
  // a planar torque is about z
  EXPECT_EQ(model.torques[0].schedule.values, (std::vector<Vec3<double>>{Vec3<double>(0, 0, 1), Vec3<double>(0, 0, 3)}));
}

TEST(SceneReader, ThreeDimensionalVectors) {
  const Model<double> model = Parse(R"({"dimension": 3,
    "bodies": [{"name": "a", "type": "particle", "mass": 1, "position": [1, 2, 3], "velocity": [4, 5, 6]}],
    "effects": [{"type": "gravity", "acceleration": [0, 0, -9.81]}]})");
  EXPECT_EQ(model.dimension, 3);
  EXPECT_EQ(model.bodies[0].position, Vec3<double>(1, 2, 3));
  EXPECT_EQ(model.bodies[0].velocity, Vec3<double>(4, 5, 6));
  const State<double> initial = InitialState(model);
  EXPECT_EQ(initial.q, (VecX<double>(3) << 1, 2, 3).finished());
  EXPECT_EQ(initial.v, (VecX<double>(3) << 4, 5, 6).finished());
  EXPECT_EQ(model.gravity[0].acceleration, Vec3<double>(0, 0, -9.81));
}

}  // namespace
}  // namespace tether
