// The scene an import builds from a kinematic tree (importers/import_model.h), on small trees made here: which
// constraint each list of joints becomes, that the scene starts on its constraints with the coordinates and
// rates it was given, what merges, collapses and splits, the effects, and every error and warning of the mapping.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "tether/dynamics/constraints/contact_geometry.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/io/scene_reader.h"
#include "tether/dynamics/model/errors.h"
#include "tether/importers/import_model.h"

namespace tether::importers {
namespace {

using Eigen::Vector3d;
using json = nlohmann::ordered_json;

TreeJoint Joint(const std::string& name, TreeJointType type, const Vector3d& p_LJ = Vector3d::Zero(),
                const Vector3d& axis_L = Vector3d::UnitZ()) {
  TreeJoint joint;
  joint.name = name;
  joint.type = type;
  joint.p_LJ = p_LJ;
  joint.axis_L = axis_L.normalized();
  return joint;
}
TreeJoint Hinge(const std::string& name, const Vector3d& p_LJ, const Vector3d& axis_L) {
  return Joint(name, TreeJointType::kHinge, p_LJ, axis_L);
}
TreeJoint Slide(const std::string& name, const Vector3d& axis_L) {
  return Joint(name, TreeJointType::kSlide, Vector3d::Zero(), axis_L);
}

// A link of 1 kg with moments (0.01, 0.02, 0.025) about a centre of mass 0.1 m along its x axis, placed
// `p_PL` from its parent and turned by 0.3 rad about (1, 2, 3) (so that no frame is the world's).
TreeLink Link(const std::string& name, int parent, const Vector3d& p_PL, std::vector<TreeJoint> joints,
              double mass = 1.0) {
  TreeLink link;
  link.name = name;
  link.parent = parent;
  link.p_PL = p_PL;
  link.q_PL = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Vector3d(1, 2, 3).normalized()));
  link.mass = mass;
  link.p_LC = Vector3d(0.1, 0, 0);
  if (mass > 0) link.I_C_L = Vector3d(0.01, 0.02, 0.025).asDiagonal();
  link.joints = std::move(joints);
  return link;
}

KinematicTree Tree(std::vector<TreeLink> links) {
  KinematicTree tree;
  tree.links = std::move(links);
  tree.gravity = Vector3d(0, 0, -9.81);
  return tree;
}

ImportedScene Import(const KinematicTree& tree, const ImportOptions& options = {}) {
  return SceneFromTree(tree, options, "model.xml");
}

std::vector<std::string> ConstraintTypes(const json& scene) {
  std::vector<std::string> types;
  for (const json& c : scene["constraints"]) types.push_back(c["type"]);
  return types;
}

bool Warned(const ImportedScene& imported, const std::string& words) {
  for (const std::string& w : imported.warnings) {
    if (w.find(words) != std::string::npos) return true;
  }
  return false;
}

// The first sample of a run of the imported scene: the coordinates and rates it starts with; the run must not
// have had to move the state onto the constraints.
struct Start {
  std::vector<double> coordinates, rates;
};
Start StartOf(const ImportedScene& imported) {
  Scene scene = ParseScene(nlohmann::json::parse(imported.scene.dump()), "imported");
  scene.model.simulation.duration = scene.model.simulation.step;
  Start start;
  const RunReport report = Simulate<double>(scene.model, RunOptions{}, [&start](const Sample<double>& s) {
    if (!start.coordinates.empty()) return;
    start.coordinates.assign(s.coordinates.data(), s.coordinates.data() + s.coordinates.size());
    start.rates.assign(s.coordinate_rates.data(), s.coordinate_rates.data() + s.coordinate_rates.size());
  });
  EXPECT_TRUE(report.warnings.empty()) << report.warnings.front();
  return start;
}

// A geom of `link` (-1 the world) of one type, at its link's origin.
TreeGeom Geom(const std::string& name, int link, TreeGeom::Type type) {
  TreeGeom geom;
  geom.name = name;
  geom.link = link;
  geom.type = type;
  geom.radius = 0.05;
  geom.length = 0.2;
  geom.size = Vector3d(0.1, 0.2, 0.3);
  geom.friction = 0.7;
  return geom;
}

