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
        for (int row : it->second) {  // a distance, one or two lines and an angle
          const std::pair<RowPrimitive, int> source{infos[row].kind, infos[row].primitive};
          if (source.first != RowPrimitive::kDistance && source.first != RowPrimitive::kLine &&
              source.first != RowPrimitive::kAngle) {
            return std::nullopt;
          }
          if (joint.primitive_count == 0 || joint.primitives[joint.primitive_count - 1] != source) {
            joint.primitives[joint.primitive_count++] = source;
          }
        }
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
      // the point rows one point primitive's, the angle rows (in its order) one angle primitive's
      joint.primitives[joint.primitive_count++] = {RowPrimitive::kPoint, infos[joint.rows[0]].primitive};
      for (int k = 1; k < 3; ++k) {
        if (infos[joint.rows[k]].primitive != joint.primitives[0].second) return std::nullopt;
      }
      if (joint.angles > 0) {
        joint.primitives[joint.primitive_count++] = {RowPrimitive::kAngle, infos[joint.rows[3]].primitive};
        for (int k = 1; k < joint.angles; ++k) {
          if (infos[joint.rows[3 + k]].primitive != joint.primitives[1].second) return std::nullopt;
        }
      }
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

// A = L L^T in place for a symmetric A: its strict lower triangle becomes L's, its diagonal L's reciprocals (so that
// the solves multiply); false where a pivot is not above `floor`.
template <int N, typename T>
bool Cholesky(double floor, Eigen::Matrix<T, N, N>* l) {
  using std::sqrt;
  Eigen::Matrix<T, N, N>& a = *l;
  for (int i = 0; i < N; ++i) {
    for (int c = 0; c < i; ++c) a(i, i) -= a(i, c) * a(i, c);
    if (!(Value(a(i, i)) > floor)) return false;
    a(i, i) = T(1.0) / sqrt(a(i, i));
    for (int r = i + 1; r < N; ++r) {
      for (int c = 0; c < i; ++c) a(r, i) -= a(r, c) * a(i, c);
      a(r, i) *= a(i, i);
    }
  }
  return true;
}

// x = L^-1 x, row by row (x has N rows; l as Cholesky leaves it).
template <int N, typename T, typename X>
void SolveLower(const Eigen::Matrix<T, N, N>& l, Eigen::MatrixBase<X>* x) {
  for (int i = 0; i < N; ++i) {
    for (int c = 0; c < i; ++c) x->row(i) -= l(i, c) * x->row(c);
    x->row(i) *= l(i, i);
  }
}

// x = L^-T x, row by row (x has N rows; l as Cholesky leaves it).
template <int N, typename T, typename X>
void SolveUpper(const Eigen::Matrix<T, N, N>& l, Eigen::MatrixBase<X>* x) {
  for (int i = N - 1; i >= 0; --i) {
    for (int r = i + 1; r < N; ++r) x->row(i) -= l(r, i) * x->row(r);
    x->row(i) *= l(i, i);
  }
}

// A body's centre of mass in the world.
template <typename T>
Vec3<T> Centre(const Model<T>& model, const VecX<T>& q, int body) {
  return q.template segment<3>(model.bodies[body].q_offset);
}

// A row in the world's axes for the tree path, as constraint_rows.h defines it for its primitive: its value C, its
// rate J v, its bias Jdot v and its block on the joint's child (translation, then rotation).
template <typename T>
struct WorldRow {
  T value, rate, bias;
  Vec6<T> child;
  T Gamma(const T& alpha, const T& beta) const { return -(bias + beta * value + alpha * rate); }
};

