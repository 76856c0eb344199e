// Definitions for constraint_rows.h; included only by the file that instantiates them.
#pragma once

#include <Eigen/Geometry>  // cross products
#include <cmath>

#include "tether/dynamics/adjoint/recorded.h"
#include "tether/dynamics/constraints/constraint_rows.h"
#include "tether/dynamics/constraints/contact_friction.h"
#include "tether/dynamics/constraints/contact_geometry.h"
#include "tether/dynamics/constraints/user_constraint.h"

namespace tether {
namespace internal {

// R_WB of a body at configuration q (identity for the world and for particles, whose frame is the world's).
template <typename T>
Mat3<T> RotationAt(const Model<T>& model, int body, const VecX<T>& q) {
  if (body == kWorld) return Mat3<T>::Identity();
  const Body<T>& b = model.bodies[body];
  if (b.kind == BodyKind::kRigid3d) return RotationMatrix(Orientation(b, q));
  if (b.kind == BodyKind::kPlanar) return PlanarRotation(q[b.q_offset + 2]);
  return Mat3<T>::Identity();
}

template <typename T>
Vec3<T> Unit(const Vec3<T>& x) {
  using std::sqrt;
  return x / sqrt(x.squaredNorm());
}

// A distance row: C = |p_b - p_a| - length, J = (-n, n) at the points (with their arms' rotational parts),
// Jdot v = (|dv|^2 - (n . dv)^2) / |d| + n . (centripetal_b - centripetal_a).
template <typename T>
TETHER_HOT_INLINE void EvaluateDistanceRow(const Model<T>& model, const BodyFrames<T>& frames,
                                           const DistancePrimitive<T>& c, const VecX<T>& q, const VecX<T>& v,
                                           bool velocity_terms, ConstraintRow<T>* row) {
  const bool vt = velocity_terms;
  const PointMotion<T> pa = MovePoint(model, frames, c.a, q, v, vt), pb = MovePoint(model, frames, c.b, q, v, vt);
  const Segment<T> segment = Between(pa, pb);
  const Vec3<T>& n = segment.n;
  row->value = segment.length - c.length;
  row->a = PointGradient(model, frames, c.a.body, Vec3<T>(-n), pa);
  row->b = PointGradient(model, frames, c.b.body, n, pb);
  if (velocity_terms) {
    const Vec3<T> dv = pb.velocity - pa.velocity;
    const T along = n.dot(dv);
    row->bias = (dv.squaredNorm() - along * along) * segment.inverse_length + n.dot(pb.centripetal - pa.centripetal);
  }
}

// A 3D point primitive's row along e_K.
template <int K, typename T>
TETHER_HOT_INLINE void PointAxisRow(const Model<T>& model, const BodyFrames<T>& frames, const PointPrimitive<T>& c,
                                    const PointMotion<T>& pa, const PointMotion<T>& pb, bool velocity_terms,
                                    ConstraintRow<T>* row) {
  row->value = pb.position[K] - pa.position[K];
  row->a = AxisGradient<K, -1>(model, frames, c.a.body, pa);
  row->b = AxisGradient<K, 1>(model, frames, c.b.body, pb);
  if (velocity_terms) row->bias = pb.centripetal[K] - pa.centripetal[K];
}

// A point primitive's rows (one per axis): C_k = e_k . (p_b - p_a), J = (-e_k, e_k) at the points,
// Jdot v = e_k . (centripetal_b - centripetal_a). Returns the row after them.
template <typename T>
TETHER_HOT_INLINE ConstraintRow<T>* EvaluatePointRows(const Model<T>& model, const BodyFrames<T>& frames,
                                                      const PointPrimitive<T>& c, const VecX<T>& q, const VecX<T>& v,
                                                      bool velocity_terms, ConstraintRow<T>* row) {
  const bool vt = velocity_terms;
  const PointMotion<T> pa = MovePoint(model, frames, c.a, q, v, vt), pb = MovePoint(model, frames, c.b, q, v, vt);
  if (model.dimension == 3) {
    PointAxisRow<0>(model, frames, c, pa, pb, velocity_terms, row);
    PointAxisRow<1>(model, frames, c, pa, pb, velocity_terms, row + 1);
    PointAxisRow<2>(model, frames, c, pa, pb, velocity_terms, row + 2);
    return row + 3;
  }
  for (int k = 0; k < model.dimension; ++k, ++row) {
    const Vec3<T> e = Vec3<T>::Unit(k);
    row->value = pb.position[k] - pa.position[k];
    row->a = PointGradient(model, frames, c.a.body, Vec3<T>(-e), pa);
    row->b = PointGradient(model, frames, c.b.body, e, pb);
    if (velocity_terms) row->bias = pb.centripetal[k] - pa.centripetal[k];
  }
  return row;
}

template <typename T>
const BodyFrame<T>* FrameOf(const Model<T>& model, const BodyFrames<T>& frames, int body);
template <typename T>
BodyVector<T> Turning(const Model<T>& model, const BodyFrames<T>& frames, int body, const Vec3<T>& g_W);

// A line primitive's rows: C_k = n_k . (p_b - p_a) - c_k with n_k = R_WA n_k^A turning with A,
// J v = n . d' + w_A . (n x d), Jdot v = n . (c_B - c_A) + 2 (w_A x n) . d' + (w_A x (w_A x n)) . d.
// Returns the row after them.
template <typename T>
TETHER_HOT_INLINE ConstraintRow<T>* EvaluateLineRows(const Model<T>& model, const BodyFrames<T>& frames,
                                                     const LinePrimitive<T>& c, const VecX<T>& q, const VecX<T>& v,
                                                     bool velocity_terms, ConstraintRow<T>* row) {
  const bool vt = velocity_terms;
  const PointMotion<T> pa = MovePoint(model, frames, c.a, q, v, vt), pb = MovePoint(model, frames, c.b, q, v, vt);
  const BodyFrame<T>* frame_a = FrameOf(model, frames, c.a.body);
  const Vec3<T> w_A = frame_a && velocity_terms ? frame_a->w_W : Zero3<T>();
  const Vec3<T> d = pb.position - pa.position;
  for (int k = 0; k < c.rows; ++k, ++row) {
    const Vec3<T> n = frame_a ? Vec3<T>(frame_a->R_WB * c.normals[k]) : c.normals[k];
    row->value = n.dot(d) - c.offsets[k];
    row->a = PointGradient(model, frames, c.a.body, Vec3<T>(-n), pa);
    if (frame_a) row->a.rotation += RotationalPart(model, frames, c.a.body, Vec3<T>(n.cross(d)));  // n turns with A
    row->b = PointGradient(model, frames, c.b.body, n, pb);
    if (velocity_terms) {
      const Vec3<T> dv = pb.velocity - pa.velocity;
      const Vec3<T> turn = w_A.cross(n);
      row->bias = n.dot(pb.centripetal - pa.centripetal) + T(2.0) * turn.dot(dv) + w_A.cross(turn).dot(d);
    }
  }
  return row;
}

// An angle primitive's rows: C_k = u_k . w_k - c_k with u_k = R_WA u_k^A, w_k = R_WB w_k^B,
// J = (u x w, -(u x w)) on the rotations, Jdot v = (w_A - w_B) . ((w_A x u) x w + u x (w_B x w)).
template <typename T>
TETHER_HOT_INLINE ConstraintRow<T>* EvaluateAngleRows(const Model<T>& model, const BodyFrames<T>& frames,
                                                      const AnglePrimitive<T>& c, bool velocity_terms,
                                                      ConstraintRow<T>* row) {
  const BodyFrame<T>* frame_a = FrameOf(model, frames, c.body_a);
  const BodyFrame<T>* frame_b = FrameOf(model, frames, c.body_b);
  const Vec3<T> zero = Zero3<T>();
  const Vec3<T>& w_A = frame_a && velocity_terms ? frame_a->w_W : zero;
  const Vec3<T>& w_B = frame_b && velocity_terms ? frame_b->w_W : zero;
  for (int k = 0; k < c.rows; ++k, ++row) {
    const Vec3<T> u = frame_a ? Vec3<T>(frame_a->R_WB * c.u[k]) : c.u[k];
    const Vec3<T> w = frame_b ? Vec3<T>(frame_b->R_WB * c.w[k]) : c.w[k];
    const Vec3<T> normal = u.cross(w);
    row->value = u.dot(w) - c.c[k];
    row->a = Turning(model, frames, c.body_a, normal);
    row->b = Turning(model, frames, c.body_b, Vec3<T>(-normal));
    if (velocity_terms) row->bias = (w_A - w_B).dot(Vec3<T>(w_A.cross(u).cross(w) + u.cross(w_B.cross(w))));
  }
  return row;
}

// The angle rows that keep B's orientation relative to A as it is at configuration q.
template <typename T>
AnglePrimitive<T> FrozenOrientation(const Model<T>& model, const Joint<T>& joint, const VecX<T>& q) {
  const Mat3<T> R_BA = RotationAt(model, joint.b.body, q).transpose() * RotationAt(model, joint.a.body, q);
  AnglePrimitive<T> p{joint.scene_index, joint.a.body, joint.b.body, 3, {}, {}, {T(0.0), T(0.0), T(0.0)}};
  for (int k = 0; k < 3; ++k) {
    p.u[k] = Vec3<T>::Unit(k);
    p.w[k] = R_BA.col((k + 1) % 3);  // A's next axis as seen in B
  }
  return p;
}

// The angle rows that keep A's axis common to A and B (n_k of A's axis normal to the axis as seen in B).
template <typename T>
AnglePrimitive<T> CommonAxis(const Model<T>& model, const Joint<T>& joint, const VecX<T>& q) {
  const Vec3<T> axis = Unit(joint.axis);
  const Mat3<T> R_BA = RotationAt(model, joint.b.body, q).transpose() * RotationAt(model, joint.a.body, q);
  AnglePrimitive<T> p{joint.scene_index, joint.a.body, joint.b.body, 2, {}, {}, {T(0.0), T(0.0), T(0.0)}};
  AxisNormals(3, axis, &p.u[0], &p.u[1]);
  p.w[0] = p.w[1] = R_BA * axis;
  return p;
}

template <typename T>
LinePrimitive<T> Line(const Model<T>& model, const Joint<T>& joint) {
  LinePrimitive<T> p{joint.scene_index, joint.a, joint.b, model.dimension - 1, {}};
  AxisNormals(model.dimension, Unit(joint.axis), &p.normals[0], &p.normals[1]);
  return p;
}

// The world position of a body point at configuration q.
template <typename T>
Vec3<T> PositionAt(const Model<T>& model, const BodyPoint<T>& point, const VecX<T>& q) {
  if (point.body == kWorld) return point.local;
  const Body<T>& b = model.bodies[point.body];
  return Translation(model.dimension, q.data() + b.q_offset) + RotationAt(model, point.body, q) * point.local;
}

// A double hinge's link invariants as they are at configuration q (constraint_rows.h).
template <typename T>
void AddDoubleHinge(const Model<T>& model, const Joint<T>& joint, const VecX<T>& q, ConstraintSet<T>* set) {
  const int index = joint.scene_index;
  const Vec3<T> a_1 = Unit(joint.axis), a_2 = Unit(joint.axis_b);
  const Vec3<T> a_1W = RotationAt(model, joint.a.body, q) * a_1, a_2W = RotationAt(model, joint.b.body, q) * a_2;
  const Vec3<T> d = PositionAt(model, joint.b, q) - PositionAt(model, joint.a, q);
  using std::sqrt;
  set->distances.push_back({index, joint.a, joint.b, T(sqrt(d.squaredNorm()))});
  set->lines.push_back({index, joint.a, joint.b, 1, {a_1}, {T(a_1W.dot(d))}});
  if (Value(a_1W.cross(a_2W).squaredNorm()) < kParallelAxes * kParallelAxes) {
    set->angles.push_back(CommonAxis(model, joint, q));
    return;
  }
  set->lines.push_back({index, joint.b, joint.a, 1, {a_2}, {T(-a_2W.dot(d))}});
  set->angles.push_back({index, joint.a.body, joint.b.body, 1, {a_1}, {a_2}, {T(a_1W.dot(a_2W))}});
}

// The angle row that keeps the angle between A's `axis` and B's `axis_b` as it is at configuration q.
template <typename T>
AnglePrimitive<T> CrossedAxes(const Model<T>& model, const Joint<T>& joint, const VecX<T>& q) {
  const Vec3<T> u = Unit(joint.axis), w = Unit(joint.axis_b);
  const Vec3<T> u_W = RotationAt(model, joint.a.body, q) * u;
  const Vec3<T> w_W = RotationAt(model, joint.b.body, q) * w;
  return {joint.scene_index, joint.a.body, joint.b.body, 1, {u}, {w}, {T(u_W.dot(w_W))}};
}

// One part of a joint (joint_kinds.h) as it is at configuration q.
template <typename T>
void AddPart(const Model<T>& model, const Joint<T>& joint, JointPart part, const VecX<T>& q, ConstraintSet<T>* set) {
  switch (part) {
    case JointPart::kNone:
      break;
    case JointPart::kDistance:
      set->distances.push_back({joint.scene_index, joint.a, joint.b, joint.length});
      break;
    case JointPart::kPoint:
      set->points.push_back({joint.scene_index, joint.a, joint.b});
      break;
    case JointPart::kLine:
      set->lines.push_back(Line(model, joint));
      break;
    case JointPart::kCommonAxis:
      set->angles.push_back(CommonAxis(model, joint, q));
      break;
    case JointPart::kCrossedAxes:
      set->angles.push_back(CrossedAxes(model, joint, q));
      break;
    case JointPart::kFrozenOrientation:
      set->angles.push_back(FrozenOrientation(model, joint, q));
      break;
    case JointPart::kDoubleHinge:
      AddDoubleHinge(model, joint, q, set);
      break;
  }
}

template <typename T>
BodyState<T> StateOf(const Model<T>& model, int body, const VecX<T>& q, const VecX<T>& v, bool velocity_terms) {
  if (body == kWorld) return {};
  const Body<T>& b = model.bodies[body];
  return {q.data() + b.q_offset, velocity_terms ? v.data() + b.v_offset : nullptr, b.q_size, b.v_size, b.kind,
          b.principal_axes};
}

// Maps a gradient over one body's velocities onto its BodyVector.
template <typename T>
BodyVector<T> GradientOf(const Model<T>& model, int body, const T* gradient) {
  BodyVector<T> g;
  g.body = body;
  if (body == kWorld) return g;
  const Body<T>& b = model.bodies[body];
  switch (b.kind) {
    case BodyKind::kParticle:
      for (int k = 0; k < model.dimension; ++k) g.translation[k] = gradient[k];
      break;
    case BodyKind::kPlanar:
      g.translation = Vec3<T>(gradient[0], gradient[1], T(0.0));
      g.rotation[2] = gradient[2];
      break;
    case BodyKind::kRigid3d:
      for (int k = 0; k < 3; ++k) {
        g.translation[k] = gradient[k];
        g.rotation[k] = gradient[3 + k];
      }
      break;
  }
  return g;
}

// A block with only a rotational part: d(...)/d w_W = g_W.
template <typename T>
BodyVector<T> Turning(const Model<T>& model, const BodyFrames<T>& frames, int body, const Vec3<T>& g_W) {
  BodyVector<T> g;
  g.body = body;
  g.rotation = RotationalPart(model, frames, body, g_W);
  return g;
}

template <typename T>
const BodyFrame<T>* FrameOf(const Model<T>& model, const BodyFrames<T>& frames, int body) {
  return body == kWorld || model.bodies[body].kind == BodyKind::kParticle ? nullptr : &frames[body];
}

}  // namespace internal

template <typename T>
void AxisNormals(int dimension, const Vec3<T>& axis, Vec3<T>* n1, Vec3<T>* n2) {
  if (dimension == 2) {
    *n1 = Perp(axis);
    *n2 = Vec3<T>::Zero();
    return;
  }
  int least = 0;
  for (int k = 1; k < 3; ++k) {
    if (std::abs(Value(axis[k])) < std::abs(Value(axis[least]))) least = k;
  }
  const Vec3<T> e = Vec3<T>::Unit(least);
  *n1 = internal::Unit(Vec3<T>(axis.cross(e)));
  *n2 = axis.cross(*n1);
}

// A joint's rows are its kind's parts (joint_kinds.h), each one primitive as it is at configuration q.
template <typename T>
ConstraintSet<T> BuildConstraintSet(const Model<T>& model, const VecX<T>& q) {
  ConstraintSet<T> set;
  for (const Joint<T>& joint : model.joints) {
    for (const JointPart part : JointKindOf(joint.type).parts) {
      internal::AddPart(model, joint, part, q, &set);
    }
  }
  return set;
}

template <typename T>
std::vector<RowInfo> DescribeRows(const Model<T>& model, const ConstraintSet<T>& set) {
  std::vector<RowInfo> infos;
  int part = 0;
  RowPrimitive kind = RowPrimitive::kDistance;
  int primitive = 0;  // within `kind`
  auto add = [&](RowPrimitive of, int scene_index, int a, int b, int count, RowLaw law = RowLaw::kEquality,
                 RowTranslation translation = RowTranslation::kEvaluated) {
    if (of != kind) {
      kind = of;
      primitive = 0;
    }
    for (int k = 0; k < count; ++k) infos.push_back({scene_index, a, b, part, law, translation, kind, primitive});
    ++part;
    ++primitive;
  };
  for (const auto& c : set.distances) add(RowPrimitive::kDistance, c.scene_index, c.a.body, c.b.body, 1);
  for (const auto& c : set.points) {  // EvaluatePointRows: row k's blocks are -e_k and e_k
    add(RowPrimitive::kPoint, c.scene_index, c.a.body, c.b.body, model.dimension);
    for (int k = 0; k < model.dimension; ++k)
      infos[infos.size() - model.dimension + k].translation = AxisTranslation(k);
  }
  for (const auto& c : set.lines) add(RowPrimitive::kLine, c.scene_index, c.a.body, c.b.body, c.rows);
  for (const auto& c : set.angles) {  // EvaluateAngleRows: Turning, no translation
    add(RowPrimitive::kAngle, c.scene_index, c.body_a, c.body_b, c.rows, RowLaw::kEquality, RowTranslation::kZero);
  }
  for (const auto& c : model.user_constraints) {
    add(RowPrimitive::kUser, c.scene_index, c.body_a, c.body_b, c.residual->NumRows());
  }
  for (const auto& c : set.limits) add(RowPrimitive::kLimit, c.scene_index, c.body_a, c.body_b, 1, RowLaw::kGap);
  for (const auto& c : set.contacts) add(RowPrimitive::kContact, c.scene_index, c.body_a, c.body_b, 1, RowLaw::kGap);
  for (const auto& c : set.contacts) {
    if (c.friction == Friction::kStick) {
      add(RowPrimitive::kSlip, c.scene_index, c.body_a, c.body_b, model.dimension - 1);
    }
  }
  return infos;
}

// the branch of an active limit's angle is the one at its bound
template <typename T>
void EvaluateLimitRow(const Model<T>& model, const LimitPrimitive<T>& limit, const BodyFrames<T>& frames,
                      const VecX<T>& q, const VecX<T>& v, bool velocity_terms, ConstraintRow<T>* row) {
  const CoordinateRow<T> x =
      EvaluateCoordinateAt(model, limit.coordinate, Value(limit.bound), frames, q, v, velocity_terms);
  const T side(static_cast<double>(limit.side));
  const T gap = side * (x.value - limit.bound);
  row->value = Value(gap) < 0.0 ? gap : T(0.0);
  row->a = x.a;
  row->b = x.b;
  for (BodyVector<T>* block : {&row->a, &row->b}) {
    block->translation *= side;
    block->rotation *= side;
  }
  if (velocity_terms) row->bias = side * CoordinateBias(model, limit.coordinate, frames, q, v);
}

namespace internal {

// The rows of the model's user constraints (user_constraint.h), from `row` on; the next row. Apart from the rows
// above, so that a scene without user constraints does not clear their buffer (kMaxUserRows rows of 14 scalars)
// at every evaluation.
template <typename T>
ConstraintRow<T>* EvaluateUserRows(const Model<T>& model, const VecX<T>& q, const VecX<T>& v, bool velocity_terms,
                                   ConstraintRow<T>* row) {
  UserRow<T> out[kMaxUserRows];
  for (const UserConstraintInstance& c : model.user_constraints) {
    const int count = c.residual->NumRows();
    const BodyState<T> sa = StateOf(model, c.body_a, q, v, velocity_terms);
    const BodyState<T> sb = StateOf(model, c.body_b, q, v, velocity_terms);
    c.residual->Evaluate(sa, sb, velocity_terms, out);
    for (int i = 0; i < count; ++i, ++row) {
      row->value = out[i].value;
      if (velocity_terms) row->bias = out[i].bias;
      row->a = GradientOf(model, c.body_a, out[i].gradient);
      row->b = GradientOf(model, c.body_b, out[i].gradient + sa.v_size);
    }
  }
  return row;
}

}  // namespace internal

template <typename T>
TETHER_FLATTEN void EvaluateConstraintRows(const Model<T>& model, const ConstraintSet<T>& set,
                                           const BodyFrames<T>& frames, const VecX<T>& q, const VecX<T>& v,
                                           bool velocity_terms, std::vector<ConstraintRow<T>>* rows) {
  ConstraintRow<T>* row = rows->data();
  const bool vt = velocity_terms;
  if (ConstraintRow<T>* next = RecordedDistanceRows(model, set.distances, frames, q, v, vt, row)) {
    row = next;
  } else {
    for (const DistancePrimitive<T>& c : set.distances)
      internal::EvaluateDistanceRow(model, frames, c, q, v, vt, row++);
  }
  if (ConstraintRow<T>* next = RecordedPointRows(model, set.points, frames, q, v, vt, row)) {
    row = next;
  } else {
    for (const PointPrimitive<T>& c : set.points) row = internal::EvaluatePointRows(model, frames, c, q, v, vt, row);
  }
  for (const LinePrimitive<T>& c : set.lines) row = internal::EvaluateLineRows(model, frames, c, q, v, vt, row);
  if (ConstraintRow<T>* next = RecordedAngleRows(model, set.angles, frames, vt, row)) {
    row = next;
  } else {
    for (const AnglePrimitive<T>& c : set.angles) row = internal::EvaluateAngleRows(model, frames, c, vt, row);
  }
  if (!model.user_constraints.empty()) row = internal::EvaluateUserRows(model, q, v, vt, row);
  for (const LimitPrimitive<T>& c : set.limits) EvaluateLimitRow(model, c, frames, q, v, vt, row++);
  for (const ContactPrimitive& c : set.contacts) row = EvaluateContactRow(model, c.feature, frames, q, v, vt, row);
  for (const ContactPrimitive& c : set.contacts) {
    if (c.friction != Friction::kStick) continue;
    const ContactPoint<T> contact = ContactPointOf(model, c.feature, frames, q, v, vt);
    Vec3<T> tangents[2];
    for (int k = 0; k < Tangents(model.dimension, contact.normal, tangents); ++k) {
      SlipRow(model, frames, contact, tangents[k], vt, row++);
    }
  }
}

template <typename T>
Violation LargestViolation(const std::vector<RowInfo>& infos, const std::vector<ConstraintRow<T>>& rows) {
  Violation worst;
  size_t i = 0;
  while (i < rows.size()) {
    double squared = 0.0;
    const int part = infos[i].part;
    const int constraint = infos[i].scene_index;
    for (; i < rows.size() && infos[i].part == part; ++i) squared += Value(rows[i].value) * Value(rows[i].value);
    const double norm = std::sqrt(squared);
    if (std::isnan(norm)) return {norm, constraint};
    if (norm > worst.largest) worst = {norm, constraint};
  }
  return worst;
}

}  // namespace tether
