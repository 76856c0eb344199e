// Kinematics of bodies and of points fixed in them, in maximal coordinates.
//
// A point Q with offset r (body axes, from the centre of mass) on a body with centre x, rotation R_WB and
// angular velocity w (world frame) moves as
//   p   = x + R_WB r = x + a                              (a: the world-frame arm)
//   p'  = x' + w x a
//   p'' = x'' + w' x a + w x (w x a)
// so a world-frame direction g sees g . p' = g . x' + w . (a x g): the body block of the generalized vector
// of "g . p" is (g, a x g), its rotational part expressed in the frame of the body's angular velocity in v
// (a planar body: the z component; a 3D body: its principal axes, R_PW (a x g)). w x (w x a) is the
// velocity-product ("centripetal") part of p''. A particle is the same with no rotation (p = x + r); the world
// has p = r.
//
// A generalized vector over one body's velocities (a Jacobian row block, a generalized force) is kept as a
// translational part and a rotational part (Vec3 each; unused components are zero). BodyFrames caches every
// rigid body's rotation and world angular velocity once per evaluation.
#pragma once

#include <cmath>
#include <vector>

#include "tether/dynamics/adjoint/recorded.h"
#include "tether/dynamics/model/configuration_space.h"
#include "tether/dynamics/model/rotation.h"

