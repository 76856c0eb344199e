// Definitions for constraint_rows.h; included only by the file that instantiates them.
#pragma once

#include <Eigen/Geometry>  // cross products for 3D slider normals
#include <cmath>

#include "tether/dynamics/constraint_rows.h"
#include "tether/dynamics/user_constraint.h"

namespace tether {
namespace internal {

template <typename T>
int SliderRows(const Model<T>& model) {
  return model.dimension - 1;
}

// Unit normals of a slider axis: in 2D perp(axis); in 3D two vectors completing the axis to an orthonormal
// frame (the second coordinate axis least aligned with it fixes the first normal).
template <typename T>
void SliderNormals(int dimension, const Vec3<T>& axis, Vec3<T>* n1, Vec3<T>* n2) {
  const Vec3<T> u = axis / axis.norm();
  if (dimension == 2) {
    *n1 = Perp(u);
    return;
  }
  int least = 0;
  for (int k = 1; k < 3; ++k) {
    if (std::abs(Value(u[k])) < std::abs(Value(u[least]))) least = k;
  }
  const Vec3<T> e = Vec3<T>::Unit(least);
  const Vec3<T> w = u.cross(e);
  *n1 = w / w.norm();
  *n2 = u.cross(*n1);
}

template <typename T>
BodyState<T> StateOf(const Model<T>& model, int body, const VecX<T>& q, const VecX<T>& v, bool velocity_terms) {
  if (body == kWorld) return {};
  const Body<T>& b = model.bodies[body];
  return {q.data() + b.offset, velocity_terms ? v.data() + b.offset : nullptr, b.size};
}

// Maps a gradient over one body's coordinates onto its BodyVector.
template <typename T>
BodyVector<T> GradientOf(const Model<T>& model, int body, const T* gradient) {
  BodyVector<T> g;
  g.body = body;
  if (body == kWorld) return g;
  const Body<T>& b = model.bodies[body];
  for (int k = 0; k < model.dimension; ++k) g.translation[k] = gradient[k];
  if (b.kind == BodyKind::kRigid) g.rotation = gradient[2];
  return g;
}

}  // namespace internal

template <typename T>
std::vector<RowInfo> DescribeRows(const Model<T>& model) {
  std::vector<RowInfo> infos;
  for (const auto& c : model.distances) infos.push_back({c.scene_index, c.a.body, c.b.body});
  for (const auto& c : model.pins) {
    for (int k = 0; k < model.dimension; ++k) infos.push_back({c.scene_index, c.a.body, c.b.body});
  }
  for (const auto& c : model.sliders) {
    for (int k = 0; k < internal::SliderRows(model); ++k) infos.push_back({c.scene_index, c.a.body, c.b.body});
  }
  for (const auto& c : model.user_constraints) {
    for (int k = 0; k < c.residual->NumRows(); ++k) infos.push_back({c.scene_index, c.body_a, c.body_b});
  }
  return infos;
}

template <typename T>
void EvaluateConstraintRows(const Model<T>& model, const VecX<T>& q, const VecX<T>& v, bool velocity_terms,
                            std::vector<ConstraintRow<T>>* rows) {
  ConstraintRow<T>* row = rows->data();
  for (const DistanceConstraint<T>& c : model.distances) {
    const PointMotion<T> pa = MovePoint(model, c.a, q, v);
    const PointMotion<T> pb = MovePoint(model, c.b, q, v);
    const Segment<T> segment = Between(pa, pb);
    const Vec3<T>& n = segment.n;
    row->value = segment.length - c.length;
    row->a = PointGradient(c.a.body, Vec3<T>(-n), pa);
    row->b = PointGradient(c.b.body, n, pb);
    if (velocity_terms) {
      const Vec3<T> dv = pb.velocity - pa.velocity;
      const T along = n.dot(dv);
      row->bias = (dv.squaredNorm() - along * along) * segment.inverse_length + n.dot(pb.centripetal - pa.centripetal);
    }
    ++row;
  }
  for (const PinConstraint<T>& c : model.pins) {
    const PointMotion<T> pa = MovePoint(model, c.a, q, v);
    const PointMotion<T> pb = MovePoint(model, c.b, q, v);
    for (int k = 0; k < model.dimension; ++k, ++row) {
      const Vec3<T> e = Vec3<T>::Unit(k);
      row->value = pb.position[k] - pa.position[k];
      row->a = PointGradient(c.a.body, Vec3<T>(-e), pa);
      row->b = PointGradient(c.b.body, e, pb);
      if (velocity_terms) row->bias = pb.centripetal[k] - pa.centripetal[k];
    }
  }
  for (const SliderConstraint<T>& c : model.sliders) {
    const PointMotion<T> pa = MovePoint(model, c.a, q, v);
    const PointMotion<T> pb = MovePoint(model, c.b, q, v);
    const bool turning = c.a.body != kWorld && model.bodies[c.a.body].kind == BodyKind::kRigid;
    const T angle_a = turning ? q[model.bodies[c.a.body].offset + 2] : T(0.0);
    const T omega_a = turning && velocity_terms ? v[model.bodies[c.a.body].offset + 2] : T(0.0);
    Vec3<T> normals[2];
    internal::SliderNormals(model.dimension, Vec3<T>(Rotate(angle_a, c.axis)), &normals[0], &normals[1]);
    const Vec3<T> d = pb.position - pa.position;
    for (int k = 0; k < internal::SliderRows(model); ++k, ++row) {
      const Vec3<T>& n = normals[k];
      row->value = n.dot(d);
      row->a = PointGradient(c.a.body, Vec3<T>(-n), pa);
      if (turning) row->a.rotation += Perp(n).dot(d);  // the normal turns with A
      row->b = PointGradient(c.b.body, n, pb);
      if (velocity_terms) {
        const Vec3<T> dv = pb.velocity - pa.velocity;
        row->bias = -(omega_a * omega_a) * n.dot(d) + T(2.0) * omega_a * Perp(n).dot(dv) +
                    n.dot(pb.centripetal - pa.centripetal);
      }
    }
  }
  UserRow<T> out[kMaxUserRows];
  for (const UserConstraintInstance& c : model.user_constraints) {
    const int count = c.residual->NumRows();
    const BodyState<T> sa = internal::StateOf(model, c.body_a, q, v, velocity_terms);
    const BodyState<T> sb = internal::StateOf(model, c.body_b, q, v, velocity_terms);
    c.residual->Evaluate(sa, sb, velocity_terms, out);
    for (int i = 0; i < count; ++i, ++row) {
      row->value = out[i].value;
      if (velocity_terms) row->bias = out[i].bias;
      row->a = internal::GradientOf(model, c.body_a, out[i].gradient);
      row->b = internal::GradientOf(model, c.body_b, out[i].gradient + sa.size);
    }
  }
}

template <typename T>
Violation LargestViolation(const std::vector<RowInfo>& infos, const std::vector<ConstraintRow<T>>& rows) {
  Violation worst;
  size_t i = 0;
  while (i < rows.size()) {
    double squared = 0.0;
    const int constraint = infos[i].scene_index;
    for (; i < rows.size() && infos[i].scene_index == constraint; ++i) squared += Value(rows[i].value) * Value(rows[i].value);
    const double norm = std::sqrt(squared);
    if (std::isnan(norm)) return {norm, constraint};
    if (norm > worst.largest) worst = {norm, constraint};
  }
  return worst;
}

}  // namespace tether