TEST(SceneFromTree, GeomsBecomeShapesAndEveryPairOfThemMayTouch) {
  // a chain world - upper - fore - hand of boxes and a capsule over a floor: the pair rules leave out the joined
  // pairs (the floor and upper's box, fore's box and either neighbour); upper's box and hand's capsule may touch,
  // with nothing excluded or warned of
  KinematicTree tree =
      Tree({Link("upper", -1, Vector3d(0, 0, 1), {Hinge("shoulder", Vector3d::Zero(), Vector3d::UnitY())}),
            Link("fore", 0, Vector3d(0.3, 0, 0), {Hinge("elbow", Vector3d::Zero(), Vector3d::UnitY())}),
            Link("hand", 1, Vector3d(0.3, 0, 0), {Hinge("wrist", Vector3d::Zero(), Vector3d::UnitY())})});
  tree.geoms = {Geom("floor", -1, TreeGeom::Type::kPlane), Geom("upper_box", 0, TreeGeom::Type::kBox),
                Geom("fore_box", 1, TreeGeom::Type::kBox), Geom("hand_capsule", 2, TreeGeom::Type::kCapsule)};
  const ImportedScene imported = Import(tree);
  ASSERT_EQ(imported.scene["shapes"].size(), 4u);
  EXPECT_EQ(imported.scene["shapes"][3]["type"], "capsule");
  EXPECT_EQ(imported.scene["shapes"][3]["friction"], 0.7);
  EXPECT_FALSE(imported.scene.contains("contact"));
  EXPECT_TRUE(imported.warnings.empty()) << imported.warnings.front();
  const Model<double> model = ParseScene(nlohmann::json::parse(imported.scene.dump()), "imported").model;
  std::vector<std::string> pairs;
  for (const ContactPair& pair : BuildContactGeometry(model).pairs) pairs.push_back(pair.label);
  EXPECT_EQ(pairs, (std::vector<std::string>{"floor|fore_box", "floor|hand_capsule", "upper_box|hand_capsule"}));
  EXPECT_NO_THROW(ParseScene(nlohmann::json::parse(imported.scene.dump()), "imported"));
  ImportOptions drawn;  // --no-contact
  drawn.contact = false;
  const ImportedScene drawn_only = Import(tree, drawn);
  for (const json& shape : drawn_only.scene["shapes"]) EXPECT_EQ(shape["contact"], false);
}

TEST(SceneFromTree, SingleJointsKeepTheirCoordinatesAndRates) {
  TreeJoint elbow = Hinge("elbow", Vector3d(-0.1, 0.05, 0), Vector3d(0, 1, 1));
  elbow.reference = 0.2;
  elbow.range = Eigen::Vector2d(-1, 2);
  TreeJoint slide = Slide("slide", Vector3d(1, 0, 1));
  slide.reference = 0.05;
  const KinematicTree tree =
      Tree({Link("upper", -1, Vector3d(0, 0, 1), {Hinge("shoulder", Vector3d::Zero(), Vector3d::UnitY())}),
            Link("fore", 0, Vector3d(0.3, 0, 0), {elbow}), Link("tip", 1, Vector3d(0.2, 0.1, 0), {slide})});
  ImportOptions options;
  options.joint_values = {{"elbow", 0.7}, {"slide", -0.04}};
  options.joint_rates = {{"shoulder", 0.5}, {"elbow", -1.2}, {"slide", 0.3}};
  const ImportedScene imported = Import(tree, options);
  EXPECT_EQ(ConstraintTypes(imported.scene), (std::vector<std::string>{"hinge", "hinge", "prismatic"}));
  EXPECT_EQ(imported.scene["constraints"][1]["range"], json::array({-1.0, 2.0}));
  const Start start = StartOf(imported);
  ASSERT_EQ(start.coordinates.size(), 3u);
  // the shoulder at its reference 0, the elbow and the slide where --joint put them, all at their --joint-velocity
  EXPECT_NEAR(start.coordinates[0], 0.0, 1e-12);
  EXPECT_NEAR(start.coordinates[1], 0.7, 1e-12);
  EXPECT_NEAR(start.coordinates[2], -0.04, 1e-12);
  EXPECT_NEAR(start.rates[0], 0.5, 1e-12);
  EXPECT_NEAR(start.rates[1], -1.2, 1e-12);
  EXPECT_NEAR(start.rates[2], 0.3, 1e-12);
}