// An angle primitive's kRows rows (c.rows of them): row k is C = u . w - c with u turning with A and w with B,
// J v = (w_A - w_B) . n with n = u x w, Jdot v = (w_A - w_B) . ((w_A x u) x w + u x (w_B x w)); its value into
// values[k], the child's rotational block +-n into column k of *blocks and its gamma into (*gamma)[k]. Two rows are a
// common axis's (CommonAxis: one w, turned once) and three a frozen orientation's (FrozenOrientation: u_k = e_k, so
// that R_WA u_k is R_WA's column k).
template <int kRows, typename T>
void AngleRows(const AnglePrimitive<T>& c, const BodyFrames<T>& frames, int child, const T& alpha, const T& beta,
               Eigen::Matrix<T, 3, kRows>* blocks, Eigen::Matrix<T, kRows, 1>* gamma, T* values) {
  static const BodyFrame<T> world;  // R = 1, w = 0
  const BodyFrame<T>& a = c.body_a == kWorld ? world : frames[c.body_a];
  const BodyFrame<T>& b = c.body_b == kWorld ? world : frames[c.body_b];
  const Vec3<T> turning = a.w_W - b.w_W;
  const double sign = c.body_a == child ? 1.0 : -1.0;
  Vec3<T> w, spin_w;  // w and w_B x w
  for (int k = 0; k < kRows; ++k) {
    if (kRows != 2 || k == 0) {
      w.noalias() = b.R_WB * c.w[k];
      spin_w = b.w_W.cross(w);
    }
    const Vec3<T> u = kRows == 3 ? Vec3<T>(a.R_WB.col(k)) : Vec3<T>(a.R_WB * c.u[k]);
    const Vec3<T> normal = u.cross(w);
    values[k] = u.dot(w) - c.c[k];
    const T bias = turning.dot(Vec3<T>(a.w_W.cross(u).cross(w) + u.cross(spin_w)));
    (*gamma)[k] = -(bias + beta * values[k] + alpha * turning.dot(normal));
    blocks->col(k) = sign * normal;
  }
}

// A distance primitive's row from the motions of its points a and b: C = |d| - L, J v = n . d', the child's block
// +-(n, r x n) at its point.
template <typename T>
WorldRow<T> DistanceRow(const DistancePrimitive<T>& c, const PointMotion<T>& pa, const PointMotion<T>& pb, int child) {
  const Segment<T> segment = Between(pa, pb);
  const Vec3<T>& n = segment.n;
  const Vec3<T> dv = pb.velocity - pa.velocity;
  WorldRow<T> row;
  row.value = segment.length - c.length;
  row.rate = n.dot(dv);
  row.bias = (dv.squaredNorm() - row.rate * row.rate) * segment.inverse_length + n.dot(pb.centripetal - pa.centripetal);
  row.child << n, (c.b.body == child ? pb.arm : pa.arm).cross(n);
  if (c.a.body == child) row.child = -row.child;
  return row;
}

// A line primitive's row k from the motions of its points a and b: C = n . d - c with n turning with A,
// J v = n . d' + w_A . (n x d), the child's block (n, r_B x n) on B and (-n, n x d - r_A x n) on A.
template <typename T>
WorldRow<T> LineRow(const LinePrimitive<T>& c, int k, const BodyFrames<T>& frames, const PointMotion<T>& pa,
                    const PointMotion<T>& pb, int child) {
  const bool world_a = c.a.body == kWorld;
  const Vec3<T> w_a = world_a ? Zero3<T>() : frames[c.a.body].w_W;
  const Vec3<T> n = world_a ? c.normals[k] : Vec3<T>(frames[c.a.body].R_WB * c.normals[k]);
  const Vec3<T> d = pb.position - pa.position, dv = pb.velocity - pa.velocity;
  const Vec3<T> n_x_d = n.cross(d), turn = w_a.cross(n);
  WorldRow<T> row;
  row.value = n.dot(d) - c.offsets[k];
  row.rate = n.dot(dv) + w_a.dot(n_x_d);
  row.bias = n.dot(pb.centripetal - pa.centripetal) + T(2.0) * turn.dot(dv) + w_a.cross(turn).dot(d);
  if (c.a.body == child) {
    row.child << -n, n_x_d - pa.arm.cross(n);
  } else {
    row.child << n, pb.arm.cross(n);
  }
  return row;
}

