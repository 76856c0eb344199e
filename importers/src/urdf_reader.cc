// ReadUrdf (import_model.h): a URDF model through urdfdom, the ROS parser, as a KinematicTree.
//
// URDF's frames: a link's frame is its parent joint's frame, placed in the parent link's frame by the joint's
// origin (X_PL); the joint turns or slides the child about or along `axis` in that frame, at the frame's origin,
// from coordinate 0. The inertial origin places the centre of mass and the axes of the tensor
// (ixx ... izz) in the link frame: I_C_L = R_LI I R_LI^T. The root link is the world (a fixed base, as MuJoCo
// and Pinocchio take it); a floating robot has a `floating` joint below a root link named, say, world.
// URDF names no gravity (tether takes 9.81 m/s^2 down z) and no time step.
#include <console_bridge/console.h>
#include <tinyxml.h>
#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <deque>
#include <map>
#include <set>

#include "tether/dynamics/io/input_file.h"
#include "tether/dynamics/model/errors.h"
#include "tether/importers/import_model.h"

namespace tether::importers {
namespace {

// Deeper XML is refused before urdfdom parses it (its parser recurses once per element: 200,000 levels overflowed
// the stack); MuJoCo's own parser stops at the same depth. A URDF is flat: a robot's link, its inertial, its
// inertia is three levels.
constexpr int kMaxXmlDepth = 500;

// The deepest nesting of elements in XML `text`, counted up to `stop` levels (then stop + 1): start tags open a
// level, end tags close one; empty-element tags, comments, declarations and processing instructions do neither.
int XmlNestingDepth(const std::string& text, int stop) {
  int depth = 0, deepest = 0;
  for (size_t at = text.find('<'); at != std::string::npos && deepest <= stop; at = text.find('<', at + 1)) {
    if (text.compare(at, 4, "<!--") == 0) {
      at = text.find("-->", at);
    } else if (at + 1 < text.size() && (text[at + 1] == '!' || text[at + 1] == '?')) {
      at = text.find('>', at);
    } else if (at + 1 < text.size() && text[at + 1] == '/') {
      --depth;
    } else {
      char quote = 0;  // the end of the tag, outside quoted attribute values
      size_t end = at + 1;
      for (; end < text.size() && (quote || text[end] != '>'); ++end) {
        if (text[end] == '"' || text[end] == '\'') quote = quote == text[end] ? 0 : quote ? quote : text[end];
      }
      if (end >= text.size()) break;
      if (text[end - 1] != '/') deepest = std::max(deepest, ++depth);
      at = end;
    }
    if (at == std::string::npos) break;
  }
  return deepest;
}

// urdfdom reports through console_bridge; its messages become part of the error instead of stray stderr lines.
class CapturedLog : public console_bridge::OutputHandler {
 public:
  CapturedLog() { console_bridge::useOutputHandler(this); }
  ~CapturedLog() override { console_bridge::restorePreviousOutputHandler(); }
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_WARN) text_ += (text_.empty() ? "" : "; ") + text;
  }
  const std::string& text() const { return text_; }

 private:
  std::string text_;
};

Eigen::Vector3d Vector3(const urdf::Vector3& v) { return Eigen::Vector3d(v.x, v.y, v.z); }
Eigen::Quaterniond Quaternion(const urdf::Rotation& r) { return Eigen::Quaterniond(r.w, r.x, r.y, r.z).normalized(); }

void ReadInertial(const urdf::Link& source, TreeLink* link) {
  if (!source.inertial) return;
  const urdf::Inertial& i = *source.inertial;
  link->mass = i.mass;
  link->p_LC = Vector3(i.origin.position);
  Eigen::Matrix3d I;
  I << i.ixx, i.ixy, i.ixz, i.ixy, i.iyy, i.iyz, i.ixz, i.iyz, i.izz;
  const Eigen::Matrix3d R_LI = Quaternion(i.origin.rotation).toRotationMatrix();
  link->I_C_L = R_LI * I * R_LI.transpose();
}

TreeJoint ScalarJoint(const urdf::Joint& source, const std::string& name, TreeJointType type,
                      const Eigen::Vector3d& axis) {
  TreeJoint joint;
  joint.name = name;
  joint.type = type;
  joint.axis_L = axis;
  if (source.dynamics) {
    joint.damping = source.dynamics->damping;
    joint.friction_loss = source.dynamics->friction;
  }
  return joint;
}

