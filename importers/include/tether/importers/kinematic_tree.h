// KinematicTree: what both importers read a model into (MJCF through MuJoCo's own compiler, URDF through
// urdfdom), before it becomes a tether scene (scene_from_tree.h).
//
// Frames (Drake's monogram notation), all at the model's reference configuration (MuJoCo's qpos0, URDF's zero
// joint values):
//   W  the world;  P  a link's parent link (W for a root link);  L  the link's own frame (MuJoCo's body frame,
//   URDF's link frame, which is its joint's frame);  C  the link's centre of mass.
// A link moves relative to its parent by its joints, applied in order, each about or along a line fixed in the
// frame the joints before it produced (MuJoCo's rule for several joints in one body):
//   X_WL = X_WP X_PL M_1(q_1) ... M_n(q_n),
// where M_k turns by q_k - reference_k about the line through p_LJ along axis_L (hinge), moves by q_k -
// reference_k along axis_L (slide), or turns freely about p_LJ (ball). A link with no joint is welded to its
// parent; a free joint frees it (X_PL is then its initial pose, and P is the world). Joint k's line is fixed in
// the frame of joints 1..k-1 and in that of joints 1..k alike, so the first joint's line is fixed in the parent
// and the last one's in the link.
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace tether::importers {

enum class TreeJointType { kHinge, kSlide, kBall, kFree };

struct TreeJoint {
  std::string name;                        // unique among the tree's joints, never empty (readers name them)
  TreeJointType type = TreeJointType::kHinge;
  Eigen::Vector3d p_LJ = Eigen::Vector3d::Zero();       // anchor, m, in L
  Eigen::Vector3d axis_L = Eigen::Vector3d::UnitZ();    // unit, in L (hinge, slide)
  double reference = 0.0;                  // the coordinate at which M_k is the identity (rad or m), where the
                                           // model starts unless told otherwise
  double stiffness = 0.0;                  // N m/rad or N/m, pulling towards spring_rest
  double spring_rest = 0.0;                // rad or m
  double damping = 0.0;                    // N m s/rad or N s/m
  double armature = 0.0;                   // kg m^2 or kg: rotor inertia added to the joint (tether has none)
  double friction_loss = 0.0;              // N m or N: dry friction (tether has none)
  std::optional<Eigen::Vector2d> range;    // [low, high], rad or m, where the model limits the joint
};

// A named point of a link (an MJCF site, a URDF link frame merged into its parent).
struct TreeSite {
  std::string name;
  Eigen::Vector3d p_LS = Eigen::Vector3d::Zero();  // m, in L
};

struct TreeLink {
  std::string name;                        // unique, never empty, never "world"
  int parent = -1;                         // index into KinematicTree::links (before this one), -1 the world
  Eigen::Vector3d p_PL = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q_PL = Eigen::Quaterniond::Identity();
  double mass = 0.0;                       // kg, >= 0
  Eigen::Vector3d p_LC = Eigen::Vector3d::Zero();
  Eigen::Matrix3d I_C_L = Eigen::Matrix3d::Zero();  // kg m^2, about C in L's axes
  bool static_link = false;                // held in place although it has no parent link (a MuJoCo mocap body)
  std::vector<TreeJoint> joints;
  std::vector<TreeSite> sites;
};

// A motor: a force or torque along one joint's coordinate, set to 0 in the scene (ready to be fitted).
struct TreeMotor {
  std::string name;
  std::string joint;
};

// Two links held together: at a point (ball joint, MuJoCo's connect) or rigidly (MuJoCo's weld, at the relative
// pose of the reference configuration). A link index of -1 is the world.
struct TreeEquality {
  enum class Type { kConnect, kWeld } type = Type::kConnect;
  std::string name;
  int link_1 = -1, link_2 = -1;
  Eigen::Vector3d p_L1 = Eigen::Vector3d::Zero();  // the point, m, in link_1's frame
};

// A collision shape of a link (an MJCF geom, a URDF <collision>), in tether's shape types (model/shapes.h).
struct TreeGeom {
  enum class Type { kSphere, kCapsule, kBox, kPlane } type = Type::kSphere;
  std::string name;                                          // never empty (readers name them)
  int link = -1;                                             // index into KinematicTree::links, -1 the world
  Eigen::Vector3d p_LG = Eigen::Vector3d::Zero();            // m, in L
  Eigen::Quaterniond q_LG = Eigen::Quaterniond::Identity();  // the shape's frame: a capsule along its x axis, a
                                                             // plane's normal its z axis
  double radius = 0.0, length = 0.0;                         // sphere, capsule (length between the cap centres)
  Eigen::Vector3d size = Eigen::Vector3d::Zero();            // box: full edge lengths
  double friction = 0.0;                                     // Coulomb's coefficient
  bool contact = true;  // false: never touches (MuJoCo's contype = conaffinity = 0)
};

// The frame of a tether capsule (its axis x) in the frame of an MJCF capsule or cylinder or a URDF cylinder (axis z):
// the rotation by -90 degrees about y, which takes x to z.
inline Eigen::Quaterniond CapsuleAxisFromZ() {
  return Eigen::Quaterniond(Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitY()));
}

struct KinematicTree {
  std::vector<TreeLink> links;             // parents before their children
  std::vector<TreeGeom> geoms;
  // pairs of links (-1 the world) whose geoms never touch each other although each touches others (MuJoCo's
  // <exclude>, and pairs whose contype and conaffinity bits never meet)
  std::vector<std::pair<int, int>> contact_excludes;
  std::vector<TreeMotor> motors;
  std::vector<TreeEquality> equalities;
  std::vector<std::string> world_sites;    // named points of the world, which markers cannot name
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();   // m/s^2
  std::optional<double> time_step;         // s
  // What the model has and tether cannot express, one sentence per kind naming the elements ("3 tendons are
  // dropped (tether has no tendons): SF, SE, EF"); the scene builder adds its own.
  std::vector<std::string> warnings;
};

// "WHAT: a, b, c" with at most `shown` names and "(and N more)" after them: one warning for one kind.
std::string ListWarning(const std::string& what, const std::vector<std::string>& names, size_t shown = 12);

}  // namespace tether::importers