namespace tether {

template <typename T>
Vec3<T> Perp(const Vec3<T>& u) {
  return Vec3<T>(-u.y(), u.x(), T(0.0));
}

// Rotates u (in the x-y plane) by angle.
template <typename T>
Vec3<T> RotatePlanar(const T& angle, const Vec3<T>& u) {
  using std::cos;
  using std::sin;
  const T c = cos(angle), s = sin(angle);
  return Vec3<T>(c * u.x() - s * u.y(), s * u.x() + c * u.y(), u.z());
}

// A rigid body's frame at one state.
template <typename T>
struct BodyFrame {
  Mat3<T> R_WB = Mat3<T>::Identity();  // body axes -> world (planar: about z)
  Mat3<T> R_WP = Mat3<T>::Identity();  // principal axes -> world (3D bodies; R_WB for planar ones)
  Vec3<T> w_W = Zero3<T>();            // angular velocity, world frame
};

// One frame per body (particles' entries unused).
template <typename T>
using BodyFrames = std::vector<BodyFrame<T>>;

// Fills frames (sized to the bodies) at (q, v); v is read only when `velocities` is true.
template <typename T>
void UpdateFrames(const Model<T>& model, const VecX<T>& q, const VecX<T>& v, bool velocities, BodyFrames<T>* frames) {
  frames->resize(model.bodies.size());
  const bool spatial_recorded = RecordedSpatialFrames(model, q, v, velocities, frames);
  for (int i : model.rigid_bodies) {
    const Body<T>& body = model.bodies[i];
    BodyFrame<T>& f = (*frames)[i];
    if (body.kind == BodyKind::kPlanar) {
      using std::cos;
      using std::sin;
      const T angle = q[body.q_offset + 2];
      const T c = cos(angle), s = sin(angle);
      f.R_WB << c, -s, T(0.0), s, c, T(0.0), T(0.0), T(0.0), T(1.0);
      f.R_WP = f.R_WB;
      if (velocities) f.w_W = Vec3<T>(T(0.0), T(0.0), v[body.v_offset + 2]);
    } else if (body.kind == BodyKind::kRigid3d && !spatial_recorded) {
      f.R_WB = RotationMatrix(Orientation(body, q));
      const bool principal = body.principal_axes == Vec4<double>(1, 0, 0, 0);
      f.R_WP = principal ? f.R_WB : Mat3<T>(f.R_WB * RotationMatrix(Vec4<T>(body.principal_axes.template cast<T>())));
      if (velocities) f.w_W = f.R_WP * v.template segment<3>(body.v_offset + 3);
    }
  }
}

// A body's translational part of q or v: d numbers (Vec3 padded with zero).
// (Written out for d = 2 or 3: a loop over d compiles to a call of memcpy, a third of the time of a Dot.)
template <typename T>
TETHER_HOT_INLINE Vec3<T> Translation(int dimension, const T* x) {
  return Vec3<T>(x[0], x[1], dimension == 3 ? x[2] : T(0.0));
}

// A generalized vector restricted to one body: translation and rotation (see above).
template <typename T>
struct BodyVector {
  int body = kWorld;
  Vec3<T> translation = Zero3<T>();
  Vec3<T> rotation = Zero3<T>();
};

template <typename T>
struct PointMotion {
  Vec3<T> position = Zero3<T>();     // p
  Vec3<T> velocity = Zero3<T>();     // p'
  Vec3<T> arm = Zero3<T>();          // a = R_WB r (zero for particles and the world)
  Vec3<T> centripetal = Zero3<T>();  // w x (w x a)
};

template <typename T>
TETHER_HOT_INLINE PointMotion<T> MovePoint(const Model<T>& model, const BodyFrames<T>& frames,
                                           const BodyPoint<T>& point, const VecX<T>& q, const VecX<T>& v,
                                           bool velocities) {
  PointMotion<T> m;
  if (point.body == kWorld) {
    m.position = point.local;
    return m;
  }
  const Body<T>& body = model.bodies[point.body];
  m.position = Translation(model.dimension, q.data() + body.q_offset);
  if (velocities) m.velocity = Translation(model.dimension, v.data() + body.v_offset);
  if (body.kind == BodyKind::kParticle) {
    m.position += point.local;
    return m;
  }
  const BodyFrame<T>& f = frames[point.body];
  if (body.kind == BodyKind::kPlanar) {  // written out: the z rows of R_WB are trivial
    m.arm = Vec3<T>(f.R_WB(0, 0) * point.local.x() + f.R_WB(0, 1) * point.local.y(),
                    f.R_WB(1, 0) * point.local.x() + f.R_WB(1, 1) * point.local.y(), T(0.0));
  } else {
    m.arm = f.R_WB * point.local;
  }
  m.position += m.arm;
  if (velocities) {
    const Vec3<T> spin = f.w_W.cross(m.arm);
    m.velocity += spin;
    m.centripetal = f.w_W.cross(spin);
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
TETHER_HOT_INLINE Segment<T> Between(const PointMotion<T>& a, const PointMotion<T>& b) {
  using std::sqrt;
  Segment<T> s;
  s.d = b.position - a.position;
  s.length = sqrt(s.d.squaredNorm());
  s.inverse_length = T(1.0) / s.length;
  s.n = s.d * s.inverse_length;
  return s;
}

// R^T x, written out: Eigen's transposed product assembles its result in memory two halves at a time and reads it
// back whole, a stalled store forward on every Jacobian block.
template <typename T>
TETHER_HOT_INLINE Vec3<T> TransposeTimes(const Mat3<T>& R, const Vec3<T>& x) {
  return Vec3<T>(R(0, 0) * x[0] + R(1, 0) * x[1] + R(2, 0) * x[2], R(0, 1) * x[0] + R(1, 1) * x[1] + R(2, 1) * x[2],
                 R(0, 2) * x[0] + R(1, 2) * x[1] + R(2, 2) * x[2]);
}

// The rotational block of a world-frame angular gradient g_W (d(...)/d w_W), in the body's velocity frame.
template <typename T>
TETHER_HOT_INLINE Vec3<T> RotationalPart(const Model<T>& model, const BodyFrames<T>& frames, int body,
                                         const Vec3<T>& g_W) {
  if (body == kWorld) return Zero3<T>();
  switch (model.bodies[body].kind) {
    case BodyKind::kParticle:
      return Zero3<T>();
    case BodyKind::kPlanar: {
      Vec3<T> z = Zero3<T>();
      z[2] = g_W.z();
      return z;
    }
    case BodyKind::kRigid3d:
      break;
  }
  return TransposeTimes(frames[body].R_WP, g_W);
}

// The generalized vector of "direction . p" for a point: d(g . p)/d(body velocities).
template <typename T>
TETHER_HOT_INLINE BodyVector<T> PointGradient(const Model<T>& model, const BodyFrames<T>& frames, int body,
                                              const Vec3<T>& direction, const PointMotion<T>& point) {
  BodyVector<T> g;
  g.body = body;
  g.translation = direction;
  if (body == kWorld) return g;
  const BodyKind kind = model.bodies[body].kind;
  if (kind == BodyKind::kPlanar) {
    g.rotation.z() = point.arm.x() * direction.y() - point.arm.y() * direction.x();
  } else if (kind == BodyKind::kRigid3d) {
    g.rotation = TransposeTimes(frames[body].R_WP, Vec3<T>(point.arm.cross(direction)));
  }
  return g;
}

// PointGradient for the direction +e_K (kSign = 1) or -e_K (kSign = -1), a 3D point row's, without the products by
// the direction's zeros: on a 3D body arm x e_K has one zero, c_i = a_j and c_j = -a_i for (i, j) = (K + 1, K + 2)
// mod 3, so R_WP^T c takes two rows of R_WP. The same values bit for bit: the terms left out are exact zeros.
template <int K, int kSign, typename T>
TETHER_HOT_INLINE BodyVector<T> AxisGradient(const Model<T>& model, const BodyFrames<T>& frames, int body,
                                             const PointMotion<T>& point) {
  const Vec3<T> direction = T(static_cast<double>(kSign)) * Vec3<T>::Unit(K);
  if (body == kWorld || model.bodies[body].kind != BodyKind::kRigid3d) {
    return PointGradient(model, frames, body, direction, point);
  }
  constexpr int i = (K + 1) % 3, j = (K + 2) % 3;
  constexpr int low = i < j ? i : j, high = i < j ? j : i;  // TransposeTimes' order
  const T c_i = kSign > 0 ? point.arm[j] : T(-point.arm[j]);
  const T c_j = kSign > 0 ? T(-point.arm[i]) : point.arm[i];
  const T& c_low = low == i ? c_i : c_j;
  const T& c_high = low == i ? c_j : c_i;
  const Mat3<T>& R_WP = frames[body].R_WP;
  BodyVector<T> g;
  g.body = body;
  g.translation = direction;
  g.rotation = Vec3<T>(R_WP(low, 0) * c_low + R_WP(high, 0) * c_high, R_WP(low, 1) * c_low + R_WP(high, 1) * c_high,
                       R_WP(low, 2) * c_low + R_WP(high, 2) * c_high);
  return g;
}

// g . x for the body's slice of a generalized vector x (velocities, accelerations, M^-1 f, ...).
// (The kinds are tested in the order of how common they are in large systems: particles first.) Here and below
// the model gives the bodies' layout only: its scalar S may differ from the values' T.
template <typename S, typename T>
TETHER_HOT_INLINE T Dot(const Model<S>& model, const BodyVector<T>& g, const VecX<T>& x) {
  if (g.body == kWorld) return T(0.0);
  const Body<S>& body = model.bodies[g.body];
  const T* x_b = x.data() + body.v_offset;
  T sum = g.translation[0] * x_b[0] + g.translation[1] * x_b[1];
  if (body.kind == BodyKind::kParticle) {
    if (model.dimension == 3) sum += g.translation[2] * x_b[2];
  } else if (body.kind == BodyKind::kPlanar) {
    sum += g.rotation[2] * x_b[2];
  } else {
    sum += g.translation[2] * x_b[2] + g.rotation[0] * x_b[3] + g.rotation[1] * x_b[4] + g.rotation[2] * x_b[5];
  }
  return sum;
}

// x += scale * g on the body's slice.
template <typename S, typename T>
TETHER_HOT_INLINE void AddScaled(const Model<S>& model, const BodyVector<T>& g, const T& scale, VecX<T>* x) {
  if (g.body == kWorld) return;
  const Body<S>& body = model.bodies[g.body];
  T* x_b = x->data() + body.v_offset;
  x_b[0] += scale * g.translation[0];
  x_b[1] += scale * g.translation[1];
  if (body.kind == BodyKind::kParticle) {
    if (model.dimension == 3) x_b[2] += scale * g.translation[2];
  } else if (body.kind == BodyKind::kPlanar) {
    x_b[2] += scale * g.rotation[2];
  } else {
    x_b[2] += scale * g.translation[2];
    for (int k = 0; k < 3; ++k) x_b[3 + k] += scale * g.rotation[k];
  }
}

// The body's slice of a generalized vector x as a block: Dot(model, g, x) = g . Slice(model, g.body, x) (the
// components the body does not have are zero).
template <typename S, typename T>
TETHER_HOT_INLINE BodyVector<T> Slice(const Model<S>& model, int body_index, const VecX<T>& x) {
  BodyVector<T> g;
  g.body = body_index;
  if (body_index == kWorld) return g;
  const Body<S>& body = model.bodies[body_index];
  const T* x_b = x.data() + body.v_offset;
  g.translation[0] = x_b[0];
  g.translation[1] = x_b[1];
  if (body.kind == BodyKind::kParticle) {
    if (model.dimension == 3) g.translation[2] = x_b[2];
  } else if (body.kind == BodyKind::kPlanar) {
    g.rotation[2] = x_b[2];
  } else {
    g.translation[2] = x_b[2];
    for (int k = 0; k < 3; ++k) g.rotation[k] = x_b[3 + k];
  }
  return g;
}

}  // namespace tether
