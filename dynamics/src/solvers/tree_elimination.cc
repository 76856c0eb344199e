#include "tether/dynamics/solvers/tree_elimination.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <type_traits>
#include <utility>

namespace tether {

std::optional<TreePlan> TreePlan::Of(const std::vector<RowInfo>& infos, const std::vector<BodyLayout>& layout,
                                     const std::vector<int>& double_hinges) {
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
      const int scene = infos[it->second[0]].scene_index;
      const bool one_constraint =
          std::all_of(it->second.begin(), it->second.end(), [&](int row) { return infos[row].scene_index == scene; });
      if (one_constraint && scene < static_cast<int>(double_hinges.size()) && double_hinges[scene] >= 0) {
        if (it->second.size() != 4) return std::nullopt;
        joint.double_hinge = double_hinges[scene];
        std::copy(it->second.begin(), it->second.end(), joint.rows.begin());
        joint_of[child] = static_cast<int>(plan.joints_.size());
        plan.joints_.push_back(joint);
        it = pairs.erase(it);
        continue;
      }
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

// A = L L^T in place for a symmetric A (its lower triangle becomes L); false where a pivot is not above `floor`.
template <int N, typename T>
bool Cholesky(double floor, Eigen::Matrix<T, N, N>* l) {
  using std::sqrt;
  Eigen::Matrix<T, N, N>& a = *l;
  for (int i = 0; i < N; ++i) {
    for (int c = 0; c < i; ++c) a(i, i) -= a(i, c) * a(i, c);
    if (!(Value(a(i, i)) > floor)) return false;
    a(i, i) = sqrt(a(i, i));
    for (int r = i + 1; r < N; ++r) {
      for (int c = 0; c < i; ++c) a(r, i) -= a(r, c) * a(i, c);
      a(r, i) /= a(i, i);
    }
  }
  return true;
}

// x = L^-1 x, row by row (x has N rows).
template <int N, typename T, typename X>
void SolveLower(const Eigen::Matrix<T, N, N>& l, Eigen::MatrixBase<X>* x) {
  for (int i = 0; i < N; ++i) {
    for (int c = 0; c < i; ++c) x->row(i) -= l(i, c) * x->row(c);
    x->row(i) /= l(i, i);
  }
}

// x = L^-T x, row by row (x has N rows).
template <int N, typename T, typename X>
void SolveUpper(const Eigen::Matrix<T, N, N>& l, Eigen::MatrixBase<X>* x) {
  for (int i = N - 1; i >= 0; --i) {
    for (int r = i + 1; r < N; ++r) x->row(i) -= l(r, i) * x->row(r);
    x->row(i) /= l(i, i);
  }
}

// T, S and b of a point-and-angle joint with kAngles angle rows (the closed form of tree_elimination.h); false where
// Y_C Y_C^T is close to singular.
template <int kAngles, typename T>
bool PointAndAngles(const TreeJoint& joint, const std::vector<ConstraintRow<T>>& rows, const VecX<T>& v, T alpha,
                    T beta, TreeJointWork<T>* w) {
  constexpr int kFree = 3 - kAngles;
  const double s = joint.child_second ? 1.0 : -1.0;
  const bool world = joint.parent == kWorld;
  // the rows' rotational blocks as columns, X^T (their translations are s e_k on the child and -s e_k on the parent for
  // the point rows, zero for the angle rows), and gamma from their rates J v; all into locals, written to *w at the
  // end (written through w as they were made, the 10-rod chain's elimination took a sixth longer)
  Mat3<T> xt_child, xt_parent;
  Vec3<T> rest_point;  // Jdot v + beta C
  for (int k = 0; k < 3; ++k) {
    const ConstraintRow<T>& row = rows[joint.rows[k]];
    xt_child.col(k) = (joint.child_second ? row.b : row.a).rotation;
    xt_parent.col(k) = (joint.child_second ? row.a : row.b).rotation;
    rest_point[k] = row.bias + beta * row.value;
  }
  const Vec3<T> v_child = v.template segment<3>(joint.child_v), w_child = v.template segment<3>(joint.child_v + 3);
  const Vec3<T> v_parent = world ? Zero3<T>() : Vec3<T>(v.template segment<3>(joint.parent_v));
  const Vec3<T> w_parent = world ? Zero3<T>() : Vec3<T>(v.template segment<3>(joint.parent_v + 3));
  const Vec3<T> gamma_point = -(rest_point + alpha * (s * (v_child - v_parent) + xt_child.transpose() * w_child +
                                                      xt_parent.transpose() * w_parent));
  Eigen::Matrix<T, 3, kAngles> yt_child, yt_parent;
  Eigen::Matrix<T, kAngles, 1> gamma_angle;
  if constexpr (kAngles > 0) {
    Eigen::Matrix<T, kAngles, 1> rest_angle;
    for (int i = 0; i < kAngles; ++i) {
      const ConstraintRow<T>& row = rows[joint.rows[3 + i]];
      yt_child.col(i) = (joint.child_second ? row.b : row.a).rotation;
      yt_parent.col(i) = (joint.child_second ? row.a : row.b).rotation;
      rest_angle[i] = row.bias + beta * row.value;
    }
    gamma_angle = -(rest_angle + alpha * (yt_child.transpose() * w_child + yt_parent.transpose() * w_parent));
  }
  // Y_C^+ = Y_C^T G^-1 with G = Y_C Y_C^T; N spans Y_C's null space
  Eigen::Matrix<T, 3, kAngles> pseudo_inverse;
  Eigen::Matrix<T, 3, kFree> null;
  if constexpr (kAngles == 0) {
    null.setIdentity();
  } else if constexpr (kAngles == 1) {
    const T g = yt_child.squaredNorm();
    if (!(Value(g) > kTreePivot)) return false;
    pseudo_inverse = yt_child / g;
    Vec3<T> n1, n2;
    AxisNormals<T>(3, yt_child, &n1, &n2);
    null << n1, n2;
  } else if constexpr (kAngles == 2) {
    const Vec3<T> y0 = yt_child.col(0), y1 = yt_child.col(1);
    const T g00 = y0.squaredNorm(), g01 = y0.dot(y1), g11 = y1.squaredNorm();
    const T determinant = g00 * g11 - g01 * g01;
    if (!(Value(determinant) > kTreePivot * std::max(1.0, std::max(Value(g00), Value(g11))))) return false;
    const T inverse = T(1.0) / determinant;
    pseudo_inverse.col(0) = (g11 * inverse) * y0 - (g01 * inverse) * y1;
    pseudo_inverse.col(1) = (g00 * inverse) * y1 - (g01 * inverse) * y0;
    null = y0.cross(y1);
  } else {
    Mat3<T> l = yt_child.transpose() * yt_child;
    if (!Cholesky(kTreePivot * std::max(1.0, Value(l.diagonal().maxCoeff())), &l)) return false;
    Mat3<T> solved = yt_child.transpose();
    SolveLower(l, &solved);
    SolveUpper(l, &solved);
    pseudo_inverse = solved.transpose();
  }
  Vec3<T> c = Zero3<T>();
  Mat3<T> k = Mat3<T>::Zero();
  if constexpr (kAngles > 0) {
    c.noalias() = pseudo_inverse * gamma_angle;
    k.noalias() = -pseudo_inverse * yt_parent.transpose();
  }
  Mat3<T> e = xt_parent.transpose();  // -s E
  e.noalias() += xt_child.transpose() * k;
  w->k = k;
  w->e = -s * e;
  w->free = kFree;
  if constexpr (kFree > 0) {
    w->directions.template block<3, kFree>(0, 0).noalias() = -s * (xt_child.transpose() * null);
    w->directions.template block<3, kFree>(3, 0) = null;
  }
  const Vec3<T> point = s * (gamma_point - xt_child.transpose() * c);
  w->offset << point, c;
  return true;
}

// T, S and b of a double hinge's four rows (the rigid following and the hinges' screws of tree_elimination.h); false
// where J_C J_C^T is close to singular.
template <typename T>
bool DoubleHinge(const Model<T>& model, const TreeJoint& joint, const std::vector<ConstraintRow<T>>& rows,
                 const BodyFrames<T>& frames, const VecX<T>& q, const VecX<T>& v, T alpha, T beta,
                 TreeJointWork<T>* w) {
  using std::sqrt;
  const bool world = joint.parent == kWorld;
  Eigen::Matrix<T, 4, 6> j_child;  // the rows first, into locals (as in PointAndAngles)
  Eigen::Matrix<T, 4, 1> gamma;
  const Vec6<T> v_child = v.template segment<6>(joint.child_v);
  const Vec6<T> v_parent = world ? Vec6<T>::Zero() : Vec6<T>(v.template segment<6>(joint.parent_v));
  for (int i = 0; i < 4; ++i) {
    const ConstraintRow<T>& row = rows[joint.rows[i]];
    const bool child_a = row.a.body == joint.child;
    const BodyVector<T>& mine = child_a ? row.a : row.b;
    const BodyVector<T>& other = child_a ? row.b : row.a;
    j_child.row(i) << mine.translation.transpose(), mine.rotation.transpose();
    const T rate = j_child.row(i).dot(v_child) + other.translation.dot(v_parent.template head<3>()) +
                   other.rotation.dot(v_parent.template tail<3>());
    gamma[i] = -(row.bias + beta * row.value + alpha * rate);
  }
  Eigen::Matrix<T, 4, 4> l = j_child * j_child.transpose();
  if (!Cholesky(kTreePivot * std::max(1.0, Value(l.diagonal().maxCoeff())), &l)) return false;
  SolveLower(l, &gamma);
  SolveUpper(l, &gamma);
  const Joint<T>& hinge = model.joints[joint.double_hinge];
  const auto centre = [&](int body) {
    return body == kWorld ? Zero3<T>() : Vec3<T>(q.template segment<3>(model.bodies[body].q_offset));
  };
  const Vec3<T> c_child = centre(joint.child);
  const Mat3<T>& r_child = frames[joint.child].R_WP;
  Vec3<T> axis[2] = {hinge.axis / sqrt(hinge.axis.squaredNorm()), hinge.axis_b / sqrt(hinge.axis_b.squaredNorm())};
  const BodyPoint<T>* points[2] = {&hinge.a, &hinge.b};
  w->free = 2;
  for (int i = 0; i < 2; ++i) {
    Vec3<T> point = points[i]->local;
    if (points[i]->body != kWorld) {
      const Mat3<T>& r_body = frames[points[i]->body].R_WB;
      axis[i] = r_body * axis[i];
      point = centre(points[i]->body) + r_body * point;
    }
    w->directions.col(i) << axis[i].cross(c_child - point), r_child.transpose() * axis[i];
  }
  if (!world) {
    const Mat3<T>& r_parent = frames[joint.parent].R_WP;
    const Vec3<T> arm = c_child - centre(joint.parent);
    w->k.noalias() = r_child.transpose() * r_parent;
    for (int k = 0; k < 3; ++k) w->e.col(k) = -arm.cross(r_parent.col(k));
  }
  w->offset.noalias() = j_child.transpose() * gamma;
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
    Eigen::Matrix<T, K, K> l = directions.transpose() * u;  // D = L L^T
    if (!Cholesky(0.0, &l)) return false;
    Eigen::Matrix<T, K, 6> w_t = u.transpose();  // W^T = L^-1 U^T
    Eigen::Matrix<T, K, 1> y = directions.transpose() * w->force;
    SolveLower(l, &w_t);
    SolveLower(l, &y);
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
    const Eigen::Matrix<T, K, K> l = w->l.template topLeftCorner<K, K>();
    SolveUpper(l, &free);
    w->acceleration.noalias() += w->directions.template leftCols<K>() * free;
  }
  return true;
}

}  // namespace

