// A humanoid-sized tree for the peer benchmark, described once for both engines, with the bodies and joints of
// MuJoCo's humanoid (libmujoco-samples' humanoid.xml) and its torso fixed: 13 bodies and 21 hinge degrees of
// freedom, no contact. The abdomen is a universal joint (z, then y: lwaist) and a hinge (x: pelvis); hips are
// ball joints (three hinges at one point in MuJoCo), knees and elbows hinges, ankles and shoulders universal
// joints (two hinges): 2 + 1 + 2 (3 + 1 + 2) + 2 (2 + 1) = 21. MuJoCo welds a body without joints to the world,
// and tether does the same by taking the fixed torso as the world frame itself (its joints' points on the torso
// are world points): the same mechanism, 12 moving bodies on 51 constraint rows. Every body's axes are the
// world's at the start; the limbs hang off-vertical, so that gravity sets the tree moving from rest.
#pragma once

#include <string>
#include <vector>

#include "tether/dynamics/scalars/scalar.h"

namespace tether::bench {

enum class TreeJoint { kFixed, kHingeX, kHingeY, kBall, kUniversalZY, kUniversalYX, kUniversalXY };

struct TreeBody {
  std::string name;
  int parent;             // index into the list; -1: the world
  TreeJoint joint;
  Vec3<double> anchor;    // the joint's point, world frame at the start
  Vec3<double> centre;    // centre of mass, world frame at the start
  double mass;            // kg
  Vec3<double> inertia;   // principal moments along the world axes, kg m^2
};

inline std::vector<TreeBody> HumanoidTree() {
  std::vector<TreeBody> tree = {
      {"torso", -1, TreeJoint::kFixed, {0, 0, 1.4}, {0, 0, 1.3}, 8.0, {0.3, 0.25, 0.1}},
      {"lwaist", 0, TreeJoint::kUniversalZY, {0, 0, 1.15}, {0.01, 0, 1.08}, 2.0, {0.02, 0.015, 0.015}},
      {"pelvis", 1, TreeJoint::kHingeX, {0, 0, 1.0}, {0.02, 0, 0.93}, 5.0, {0.05, 0.04, 0.04}}};
  for (double side : {1.0, -1.0}) {
    const std::string s = side > 0 ? "_left" : "_right";
    const int thigh = static_cast<int>(tree.size());
    tree.push_back({"thigh" + s, 2, TreeJoint::kBall, {0, 0.1 * side, 0.9}, {0.12, 0.1 * side, 0.72}, 4.5, {0.07, 0.07, 0.01}});
    tree.push_back({"shin" + s, thigh, TreeJoint::kHingeY, {0.2, 0.1 * side, 0.55}, {0.2, 0.1 * side, 0.35}, 2.6,
                    {0.04, 0.04, 0.005}});
    tree.push_back({"foot" + s, thigh + 1, TreeJoint::kUniversalYX, {0.2, 0.1 * side, 0.15}, {0.26, 0.1 * side, 0.1},
                    1.2, {0.002, 0.006, 0.006}});
    const int arm = static_cast<int>(tree.size());
    tree.push_back({"upper_arm" + s, 0, TreeJoint::kUniversalXY, {0, 0.18 * side, 1.5}, {0, 0.31 * side, 1.47},
                    1.6, {0.003, 0.015, 0.015}});
    tree.push_back({"lower_arm" + s, arm, TreeJoint::kHingeX, {0, 0.44 * side, 1.45}, {0, 0.56 * side, 1.45}, 1.2,
                    {0.002, 0.01, 0.01}});
  }
  return tree;
}

}  // namespace tether::bench
