// URDF through urdfdom (importers/src/urdf_reader.cc): the frames and inertias it reads, the joints each URDF
// joint type becomes, and its errors and warnings. (Its motion against MuJoCo: mujoco_round_trip_test.cc.)
#include <gtest/gtest.h>

#include <string>

#include "test_files.h"
#include "tether/dynamics/model/errors.h"
#include "tether/importers/import_model.h"

namespace tether::importers {
namespace {

using Eigen::Vector3d;

std::string Robot(const std::string& body) { return "<?xml version=\"1.0\"?>\n<robot name=\"r\">\n" + body + "</robot>\n"; }

std::string Inertial(const std::string& origin = "<origin xyz=\"0 0 0\"/>") {
  return "<inertial>" + origin +
         "<mass value=\"2\"/><inertia ixx=\"0.02\" ixy=\"0.001\" ixz=\"0\" iyy=\"0.03\" iyz=\"0\" izz=\"0.04\"/></inertial>";
}

std::string Joint(const std::string& name, const std::string& type, const std::string& parent, const std::string& child,
                  const std::string& extra = "") {
  return "<joint name=\"" + name + "\" type=\"" + type + "\"><parent link=\"" + parent + "\"/><child link=\"" + child +
         "\"/>" + extra + "</joint>\n";
}

KinematicTree Read(const std::string& urdf) {
  const testing::TempFolder folder;
  return ReadUrdf(folder.Write("robot.urdf", urdf));
}

bool Warned(const KinematicTree& tree, const std::string& words) {
  for (const std::string& w : tree.warnings) {
    if (w.find(words) != std::string::npos) return true;
  }
  return false;
}

TEST(UrdfReader, ReadsFramesInertiasAndJoints) {
  const KinematicTree tree = Read(Robot(
      "<link name=\"base\"/>\n<link name=\"arm\">" +
      Inertial("<origin xyz=\"0.1 0 0.2\" rpy=\"0 0 1.5707963267948966\"/>") + "</link>\n" +
      Joint("shoulder", "revolute", "base", "arm",
            "<origin xyz=\"0 0 1\" rpy=\"0.1 0.2 0.3\"/><axis xyz=\"0 0 2\"/>"
            "<limit lower=\"-1\" upper=\"1.5\" effort=\"10\" velocity=\"1\"/><dynamics damping=\"0.4\" friction=\"0.1\"/>")));
  ASSERT_EQ(tree.links.size(), 1u);  // the root link is the world
  const TreeLink& arm = tree.links[0];
  EXPECT_EQ(arm.name, "arm");
  EXPECT_EQ(arm.parent, -1);
  EXPECT_TRUE(arm.p_PL.isApprox(Vector3d(0, 0, 1)));
  // URDF's rpy: R = Rz(yaw) Ry(pitch) Rx(roll)
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(0.3, Vector3d::UnitZ()) * Eigen::AngleAxisd(0.2, Vector3d::UnitY()) *
                             Eigen::AngleAxisd(0.1, Vector3d::UnitX())).toRotationMatrix();
  EXPECT_TRUE(arm.q_PL.toRotationMatrix().isApprox(R, 1e-15));
  EXPECT_EQ(arm.mass, 2.0);
  EXPECT_TRUE(arm.p_LC.isApprox(Vector3d(0.1, 0, 0.2)));
  // the tensor given in the inertial frame, turned 90 degrees about z into the link frame: ixx and iyy swap and
  // the product of inertia changes sign
  Eigen::Matrix3d I_C_L;
  I_C_L << 0.03, -0.001, 0, -0.001, 0.02, 0, 0, 0, 0.04;
  EXPECT_TRUE(arm.I_C_L.isApprox(I_C_L, 1e-14)) << arm.I_C_L;
  ASSERT_EQ(arm.joints.size(), 1u);
  const TreeJoint& shoulder = arm.joints[0];
  EXPECT_EQ(shoulder.type, TreeJointType::kHinge);
  EXPECT_TRUE(shoulder.axis_L.isApprox(Vector3d::UnitZ()));
  EXPECT_TRUE(shoulder.p_LJ.isZero());
  EXPECT_EQ(shoulder.damping, 0.4);
  EXPECT_EQ(shoulder.friction_loss, 0.1);
  ASSERT_TRUE(shoulder.range);
  EXPECT_EQ(*shoulder.range, Eigen::Vector2d(-1, 1.5));
  ASSERT_EQ(tree.motors.size(), 1u);  // an effort limit: a driven joint
  EXPECT_EQ(tree.motors[0].joint, "shoulder");
  EXPECT_EQ(tree.gravity, Vector3d(0, 0, -9.81));
  EXPECT_FALSE(tree.time_step);
}

TEST(UrdfReader, MapsEveryJointType) {
  const KinematicTree tree = Read(Robot(
      "<link name=\"world\"/>\n<link name=\"a\">" + Inertial() + "</link><link name=\"b\">" + Inertial() +
      "</link><link name=\"c\">" + Inertial() + "</link><link name=\"d\">" + Inertial() + "</link><link name=\"e\">" +
      Inertial() + "</link>\n" + Joint("free", "floating", "world", "a") +
      Joint("wheel", "continuous", "a", "b", "<axis xyz=\"0 1 0\"/><limit effort=\"5\" velocity=\"1\"/>") +
      Joint("lift", "prismatic", "b", "c", "<axis xyz=\"0 0 1\"/><limit lower=\"0\" upper=\"0.1\" effort=\"0\" velocity=\"1\"/>") +
      Joint("mount", "fixed", "c", "d") + Joint("table", "planar", "d", "e", "<axis xyz=\"0 0 1\"/>")));
  ASSERT_EQ(tree.links.size(), 5u);
  EXPECT_EQ(tree.links[0].joints[0].type, TreeJointType::kFree);
  EXPECT_EQ(tree.links[1].joints[0].type, TreeJointType::kHinge);
  EXPECT_FALSE(tree.links[1].joints[0].range);  // continuous: no limits
  EXPECT_EQ(tree.links[2].joints[0].type, TreeJointType::kSlide);
  EXPECT_TRUE(tree.links[3].joints.empty());
  ASSERT_EQ(tree.links[4].joints.size(), 3u);  // planar: two slides across the axis and a hinge about it
  EXPECT_EQ(tree.links[4].joints[0].name, "table_u");
  EXPECT_EQ(tree.links[4].joints[2].name, "table");
  EXPECT_NEAR(tree.links[4].joints[0].axis_L.dot(Vector3d::UnitZ()), 0.0, 1e-15);
  EXPECT_NEAR(tree.links[4].joints[1].axis_L.dot(tree.links[4].joints[0].axis_L), 0.0, 1e-15);
  EXPECT_TRUE(Warned(tree, "planar joints are read as two slides across the axis (NAME_u, NAME_v) and a hinge about "
                           "it (NAME): table"));
  ASSERT_EQ(tree.motors.size(), 1u);  // the wheel's effort limit; the lift's is 0
  EXPECT_EQ(tree.motors[0].joint, "wheel");
  // the planar joint is three joints no single constraint combines: split, and the scene is valid
  const ImportedScene imported = SceneFromTree(tree, {}, "robot.urdf");
  EXPECT_EQ(imported.scene["constraints"].size(), 6u);  // wheel, lift, the weld to d, three for the table
}

TEST(UrdfReader, WarnsAboutWhatTetherDoesNotSimulate) {
  const KinematicTree tree = Read(Robot(
      "<link name=\"base\">" + Inertial() + "</link>\n<link name=\"a\">" + Inertial() +
      "<collision><geometry><box size=\"1 1 1\"/></geometry></collision></link>\n<link name=\"b\">" + Inertial() +
      "</link>\n" + Joint("j1", "revolute", "base", "a", "<limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/>") +
      Joint("j2", "revolute", "a", "b", "<limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/><mimic joint=\"j1\"/>")));
  EXPECT_TRUE(Warned(tree, "the root link 'base' is the world (a fixed base), so its mass does not move"));
  EXPECT_TRUE(Warned(tree, "mimic couplings are dropped (tether has none): j2 (follows j1)"));
  ASSERT_EQ(tree.geoms.size(), 1u);  // the collision box becomes a shape of link a
  EXPECT_EQ(tree.geoms[0].type, TreeGeom::Type::kBox);
  EXPECT_EQ(tree.geoms[0].size, Vector3d(1, 1, 1));
  EXPECT_EQ(tree.links[tree.geoms[0].link].name, "a");
}

TEST(UrdfReader, RefusesWhatItCannotRead) {
  auto refused = [](const std::string& urdf, const std::string& words) {
    try {
      Read(urdf);
      ADD_FAILURE() << "accepted; expected: " << words;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  refused("<robot name=\"r\"><link name=\"a\"/>", "robot.urdf: not a valid URDF model: ");
  refused(Robot("<link name=\"a\"/><link name=\"b\"/>" + Joint("j", "revolute", "a", "c")),
          "robot.urdf: not a valid URDF model: ");
  refused(Robot("<link name=\"a\"/><link name=\"b\">" + Inertial() + "</link>" +
                Joint("j", "continuous", "a", "b", "<axis xyz=\"0 0 0\"/>")),
          "robot.urdf: joint 'j' has a zero axis");
  // not a tree: a link with two parents (urdfdom kept one joint twice and lost the other), joints in a cycle
  // (walked for ever)
  const std::string links = "<link name=\"base\"/><link name=\"a\">" + Inertial() + "</link><link name=\"b\">" +
                            Inertial() + "</link><link name=\"c\">" + Inertial() + "</link>";
  refused(Robot(links + Joint("j1", "continuous", "base", "a") + Joint("j2", "continuous", "base", "b") +
                Joint("j3", "continuous", "a", "b") + Joint("j4", "continuous", "base", "c")),
          "link 'b' is the child of two joints ('j2' and 'j3')");
  refused(Robot(links + Joint("j1", "continuous", "base", "c") + Joint("j2", "continuous", "a", "b") +
                Joint("j3", "continuous", "b", "a")),
          "the joints above link 'a' form a cycle");
  try {
    ReadUrdf("/nonexistent/robot.urdf");
    ADD_FAILURE() << "accepted a missing file";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "/nonexistent/robot.urdf: cannot open the model file (no such file)");
  }
}

}  // namespace
}  // namespace tether::importers