// S, b and d of a point-and-angle joint with kAngles angle rows (the closed form of tree_elimination.h), in the
// world's axes from its point and angle primitives, with the bodies' centres c_C - c_P; the rows' values into rows.
// False where Y_C Y_C^T is close to singular.
template <int kAngles, typename T>
bool PointAndAngles(const Model<T>& model, const TreeJoint& joint, const ConstraintSet<T>& set,
                    const BodyFrames<T>& frames, const Vec3<T>& centres, const VecX<T>& q, const VecX<T>& v, T alpha,
                    T beta, std::vector<ConstraintRow<T>>* rows, TreeJointWork<T>* w) {
  constexpr int kFree = 3 - kAngles;
  const double s = joint.child_second ? 1.0 : -1.0;
  const PointPrimitive<T>& point = set.points[joint.primitives[0].second];
  const PointMotion<T> pa = MovePoint(model, frames, point.a, q, v, true);
  const PointMotion<T> pb = MovePoint(model, frames, point.b, q, v, true);
  const Vec3<T> separation = pb.position - pa.position;  // the point rows' values
  const Vec3<T> gamma_point =
      -((pb.centripetal - pa.centripetal) + beta * separation + alpha * (pb.velocity - pa.velocity));
  const Vec3<T>& arm = joint.child_second ? pb.arm : pa.arm;  // r_C
  for (int k = 0; k < 3; ++k) (*rows)[joint.rows[k]].value = separation[k];
  // the angle rows: their values, the child's blocks -s (u x w) (the columns of Y_C^T) and gamma
  Eigen::Matrix<T, 3, kAngles> yt_child;
  Eigen::Matrix<T, kAngles, 1> gamma_angle;
  if constexpr (kAngles > 0) {
    T values[kAngles];
    AngleRows(set.angles[joint.primitives[1].second], frames, joint.child, alpha, beta, &yt_child, &gamma_angle,
              values);
    for (int i = 0; i < kAngles; ++i) (*rows)[joint.rows[3 + i]].value = values[i];
  }
  // c = Y_C^+ gamma_angle with Y_C^+ = Y_C^T G^-1, G = Y_C Y_C^T; N spans Y_C's null space
  Vec3<T> c = Zero3<T>();
  Eigen::Matrix<T, 3, kFree> null;
  if constexpr (kAngles == 0) {
    null.setIdentity();
  } else if constexpr (kAngles == 1) {
    const T g = yt_child.squaredNorm();
    if (!(Value(g) > kTreePivot)) return false;
    c = yt_child * (gamma_angle[0] / g);
    Vec3<T> n1, n2;
    AxisNormals<T>(3, yt_child, &n1, &n2);
    null << n1, n2;
  } else if constexpr (kAngles == 2) {
    const Vec3<T> y0 = yt_child.col(0), y1 = yt_child.col(1);
    const T g00 = y0.squaredNorm(), g01 = y0.dot(y1), g11 = y1.squaredNorm();
    const T determinant = g00 * g11 - g01 * g01;
    if (!(Value(determinant) > kTreePivot * std::max(1.0, std::max(Value(g00), Value(g11))))) return false;
    const T inverse = T(1.0) / determinant;
    c = ((g11 * gamma_angle[0] - g01 * gamma_angle[1]) * inverse) * y0 +
        ((g00 * gamma_angle[1] - g01 * gamma_angle[0]) * inverse) * y1;
    null = y0.cross(y1);
  } else {
    Mat3<T> l = yt_child.transpose() * yt_child;
    if (!Cholesky(kTreePivot * std::max(1.0, Value(l.diagonal().maxCoeff())), &l)) return false;
    SolveLower(l, &gamma_angle);
    SolveUpper(l, &gamma_angle);
    c.noalias() = yt_child * gamma_angle;
  }
  w->free = kFree;
  if constexpr (kFree > 0) {
    for (int k = 0; k < kFree; ++k) {
      w->directions.template block<3, 1>(0, k) = arm.cross(Vec3<T>(null.col(k)));
      w->directions.template block<3, 1>(3, k) = null.col(k);
    }
  }
  w->offset << s * gamma_point + arm.cross(c), c;
  w->arm = centres - s * separation;
  return true;
}