// The bodies' velocities from --joint-velocity are those of their placement: a central difference of the
// positions imported at coordinates q -+ e rate.
TEST(SceneFromTree, BodyVelocitiesAreTheRatesOfTheirPlacement) {
  const KinematicTree tree =
      Tree({Link("a", -1, Vector3d(0, 0, 1), {Hinge("j1", Vector3d(0.05, 0, 0), Vector3d(0, 1, 0))}),
            Link("b", 0, Vector3d(0.3, 0, 0), {Slide("j2", Vector3d(1, 1, 0))}),
            Link("c", 1, Vector3d(0.2, 0.1, 0), {Hinge("j3", Vector3d(0, 0.1, 0), Vector3d(1, 0, 1))})});
  const std::vector<std::pair<std::string, double>> rates = {{"j1", 0.8}, {"j2", -0.5}, {"j3", 1.7}};
  ImportOptions moving;
  moving.joint_values = {{"j1", 0.4}, {"j2", 0.1}, {"j3", -0.6}};
  moving.joint_rates = rates;
  const json scene = Import(tree, moving).scene;
  const double e = 1e-6;
  auto at = [&](double sign) {
    ImportOptions options;
    for (size_t k = 0; k < rates.size(); ++k) {
      options.joint_values.emplace_back(rates[k].first, moving.joint_values[k].second + sign * e * rates[k].second);
    }
    return Import(tree, options).scene;
  };
  const json plus = at(1), minus = at(-1);
  for (size_t b = 0; b < 3; ++b) {
    for (int k = 0; k < 3; ++k) {
      const double difference =
          (plus["bodies"][b]["position"][k].get<double>() - minus["bodies"][b]["position"][k].get<double>()) / (2 * e);
      EXPECT_NEAR(scene["bodies"][b]["velocity"][k].get<double>(), difference, 1e-8) << "body " << b << ", " << k;
    }
  }
}

TEST(SceneFromTree, HingesInSeriesBecomeOneExactJoint) {
  const Vector3d x = Vector3d::UnitX(), y = Vector3d::UnitY(), z = Vector3d::UnitZ();
  struct Case {
    std::vector<TreeJoint> joints;
    std::string type;
  };
  const std::vector<Case> cases = {
      {{Hinge("a", Vector3d::Zero(), z), Hinge("b", Vector3d::Zero(), y)}, "universal"},
      {{Hinge("a", Vector3d(0, 0, 0.1), z), Hinge("b", Vector3d(0, 0.2, 0.1), y)}, "universal"},  // lines meet
      {{Hinge("a", Vector3d(0, 0, 0.08), y), Hinge("b", Vector3d(0, 0, 0.04), Vector3d(1, 0, 0.5))}, "double_hinge"},
      {{Hinge("a", Vector3d(0, 0, 0.1), y), Hinge("b", Vector3d(0.2, 0, 0), y)}, "double_hinge"},  // parallel
      {{Hinge("a", Vector3d::Zero(), z), Hinge("b", Vector3d::Zero(), y), Hinge("c", Vector3d::Zero(), x)}, "pin"},
      {{Slide("a", z), Hinge("b", Vector3d(0.1, 0, 0), z)}, "cylindrical"},
      {{Hinge("a", Vector3d(0.1, 0, 0), z), Slide("b", z)}, "cylindrical"},
      {{Joint("a", TreeJointType::kBall, Vector3d(0.1, 0, 0))}, "pin"}};
  for (const Case& c : cases) {
    const KinematicTree tree = Tree({Link("body", -1, Vector3d(0, 0, 1), c.joints)});
    ImportOptions options;
    for (const TreeJoint& j : c.joints) {
      if (j.type != TreeJointType::kBall) options.joint_rates.emplace_back(j.name, 0.9);
    }
    const ImportedScene imported = Import(tree, options);
    EXPECT_EQ(ConstraintTypes(imported.scene), std::vector<std::string>{c.type}) << imported.scene.dump();
    EXPECT_FALSE(Warned(imported, "split")) << c.type;
    StartOf(imported);  // on its constraints from the start
  }
}

