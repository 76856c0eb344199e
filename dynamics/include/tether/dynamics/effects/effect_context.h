// EffectContext<T>: what an effect (effects/*.h) sees of a state when it adds its generalized force f(t, q, v) or
// its potential energy: the model, t, q, v, and the few operations every force law is written with.
//
//   CentreOf(body)                a body's centre of mass x
//   Move(p)                       a body point's world position p and, with velocities, p' (kinematics.h)
//   Between(pa, pb)               the segment between two points: p_b - p_a, its length and direction
//   AddForce(p, motion, F, f)     a world-frame force F at the point: f_x += F, a rotation's part += a x F
//   AddTorque(body, tau_W, f)     a world-frame torque on a rigid body (planar: its z component)
//   Coordinate(joint, c)          a joint coordinate's value, rate and generalized row (joint_coordinates.h)
//   AddAlong(row, tau, f)         a force tau along that coordinate: f += tau dq'/dv on both bodies
//   AddAlongCoordinate(joint, c, tau, f)  the same from the coordinate itself (the adjoint records it as one
//                                 operation where it can: adjoint/recorded.h), nothing for a double zero (the
//                                 motors of an imported model at rest: five of MuJoCo's humanoid)
// Written against this view, an effect's header needs nothing of the kinematics, and a new effect touches no
// other file of the dynamics (docs/architecture.md, "Add an effect").
#pragma once

#include <type_traits>

#include "tether/dynamics/adjoint/recorded.h"
#include "tether/dynamics/constraints/joint_coordinates.h"

namespace tether {

template <typename T>
struct EffectContext {
  const Model<T>& model;
  const JointCoordinates<T>& coordinates;
  const BodyFrames<T>& frames;
  double t;
  const VecX<T>& q;
  const VecX<T>& v;

  int dimension() const { return model.dimension; }

  // x, a body's centre of mass in the world (components beyond the dimension zero)
  TETHER_HOT_INLINE Vec3<T> CentreOf(const Body<T>& body) const {
    return Translation(model.dimension, q.data() + body.q_offset);
  }

  TETHER_HOT_INLINE PointMotion<T> Move(const BodyPoint<T>& point, bool velocities) const {
    return MovePoint(model, frames, point, q, v, velocities);
  }

  // the line from a to b: its vector, length and direction
  TETHER_HOT_INLINE Segment<T> Between(const PointMotion<T>& a, const PointMotion<T>& b) const {
    return tether::Between(a, b);
  }

  TETHER_HOT_INLINE void AddForce(int body, const PointMotion<T>& motion, const Vec3<T>& force_W, VecX<T>* f) const {
    AddScaled(model, PointGradient(model, frames, body, force_W, motion), T(1.0), f);
  }
  // scale * direction_W at the point (a tension along a line: one product fewer than forming the force)
  TETHER_HOT_INLINE void AddForce(int body, const PointMotion<T>& motion, const Vec3<T>& direction_W, const T& scale,
                                  VecX<T>* f) const {
    AddScaled(model, PointGradient(model, frames, body, direction_W, motion), scale, f);
  }

  TETHER_HOT_INLINE void AddTorque(int body, const Vec3<T>& torque_W, VecX<T>* f) const {
    BodyVector<T> g;
    g.body = body;
    g.rotation = RotationalPart(model, frames, body, torque_W);
    AddScaled(model, g, T(1.0), f);
  }

  // (without `value`, an angle's value is left zero: EvaluateCoordinate)
  TETHER_HOT_INLINE CoordinateRow<T> Coordinate(int joint, JointCoordinate coordinate, bool velocities,
                                                bool value = true) const {
    return EvaluateCoordinate(model, coordinates, coordinates.Find(joint, coordinate), frames, q, v, velocities, value);
  }

  TETHER_HOT_INLINE void AddAlong(const CoordinateRow<T>& row, const T& value, VecX<T>* f) const {
    AddScaled(model, row.a, value, f);
    AddScaled(model, row.b, value, f);
  }

  TETHER_HOT_INLINE void AddAlongCoordinate(int joint, JointCoordinate coordinate, const T& value, VecX<T>* f) const {
    if constexpr (std::is_same_v<T, double>) {
      if (value == 0.0) return;  // adds nothing; a Jet or Rev zero can still carry derivatives
    }
    const int k = coordinates.Find(joint, coordinate);
    if (RecordedAngleTorque(model, coordinates, k, frames, value, f)) return;
    AddAlong(EvaluateCoordinate(model, coordinates, k, frames, q, v, false, false), value, f);  // the direction
  }
};

}  // namespace tether