template <typename T>
TETHER_FLATTEN bool TreeAcceleration(const Model<T>& model, const TreePlan& plan,
                                     const std::vector<ConstraintRow<T>>& rows, const BodyFrames<T>& frames,
                                     const std::vector<Mat3<T>>& principal_inertia, const VecX<T>& inverse_diagonal,
                                     const std::vector<Mat3<T>>& inverse_rotational, const VecX<T>& q, const VecX<T>& v,
                                     const T& alpha, const T& beta, const VecX<T>& force, TreeWork<T>* work,
                                     VecX<T>* a) {
  const std::vector<TreeJoint>& joints = plan.joints();
  work->resize(joints.size());
  for (size_t j = 0; j < joints.size(); ++j) {
    const TreeJoint& joint = joints[j];
    TreeJointWork<T>& w = (*work)[j];
    bool made;
    if (joint.double_hinge >= 0) {
      made = DoubleHinge(model, joint, rows, frames, q, v, alpha, beta, &w);
    } else if (joint.angles == 2) {
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

#define TETHER_INSTANTIATE_TREE(T)                                                                                   \
  template bool TreeAcceleration<T>(const Model<T>&, const TreePlan&, const std::vector<ConstraintRow<T>>&,          \
                                    const BodyFrames<T>&, const std::vector<Mat3<T>>&, const VecX<T>&,               \
                                    const std::vector<Mat3<T>>&, const VecX<T>&, const VecX<T>&, const T&, const T&, \
                                    const VecX<T>&, TreeWork<T>*, VecX<T>*);
TETHER_INSTANTIATE_TREE(double)
TETHER_INSTANTIATE_TREE(::tether::Jet)

}  // namespace tether
