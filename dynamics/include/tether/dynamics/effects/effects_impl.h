// Definitions for effects.h; included only by the file that instantiates them.
#pragma once

#include <cmath>
#include <type_traits>

#include "tether/dynamics/effects/effects.h"
#include "tether/dynamics/effects/schedule.h"

namespace tether {

template <typename T>
Mat3<T> PrincipalInertia(const Mat3<T>& inertia_tensor, const Vec4<double>& principal_axes) {
  Mat3<T> symmetric = inertia_tensor;  // the upper triangle holds the products of inertia (parameters.h)
  symmetric(1, 0) = symmetric(0, 1);
  symmetric(2, 0) = symmetric(0, 2);
  symmetric(2, 1) = symmetric(1, 2);
  if (principal_axes == Vec4<double>(1, 0, 0, 0)) return symmetric;
  const Mat3<T> R_BP = RotationMatrix(Vec4<T>(principal_axes.template cast<T>()));
  return R_BP.transpose() * symmetric * R_BP;
}

template <typename T>
TETHER_FLATTEN void AccumulateForces(const Model<T>& model, const JointCoordinates<T>& coordinates,
                                     const BodyFrames<T>& frames, double t, const VecX<T>& q, const VecX<T>& v,
                                     VecX<T>* f) {
  const int d = model.dimension;
  for (const GravityEffect<T>& g : model.gravity) {
    for (const Body<T>& body : model.bodies) {
      for (int k = 0; k < d; ++k) (*f)[body.v_offset + k] += body.mass * g.acceleration[k];
    }
  }
  for (const DampingEffect<T>& e : model.damping) {
    for (int index : e.bodies) {
      const Body<T>& body = model.bodies[index];
      for (int k = 0; k < d; ++k) (*f)[body.v_offset + k] -= e.coefficient * v[body.v_offset + k];
      if (body.kind == BodyKind::kPlanar) (*f)[body.v_offset + 2] -= e.angular_coefficient * v[body.v_offset + 2];
      if (body.kind == BodyKind::kRigid3d) {
        for (int k = 3; k < 6; ++k) (*f)[body.v_offset + k] -= e.angular_coefficient * v[body.v_offset + k];
      }
    }
  }
  for (const SpringEffect<T>& s : model.springs) {
    const PointMotion<T> pa = MovePoint(model, frames, s.a, q, v, true);
    const PointMotion<T> pb = MovePoint(model, frames, s.b, q, v, true);
    const Segment<T> segment = Between(pa, pb);
    const T tension =
        s.stiffness * (segment.length - s.rest_length) + s.damping * segment.n.dot(pb.velocity - pa.velocity);
    AddScaled(model, PointGradient(model, frames, s.a.body, segment.n, pa), tension, f);
    AddScaled(model, PointGradient(model, frames, s.b.body, segment.n, pb), T(-tension), f);
  }
  for (const ForceEffect<T>& e : model.forces) {
    const PointMotion<T> p = MovePoint(model, frames, BodyPoint<T>{e.body, e.point}, q, v, false);
    const Vec3<T> value = e.schedule.empty() ? e.value : ScheduleValue(e.schedule, t);
    AddScaled(model, PointGradient(model, frames, e.body, value, p), T(1.0), f);
  }
  for (const TorqueEffect<T>& e : model.torques) {
    const Vec3<T> value = e.schedule.empty() ? e.value : ScheduleValue(e.schedule, t);
    BodyVector<T> g;
    g.body = e.body;
    g.rotation = RotationalPart(model, frames, e.body, value);
    AddScaled(model, g, T(1.0), f);
  }
  for (const JointTorqueEffect<T>& e : model.joint_torques) {
    const int k = coordinates.Find(e.joint, e.coordinate);
    const T value = e.schedule.empty() ? e.value : ScheduleValue(e.schedule, t);
    if constexpr (std::is_same_v<T, Rev>) {
      if (RecordAngleTorque(model, coordinates, k, frames, value, f)) continue;
    }
    const CoordinateRow<T> row = EvaluateCoordinate(model, coordinates, k, frames, q, v, false);
    AddScaled(model, row.a, value, f);
    AddScaled(model, row.b, value, f);
  }
  for (const JointSpringEffect<T>& e : model.joint_springs) {
    const int k = coordinates.Find(e.joint, e.coordinate);
    const CoordinateRow<T> row = EvaluateCoordinate(model, coordinates, k, frames, q, v, true);
    const T value = -e.stiffness * (row.value - e.rest) - e.damping * row.rate;
    AddScaled(model, row.a, value, f);
    AddScaled(model, row.b, value, f);
  }
  if constexpr (std::is_same_v<T, Rev>) {
    RecordGyroscopicTorques(model, v, f);
  } else {
    for (int index : model.spatial_bodies) {
      const Body<T>& body = model.bodies[index];
      const Vec3<T> w_P = v.template segment<3>(body.v_offset + 3);
      f->template segment<3>(body.v_offset + 3) -= w_P.cross(Vec3<T>(PrincipalInertia(body) * w_P));
    }
  }
}

template <typename T>
T Energy(const Model<T>& model, const JointCoordinates<T>& coordinates, const BodyFrames<T>& frames, const VecX<T>& q,
         const VecX<T>& v) {
  T energy(0.0);
  for (const Body<T>& body : model.bodies) {
    const Vec3<T> velocity = Translation(model.dimension, v.data() + body.v_offset);
    energy += T(0.5) * body.mass * velocity.squaredNorm();
    if (body.kind == BodyKind::kPlanar) energy += T(0.5) * body.inertia * v[body.v_offset + 2] * v[body.v_offset + 2];
    if (body.kind == BodyKind::kRigid3d) {
      const Vec3<T> w_P = v.template segment<3>(body.v_offset + 3);
      energy += T(0.5) * w_P.dot(PrincipalInertia(body) * w_P);
    }
    for (const GravityEffect<T>& g : model.gravity) {
      energy -= body.mass * g.acceleration.dot(Translation(model.dimension, q.data() + body.q_offset));
    }
  }
  for (const SpringEffect<T>& s : model.springs) {
    const PointMotion<T> pa = MovePoint(model, frames, s.a, q, v, false);
    const PointMotion<T> pb = MovePoint(model, frames, s.b, q, v, false);
    const T stretch = Between(pa, pb).length - s.rest_length;
    energy += T(0.5) * s.stiffness * stretch * stretch;
  }
  for (const JointSpringEffect<T>& e : model.joint_springs) {
    const int k = coordinates.Find(e.joint, e.coordinate);
    const T stretch = EvaluateCoordinate(model, coordinates, k, frames, q, v, false).value - e.rest;
    energy += T(0.5) * e.stiffness * stretch * stretch;
  }
  return energy;
}

}  // namespace tether
