#include "joint_mapping.h"

#include <Eigen/Dense>
#include <cmath>

namespace tether::importers {
namespace {

using Eigen::Vector3d;

bool IsHinge(const PlacedJoint& j) { return j.joint->type == TreeJointType::kHinge; }
bool IsSlide(const PlacedJoint& j) { return j.joint->type == TreeJointType::kSlide; }

bool Parallel(const Vector3d& u, const Vector3d& w) { return u.cross(w).norm() < kParallel; }

// The point nearest to all the lines (p_k, u_k) in the least-squares sense, with the largest distance of a line
// from it; nullopt when the lines are all parallel (no such point).
std::optional<std::pair<Vector3d, double>> NearestPoint(const std::vector<PlacedJoint>& lines) {
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Vector3d right = Vector3d::Zero();
  for (const PlacedJoint& line : lines) {
    const Eigen::Matrix3d across = Eigen::Matrix3d::Identity() - line.axis_W * line.axis_W.transpose();
    normal += across;
    right += across * line.p_WJ;
  }
  const Eigen::FullPivLU<Eigen::Matrix3d> lu(normal);
  if (lu.rank() < 3) return std::nullopt;
  const Vector3d x = lu.solve(right);
  double farthest = 0.0;
  for (const PlacedJoint& line : lines) {
    farthest = std::max(farthest, (x - line.p_WJ).cross(line.axis_W).norm());
  }
  return std::make_pair(x, farthest);
}

ConstraintSpec Spec(const std::string& type, const std::vector<PlacedJoint>& joints) {
  ConstraintSpec spec;
  spec.type = type;
  for (const PlacedJoint& j : joints) spec.joints.push_back(&j);
  return spec;
}

}  // namespace

std::optional<ConstraintSpec> SingleJointConstraint(const PlacedJoint& joint) {
  ConstraintSpec spec;
  spec.joints = {&joint};
  spec.axis_A_W = joint.axis_W;
  switch (joint.joint->type) {
    case TreeJointType::kHinge:
      spec.type = "hinge";
      spec.p_WA = spec.p_WB = joint.p_WJ;
      spec.angle = joint.value;
      return spec;
    case TreeJointType::kSlide:
      // B's point is the anchor as B carries it; A's is where that point is at coordinate 0, so that the
      // prismatic joint's displacement (p_B - p_A) . u is the model's coordinate
      spec.type = "prismatic";
      spec.p_WB = joint.X_W_after * joint.joint->p_LJ;
      spec.p_WA = spec.p_WB - joint.value * joint.axis_W;
      return spec;
    case TreeJointType::kBall:
      spec.type = "pin";
      spec.p_WA = spec.p_WB = joint.p_WJ;
      return spec;
    case TreeJointType::kFree:
      return std::nullopt;
  }
  return std::nullopt;
}

std::optional<ConstraintSpec> CombinedConstraint(const std::vector<PlacedJoint>& joints, double size) {
  const double apart = kSameLine * (1.0 + size);
  const size_t n = joints.size();
  size_t hinges = 0, slides = 0;
  for (const PlacedJoint& j : joints) {
    hinges += IsHinge(j);
    slides += IsSlide(j);
  }
  if (n == 2 && hinges == 2) {
    const PlacedJoint &first = joints[0], &second = joints[1];
    const Vector3d normal = first.axis_W.cross(second.axis_W);
    const Vector3d d = second.p_WJ - first.p_WJ;
    const bool parallel = Parallel(first.axis_W, second.axis_W);
    const double distance = parallel ? d.cross(first.axis_W).norm() : std::abs(d.dot(normal)) / normal.norm();
    if (parallel && distance < apart) return std::nullopt;  // one line: a single hinge with two coordinates
    ConstraintSpec spec = Spec(distance < apart ? "universal" : "double_hinge", joints);
    spec.axis_A_W = first.axis_W;
    spec.axis_B_W = second.axis_W;
    if (distance < apart) {
      spec.p_WA = spec.p_WB = NearestPoint(joints)->first;
    } else {
      spec.p_WA = first.p_WJ;
      spec.p_WB = second.p_WJ;
    }
    return spec;
  }
  if (n == 3 && hinges == 3) {
    Eigen::Matrix3d axes;
    for (int k = 0; k < 3; ++k) axes.col(k) = joints[k].axis_W;
    const auto nearest = NearestPoint(joints);
    if (!nearest || nearest->second >= apart || std::abs(axes.determinant()) < kParallel) return std::nullopt;
    ConstraintSpec spec = Spec("pin", joints);
    spec.p_WA = spec.p_WB = nearest->first;
    return spec;
  }
  const bool same_direction =
      n == 2 && Parallel(joints[0].axis_W, joints[1].axis_W) && joints[0].axis_W.dot(joints[1].axis_W) > 0;
  if (hinges == 1 && slides == 1 && same_direction) {  // one axis for both coordinates, as the model has them
    const PlacedJoint& hinge = IsHinge(joints[0]) ? joints[0] : joints[1];
    const PlacedJoint& slide = IsSlide(joints[0]) ? joints[0] : joints[1];
    ConstraintSpec spec = Spec("cylindrical", joints);
    spec.axis_A_W = hinge.axis_W;
    spec.p_WB = joints[1].X_W_after * hinge.joint->p_LJ;  // the hinge's anchor as B carries it
    spec.p_WA = spec.p_WB - slide.value * slide.axis_W;   // displacement = the slide's coordinate
    spec.angle = hinge.value;
    return spec;
  }
  return std::nullopt;
}

}  // namespace tether::importers