TEST(SceneFromTree, ACylindricalJointKeepsBothCoordinates) {
  TreeJoint slide = Slide("lift", Vector3d::UnitZ()), turn = Hinge("turn", Vector3d(0.1, 0, 0), Vector3d::UnitZ());
  slide.damping = 2.0;
  turn.stiffness = 3.0;
  KinematicTree tree = Tree({Link("body", -1, Vector3d(0, 0, 1), {slide, turn})});
  tree.motors = {{"lift_motor", "lift"}};
  ImportOptions options;
  options.joint_values = {{"lift", 0.25}, {"turn", -0.5}};
  const ImportedScene imported = Import(tree, options);
  const Start start = StartOf(imported);
  ASSERT_EQ(start.coordinates.size(), 2u);
  EXPECT_NEAR(start.coordinates[0], -0.5, 1e-12);  // angle, then displacement
  EXPECT_NEAR(start.coordinates[1], 0.25, 1e-12);
  const json& effects = imported.scene["effects"];
  EXPECT_EQ(effects[1]["coordinate"], "displacement");
  EXPECT_EQ(effects[1]["damping"], 2.0);
  EXPECT_EQ(effects[2]["coordinate"], "angle");
  EXPECT_EQ(effects[2]["stiffness"], 3.0);
  EXPECT_EQ(effects[3],
            (json{{"type", "joint_torque"}, {"joint", "lift+turn"}, {"coordinate", "displacement"}, {"value", 0.0}}));
}

TEST(SceneFromTree, JointsNoConstraintCombinesAreSplitThroughLightBodies) {
  const Vector3d z = Vector3d::UnitZ();
  const std::vector<std::vector<TreeJoint>> lists = {
      {Hinge("a", Vector3d::Zero(), z), Hinge("b", Vector3d(0, 0, 0.3), z)},                 // one line
      {Hinge("a", Vector3d::Zero(), z), Hinge("b", Vector3d(0, 0, 0.1), Vector3d::UnitY()),  // not concurrent
       Hinge("c", Vector3d(0.1, 0, 0), Vector3d::UnitX())},
      {Slide("a", z), Hinge("b", Vector3d::Zero(), -z)},  // opposite directions
      {Slide("a", Vector3d::UnitX()), Slide("b", Vector3d::UnitY())},
      {Joint("a", TreeJointType::kBall), Hinge("b", Vector3d(0.1, 0, 0), z)}};
  for (size_t k = 0; k < lists.size(); ++k) {
    const std::vector<TreeJoint>& joints = lists[k];
    const ImportedScene imported = Import(Tree({Link("body", -1, Vector3d(0, 0, 1), joints)}));
    EXPECT_EQ(imported.scene["constraints"].size(), joints.size()) << "case " << k;
    EXPECT_EQ(imported.scene["bodies"].size(), joints.size()) << "case " << k;
    EXPECT_TRUE(Warned(imported, "split")) << "case " << k;
    EXPECT_EQ(imported.scene["bodies"][1]["name"], "a_link");
    EXPECT_NEAR(imported.scene["bodies"][1]["mass"].get<double>(), 1e-6, 1e-18);
    StartOf(imported);
  }
  // --split-joints splits what could be combined, so that every joint keeps its coordinate, spring and motor
  TreeJoint a = Hinge("a", Vector3d::Zero(), z), b = Hinge("b", Vector3d::Zero(), Vector3d::UnitY());
  b.damping = 0.5;
  KinematicTree tree = Tree({Link("body", -1, Vector3d(0, 0, 1), {a, b})});
  tree.motors = {{"b", "b"}};
  ImportOptions split;
  split.split_joints = true;
  const ImportedScene imported = Import(tree, split);
  EXPECT_EQ(ConstraintTypes(imported.scene), (std::vector<std::string>{"hinge", "hinge"}));
  EXPECT_EQ(imported.scene["effects"].size(), 3u);  // gravity, b's damper, b's motor
  const ImportedScene combined = Import(tree);
  EXPECT_EQ(ConstraintTypes(combined.scene), std::vector<std::string>{"universal"});
  EXPECT_TRUE(Warned(combined, "stiffness and damping of joints without a coordinate of their own"));
  EXPECT_TRUE(Warned(combined, "motors of joints without a coordinate of their own"));
}

