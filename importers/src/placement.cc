#include "placement.h"

namespace tether::importers {
namespace {

// M_k: the motion of a hinge or slide at coordinate q, in the link frame L (identity for ball and free joints).
Eigen::Isometry3d JointMotion(const TreeJoint& joint, double q) {
  Eigen::Isometry3d M = Eigen::Isometry3d::Identity();
  const double delta = q - joint.reference;
  if (joint.type == TreeJointType::kHinge) {
    M.linear() = Eigen::AngleAxisd(delta, joint.axis_L).toRotationMatrix();
    M.translation() = joint.p_LJ - M.linear() * joint.p_LJ;  // turning about the anchor
  } else if (joint.type == TreeJointType::kSlide) {
    M.translation() = delta * joint.axis_L;
  }
  return M;
}

double Lookup(const std::map<std::string, double>& table, const std::string& name, double otherwise) {
  const auto it = table.find(name);
  return it == table.end() ? otherwise : it->second;
}

}  // namespace

std::vector<PlacedLink> PlaceLinks(const KinematicTree& tree, const std::map<std::string, double>& values,
                                   const std::map<std::string, double>& rates) {
  std::vector<PlacedLink> placed(tree.links.size());
  for (size_t i = 0; i < tree.links.size(); ++i) {
    const TreeLink& link = tree.links[i];
    Eigen::Isometry3d X_WP = Eigen::Isometry3d::Identity();
    Twist V_WP;
    if (link.parent >= 0) {
      X_WP = placed[link.parent].X_WL;
      V_WP = placed[link.parent].V_WL;
    }
    Eigen::Isometry3d X_PL = Eigen::Isometry3d::Identity();
    X_PL.linear() = link.q_PL.normalized().toRotationMatrix();
    X_PL.translation() = link.p_PL;
    Eigen::Isometry3d F = X_WP * X_PL;
    Twist V = V_WP;
    for (const TreeJoint& joint : link.joints) {
      PlacedJoint p;
      p.joint = &joint;
      p.p_WJ = F * joint.p_LJ;
      p.axis_W = F.linear() * joint.axis_L;
      const bool moves = joint.type == TreeJointType::kHinge || joint.type == TreeJointType::kSlide;
      p.value = moves ? Lookup(values, joint.name, joint.reference) : 0.0;
      p.rate = moves ? Lookup(rates, joint.name, 0.0) : 0.0;
      F = F * JointMotion(joint, p.value);
      if (joint.type == TreeJointType::kHinge) {
        V.w += p.rate * p.axis_W;
        V.v_O += p.rate * p.p_WJ.cross(p.axis_W);
      } else if (joint.type == TreeJointType::kSlide) {
        V.v_O += p.rate * p.axis_W;
      }
      p.X_W_after = F;
      p.V_after = V;
      placed[i].joints.push_back(p);
    }
    placed[i].X_WL = F;
    placed[i].V_WL = V;
  }
  return placed;
}

}  // namespace tether::importers
