// Which tether constraint holds a link to its parent the way its model joints do (docs/import.md):
//
//   one hinge -> hinge;  one slide -> prismatic;  one ball -> pin (a ball joint);  a free joint -> nothing
//   two hinges whose lines meet at X, axes apart                     -> universal at X
//   two hinges whose lines do not meet (skew or parallel)            -> double_hinge
//   three hinges whose lines all pass through X, axes independent    -> pin at X
//   a hinge and a slide along the same direction (either order)      -> cylindrical (an opposite direction would
//                                                                       flip one of its coordinates)
// Each is exact: the constraint's configurations are the joints' (a universal's rows hold the angle between an
// axis fixed in A and one fixed in B, which is what two hinges in series through X keep). Any other list of
// joints has no single tether constraint; the scene builder then splits it (scene_from_tree.cc).
//
// Geometry is compared with kSameLine: lines closer than kSameLine (1 + the model's size) metres meet, axes
// whose cross product is below kParallel are parallel.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "placement.h"

namespace tether::importers {

inline constexpr double kSameLine = 1e-9;
inline constexpr double kParallel = 1e-9;

// A tether constraint between bodies A (the parent side) and B, in world terms at the initial state.
struct ConstraintSpec {
  std::string type;                                   // "hinge", "prismatic", "pin", "universal", ...
  std::vector<const PlacedJoint*> joints;             // the model joints it stands for, in order
  Eigen::Vector3d p_WA = Eigen::Vector3d::Zero();     // the point fixed in A
  Eigen::Vector3d p_WB = Eigen::Vector3d::Zero();     // the point fixed in B
  Eigen::Vector3d axis_A_W = Eigen::Vector3d::UnitX();  // `axis`, or the first of `axes` (fixed in A)
  Eigen::Vector3d axis_B_W = Eigen::Vector3d::UnitY();  // the second of `axes` (fixed in B)
  double angle = 0.0;                                 // hinge, cylindrical: the angle at the start
};

// The constraint for one hinge, slide or ball joint (a free joint has none: nullopt).
std::optional<ConstraintSpec> SingleJointConstraint(const PlacedJoint& joint);

// The one constraint that is exactly these joints in series (two or more), or nullopt when there is none.
// `size` is the model's length scale (m) for kSameLine.
std::optional<ConstraintSpec> CombinedConstraint(const std::vector<PlacedJoint>& joints, double size);

}  // namespace tether::importers