// S, b and d of a double hinge's four rows (the hinges' screws of tree_elimination.h, in the world), from the bodies'
// centres c_C - c_P; the rows from their primitives in the world's axes, their values into rows. False where
// J_C J_C^T is close to singular.
template <typename T>
bool DoubleHinge(const Model<T>& model, const TreeJoint& joint, const ConstraintSet<T>& set,
                 const BodyFrames<T>& frames, const Vec3<T>& centres, const VecX<T>& q, const VecX<T>& v, T alpha,
                 T beta, std::vector<ConstraintRow<T>>* rows, TreeJointWork<T>* w) {
  using std::sqrt;
  Eigen::Matrix<T, 4, 6> j_child;  // the rows first, into locals (as in PointAndAngles)
  Eigen::Matrix<T, 4, 1> gamma;
  int i = 0;
  const auto put = [&](const T& value, const Vec6<T>& child, const T& row_gamma) {  // row i
    (*rows)[joint.rows[i]].value = value;
    j_child.row(i) = child.transpose();
    gamma[i++] = row_gamma;
  };
  const auto add = [&](const WorldRow<T>& row) { put(row.value, row.child, row.Gamma(alpha, beta)); };
  const auto add_angles = [&](const AnglePrimitive<T>& angle, auto count) {  // kRows = count rows (AngleRows)
    constexpr int kRows = decltype(count)::value;
    Eigen::Matrix<T, 3, kRows> blocks;
    Eigen::Matrix<T, kRows, 1> gammas;
    T values[kRows];
    AngleRows(angle, frames, joint.child, alpha, beta, &blocks, &gammas, values);
    for (int k = 0; k < kRows; ++k) put(values[k], (Vec6<T>() << Zero3<T>(), blocks.col(k)).finished(), gammas[k]);
  };
  // the distance and the lines join the hinge's two points (AddDoubleHinge), the second line from b to a: their
  // motions are taken once
  const Joint<T>& hinge = model.joints[joint.double_hinge];
  const PointMotion<T> motion_a = MovePoint(model, frames, hinge.a, q, v, true);
  const PointMotion<T> motion_b = MovePoint(model, frames, hinge.b, q, v, true);
  for (int p = 0; p < joint.primitive_count; ++p) {
    const auto [kind, index] = joint.primitives[p];
    if (kind == RowPrimitive::kDistance) {
      add(DistanceRow(set.distances[index], motion_a, motion_b, joint.child));
    } else if (kind == RowPrimitive::kLine) {
      const LinePrimitive<T>& line = set.lines[index];
      const bool forward = line.a.body == hinge.a.body;
      for (int k = 0; k < line.rows; ++k) {
        add(LineRow(line, k, frames, forward ? motion_a : motion_b, forward ? motion_b : motion_a, joint.child));
      }
    } else if (set.angles[index].rows == 1) {
      add_angles(set.angles[index], std::integral_constant<int, 1>());
    } else {
      add_angles(set.angles[index], std::integral_constant<int, 2>());
    }
  }
  Eigen::Matrix<T, 4, 4> l = j_child * j_child.transpose();
  if (!Cholesky(kTreePivot * std::max(1.0, Value(l.diagonal().maxCoeff())), &l)) return false;
  SolveLower(l, &gamma);
  SolveUpper(l, &gamma);
  const Vec3<T> c_child = Centre(model, q, joint.child);
  Vec3<T> axis[2] = {hinge.axis / sqrt(hinge.axis.squaredNorm()), hinge.axis_b / sqrt(hinge.axis_b.squaredNorm())};
  const int bodies[2] = {hinge.a.body, hinge.b.body};
  const Vec3<T>* points[2] = {&motion_a.position, &motion_b.position};
  w->free = 2;
  for (int h = 0; h < 2; ++h) {
    if (bodies[h] != kWorld) axis[h] = frames[bodies[h]].R_WB * axis[h];
    w->directions.col(h) << axis[h].cross(c_child - *points[h]), axis[h];
  }
  w->offset.noalias() = j_child.transpose() * gamma;
  w->arm = centres;
  return true;
}