TEST(SceneFromTree, WeldedLinksAreWeldsOrMergedAndMasslessOnesMergeIntoMarkers) {
  TreeLink base = Link("base", -1, Vector3d(0, 0, 1), {Hinge("j", Vector3d::Zero(), Vector3d::UnitY())});
  TreeLink camera = Link("camera", 0, Vector3d(0.2, 0, 0.1), {}, 0.5);
  camera.sites = {{"lens", Vector3d(0.05, 0, 0)}};
  TreeLink tool = Link("tool", 0, Vector3d(0.4, 0, 0), {}, 0.0);
  const KinematicTree tree = Tree({base, camera, tool});
  const ImportedScene welded = Import(tree);
  EXPECT_EQ(ConstraintTypes(welded.scene), (std::vector<std::string>{"hinge", "weld"}));
  EXPECT_EQ(welded.scene["bodies"].size(), 2u);
  EXPECT_EQ(welded.scene["markers"][0]["name"], "tool");  // the massless link's frame
  EXPECT_EQ(welded.scene["markers"][0]["body"], "base");
  EXPECT_EQ(welded.scene["markers"][1]["name"], "lens");
  EXPECT_EQ(welded.scene["markers"][1]["body"], "camera");
  StartOf(welded);

  ImportOptions merge;
  merge.merge_fixed = true;
  const ImportedScene merged = Import(tree, merge);
  EXPECT_EQ(ConstraintTypes(merged.scene), std::vector<std::string>{"hinge"});
  EXPECT_EQ(merged.scene["bodies"].size(), 1u);
  EXPECT_NEAR(merged.scene["bodies"][0]["mass"].get<double>(), 1.5, 1e-15);
  EXPECT_EQ(merged.scene["markers"][0]["name"], "camera");
  // the merged centre of mass is the mass-weighted mean of the two
  const json& w = welded.scene["bodies"];
  for (int k = 0; k < 3; ++k) {
    const double mean = (1.0 * w[0]["position"][k].get<double>() + 0.5 * w[1]["position"][k].get<double>()) / 1.5;
    EXPECT_NEAR(merged.scene["bodies"][0]["position"][k].get<double>(), mean, 1e-15);
  }
}

TEST(SceneFromTree, AMasslessLinkWithJointsHandsThemToTheLinkItCarries) {
  const KinematicTree tree =
      Tree({Link("wrist", -1, Vector3d(0, 0, 1), {Hinge("roll", Vector3d::Zero(), Vector3d::UnitX())}, 0.0),
            Link("hand", 0, Vector3d(0, 0.04, 0.05), {Hinge("yaw", Vector3d::Zero(), Vector3d::UnitZ())})});
  const ImportedScene imported = Import(tree);
  EXPECT_EQ(ConstraintTypes(imported.scene), std::vector<std::string>{"double_hinge"});
  EXPECT_EQ(imported.scene["bodies"].size(), 1u);
  EXPECT_TRUE(Warned(imported, "massless links with joints are not bodies"));
  StartOf(imported);
  // carrying two links, it cannot: it weighs 1e-6 of the heaviest link instead
  KinematicTree forked = tree;
  forked.links.push_back(
      Link("thumb", 0, Vector3d(0, -0.04, 0.05), {Hinge("pinch", Vector3d::Zero(), Vector3d::UnitY())}));
  const ImportedScene weighted = Import(forked);
  EXPECT_EQ(weighted.scene["bodies"].size(), 3u);
  EXPECT_NEAR(weighted.scene["bodies"][0]["mass"].get<double>(), 1e-6, 1e-18);
  EXPECT_TRUE(Warned(weighted, "are given 1e-06 of the heaviest link's mass"));
}