// The joints of a link's parent joint; a planar joint is two slides across its axis and a hinge about it.
std::vector<TreeJoint> ReadJoints(const urdf::Joint& source, const std::string& path) {
  const Eigen::Vector3d axis = Vector3(source.axis);
  const bool needs_axis = source.type != urdf::Joint::FIXED && source.type != urdf::Joint::FLOATING;
  if (needs_axis && !(axis.norm() > 0)) throw InputError(path + ": joint '" + source.name + "' has a zero axis");
  switch (source.type) {
    case urdf::Joint::REVOLUTE:
    case urdf::Joint::CONTINUOUS:
    case urdf::Joint::PRISMATIC: {
      const TreeJointType type = source.type == urdf::Joint::PRISMATIC ? TreeJointType::kSlide : TreeJointType::kHinge;
      TreeJoint joint = ScalarJoint(source, source.name, type, axis.normalized());
      if (source.type != urdf::Joint::CONTINUOUS && source.limits) {
        joint.range = Eigen::Vector2d(source.limits->lower, source.limits->upper);
      }
      return {joint};
    }
    case urdf::Joint::FLOATING: {
      TreeJoint joint;
      joint.name = source.name;
      joint.type = TreeJointType::kFree;
      return {joint};
    }
    case urdf::Joint::PLANAR: {
      const Eigen::Vector3d normal = axis.normalized();
      const Eigen::Vector3d u = normal.unitOrthogonal(), v = normal.cross(u);
      return {ScalarJoint(source, source.name + "_u", TreeJointType::kSlide, u),
              ScalarJoint(source, source.name + "_v", TreeJointType::kSlide, v),
              ScalarJoint(source, source.name, TreeJointType::kHinge, normal)};
    }
    case urdf::Joint::FIXED:
      return {};
    default:
      throw InputError(path + ": joint '" + source.name + "' has an unknown type");
  }
}

// A URDF is a tree: urdfdom takes a link that is the child of two joints (one of them lost, the other doubled
// below it) and joints that close a cycle (walked for ever), so both are refused here, naming the joints.
// The joints' tree, read from the text before urdfdom reads it: a link that is the child of two joints, or joints
// that form a cycle, are refused here. urdfdom links each link to its children by shared pointers before it looks
// for the root, so on a cycle it fails ("two root links") leaving the cycle's links to own each other: a leak
// inside its parse that no caller can free (the fuzzer's finding). TinyXML is urdfdom's own XML parser; text it
// cannot parse, or a robot without joints, is left for urdfdom to refuse or read.
void CheckTree(const std::string& text, const std::string& path) {
  TiXmlDocument document;
  document.Parse(text.c_str());
  const TiXmlElement* robot = document.Error() ? nullptr : document.FirstChildElement("robot");
  if (!robot) return;
  std::map<std::string, std::string> parent_joint, parent_of;  // link -> the joint it is the child of, its parent
  for (const TiXmlElement* joint = robot->FirstChildElement("joint"); joint;
       joint = joint->NextSiblingElement("joint")) {
    const TiXmlElement* parent = joint->FirstChildElement("parent");
    const TiXmlElement* child = joint->FirstChildElement("child");
    const char* name = joint->Attribute("name");
    const char* parent_link = parent ? parent->Attribute("link") : nullptr;
    const char* child_link = child ? child->Attribute("link") : nullptr;
    if (!name || !parent_link || !child_link) return;  // urdfdom refuses it, building nothing
    const auto [at, added] = parent_joint.emplace(child_link, name);
    if (!added) {
      throw InputError(path + ": link '" + child_link + "' is the child of two joints ('" + at->second + "' and '" +
                       name + "'): a URDF is a tree (close a loop with a constraint after import)");
    }
    parent_of[child_link] = parent_link;
  }
  // up from every link the root must come within as many steps as there are joints; a walk stops at a link an
  // earlier one reached the root from, so that every link is walked once (a long chain is not quadratic)
  std::set<std::string> rooted;
  for (const auto& [link, joint] : parent_joint) {
    std::vector<std::string> walked;
    for (std::string at = link; parent_of.count(at) && !rooted.count(at); at = parent_of.at(at)) {
      if (walked.size() > parent_joint.size()) {
        throw InputError(path + ": the joints above link '" + link + "' form a cycle (through joint '" + joint +
                         "'): a URDF is a tree");
      }
      walked.push_back(at);
    }
    rooted.insert(walked.begin(), walked.end());
  }
}