// I_P += X^T I X for the rigid transport X = [1 -[d]x; 0 1] (d: the child's centre from its parent's): with
// I = [A B; B^T C] and G = B - A [d]x = B + (d x A)^T (columnwise cross products),
//   X^T I X = [A G; G^T C + d x G + (d x B)^T].
// Both are symmetric: only their lower triangles are read and written (A's, G^T, C's).
template <typename T>
void AddShiftedInertia(const Vec3<T>& d, const Eigen::Matrix<T, 6, 6>& inertia, Eigen::Matrix<T, 6, 6>* out) {
  const auto cross = [&d](const auto& m) {
    Mat3<T> out;
    for (int k = 0; k < 3; ++k) out.col(k) = d.cross(Vec3<T>(m.col(k)));
    return out;
  };
  const Mat3<T> a = inertia.template topLeftCorner<3, 3>().template selfadjointView<Eigen::Lower>();
  const Mat3<T> b_t = inertia.template bottomLeftCorner<3, 3>();  // B^T
  const Mat3<T> g_t = b_t + cross(a);                             // G^T
  const Mat3<T> c = cross(g_t.transpose()) + cross(b_t.transpose()).transpose();
  for (int col = 0; col < 3; ++col) {
    for (int row = col; row < 3; ++row) {
      (*out)(row, col) += a(row, col);
      (*out)(3 + row, 3 + col) += inertia(3 + row, 3 + col) + c(row, col);
    }
  }
  out->template bottomLeftCorner<3, 3>() += g_t;
}

