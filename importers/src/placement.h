// The forward kinematics of a KinematicTree (kinematic_tree.h): every link's pose and twist in the world, and
// every joint's line, at given joint coordinates and rates.
//
//   F_0 = X_WP X_PL,  F_k = F_{k-1} M_k(q_k),  X_WL = F_n;   joint k's line: (F_{k-1} p_LJ, R(F_{k-1}) axis_L)
//   V_0 = V_WP,       V_k = V_{k-1} + (a_k x u_k q_k', u_k q_k') (hinge) or (0, u_k q_k') (slide)
// where a twist V = (w, v_O) is taken at the world origin (the velocity of the moving point at x is
// v_O + w x x), so that the twists of joints in series add. Ball and free joints stay at their reference
// orientation, at rest relative to the parent.
#pragma once

#include <Eigen/Geometry>
#include <map>
#include <string>
#include <vector>

#include "tether/importers/kinematic_tree.h"

namespace tether::importers {

struct Twist {
  Eigen::Vector3d w = Eigen::Vector3d::Zero();    // rad/s, world
  Eigen::Vector3d v_O = Eigen::Vector3d::Zero();  // m/s, of the point at the world origin
  Eigen::Vector3d VelocityAt(const Eigen::Vector3d& p_W) const { return v_O + w.cross(p_W); }
};

struct PlacedJoint {
  const TreeJoint* joint = nullptr;
  Eigen::Vector3d p_WJ = Eigen::Vector3d::Zero();    // a point of the joint's line (its anchor)
  Eigen::Vector3d axis_W = Eigen::Vector3d::UnitZ();  // unit
  double value = 0.0, rate = 0.0;                     // hinge, slide: the coordinate and its rate
  Eigen::Isometry3d X_W_after = Eigen::Isometry3d::Identity();  // F_k: the frame this joint leaves the link in
  Twist V_after;
};

struct PlacedLink {
  Eigen::Isometry3d X_WL = Eigen::Isometry3d::Identity();
  Twist V_WL;
  std::vector<PlacedJoint> joints;
};

// Coordinates and rates by joint name; a joint not named takes its reference and rate 0.
std::vector<PlacedLink> PlaceLinks(const KinematicTree& tree, const std::map<std::string, double>& values,
                                   const std::map<std::string, double>& rates);

}  // namespace tether::importers
