#include "tether/importers/mujoco_tree.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>

#include "tether/dynamics/io/input_file.h"
#include "tether/dynamics/model/errors.h"
#include "tether/importers/import_model.h"

namespace tether::importers {
namespace {

// An element's name, or KIND + its id when the model leaves it unnamed (MJCF names are optional).
std::string NameOf(const mjModel& m, mjtObj type, int id, const std::string& kind) {
  const char* name = mj_id2name(&m, type, id);
  return name && *name ? std::string(name) : kind + std::to_string(id);
}

Eigen::Vector3d Vector3(const mjtNum* x) { return Eigen::Vector3d(x[0], x[1], x[2]); }
Eigen::Quaterniond Quaternion(const mjtNum* q) { return Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized(); }

bool Disabled(const mjModel& m, int flag) { return (m.opt.disableflags & flag) != 0; }

TreeJoint ReadJoint(const mjModel& m, int j, const std::string& link_name, int index_in_link) {
  TreeJoint joint;
  const char* name = mj_id2name(&m, mjOBJ_JOINT, j);
  joint.name = name && *name ? std::string(name)
                             : link_name + "_joint" + (index_in_link > 0 ? std::to_string(index_in_link + 1) : "");
  switch (m.jnt_type[j]) {
    case mjJNT_FREE:
      joint.type = TreeJointType::kFree;
      break;
    case mjJNT_BALL:
      joint.type = TreeJointType::kBall;
      break;
    case mjJNT_SLIDE:
      joint.type = TreeJointType::kSlide;
      break;
    default:
      joint.type = TreeJointType::kHinge;
      break;
  }
  joint.p_LJ = Vector3(m.jnt_pos + 3 * j);
  joint.axis_L = Vector3(m.jnt_axis + 3 * j).normalized();
  const int qpos = m.jnt_qposadr[j], dof = m.jnt_dofadr[j];
  const bool scalar = joint.type == TreeJointType::kHinge || joint.type == TreeJointType::kSlide;
  if (scalar) joint.reference = m.qpos0[qpos];
  const bool passive = !Disabled(m, mjDSBL_PASSIVE);
  if (passive) {
    joint.stiffness = m.jnt_stiffness[j];
    joint.damping = m.dof_damping[dof];
    if (scalar) joint.spring_rest = m.qpos_spring[qpos];
  }
  joint.armature = m.dof_armature[dof];
  if (!Disabled(m, mjDSBL_FRICTIONLOSS) && !Disabled(m, mjDSBL_CONSTRAINT))
    joint.friction_loss = m.dof_frictionloss[dof];
  if (m.jnt_limited[j] && !Disabled(m, mjDSBL_LIMIT) && !Disabled(m, mjDSBL_CONSTRAINT)) {
    joint.range = Eigen::Vector2d(m.jnt_range[2 * j], m.jnt_range[2 * j + 1]);
  }
  return joint;
}

// A motor: force = gear * ctrl on one joint, with no activation dynamics, a fixed gain and no bias.
bool IsJointMotor(const mjModel& m, int u) {
  const int transmission = m.actuator_trntype[u];
  return (transmission == mjTRN_JOINT || transmission == mjTRN_JOINTINPARENT) && m.actuator_dyntype[u] == mjDYN_NONE &&
         m.actuator_gaintype[u] == mjGAIN_FIXED && m.actuator_biastype[u] == mjBIAS_NONE;
}

std::string ActuatorKind(const mjModel& m, int u) {
  if (m.actuator_dyntype[u] == mjDYN_MUSCLE || m.actuator_gaintype[u] == mjGAIN_MUSCLE) return "a muscle";
  if (m.actuator_biastype[u] == mjBIAS_AFFINE) return "a servo";
  switch (m.actuator_trntype[u]) {
    case mjTRN_SLIDERCRANK:
      return "on a slider-crank";
    case mjTRN_TENDON:
      return "on a tendon";
    case mjTRN_SITE:
      return "on a site";
    case mjTRN_BODY:
      return "an adhesion actuator";
    default:
      return "with activation dynamics or a custom gain";
  }
}

void ReadActuators(const mjModel& m, KinematicTree* tree) {
  std::vector<std::string> others;
  for (int u = 0; u < m.nu; ++u) {
    const std::string name = NameOf(m, mjOBJ_ACTUATOR, u, "actuator");
    if (IsJointMotor(m, u)) {
      tree->motors.push_back({name, NameOf(m, mjOBJ_JOINT, m.actuator_trnid[2 * u], "joint")});
    } else {
      others.push_back(name + " (" + ActuatorKind(m, u) + ")");
    }
  }
  if (!others.empty()) {
    tree->warnings.push_back(ListWarning("actuators other than motors on joints are dropped", others));
  }
}

void ReadEqualities(const mjModel& m, KinematicTree* tree) {
  std::vector<std::string> dropped;
  const bool disabled = Disabled(m, mjDSBL_EQUALITY) || Disabled(m, mjDSBL_CONSTRAINT);
  for (int e = 0; e < m.neq; ++e) {
    const std::string name = NameOf(m, mjOBJ_EQUALITY, e, "equality");
    const int type = m.eq_type[e];
    if (disabled || !m.eq_active[e] || (type != mjEQ_CONNECT && type != mjEQ_WELD)) {
      dropped.push_back(name + (disabled || !m.eq_active[e] ? " (inactive)" : " (couples joints or tendons)"));
      continue;
    }
    TreeEquality eq;
    eq.type = type == mjEQ_CONNECT ? TreeEquality::Type::kConnect : TreeEquality::Type::kWeld;
    eq.name = name;
    eq.link_1 = m.eq_obj1id[e] - 1;
    eq.link_2 = m.eq_obj2id[e] - 1;
    eq.p_L1 = Vector3(m.eq_data + mjNEQDATA * e);
    tree->equalities.push_back(eq);
  }
  if (!dropped.empty()) {
    tree->warnings.push_back(ListWarning("equality constraints tether cannot express are dropped", dropped));
  }
}

// MuJoCo's geoms as shapes: sphere, capsule (MuJoCo's is along its z axis, tether's along x), box (MuJoCo's size
// is half the edges), plane; a cylinder as the capsule of its radius and overall length, with a warning; the
// other types, one warning per kind. The pair rules: a geom with contype = conaffinity = 0 never touches;
// <exclude> pairs, and body pairs none of whose geoms' bits meet ((contype_a & conaffinity_b) |
// (contype_b & conaffinity_a) = 0 for every pair), become exclusions.
void ReadGeoms(const mjModel& m, KinematicTree* tree) {
  const bool contacts = !Disabled(m, mjDSBL_CONTACT) && !Disabled(m, mjDSBL_CONSTRAINT);
  std::map<std::string, std::vector<std::string>> dropped;  // by kind
  std::vector<std::string> cylinders;
  std::vector<int> kept;
  for (int g = 0; g < m.ngeom; ++g) {
    TreeGeom geom;
    geom.name = NameOf(m, mjOBJ_GEOM, g, "geom");
    geom.link = m.geom_bodyid[g] - 1;
    geom.p_LG = Vector3(m.geom_pos + 3 * g);
    geom.q_LG = Quaternion(m.geom_quat + 4 * g);
    const mjtNum* size = m.geom_size + 3 * g;
    switch (m.geom_type[g]) {
      case mjGEOM_SPHERE:
        geom.type = TreeGeom::Type::kSphere;
        geom.radius = size[0];
        break;
      case mjGEOM_CYLINDER:
        cylinders.push_back(geom.name);
        [[fallthrough]];
      case mjGEOM_CAPSULE:
        geom.type = TreeGeom::Type::kCapsule;
        geom.radius = size[0];
        geom.length = m.geom_type[g] == mjGEOM_CAPSULE ? 2 * size[1] : std::max(2 * size[1] - 2 * size[0], 0.0);
        geom.q_LG = geom.q_LG * CapsuleAxisFromZ();
        break;
      case mjGEOM_BOX:
        geom.type = TreeGeom::Type::kBox;
        geom.size = 2 * Vector3(size);
        break;
      case mjGEOM_PLANE:
        geom.type = TreeGeom::Type::kPlane;
        break;
      default: {
        const int type = m.geom_type[g];
        const std::string kind = type == mjGEOM_MESH        ? "meshes"
                                 : type == mjGEOM_HFIELD    ? "height fields"
                                 : type == mjGEOM_ELLIPSOID ? "ellipsoids"
                                                            : "other geom types";
        dropped[kind].push_back(geom.name);
        continue;
      }
    }
    geom.friction = m.geom_friction[3 * g];
    geom.contact = contacts && (m.geom_contype[g] || m.geom_conaffinity[g]);
    tree->geoms.push_back(geom);
    kept.push_back(g);
  }
  for (const auto& [kind, names] : dropped) {
    tree->warnings.push_back(ListWarning(kind + " are dropped (tether's shapes are spheres, capsules, boxes and "
                                                "planes)",
                                         names));
  }
  if (!cylinders.empty()) {
    tree->warnings.push_back(
        ListWarning("cylinders become capsules of the same radius and overall length (rounded "
                    "ends instead of flat ones)",
                    cylinders));
  }
  std::set<std::pair<int, int>> meet, touching;  // body pairs (MuJoCo's ids) some of whose geoms may touch
  for (size_t i = 0; i < kept.size(); ++i) {
    for (size_t j = i + 1; j < kept.size(); ++j) {
      const int a = kept[i], b = kept[j];
      const int body_a = m.geom_bodyid[a], body_b = m.geom_bodyid[b];
      if (!tree->geoms[i].contact || !tree->geoms[j].contact || body_a == body_b) continue;
      const std::pair<int, int> key(std::min(body_a, body_b), std::max(body_a, body_b));
      touching.insert(key);
      if ((m.geom_contype[a] & m.geom_conaffinity[b]) || (m.geom_contype[b] & m.geom_conaffinity[a])) meet.insert(key);
    }
  }
  std::set<std::pair<int, int>> excluded;
  for (const auto& key : touching) {
    if (!meet.count(key)) excluded.insert(key);
  }
  for (int e = 0; e < m.nexclude; ++e) {
    const int a = m.exclude_signature[e] >> 16, b = m.exclude_signature[e] & 0xFFFF;
    excluded.insert({std::min(a, b), std::max(a, b)});
  }
  for (const auto& [a, b] : excluded) tree->contact_excludes.emplace_back(a - 1, b - 1);
}

void WarnAboutDroppedPhysics(const mjModel& m, KinematicTree* tree) {
  std::vector<std::string> tendons;
  for (int t = 0; t < m.ntendon; ++t) tendons.push_back(NameOf(m, mjOBJ_TENDON, t, "tendon"));
  if (!tendons.empty()) tree->warnings.push_back(ListWarning("tendons are dropped (tether has none)", tendons));
  if (m.opt.density > 0 || m.opt.viscosity > 0) {
    std::ostringstream medium;
    medium << "fluid forces are dropped (tether has none): the medium's density " << m.opt.density
           << " kg/m^3 and viscosity " << m.opt.viscosity << " Pa s";
    tree->warnings.push_back(medium.str());
  }
}

}  // namespace

KinematicTree TreeFromMujoco(const mjModel& m) {
  KinematicTree tree;
  if (!Disabled(m, mjDSBL_GRAVITY)) tree.gravity = Vector3(m.opt.gravity);
  tree.time_step = m.opt.timestep;
  for (int b = 1; b < m.nbody; ++b) {
    TreeLink link;
    link.name = NameOf(m, mjOBJ_BODY, b, "body");
    link.parent = m.body_parentid[b] - 1;
    link.p_PL = Vector3(m.body_pos + 3 * b);
    link.q_PL = Quaternion(m.body_quat + 4 * b);
    link.mass = m.body_mass[b];
    link.p_LC = Vector3(m.body_ipos + 3 * b);
    const Eigen::Matrix3d R_LI = Quaternion(m.body_iquat + 4 * b).toRotationMatrix();
    link.I_C_L = R_LI * Vector3(m.body_inertia + 3 * b).asDiagonal() * R_LI.transpose();
    link.static_link = m.body_mocapid[b] >= 0;
    for (int k = 0; k < m.body_jntnum[b]; ++k) link.joints.push_back(ReadJoint(m, m.body_jntadr[b] + k, link.name, k));
    tree.links.push_back(link);
  }
  for (int s = 0; s < m.nsite; ++s) {
    TreeSite site{NameOf(m, mjOBJ_SITE, s, "site"), Vector3(m.site_pos + 3 * s)};
    if (m.site_bodyid[s] == 0) {
      tree.world_sites.push_back(site.name);
    } else {
      tree.links[m.site_bodyid[s] - 1].sites.push_back(site);
    }
  }
  std::vector<std::string> mocap;
  for (const TreeLink& link : tree.links) {
    if (link.static_link) mocap.push_back(link.name);
  }
  if (!mocap.empty()) {
    tree.warnings.push_back(ListWarning("mocap bodies are held where they start (tether cannot move them)", mocap));
  }
  ReadActuators(m, &tree);
  ReadEqualities(m, &tree);
  ReadGeoms(m, &tree);
  WarnAboutDroppedPhysics(m, &tree);
  return tree;
}

namespace {

// MuJoCo's messages have line ends (and a trailing one): one line here.
std::string OneLine(std::string message) {
  for (char& c : message) c = c == '\n' ? ' ' : c;
  while (!message.empty() && message.back() == ' ') message.pop_back();
  return message;
}

// MuJoCo's warnings go to stdout and to MUJOCO_LOG.TXT in the working folder unless a handler takes them (a stray
// file, and a line in the middle of a scene that `import` writes to stdout): while tether loads a model they are
// collected here instead, and become the import's warnings. (MuJoCo calls the handler on the loading thread.)
class MujocoWarnings {
 public:
  MujocoWarnings() : previous_(mju_user_warning) {
    Collected().clear();
    mju_user_warning = &Collect;
  }
  ~MujocoWarnings() { mju_user_warning = previous_; }
  MujocoWarnings(const MujocoWarnings&) = delete;
  MujocoWarnings& operator=(const MujocoWarnings&) = delete;
  const std::vector<std::string>& messages() const { return Collected(); }

 private:
  static std::vector<std::string>& Collected() {
    static thread_local std::vector<std::string> messages;
    return messages;
  }
  static void Collect(const char* message) { Collected().push_back(OneLine(message)); }
  void (*previous_)(const char*);
};

}  // namespace

KinematicTree ReadMjcf(const std::string& path) {
  CheckInputFile(path, "model file");
  const MujocoWarnings warnings;
  char error[1024] = "";
  const std::unique_ptr<mjModel, void (*)(mjModel*)> model(mj_loadXML(path.c_str(), nullptr, error, sizeof error),
                                                           mj_deleteModel);
  const std::string message = OneLine(error);
  if (!model) throw InputError(path + ": MuJoCo cannot compile it: " + message);
  KinematicTree tree = TreeFromMujoco(*model);
  if (!message.empty()) tree.warnings.insert(tree.warnings.begin(), "MuJoCo's compiler: " + message);
  for (const std::string& warning : warnings.messages())
    tree.warnings.insert(tree.warnings.begin(), "MuJoCo: " + warning);
  return tree;
}

}  // namespace tether::importers
