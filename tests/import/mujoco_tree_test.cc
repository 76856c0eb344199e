// MJCF through MuJoCo's compiler (importers/src/mujoco_tree.cc): what it reads from the compiled model, the names
// it gives unnamed elements, the option flags it honours, and its errors and warnings. (Its motion against
// MuJoCo: mujoco_round_trip_test.cc.)
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "test_files.h"
#include "tether/dynamics/model/errors.h"
#include "tether/importers/import_model.h"

namespace tether::importers {
namespace {

using Eigen::Vector3d;

KinematicTree Read(const std::string& body, const std::string& option = "") {
  const testing::TempFolder folder;
  return ReadMjcf(folder.Write("model.xml", "<mujoco>" + option + body + "</mujoco>"));
}

bool Warned(const KinematicTree& tree, const std::string& words) {
  for (const std::string& w : tree.warnings) {
    if (w.find(words) != std::string::npos) return true;
  }
  return false;
}

const char* kArm = R"(
  <worldbody>
    <site name="anchor" pos="0 0 2"/>
    <body name="upper" pos="0 0 1" euler="0 0 30">
      <joint name="shoulder" type="hinge" axis="0 1 0" pos="0 0 0.1" ref="10" range="-45 90" limited="true"
             stiffness="2" springref="5" damping="0.3" armature="0.01" frictionloss="0.2"/>
      <geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.03" contype="0" conaffinity="0"/>
      <site name="elbow_site" pos="0.4 0 0"/>
      <body pos="0.4 0 0">
        <joint type="slide" axis="1 0 0"/>
        <geom name="fore" type="box" size="0.1 0.02 0.02" pos="0.1 0 0" mass="0.5"/>
      </body>
    </body>
  </worldbody>
  <actuator>
    <motor name="drive" joint="shoulder" gear="20"/>
    <position name="servo" joint="shoulder" kp="10"/>
  </actuator>)";

TEST(MujocoTree, ReadsTheCompiledModel) {
  const KinematicTree tree = Read(kArm, R"(<option timestep="0.004" gravity="0 0 -9"/>)");
  ASSERT_EQ(tree.links.size(), 2u);
  const TreeLink& upper = tree.links[0];
  EXPECT_EQ(upper.name, "upper");
  EXPECT_EQ(upper.parent, -1);
  EXPECT_TRUE(upper.q_PL.isApprox(Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 6, Vector3d::UnitZ()))));
  EXPECT_GT(upper.mass, 0);  // inferred from the capsule
  EXPECT_NEAR(upper.p_LC.x(), 0.2, 1e-12);
  const TreeJoint& shoulder = upper.joints[0];
  EXPECT_EQ(shoulder.type, TreeJointType::kHinge);
  EXPECT_TRUE(shoulder.p_LJ.isApprox(Vector3d(0, 0, 0.1)));
  EXPECT_NEAR(shoulder.reference, M_PI / 18, 1e-15);  // angles compiled to radians
  EXPECT_NEAR(shoulder.spring_rest, M_PI / 36, 1e-15);
  EXPECT_EQ(shoulder.stiffness, 2.0);
  EXPECT_EQ(shoulder.damping, 0.3);
  EXPECT_EQ(shoulder.armature, 0.01);
  EXPECT_EQ(shoulder.friction_loss, 0.2);
  ASSERT_TRUE(shoulder.range);
  EXPECT_NEAR((*shoulder.range)[1], M_PI / 2, 1e-15);
  EXPECT_EQ(upper.sites[0].name, "elbow_site");
  // unnamed elements take their kind and id, or their link's name
  EXPECT_EQ(tree.links[1].name, "body2");
  EXPECT_EQ(tree.links[1].joints[0].name, "body2_joint");
  EXPECT_EQ(tree.links[1].mass, 0.5);
  EXPECT_EQ(tree.world_sites, std::vector<std::string>{"anchor"});
  ASSERT_EQ(tree.motors.size(), 1u);
  EXPECT_EQ(tree.motors[0].name, "drive");
  EXPECT_EQ(tree.gravity, Vector3d(0, 0, -9));
  EXPECT_EQ(tree.time_step, 0.004);
  EXPECT_TRUE(Warned(tree, "actuators other than motors on joints are dropped: servo (a servo)"));
  // the geoms become shapes (MuJoCo's box size is half the edges)
  const auto fore =
      std::find_if(tree.geoms.begin(), tree.geoms.end(), [](const TreeGeom& g) { return g.name == "fore"; });
  ASSERT_NE(fore, tree.geoms.end());
  EXPECT_EQ(fore->type, TreeGeom::Type::kBox);
  EXPECT_TRUE(fore->size.isApprox(Vector3d(0.2, 0.04, 0.04)));
  EXPECT_TRUE(fore->p_LG.isApprox(Vector3d(0.1, 0, 0)));
  EXPECT_TRUE(fore->contact);
}