TEST(SceneFromTree, FixedBodiesArePartOfTheWorld) {
  // a torso on a free joint with a head welded to it and an arm on a hinge: --fix torso makes the torso and its
  // head the world's (no body, no weld), and the arm hangs from the world where the shoulder is
  const KinematicTree tree =
      Tree({Link("torso", -1, Vector3d(0, 0, 1.5), {Joint("root", TreeJointType::kFree)}),
            Link("head", 0, Vector3d(0, 0, 0.3), {}),
            Link("arm", 0, Vector3d(0, 0.2, 0), {Hinge("shoulder", Vector3d::Zero(), Vector3d::UnitX())})});
  const ImportedScene free = Import(tree);
  EXPECT_EQ(ConstraintTypes(free.scene), (std::vector<std::string>{"weld", "hinge"}));
  EXPECT_EQ(free.scene["bodies"].size(), 3u);
  ImportOptions fix;
  fix.fixed_bodies = {"torso"};
  const ImportedScene fixed = Import(tree, fix);
  EXPECT_EQ(ConstraintTypes(fixed.scene), std::vector<std::string>{"hinge"});
  ASSERT_EQ(fixed.scene["bodies"].size(), 1u);
  EXPECT_EQ(fixed.scene["bodies"][0]["name"], "arm");
  EXPECT_EQ(fixed.scene["constraints"][0]["bodies"], json::array({"world", "arm"}));
  EXPECT_EQ(fixed.scene["bodies"][0]["position"], free.scene["bodies"][2]["position"]);  // where it was
  EXPECT_TRUE(Warned(fixed, "--fix makes bodies part of the world in place of their joints: root"));
  StartOf(fixed);
  ImportOptions alone;  // nothing left to move
  alone.fixed_bodies = {"torso", "arm"};
  EXPECT_THROW(Import(tree, alone), InputError);
}

TEST(SceneFromTree, EffectsCarryTheModelsGravitySpringsDampersAndMotors) {
  TreeJoint knee = Hinge("knee", Vector3d::Zero(), Vector3d::UnitY());
  knee.stiffness = 4.0;
  knee.spring_rest = 0.3;
  knee.damping = 0.2;
  KinematicTree tree = Tree({Link("shin", -1, Vector3d(0, 0, 1), {knee})});
  tree.motors = {{"knee_motor", "knee"}};
  tree.time_step = 0.005;
  const json scene = Import(tree).scene;
  EXPECT_EQ(scene["effects"][0], (json{{"type", "gravity"}, {"acceleration", {0.0, 0.0, -9.81}}}));
  EXPECT_EQ(scene["effects"][1],
            (json{{"type", "joint_spring"}, {"joint", "knee"}, {"stiffness", 4.0}, {"rest", 0.3}, {"damping", 0.2}}));
  EXPECT_EQ(scene["effects"][2], (json{{"type", "joint_torque"}, {"joint", "knee"}, {"value", 0.0}}));
  EXPECT_EQ(scene["simulation"], (json{{"step", 0.005}}));
}

TEST(SceneFromTree, WarnsOncePerKindOfJointPropertyItCannotKeep) {
  TreeJoint a = Hinge("a", Vector3d::Zero(), Vector3d::UnitZ()), b = Hinge("b", Vector3d::Zero(), Vector3d::UnitY());
  a.range = b.range = Eigen::Vector2d(-1, 1);
  a.armature = 0.01;
  b.friction_loss = 0.1;
  TreeJoint c = Hinge("c", Vector3d::Zero(), Vector3d::UnitY());
  c.range = Eigen::Vector2d(-0.5, 0.5);
  KinematicTree tree =
      Tree({Link("upper", -1, Vector3d(0, 0, 1), {a, b}), Link("upper_joint", 0, Vector3d(0, 0, -0.3), {c})});
  tree.links[1].joints[0].name = "upper";  // a joint named like a body: renamed
  const ImportedScene imported = Import(tree);
  EXPECT_FALSE(Warned(imported, "range"));  // c's limits are kept, and enforced
  EXPECT_TRUE(Warned(imported,
                     "limits of joints without a coordinate of their own in the scene (combined into one "
                     "constraint, which --split-joints avoids, or replaced by --fix) are dropped: a, b"));
  EXPECT_TRUE(Warned(imported, "joint armature (rotor inertia) is dropped (tether has none): a"));
  EXPECT_TRUE(Warned(imported, "joint friction loss (dry friction) is dropped (tether has none): b"));
  EXPECT_TRUE(Warned(imported, "names already taken are given a suffix: upper -> upper_joint2"));
}

