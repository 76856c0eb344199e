#include "tether/dynamics/solvers/tree_elimination.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <map>
#include <type_traits>
#include <utility>

namespace tether {

std::optional<TreePlan> TreePlan::Of(const std::vector<RowInfo>& infos, const std::vector<BodyLayout>& layout) {
  if (infos.empty()) return std::nullopt;
  for (const BodyLayout& body : layout) {
    if (body.kind != BodyKind::kRigid3d) return std::nullopt;
  }
  std::map<std::pair<int, int>, std::vector<int>> pairs;  // the rows of each body pair, in row order
  for (size_t i = 0; i < infos.size(); ++i) {
    const RowInfo& info = infos[i];
    if (info.law != RowLaw::kEquality || info.body_a == info.body_b) return std::nullopt;
    pairs[{std::min(info.body_a, info.body_b), std::max(info.body_a, info.body_b)}].push_back(static_cast<int>(i));
  }
  TreePlan plan;
  std::vector<int> joint_of(layout.size(), -1);
  std::vector<bool> reached(layout.size(), false);
  std::vector<int> frontier{kWorld};
  for (size_t f = 0; f < frontier.size(); ++f) {  // breadth first from the world: parents before children
    const int parent = frontier[f];
    for (auto it = pairs.begin(); it != pairs.end();) {
      const auto [a, b] = it->first;
      if (a != parent && b != parent) {
        ++it;
        continue;
      }
      const int child = a == parent ? b : a;
      if (child == kWorld || reached[child]) return std::nullopt;  // a loop
      reached[child] = true;
      frontier.push_back(child);
      TreeJoint joint;
      joint.child = child;
      joint.parent = parent;
      joint.parent_joint = parent == kWorld ? -1 : joint_of[parent];
      joint.child_v = layout[child].v_offset;
      joint.parent_v = parent == kWorld ? 0 : layout[parent].v_offset;
      joint.child_second = infos[it->second[0]].body_b == child;
      int axes = 0;
      for (int row : it->second) {
        const RowInfo& info = infos[row];
        const int axis = info.translation == RowTranslation::kZero || info.translation == RowTranslation::kEvaluated
                             ? -1
                             : TranslationAxis(info.translation);
        if ((info.body_b == child) != joint.child_second) return std::nullopt;  // rows of both orientations
        if (info.translation == RowTranslation::kZero && joint.angles < 3) {
          joint.rows[3 + joint.angles++] = row;
        } else if (axis >= 0 && !(axes >> axis & 1)) {
          axes |= 1 << axis;
          joint.rows[axis] = row;
        } else {
          return std::nullopt;  // not a point part and angle rows
        }
      }
      if (axes != 7) return std::nullopt;
      joint_of[child] = static_cast<int>(plan.joints_.size());
      plan.joints_.push_back(joint);
      it = pairs.erase(it);
    }
  }
  if (!pairs.empty()) return std::nullopt;  // rows between bodies the world does not reach through the tree
  for (size_t i = 0; i < layout.size(); ++i) {
    if (!reached[i]) plan.free_bodies_.push_back(static_cast<int>(i));
  }
  return plan;
}

namespace {

// T, S and b of a point-and-angle joint with kAngles angle rows (the closed form of tree_elimination.h); false where
// Y_C Y_C^T is close to singular.
template <int kAngles, typename T>
bool PointAndAngles(const TreeJoint& joint, const std::vector<ConstraintRow<T>>& rows, const VecX<T>& v, const T& alpha,
                    const T& beta, TreeJointWork<T>* w) {
  constexpr int kFree = 3 - kAngles;
  const double s = joint.child_second ? 1.0 : -1.0;
  const bool world = joint.parent == kWorld;
  // the rows' rotational blocks (their translations are s e_k on the child and -s e_k on the parent for the point
  // rows, zero for the angle rows), and gamma from their rates J v
  Mat3<T> x_child, x_parent;
  Vec3<T> rest_point;  // Jdot v + beta C
  for (int k = 0; k < 3; ++k) {
    const ConstraintRow<T>& row = rows[joint.rows[k]];
    x_child.row(k) = (joint.child_second ? row.b : row.a).rotation.transpose();
    x_parent.row(k) = (joint.child_second ? row.a : row.b).rotation.transpose();
    rest_point[k] = row.bias + beta * row.value;
  }
  const Vec3<T> v_child = v.template segment<3>(joint.child_v), w_child = v.template segment<3>(joint.child_v + 3);
  const Vec3<T> v_parent = world ? Zero3<T>() : Vec3<T>(v.template segment<3>(joint.parent_v));
  const Vec3<T> w_parent = world ? Zero3<T>() : Vec3<T>(v.template segment<3>(joint.parent_v + 3));
  const Vec3<T> gamma_point = -(rest_point + alpha * (s * (v_child - v_parent) + x_child * w_child +
                                                      (world ? Zero3<T>() : Vec3<T>(x_parent * w_parent))));
  Eigen::Matrix<T, kAngles, 3> y_child, y_parent;
  Eigen::Matrix<T, kAngles, 1> gamma_angle;
  if constexpr (kAngles > 0) {
    Eigen::Matrix<T, kAngles, 1> rest_angle;
    for (int i = 0; i < kAngles; ++i) {
      const ConstraintRow<T>& row = rows[joint.rows[3 + i]];
      y_child.row(i) = (joint.child_second ? row.b : row.a).rotation.transpose();
      y_parent.row(i) = (joint.child_second ? row.a : row.b).rotation.transpose();
      rest_angle[i] = row.bias + beta * row.value;
    }
    gamma_angle = -(rest_angle + alpha * (y_child * w_child + y_parent * w_parent));
  }
  // Y_C^+ = Y_C^T G^-1 with G = Y_C Y_C^T; N spans Y_C's null space
  Eigen::Matrix<T, 3, kAngles> pseudo_inverse;
  Eigen::Matrix<T, 3, kFree> null;
  if constexpr (kAngles == 0) {
    null.setIdentity();
  } else if constexpr (kAngles == 1) {
    const T g = y_child.squaredNorm();
    if (!(Value(g) > kTreePivot)) return false;
    pseudo_inverse = y_child.transpose() / g;
    Vec3<T> n1, n2;
    AxisNormals<T>(3, y_child.transpose(), &n1, &n2);
    null << n1, n2;
  } else if constexpr (kAngles == 2) {
    const Vec3<T> y0 = y_child.row(0).transpose(), y1 = y_child.row(1).transpose();
    const T g00 = y0.squaredNorm(), g01 = y0.dot(y1), g11 = y1.squaredNorm();
    const T determinant = g00 * g11 - g01 * g01;
    if (!(Value(determinant) > kTreePivot * std::max(1.0, std::max(Value(g00), Value(g11))))) return false;
    pseudo_inverse.col(0) = (g11 * y0 - g01 * y1) / determinant;
    pseudo_inverse.col(1) = (g00 * y1 - g01 * y0) / determinant;
    null = y0.cross(y1);
  } else {
    const Mat3<T> g = y_child * y_child.transpose();
    const Eigen::LLT<Mat3<T>> llt(g);
    const double largest = std::max(1.0, Value(g.diagonal().maxCoeff()));
    for (int i = 0; i < 3; ++i) {
      if (!(Value(llt.matrixLLT()(i, i)) * Value(llt.matrixLLT()(i, i)) > kTreePivot * largest)) return false;
    }
    pseudo_inverse = llt.solve(y_child).transpose();
  }
  Vec3<T> c = Zero3<T>();
  w->k.setZero();
  if constexpr (kAngles > 0) {
    c.noalias() = pseudo_inverse * gamma_angle;
    w->k.noalias() = -pseudo_inverse * y_parent;
  }
  w->e.noalias() = -s * (x_parent + x_child * w->k);
  w->free = kFree;
  if constexpr (kFree > 0) {
    w->directions.template block<3, kFree>(0, 0).noalias() = -s * (x_child * null);
    w->directions.template block<3, kFree>(3, 0) = null;
  }
  w->offset << s * (gamma_point - x_child * c), c;
  return true;
}

// y += T^T x for a joint's T = [1 E; 0 K].
template <typename T>
void AddTransportTransposed(const TreeJointWork<T>& w, const Vec6<T>& x, Vec6<T>* y) {
  y->template head<3>() += x.template head<3>();
  y->template tail<3>().noalias() += w.e.transpose() * x.template head<3>() + w.k.transpose() * x.template tail<3>();
}

// I_P += T^T I T for a joint's T = [1 E; 0 K], in 3 x 3 products.
template <typename T>
void AddTransportedInertia(const TreeJointWork<T>& w, const Eigen::Matrix<T, 6, 6>& inertia,
                           Eigen::Matrix<T, 6, 6>* out) {
  const auto a = inertia.template topLeftCorner<3, 3>();
  const auto b = inertia.template topRightCorner<3, 3>();
  const auto c = inertia.template bottomRightCorner<3, 3>();
  Mat3<T> top, bottom;
  top.noalias() = a * w.e + b * w.k;                 // the first three rows of I T
  bottom.noalias() = b.transpose() * w.e + c * w.k;  // the last three
  out->template topLeftCorner<3, 3>() += a;
  out->template topRightCorner<3, 3>() += top;
  out->template bottomLeftCorner<3, 3>() += top.transpose();
  out->template bottomRightCorner<3, 3>().noalias() += w.e.transpose() * top + w.k.transpose() * bottom;
}

// T x for a joint's T = [1 E; 0 K].
template <typename T>
Vec6<T> Transport(const TreeJointWork<T>& w, const Vec6<T>& x) {
  Vec6<T> out;
  out << x.template head<3>() + w.e * x.template tail<3>(), w.k * x.template tail<3>();
  return out;
}

// Calls f(std::integral_constant<int, k>) for k = free in [0, 3], so that a joint's blocks have fixed sizes.
template <typename F>
bool WithFreeCount(int free, F f) {
  switch (free) {
    case 0:
      return f(std::integral_constant<int, 0>());
    case 1:
      return f(std::integral_constant<int, 1>());
    case 2:
      return f(std::integral_constant<int, 2>());
    default:
      return f(std::integral_constant<int, 3>());
  }
}

// The backward step of a joint with K free directions: z, D = L L^T, W, y, and I - W W^T, z - W y in place of I and
// z (what the parent receives). False where D is not positive definite.
template <int K, typename T>
bool Eliminate(TreeJointWork<T>* w) {
  w->force.noalias() -= w->inertia * w->offset;  // z
  if constexpr (K > 0) {
    const Eigen::Matrix<T, 6, K> directions = w->directions.template leftCols<K>();
    const Eigen::Matrix<T, 6, K> u = w->inertia * directions;
    Eigen::Matrix<T, K, K> l = directions.transpose() * u;
    for (int i = 0; i < K; ++i) {  // D = L L^T, in place (the lower triangle)
      for (int c = 0; c < i; ++c) l(i, i) -= l(i, c) * l(i, c);
      if (!(Value(l(i, i)) > 0.0)) return false;
      using std::sqrt;
      l(i, i) = sqrt(l(i, i));
      for (int r = i + 1; r < K; ++r) {
        for (int c = 0; c < i; ++c) l(r, i) -= l(r, c) * l(i, c);
        l(r, i) /= l(i, i);
      }
    }
    Eigen::Matrix<T, K, 6> w_t = u.transpose();
    Eigen::Matrix<T, K, 1> y = directions.transpose() * w->force;
    for (int i = 0; i < K; ++i) {  // W^T = L^-1 U^T, y = L^-1 S^T z
      for (int c = 0; c < i; ++c) {
        w_t.row(i) -= l(i, c) * w_t.row(c);
        y[i] -= l(i, c) * y[c];
      }
      w_t.row(i) /= l(i, i);
      y[i] /= l(i, i);
    }
    w->inertia.noalias() -= w_t.transpose() * w_t;
    w->force.noalias() -= w_t.transpose() * y;
    w->l.template topLeftCorner<K, K>() = l;
    w->w.template leftCols<K>() = w_t.transpose();
    w->y.template head<K>() = y;
  }
  return true;
}

// The forward step: a_C = T a_P + b + S L^-T (y - W^T T a_P), from T a_P.
template <int K, typename T>
bool Accelerate(const Vec6<T>& transported, TreeJointWork<T>* w) {
  w->acceleration = transported + w->offset;
  if constexpr (K > 0) {
    Eigen::Matrix<T, K, 1> free = w->y.template head<K>() - w->w.template leftCols<K>().transpose() * transported;
    const auto l = w->l.template topLeftCorner<K, K>();
    for (int i = K - 1; i >= 0; --i) {  // L^-T
      for (int r = i + 1; r < K; ++r) free[i] -= l(r, i) * free[r];
      free[i] /= l(i, i);
    }
    w->acceleration.noalias() += w->directions.template leftCols<K>() * free;
  }
  return true;
}

}  // namespace

template <typename S, typename T>
TETHER_FLATTEN bool TreeAcceleration(const Model<S>& model, const TreePlan& plan,
                                     const std::vector<ConstraintRow<T>>& rows,
                                     const std::vector<Mat3<T>>& principal_inertia, const VecX<T>& inverse_diagonal,
                                     const std::vector<Mat3<T>>& inverse_rotational, const VecX<T>& v, const T& alpha,
                                     const T& beta, const VecX<T>& force, TreeWork<T>* work, VecX<T>* a) {
  const std::vector<TreeJoint>& joints = plan.joints();
  work->resize(joints.size());
  for (size_t j = 0; j < joints.size(); ++j) {
    const TreeJoint& joint = joints[j];
    TreeJointWork<T>& w = (*work)[j];
    bool made;
    if (joint.angles == 2) {
      made = PointAndAngles<2>(joint, rows, v, alpha, beta, &w);
    } else if (joint.angles == 0) {
      made = PointAndAngles<0>(joint, rows, v, alpha, beta, &w);
    } else if (joint.angles == 1) {
      made = PointAndAngles<1>(joint, rows, v, alpha, beta, &w);
    } else {
      made = PointAndAngles<3>(joint, rows, v, alpha, beta, &w);
    }
    if (!made) return false;
    w.inertia.setZero();
    w.inertia.template topLeftCorner<3, 3>().diagonal().setConstant(T(model.bodies[joint.child].mass));
    w.inertia.template bottomRightCorner<3, 3>() = principal_inertia[joint.child];
    w.force = force.template segment<6>(joint.child_v);
  }
  for (size_t j = joints.size(); j-- > 0;) {  // children first
    const TreeJoint& joint = joints[j];
    TreeJointWork<T>& w = (*work)[j];
    if (!WithFreeCount(w.free, [&](auto k) { return Eliminate<k()>(&w); })) return false;
    if (joint.parent == kWorld) continue;
    TreeJointWork<T>& parent = (*work)[joint.parent_joint];
    AddTransportedInertia(w, w.inertia, &parent.inertia);
    AddTransportTransposed(w, w.force, &parent.force);
  }
  for (size_t j = 0; j < joints.size(); ++j) {  // parents first
    const TreeJoint& joint = joints[j];
    TreeJointWork<T>& w = (*work)[j];
    Vec6<T> transported = Vec6<T>::Zero();
    if (joint.parent != kWorld) transported = Transport(w, (*work)[joint.parent_joint].acceleration);
    WithFreeCount(w.free, [&](auto k) { return Accelerate<k()>(transported, &w); });
    a->template segment<6>(joint.child_v) = w.acceleration;
  }
  for (int body : plan.free_bodies()) {  // M^-1 f as ApplyInverseMass takes it
    const int o = model.bodies[body].v_offset;
    for (int k = 0; k < 3; ++k) (*a)[o + k] = inverse_diagonal[o + k] * force[o + k];
    a->template segment<3>(o + 3) = inverse_rotational[body] * force.template segment<3>(o + 3);
  }
  return true;
}

#define TETHER_INSTANTIATE_TREE(T)                                                                               \
  template bool TreeAcceleration<T, T>(const Model<T>&, const TreePlan&, const std::vector<ConstraintRow<T>>&,   \
                                       const std::vector<Mat3<T>>&, const VecX<T>&, const std::vector<Mat3<T>>&, \
                                       const VecX<T>&, const T&, const T&, const VecX<T>&, TreeWork<T>*, VecX<T>*);
TETHER_INSTANTIATE_TREE(double)
TETHER_INSTANTIATE_TREE(::tether::Jet)

}  // namespace tether
