// Models imported from MJCF move as MuJoCo moves them. MuJoCo, in reduced coordinates with its RK4 at a step
// fine enough to be the reference (kReferenceStep), and tether, in maximal coordinates with rk4 at
// h = kTetherStep, start from the same joint velocities; after one second every body's centre of mass agrees to
// kAgreement. What tether does not simulate is switched off in MuJoCo: contacts, joint limits, actuators, and
// (zeroed in the model before it is imported) joint stiffness, damping, armature and friction loss, and fluid
// forces; MuJoCo's soft equality constraints are made nearly rigid (solref at two steps, solimp 0.9999). A wrong
// frame, axis, anchor, inertia or joint mapping moves the bodies by millimetres to metres.
//
// Every sample model tether can express is here (libmujoco-samples: the composites with tendons and the models
// with tendon-driven joints cannot be; the tendon arm is here without its tendons), the large ones for a shorter
// time. --split-joints is measured on the humanoid, with its joint springs and dampers (which only split joints
// keep): its intermediate bodies of 1e-6 of a body's mass and inertia move it by 1.4e-7 m in 1 s
// (kSplitAgreement holds it).
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "test_files.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/io/scene_reader.h"
#include "tether/importers/import_model.h"
#include "tether/importers/mujoco_tree.h"

namespace tether::importers {
namespace {

constexpr double kReferenceStep = 1e-4;   // s, MuJoCo's RK4
constexpr double kTetherStep = 1e-3;      // s, tether's rk4
constexpr double kAgreement = 1e-5;       // m, every centre of mass after kSeconds
constexpr double kSplitAgreement = 1e-6;  // m, with --split-joints (measured 1.4e-7 on the humanoid)

const std::string kModels = "/usr/share/mujoco/model/";

using MjModelPtr = std::unique_ptr<mjModel, void (*)(mjModel*)>;
using MjDataPtr = std::unique_ptr<mjData, void (*)(mjData*)>;

MjModelPtr Load(const std::string& path) {
  char error[1024] = "";
  MjModelPtr model(mj_loadXML(path.c_str(), nullptr, error, sizeof error), mj_deleteModel);
  EXPECT_TRUE(model) << path << ": " << error;
  return model;
}

// Every joint's range left out.
void DropRanges(KinematicTree* tree) {
  for (TreeLink& link : tree->links) {
    for (TreeJoint& joint : link.joints) joint.range.reset();
  }
}

// Only what both simulate alike: no contacts, limits (MuJoCo's are soft, tether's hard), actuators, armature, friction
// or fluid, and no joint springs or dampers unless `springs` (then every joint must keep its own coordinate: single
// joints, or --split-joints); RK4. The tree loses alike what MuJoCo loses.
void KeepRigidBodyDynamics(mjModel* m, KinematicTree* tree, bool springs) {
  DropRanges(tree);
  tree->geoms.clear();
  tree->contact_excludes.clear();
  for (TreeLink& link : tree->links) {
    for (TreeJoint& joint : link.joints) {
      joint.armature = joint.friction_loss = 0;
      if (!springs) joint.stiffness = joint.damping = 0;
    }
  }
  m->opt.disableflags |= mjDSBL_CONTACT | mjDSBL_LIMIT | mjDSBL_ACTUATION | mjDSBL_FRICTIONLOSS;
  m->opt.density = m->opt.viscosity = 0;
  for (int d = 0; d < m->nv; ++d) m->dof_armature[d] = m->dof_frictionloss[d] = 0;
  if (springs) return;
  for (int j = 0; j < m->njnt; ++j) m->jnt_stiffness[j] = 0;
  for (int d = 0; d < m->nv; ++d) m->dof_damping[d] = 0;
  m->opt.integrator = mjINT_RK4;
}

// MuJoCo at `step`, its equality constraints as rigid as it allows: solref at two steps, solimp at its 0.9999.
void SetStep(mjModel* m, double step) {
  m->opt.timestep = step;
  for (int e = 0; e < m->neq; ++e) {
    m->eq_solref[mjNREF * e] = 2 * step;
    m->eq_solref[mjNREF * e + 1] = 1;
    m->eq_solimp[mjNIMP * e] = m->eq_solimp[mjNIMP * e + 1] = 0.9999;
  }
}

// Joint rates drawn from [-1, 1] rad/s (m/s) for every hinge and slide of the tree, seeded, by name.
std::vector<std::pair<std::string, double>> JointRates(const KinematicTree& tree, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<std::pair<std::string, double>> rates;
  for (const TreeLink& link : tree.links) {
    for (const TreeJoint& joint : link.joints) {
      if (joint.type == TreeJointType::kHinge || joint.type == TreeJointType::kSlide) {
        rates.emplace_back(joint.name, uniform(random));
      }
    }
  }
  return rates;
}

// MuJoCo's joint of a tree joint: by name, or for a joint the model leaves unnamed by its place (the tree lists
// a body's joints in MuJoCo's order and the bodies in order, so its k-th joint is MuJoCo's joint k).
int MujocoJoint(const mjModel& m, const KinematicTree& tree, const std::string& name) {
  const int j = mj_name2id(&m, mjOBJ_JOINT, name.c_str());
  if (j >= 0) return j;
  int k = 0;
  for (const TreeLink& link : tree.links) {
    for (const TreeJoint& joint : link.joints) {
      if (joint.name == name) return k;
      ++k;
    }
  }
  return -1;
}

// MuJoCo's id of the body a tether body was made from (its name, or "body<id>" for an unnamed one), or -1.
int MujocoBody(const mjModel& m, const std::string& name) {
  const int b = mj_name2id(&m, mjOBJ_BODY, name.c_str());
  if (b >= 0 || name.rfind("body", 0) != 0) return b;
  const int id = std::atoi(name.c_str() + 4);
  return id > 0 && id < m.nbody && "body" + std::to_string(id) == name ? id : -1;
}

struct Comparison {
  int compared = 0;        // bodies both engines have
  double departure = 0.0;  // the largest distance between their centres of mass at the end, m
  double moved = 0.0;      // the largest distance a body's centre of mass moved in MuJoCo, m
};

// Both engines from the same joint rates for `seconds`: MuJoCo on model `m`, tether on the scene made from `tree`.
Comparison Compare(mjModel* m, KinematicTree tree, double seconds, const ImportOptions& extra, bool springs,
                   const std::string& source) {
  KeepRigidBodyDynamics(m, &tree, springs);
  ImportOptions options = extra;
  options.joint_rates = JointRates(tree, 7);
  const ImportedScene imported = SceneFromTree(tree, options, source);
  Scene scene = ParseScene(nlohmann::json::parse(imported.scene.dump()), source);
  scene.model.simulation.integrator = Integrator::kRk4;
  scene.model.simulation.step = kTetherStep;
  scene.model.simulation.duration = seconds;
  VecX<double> q;
  Simulate<double>(scene.model, RunOptions{}, [&q](const Sample<double>& s) { q = s.q; });

  // MuJoCo's centres of mass at the start and after `seconds`. Its equality constraints stay soft however stiff
  // they are made, an error of the first order in its step (measured on the loop: 5.05e-5 m at 1e-4 s, 1.26e-5
  // m at 2.5e-5 s), and its RK4 is of the first order too once joint springs or dampers act (a two-link arm with
  // them: 1.7e-5 m from tether at 1e-4 s, 4.3e-6 m at 2.5e-5 s), so with either the reference is the Richardson
  // extrapolation 2 x(h/2) - x(h).
  std::vector<double> start;
  auto run = [&](double step) {
    SetStep(m, step);
    MjDataPtr d(mj_makeData(m), mj_deleteData);
    for (const auto& [name, rate] : options.joint_rates) d->qvel[m->jnt_dofadr[MujocoJoint(*m, tree, name)]] = rate;
    mj_forward(m, d.get());
    start.assign(d->xipos, d->xipos + 3 * m->nbody);
    for (long k = 0; k < std::lround(seconds / step); ++k) mj_step(m, d.get());
    mj_forward(m, d.get());
    return std::vector<double>(d->xipos, d->xipos + 3 * m->nbody);
  };
  std::vector<double> end = run(kReferenceStep);
  if (m->neq > 0 || springs) {
    const std::vector<double> finer = run(kReferenceStep / 2);
    for (size_t k = 0; k < end.size(); ++k) end[k] = 2 * finer[k] - end[k];
  }

  Comparison c;
  for (const Body<double>& body : scene.model.bodies) {
    const int b = MujocoBody(*m, body.name);
    if (b < 0) continue;
    const Vec3<double> p_WC(end[3 * b], end[3 * b + 1], end[3 * b + 2]);
    c.departure = std::max(c.departure, (q.segment<3>(body.q_offset) - p_WC).norm());
    c.moved = std::max(c.moved, (p_WC - Vec3<double>(start[3 * b], start[3 * b + 1], start[3 * b + 2])).norm());
    ++c.compared;
  }
  return c;
}

struct Case {
  const char* file;
  double seconds;
  int bodies;  // that both engines have
  bool split = false;
  bool springs = false;  // joint springs and dampers kept (where every joint keeps its coordinate)
};

class MujocoRoundTrip : public ::testing::TestWithParam<Case> {};

TEST_P(MujocoRoundTrip, EveryCentreOfMassMovesAsInMujoco) {
  const Case c = GetParam();
  ImportOptions options;
  options.split_joints = c.split;
  const MjModelPtr m = Load(kModels + c.file);
  ASSERT_TRUE(m);
  const Comparison comparison = Compare(m.get(), TreeFromMujoco(*m), c.seconds, options, c.springs, c.file);
  EXPECT_EQ(comparison.compared, c.bodies);
  EXPECT_LT(comparison.departure, c.split ? kSplitAgreement : kAgreement);
  EXPECT_GT(comparison.moved, 1e-2);  // the comparison means something
  // the figures docs/import.md quotes
  std::printf("%s%s%s: %d bodies, %g s: departure %.2g m, moved up to %.2g m\n", c.file, c.split ? " (split)" : "",
              c.springs ? " (springs)" : "", comparison.compared, c.seconds, comparison.departure, comparison.moved);
}

INSTANTIATE_TEST_SUITE_P(
    SampleModels, MujocoRoundTrip,
    ::testing::Values(Case{"humanoid/humanoid.xml", 1.0, 16}, Case{"humanoid/humanoid.xml", 1.0, 16, true, true},
                      Case{"hammock/humanoid_body.xml", 1.0, 16}, Case{"humanoid100/humanoid_body.xml", 1.0, 16},
                      Case{"humanoid/22_humanoids.xml", 0.1, 352}, Case{"humanoid100/humanoid100.xml", 0.05, 116},
                      Case{"tendon_arm/arm26.xml", 1.0, 2, false, true}, Case{"slider_crank/slider_crank.xml", 1.0, 3},
                      Case{"mug/mug.xml", 1.0, 2}, Case{"composite/rope.xml", 1.0, 21},
                      Case{"composite/loop.xml", 1.0, 20}, Case{"composite/particle.xml", 0.1, 1000}),
    [](const ::testing::TestParamInfo<Case>& info) {
      std::string name = info.param.file;  // "folder/model.xml" -> folder_model
      name = name.substr(0, name.rfind('.'));
      for (char& ch : name) ch = std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
      return name + (info.param.split ? "_split" : "") + (info.param.springs ? "_springs" : "");
    });

// --joint places the bodies as MuJoCo's forward kinematics does at those coordinates: every centre of mass and
// orientation of the humanoid at random joint angles of up to 1 rad.
TEST(MujocoPlacement, JointValuesPlaceTheBodiesAsMujocoDoes) {
  const MjModelPtr m = Load(kModels + "humanoid/humanoid.xml");
  ASSERT_TRUE(m);
  KinematicTree tree = TreeFromMujoco(*m);
  DropRanges(&tree);  // the angles below may lie outside the joints' ranges
  MjDataPtr d(mj_makeData(m.get()), mj_deleteData);
  std::mt19937 random(3);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  ImportOptions options;
  for (int j = 0; j < m->njnt; ++j) {
    if (m->jnt_type[j] != mjJNT_HINGE) continue;
    d->qpos[m->jnt_qposadr[j]] = uniform(random);
    options.joint_values.emplace_back(mj_id2name(m.get(), mjOBJ_JOINT, j), d->qpos[m->jnt_qposadr[j]]);
  }
  mj_kinematics(m.get(), d.get());
  const ImportedScene imported = SceneFromTree(tree, options, "humanoid.xml");
  int compared = 0;
  for (const auto& body : imported.scene["bodies"]) {
    const int b = MujocoBody(*m, body["name"]);
    ASSERT_GE(b, 0);
    const std::vector<double> p = body["position"], q = body["orientation"];
    EXPECT_LT((Vec3<double>(p.data()) - Vec3<double>(d->xipos + 3 * b)).norm(), 1e-14) << body["name"];
    const Eigen::Quaterniond mujoco(d->xquat[4 * b], d->xquat[4 * b + 1], d->xquat[4 * b + 2], d->xquat[4 * b + 3]);
    EXPECT_LT(mujoco.angularDistance(Eigen::Quaterniond(q[0], q[1], q[2], q[3])), 1e-14) << body["name"];
    ++compared;
  }
  EXPECT_EQ(compared, 16);
}

// The geoms become shapes where MuJoCo places them: every shape's centre and axes at the start (a capsule's x axis
// along MuJoCo's z) to 1e-14, and its sizes.
TEST(MujocoPlacement, GeomsBecomeShapesWhereMujocoPlacesThem) {
  const MjModelPtr m = Load(kModels + "humanoid/humanoid.xml");
  ASSERT_TRUE(m);
  MjDataPtr d(mj_makeData(m.get()), mj_deleteData);
  mj_kinematics(m.get(), d.get());
  const ImportedScene imported = SceneFromTree(TreeFromMujoco(*m), {}, "humanoid.xml");
  std::map<std::string, Eigen::Isometry3d> body_poses;
  for (const auto& body : imported.scene["bodies"]) {
    const std::vector<double> p = body["position"], q = body["orientation"];
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translate(Vec3<double>(p.data())).rotate(Eigen::Quaterniond(q[0], q[1], q[2], q[3]));
    body_poses[body["name"]] = pose;
  }
  int compared = 0;
  for (int g = 0; g < m->ngeom; ++g) {
    const std::string name = mj_id2name(m.get(), mjOBJ_GEOM, g);
    const auto shape = std::find_if(imported.scene["shapes"].begin(), imported.scene["shapes"].end(),
                                    [&](const auto& s) { return s["name"] == name || s["name"] == name + "_shape"; });
    ASSERT_NE(shape, imported.scene["shapes"].end()) << name;
    const std::string body = (*shape)["body"];
    const Eigen::Isometry3d X_WB = body == "world" ? Eigen::Isometry3d::Identity() : body_poses.at(body);
    const std::vector<double> p = (*shape)["position"], q = (*shape)["orientation"];
    const Vec3<double> p_W = X_WB * Vec3<double>(p.data());
    const Mat3<double> R_WS = X_WB.linear() * Eigen::Quaterniond(q[0], q[1], q[2], q[3]).toRotationMatrix();
    const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> R_mujoco(d->geom_xmat + 9 * g);
    EXPECT_LT((p_W - Vec3<double>(d->geom_xpos + 3 * g)).norm(), 1e-14) << name;
    const double* size = m->geom_size + 3 * g;
    if (m->geom_type[g] == mjGEOM_CAPSULE) {
      EXPECT_LT((R_WS.col(0) - R_mujoco.col(2)).norm(), 1e-14) << name;
      EXPECT_DOUBLE_EQ(shape->value("length", 0.0), 2 * size[1]) << name;
    } else if (m->geom_type[g] == mjGEOM_PLANE) {
      EXPECT_LT((R_WS.col(2) - R_mujoco.col(2)).norm(), 1e-14) << name;
    }
    EXPECT_DOUBLE_EQ(shape->value("radius", 0.0), m->geom_type[g] == mjGEOM_PLANE ? 0.0 : size[0]) << name;
    ++compared;
  }
  EXPECT_EQ(compared, 20);
}

// The URDF test arm (docs/examples/urdf_arm/arm.urdf) against MuJoCo's own URDF reader, which fuses fixed links
// into their parents (so tether merges them too) and refuses a massless moving link: MuJoCo's copy gives the
// wrist, which tether joins to the hand as one double hinge, 1e-9 kg and 1e-12 kg m^2 (a change of the motion far
// below kAgreement).
TEST(UrdfRoundTrip, TestArmMovesAsInMujoco) {
  const std::string arm = std::string(TETHER_SOURCE_DIR) + "/docs/examples/urdf_arm/arm.urdf";
  std::string text = testing::ReadText(arm);
  const std::string massless = "<link name=\"wrist\"/>";
  ASSERT_NE(text.find(massless), std::string::npos);
  text.replace(text.find(massless), massless.size(),
               "<link name=\"wrist\"><inertial><mass value=\"1e-9\"/><inertia ixx=\"1e-12\" ixy=\"0\" ixz=\"0\" "
               "iyy=\"1e-12\" iyz=\"0\" izz=\"1e-12\"/></inertial></link>");
  const testing::TempFolder folder;
  const MjModelPtr m = Load(folder.Write("arm.urdf", text));
  ASSERT_TRUE(m);
  ImportOptions options;
  options.merge_fixed = true;
  const Comparison comparison = Compare(m.get(), ReadUrdf(arm), 1.0, options, false, arm);
  EXPECT_EQ(comparison.compared, 5);  // shoulder, upper_arm (with camera_mount), forearm, hand, finger (with tool0)
  EXPECT_LT(comparison.departure, kAgreement);
  EXPECT_GT(comparison.moved, 1e-2);
  std::printf("urdf_arm/arm.urdf: %d bodies, 1 s: departure %.2g m, moved up to %.2g m\n", comparison.compared,
              comparison.departure, comparison.moved);
}

}  // namespace
}  // namespace tether::importers