// The upper triangle of a symmetric I from its lower one.
template <typename T>
void Mirror(Eigen::Matrix<T, 6, 6>* inertia) {
  for (int col = 1; col < 6; ++col) {
    for (int row = 0; row < col; ++row) (*inertia)(row, col) = (*inertia)(col, row);
  }
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

// The backward step of a joint with K free directions: z, D = L L^T, W, y, and, for a parent that is a body, I - W W^T
// and z - W y in place of I and z (what the parent receives). False where D is not positive definite.
template <int K, typename T>
bool Eliminate(bool to_parent, TreeJointWork<T>* w) {
  Mirror(&w->inertia);
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
    if (to_parent) {
      for (int col = 0; col < 6; ++col) {  // the lower triangle, as the parent reads it
        for (int row = col; row < 6; ++row) w->inertia(row, col) -= w_t.col(row).dot(w_t.col(col));
      }
      w->force.noalias() -= w_t.transpose() * y;
    }
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
TETHER_FLATTEN bool TreeAcceleration(const Model<T>& model, const TreePlan& plan, const ConstraintSet<T>& set,
                                     const BodyFrames<T>& frames, const std::vector<Mat3<T>>& principal_inertia,
                                     const VecX<T>& inverse_diagonal, const std::vector<Mat3<T>>& inverse_rotational,
                                     const VecX<T>& q, const VecX<T>& v, const T& alpha, const T& beta,
                                     const VecX<T>& force, TreeWork<T>* work, std::vector<ConstraintRow<T>>* rows,
                                     VecX<T>* a) {
  const std::vector<TreeJoint>& joints = plan.joints();
  work->resize(joints.size());
  for (size_t j = 0; j < joints.size(); ++j) {  // S, b, and each body's own inertia and force, in the world
    const TreeJoint& joint = joints[j];
    TreeJointWork<T>& w = (*work)[j];
    const Mat3<T>& r_child = frames[joint.child].R_WP;
    const Vec3<T> centres =
        Centre(model, q, joint.child) - (joint.parent == kWorld ? Zero3<T>() : Centre(model, q, joint.parent));
    bool made;
    if (joint.double_hinge >= 0) {
      made = DoubleHinge(model, joint, set, frames, centres, q, v, alpha, beta, rows, &w);
    } else if (joint.angles == 2) {
      made = PointAndAngles<2>(model, joint, set, frames, centres, q, v, alpha, beta, rows, &w);
    } else if (joint.angles == 0) {
      made = PointAndAngles<0>(model, joint, set, frames, centres, q, v, alpha, beta, rows, &w);
    } else if (joint.angles == 1) {
      made = PointAndAngles<1>(model, joint, set, frames, centres, q, v, alpha, beta, rows, &w);
    } else {
      made = PointAndAngles<3>(model, joint, set, frames, centres, q, v, alpha, beta, rows, &w);
    }
    if (!made) return false;
    const Mat3<T> r_inertia = r_child * principal_inertia[joint.child];
    const T mass(model.bodies[joint.child].mass);
    for (int col = 0; col < 3; ++col) {  // the lower triangle of diag(m 1, R J R^T) (AddShiftedInertia)
      for (int row = col; row < 3; ++row) {
        w.inertia(row, col) = row == col ? mass : T(0.0);
        w.inertia(3 + row, 3 + col) = r_inertia.row(row).dot(r_child.row(col));
      }
      w.inertia.template block<3, 1>(3, col).setZero();
    }
    w.force.template head<3>() = force.template segment<3>(joint.child_v);
    w.force.template tail<3>().noalias() = r_child * force.template segment<3>(joint.child_v + 3);
  }
  for (size_t j = joints.size(); j-- > 0;) {  // children first
    const TreeJoint& joint = joints[j];
    TreeJointWork<T>& w = (*work)[j];
    const bool to_parent = joint.parent != kWorld;
    if (!WithFreeCount(w.free, [&](auto k) { return Eliminate<k()>(to_parent, &w); })) return false;
    if (!to_parent) continue;
    TreeJointWork<T>& parent = (*work)[joint.parent_joint];
    AddShiftedInertia(w.arm, w.inertia, &parent.inertia);
    parent.force.template head<3>() += w.force.template head<3>();  // X^T p = [f; d x f + tau]
    parent.force.template tail<3>() += w.arm.cross(Vec3<T>(w.force.template head<3>())) + w.force.template tail<3>();
  }
  for (size_t j = 0; j < joints.size(); ++j) {  // parents first
    const TreeJoint& joint = joints[j];
    TreeJointWork<T>& w = (*work)[j];
    Vec6<T> transported = Vec6<T>::Zero();  // X a_P = [a - d x alpha; alpha]
    if (joint.parent != kWorld) {
      const Vec6<T>& parent = (*work)[joint.parent_joint].acceleration;
      const Vec3<T> alpha_parent = parent.template tail<3>();
      transported.template head<3>() = parent.template head<3>() - w.arm.cross(alpha_parent);
      transported.template tail<3>() = alpha_parent;
    }
    WithFreeCount(w.free, [&](auto k) { return Accelerate<k()>(transported, &w); });
    a->template segment<3>(joint.child_v) = w.acceleration.template head<3>();
    a->template segment<3>(joint.child_v + 3) =
        TransposeTimes(frames[joint.child].R_WP, Vec3<T>(w.acceleration.template tail<3>()));
  }
  for (int body : plan.free_bodies()) {  // M^-1 f as ApplyInverseMass takes it
    const int o = model.bodies[body].v_offset;
    for (int k = 0; k < 3; ++k) (*a)[o + k] = inverse_diagonal[o + k] * force[o + k];
    a->template segment<3>(o + 3) = inverse_rotational[body] * force.template segment<3>(o + 3);
  }
  return true;
}

#define TETHER_INSTANTIATE_TREE(T)                                                                                    \
  template bool TreeAcceleration<T>(const Model<T>&, const TreePlan&, const ConstraintSet<T>&, const BodyFrames<T>&,  \
                                    const std::vector<Mat3<T>>&, const VecX<T>&, const std::vector<Mat3<T>>&,         \
                                    const VecX<T>&, const VecX<T>&, const T&, const T&, const VecX<T>&, TreeWork<T>*, \
                                    std::vector<ConstraintRow<T>>*, VecX<T>*);
TETHER_INSTANTIATE_TREE(double)
TETHER_INSTANTIATE_TREE(::tether::Jet)

}  // namespace tether