TEST(SceneFromTree, SitesOfTheWorldAndOfStaticLinksAreDroppedWithAWarning) {
  TreeLink wall = Link("wall", -1, Vector3d(1, 0, 0), {});
  wall.sites = {{"hook", Vector3d::Zero()}};
  KinematicTree tree =
      Tree({wall, Link("door", 0, Vector3d(0, 0.5, 0), {Hinge("hinge", Vector3d::Zero(), Vector3d::UnitZ())})});
  tree.world_sites = {"origin"};
  const ImportedScene imported = Import(tree);
  EXPECT_EQ(imported.scene["constraints"][0]["bodies"], json::array({"world", "door"}));
  EXPECT_TRUE(Warned(imported,
                     "sites of the world, of static bodies and of massless links are dropped (a marker "
                     "names a point of a moving body): origin, hook"));
}

TEST(SceneFromTree, EqualitiesAreExactConstraintsOrDroppedWithAWarning) {
  KinematicTree tree = Tree({Link("crank", -1, Vector3d(0, 0, 1), {Hinge("c", Vector3d::Zero(), Vector3d::UnitY())}),
                             Link("rocker", -1, Vector3d(0.5, 0, 1), {Hinge("r", Vector3d::Zero(), Vector3d::UnitY())}),
                             Link("counterweight", 0, Vector3d(-0.1, 0, 0), {}, 0.0)});
  tree.equalities = {{TreeEquality::Type::kConnect, "coupler", 0, 1, Vector3d(0.25, 0, 0)},
                     {TreeEquality::Type::kWeld, "inside", 0, 2, Vector3d::Zero()}};
  const ImportedScene imported = Import(tree);
  EXPECT_EQ(ConstraintTypes(imported.scene), (std::vector<std::string>{"hinge", "hinge", "pin"}));
  EXPECT_EQ(imported.scene["constraints"][2]["name"], "coupler");
  EXPECT_TRUE(Warned(imported,
                     "equality constraints between parts of one body, or on massless links, are dropped: "
                     "inside"));
}

TEST(SceneFromTree, RefusesWhatItCannotImport) {
  auto refused = [](const KinematicTree& tree, const ImportOptions& options, const std::string& words) {
    try {
      Import(tree, options);
      ADD_FAILURE() << "accepted; expected: " << words;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  const KinematicTree arm =
      Tree({Link("arm", -1, Vector3d(0, 0, 1),
                 {Hinge("shoulder", Vector3d::Zero(), Vector3d::UnitY()), Joint("ball", TreeJointType::kBall)})});
  ImportOptions options;
  refused(Tree({Link("statue", -1, Vector3d::Zero(), {})}), options,
          "model.xml: nothing to import: the model has no moving body");
  options.joint_values = {{"elbow", 1.0}};
  refused(arm, options, "--joint elbow: the model has no joint named 'elbow'");
  options.joint_values = {{"ball", 1.0}};
  refused(arm, options, "--joint ball: a ball or free joint has no single coordinate");
  options.joint_values = {{"shoulder", 1.0}, {"shoulder", 2.0}};
  refused(arm, options, "--joint shoulder: given twice");
  options.joint_values = {{"shoulder", NAN}};
  refused(arm, options, "--joint shoulder: the value must be finite");
  options.joint_values.clear();
  options.joint_rates = {{"wrist", 1.0}};
  refused(arm, options, "--joint-velocity wrist: the model has no joint named 'wrist'");
  options.joint_rates.clear();
  options.fixed_bodies = {"leg"};
  refused(arm, options, "--fix leg: no moving body of model.xml is named 'leg'");
  options.fixed_bodies = {"arm"};
  options.joint_rates = {{"shoulder", 1.0}};
  refused(arm, options, "--joint-velocity shoulder: the joint's body 'arm' is held by --fix");
  KinematicTree flat = arm;
  flat.links[0].I_C_L = Vector3d(0.01, 0.02, 0).asDiagonal();
  refused(flat, {}, "model.xml: link 'arm': its principal moments of inertia (");
  refused(flat, {}, "kg m^2) must be positive in tether, the smallest at least 1e-12 of the largest");
  KinematicTree impossible = arm;
  impossible.links[0].I_C_L = Vector3d(0.01, 0.02, 0.04).asDiagonal();
  refused(impossible, {}, "model.xml: link 'arm': no rigid body has the principal moments 0.01, 0.02, 0.04 kg m^2");
}

}  // namespace
}  // namespace tether::importers