TEST(MujocoTree, HonoursTheOptionFlags) {
  const KinematicTree tree = Read(kArm, R"(<option><flag gravity="disable" passive="disable" limit="disable"
                                                     contact="disable" frictionloss="disable"/></option>)");
  EXPECT_EQ(tree.gravity, Vector3d::Zero());
  const TreeJoint& shoulder = tree.links[0].joints[0];
  EXPECT_EQ(shoulder.stiffness, 0.0);
  EXPECT_EQ(shoulder.damping, 0.0);
  EXPECT_EQ(shoulder.friction_loss, 0.0);
  EXPECT_FALSE(shoulder.range);
  EXPECT_FALSE(Warned(tree, "contacts"));
}

TEST(MujocoTree, WarnsAboutWhatTetherDoesNotSimulate) {
  const KinematicTree tree = Read(R"(
  <option density="1.2" viscosity="0.00002"/>
  <worldbody>
    <body name="target" mocap="true"><site name="goal"/></body>
    <body name="a" pos="0 0 1"><freejoint/><geom type="sphere" size="0.1"/><site name="s1"/></body>
    <body name="b" pos="1 0 1"><joint name="hb" axis="0 1 0"/><geom type="sphere" size="0.1"/><site name="s2"/></body>
    <body name="c" pos="2 0 1"><joint name="hc" axis="0 1 0"/><geom type="sphere" size="0.1"/></body>
  </worldbody>
  <tendon><spatial name="rope"><site site="s1"/><site site="s2"/></spatial></tendon>
  <equality>
    <connect name="tie" body1="a" body2="b" anchor="0.5 0 0"/>
    <joint name="gear" joint1="hb" joint2="hc"/>
    <weld name="off" body1="a" body2="c" active="false"/>
  </equality>
  <actuator><muscle name="m" tendon="rope"/></actuator>)");
  EXPECT_TRUE(Warned(tree, "tendons are dropped (tether has none): rope"));
  EXPECT_TRUE(Warned(tree, "actuators other than motors on joints are dropped: m (a muscle)"));
  EXPECT_TRUE(Warned(tree, "equality constraints tether cannot express are dropped: gear (couples joints or "
                           "tendons), off (inactive)"));
  EXPECT_TRUE(Warned(tree, "fluid forces are dropped (tether has none): the medium's density 1.2 kg/m^3 and "
                           "viscosity 2e-05 Pa s"));
  EXPECT_TRUE(Warned(tree, "mocap bodies are held where they start (tether cannot move them): target"));
  ASSERT_EQ(tree.equalities.size(), 1u);
  EXPECT_EQ(tree.equalities[0].name, "tie");
  EXPECT_TRUE(tree.equalities[0].p_L1.isApprox(Vector3d(0.5, 0, 0)));
  // the scene: a free body and two hinged ones, the connect a pin, the mocap body part of the world
  const ImportedScene imported = SceneFromTree(tree, {}, "model.xml");
  EXPECT_EQ(imported.scene["bodies"].size(), 3u);
  EXPECT_EQ(imported.scene["constraints"].size(), 3u);
  EXPECT_EQ(imported.scene["constraints"][2]["type"], "pin");
  EXPECT_EQ(imported.scene["markers"].size(), 2u);
}

TEST(MujocoTree, RefusesWhatMujocoCannotCompile) {
  try {
    Read("<worldbody><body><joint type=\"hinge\"/></body></worldbody>");  // a moving body without mass
    ADD_FAILURE() << "accepted a massless moving body";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("model.xml: MuJoCo cannot compile it: Error: mass and inertia of moving bodies "
                                         "must be larger than mjMINVAL"),
              std::string::npos)
        << e.what();
  }
  try {
    ReadMjcf("/nonexistent/model.xml");
    ADD_FAILURE() << "accepted a missing file";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "/nonexistent/model.xml: cannot open the model file (no such file)");
  }
}

}  // namespace
}  // namespace tether::importers
