// Kinematics of bodies and of points fixed in them, in maximal coordinates.
//
// For a point with body-local offset r on a planar rigid body with centre x and angle theta:
//   p   = x + R(theta) r
//   p'  = x' + theta' perp(R r)                       perp(u) = (-u_y, u_x, 0)
//   p'' = x'' + theta'' perp(R r) - theta'^2 R r
// so dp/dx = I, dp/dtheta = perp(R r) (the "lever"), and -theta'^2 R r is the velocity-product
// ("centripetal") part of p''. A particle is the same with no angle (p = x + r); the world has p = r.
//
// A generalized vector over one body's coordinates (a Jacobian row block, a generalized force) is kept as a
// translational part (a Vec3 whose unused components are zero) and a rotational part (planar rigid bodies).
#pragma once

#include <cmath>

#include "tether/dynamics/model.h"

namespace tether {

template <typename T>
Vec3<T> Perp(const Vec3<T>& u) {
  return Vec3<T>(-u.y(), u.x(), T(0.0));
}

// Rotates u (in the x-y plane) by angle.
template <typename T>
Vec3<T> Rotate(const T& angle, const Vec3<T>& u) {
  using std::cos;
  using std::sin;
  const T c = cos(angle), s = sin(angle);
  return Vec3<T>(c * u.x() - s * u.y(), s * u.x() + c * u.y(), u.z());
}

// Translational part of a body's coordinates (or velocities) in q.
// (Written out for d = 2 or 3: a loop over d compiles to a call of memcpy, a third of the time of a Dot.)
template <typename T>
Vec3<T> Translation(const Body<T>& body, int dimension, const VecX<T>& q) {
  const T* x = q.data() + body.offset;
  return Vec3<T>(x[0], x[1], dimension == 3 ? x[2] : T(0.0));
}

// Angle (or angular velocity) of a planar rigid body; zero for a particle.
template <typename T>
T Rotation(const Body<T>& body, const VecX<T>& q) {
  return body.kind == BodyKind::kRigid ? q[body.offset + 2] : T(0.0);
}

// A generalized vector restricted to one body: translation and (planar rigid bodies) rotation.
template <typename T>
struct BodyVector {
  int body = kWorld;
  Vec3<T> translation = Vec3<T>::Zero();
  T rotation = T(0.0);
};

template <typename T>
struct PointMotion {
  Vec3<T> position = Vec3<T>::Zero();     // p
  Vec3<T> velocity = Vec3<T>::Zero();     // p'
  Vec3<T> lever = Vec3<T>::Zero();        // dp/dtheta = perp(R r)
  Vec3<T> centripetal = Vec3<T>::Zero();  // -theta'^2 R r
};

template <typename T>
PointMotion<T> MovePoint(const Model<T>& model, const BodyPoint<T>& point, const VecX<T>& q, const VecX<T>& v) {
  PointMotion<T> m;
  if (point.body == kWorld) {
    m.position = point.local;
    return m;
  }
  const Body<T>& body = model.bodies[point.body];
  m.position = Translation(body, model.dimension, q);
  m.velocity = Translation(body, model.dimension, v);
  if (body.kind == BodyKind::kRigid) {
    const Vec3<T> arm = Rotate(q[body.offset + 2], point.local);
    const T omega = v[body.offset + 2];
    m.position += arm;
    m.lever = Perp(arm);
    m.velocity += omega * m.lever;
    m.centripetal = -(omega * omega) * arm;
  } else {
    m.position += point.local;
  }
  return m;
}

// The segment from point a to point b: d = p_b - p_a, its length |d| and direction n = d / |d| (undefined
// when the points coincide; scenes are checked for that at the start).
template <typename T>
struct Segment {
  Vec3<T> d;
  T length;
  T inverse_length;  // 1 / |d|: one division serves n and the callers
  Vec3<T> n;
};

template <typename T>
Segment<T> Between(const PointMotion<T>& a, const PointMotion<T>& b) {
  using std::sqrt;
  Segment<T> s;
  s.d = b.position - a.position;
  s.length = sqrt(s.d.squaredNorm());
  s.inverse_length = T(1.0) / s.length;
  s.n = s.d * s.inverse_length;
  return s;
}

// The generalized vector of "direction . p" for a point: d(n . p)/d(body coordinates).
template <typename T>
BodyVector<T> PointGradient(int body, const Vec3<T>& direction, const PointMotion<T>& point) {
  return {body, direction, direction.dot(point.lever)};
}

// g . x for the body's slice of a generalized vector x (velocities, accelerations, M^-1 f, ...).
template <typename T>
T Dot(const Model<T>& model, const BodyVector<T>& g, const VecX<T>& x) {
  if (g.body == kWorld) return T(0.0);
  const Body<T>& body = model.bodies[g.body];
  const T* x_b = x.data() + body.offset;
  T sum = g.translation[0] * x_b[0] + g.translation[1] * x_b[1];
  if (model.dimension == 3) sum += g.translation[2] * x_b[2];
  if (body.kind == BodyKind::kRigid) sum += g.rotation * x_b[2];
  return sum;
}

// x += scale * g on the body's slice.
template <typename T>
void AddScaled(const Model<T>& model, const BodyVector<T>& g, const T& scale, VecX<T>* x) {
  if (g.body == kWorld) return;
  const Body<T>& body = model.bodies[g.body];
  T* x_b = x->data() + body.offset;
  x_b[0] += scale * g.translation[0];
  x_b[1] += scale * g.translation[1];
  if (model.dimension == 3) x_b[2] += scale * g.translation[2];
  if (body.kind == BodyKind::kRigid) x_b[2] += scale * g.rotation;
}

}  // namespace tether