// A link's <collision> shapes as tether shapes (link -1: the world): a sphere, a box, a cylinder as the capsule
// of its radius and overall length (listed in `cylinders` for the warning); a mesh is listed in `meshes`.
void ReadCollisions(const urdf::Link& source, int link, KinematicTree* tree, std::vector<std::string>* cylinders,
                    std::vector<std::string>* meshes) {
  std::vector<urdf::CollisionSharedPtr> collisions = source.collision_array;
  if (collisions.empty() && source.collision) collisions.push_back(source.collision);
  for (size_t k = 0; k < collisions.size(); ++k) {
    const urdf::Collision& collision = *collisions[k];
    if (!collision.geometry) continue;
    TreeGeom geom;
    geom.name =
        !collision.name.empty() ? collision.name : source.name + "_collision" + (k ? std::to_string(k + 1) : "");
    geom.link = link;
    geom.p_LG = Vector3(collision.origin.position);
    geom.q_LG = Quaternion(collision.origin.rotation);
    switch (collision.geometry->type) {
      case urdf::Geometry::SPHERE:
        geom.type = TreeGeom::Type::kSphere;
        geom.radius = static_cast<const urdf::Sphere&>(*collision.geometry).radius;
        break;
      case urdf::Geometry::BOX:
        geom.type = TreeGeom::Type::kBox;
        geom.size = Vector3(static_cast<const urdf::Box&>(*collision.geometry).dim);
        break;
      case urdf::Geometry::CYLINDER: {
        const auto& cylinder = static_cast<const urdf::Cylinder&>(*collision.geometry);
        geom.type = TreeGeom::Type::kCapsule;
        geom.radius = cylinder.radius;
        geom.length = std::max(cylinder.length - 2 * cylinder.radius, 0.0);
        geom.q_LG = geom.q_LG * CapsuleAxisFromZ();
        cylinders->push_back(geom.name);
        break;
      }
      default:
        meshes->push_back(geom.name);
        continue;
    }
    tree->geoms.push_back(geom);
  }
}

}  // namespace

KinematicTree ReadUrdf(const std::string& path) {
  // NULs after the end: TinyXML 2.6 (under CheckTree and urdfdom) reads up to three bytes past a multi-byte UTF-8
  // lead byte, and a file ending in one made it read past the buffer (a fuzzed file, fuzz/corpus/findings/urdf/).
  const std::string text = ReadInputFile(path, "model file") + std::string(4, '\0');
  if (XmlNestingDepth(text, kMaxXmlDepth) > kMaxXmlDepth) {  // urdfdom's parser recurses once per level
    throw InputError(path + ": not a valid URDF model: elements nested deeper than " + std::to_string(kMaxXmlDepth) +
                     " levels");
  }
  CheckTree(text, path);
  urdf::ModelInterfaceSharedPtr model;
  {
    CapturedLog log;
    model = urdf::parseURDF(text);
    if (!model)
      throw InputError(path + ": not a valid URDF model: " + (log.text().empty() ? "urdfdom refused it" : log.text()));
  }
  KinematicTree tree;
  tree.gravity = Eigen::Vector3d(0, 0, -9.81);
  const urdf::LinkConstSharedPtr root = model->getRoot();
  std::vector<std::string> mimics, planar, cylinders, meshes;
  if (root->inertial && root->inertial->mass > 0) {
    tree.warnings.push_back("the root link '" + root->name +
                            "' is the world (a fixed base), so its mass does not "
                            "move; a floating base is a 'floating' joint below a root link");
  }
  // breadth first from the root, so that parents come before their children
  ReadCollisions(*root, -1, &tree, &cylinders, &meshes);  // the root link is the world
  std::map<std::string, int> index;
  std::deque<std::pair<urdf::LinkSharedPtr, int>> queue;
  for (const urdf::LinkSharedPtr& child : root->child_links) queue.emplace_back(child, -1);
  while (!queue.empty()) {
    const auto [source, parent] = queue.front();
    queue.pop_front();
    const urdf::Joint& joint = *source->parent_joint;
    TreeLink link;
    link.name = source->name;
    link.parent = parent;
    link.p_PL = Vector3(joint.parent_to_joint_origin_transform.position);
    link.q_PL = Quaternion(joint.parent_to_joint_origin_transform.rotation);
    ReadInertial(*source, &link);
    link.joints = ReadJoints(joint, path);
    if (joint.type == urdf::Joint::PLANAR) planar.push_back(joint.name);
    const bool driven = joint.type == urdf::Joint::REVOLUTE || joint.type == urdf::Joint::CONTINUOUS ||
                        joint.type == urdf::Joint::PRISMATIC;
    if (driven && joint.limits && joint.limits->effort > 0) tree.motors.push_back({joint.name, joint.name});
    if (joint.mimic) mimics.push_back(joint.name + " (follows " + joint.mimic->joint_name + ")");
    const int self = static_cast<int>(tree.links.size());
    ReadCollisions(*source, self, &tree, &cylinders, &meshes);
    tree.links.push_back(link);
    for (const urdf::LinkSharedPtr& child : source->child_links) queue.emplace_back(child, self);
  }
  if (!mimics.empty()) tree.warnings.push_back(ListWarning("mimic couplings are dropped (tether has none)", mimics));
  if (!cylinders.empty()) {
    tree.warnings.push_back(
        ListWarning("cylinders become capsules of the same radius and overall length (rounded "
                    "ends instead of flat ones)",
                    cylinders));
  }
  if (!meshes.empty()) {
    tree.warnings.push_back(
        ListWarning("meshes are dropped (tether's shapes are spheres, capsules, boxes and planes)", meshes));
  }
  if (!planar.empty()) {
    tree.warnings.push_back(
        ListWarning("planar joints are read as two slides across the axis (NAME_u, NAME_v) and a "
                    "hinge about it (NAME)",
                    planar));
  }
  return tree;
}

}  // namespace tether::importers
