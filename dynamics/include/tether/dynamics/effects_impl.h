// Definitions for effects.h; included only by the file that instantiates them.
#pragma once

#include <cmath>

#include "tether/dynamics/effects.h"
#include "tether/dynamics/kinematics.h"
#include "tether/dynamics/schedule.h"

namespace tether {

template <typename T>
void AccumulateForces(const Model<T>& model, double t, const VecX<T>& q, const VecX<T>& v, VecX<T>* f) {
  for (const GravityEffect<T>& g : model.gravity) {
    for (const Body<T>& body : model.bodies) {
      for (int k = 0; k < model.dimension; ++k) (*f)[body.offset + k] += body.mass * g.acceleration[k];
    }
  }
  for (const DampingEffect<T>& d : model.damping) {
    for (int index : d.bodies) {
      const Body<T>& body = model.bodies[index];
      for (int k = 0; k < model.dimension; ++k) (*f)[body.offset + k] -= d.coefficient * v[body.offset + k];
      if (body.kind == BodyKind::kRigid) (*f)[body.offset + 2] -= d.angular_coefficient * v[body.offset + 2];
    }
  }
  for (const SpringEffect<T>& s : model.springs) {
    const PointMotion<T> pa = MovePoint(model, s.a, q, v);
    const PointMotion<T> pb = MovePoint(model, s.b, q, v);
    const Segment<T> segment = Between(pa, pb);
    const T tension = s.stiffness * (segment.length - s.rest_length) +
                      s.damping * segment.n.dot(pb.velocity - pa.velocity);
    AddScaled(model, PointGradient(s.a.body, segment.n, pa), tension, f);
    AddScaled(model, PointGradient(s.b.body, segment.n, pb), T(-tension), f);
  }
  for (const ForceEffect<T>& e : model.forces) {
    const PointMotion<T> p = MovePoint(model, BodyPoint<T>{e.body, e.point}, q, v);
    const Vec3<T> value = e.schedule.empty() ? e.value : Sample(e.schedule, t);
    AddScaled(model, PointGradient(e.body, value, p), T(1.0), f);
  }
  for (const TorqueEffect<T>& e : model.torques) {
    (*f)[model.bodies[e.body].offset + 2] += e.schedule.empty() ? e.value : Sample(e.schedule, t);
  }
}

template <typename T>
T Energy(const Model<T>& model, const VecX<T>& q, const VecX<T>& v) {
  T energy(0.0);
  for (const Body<T>& body : model.bodies) {
    const Vec3<T> velocity = Translation(body, model.dimension, v);
    energy += T(0.5) * body.mass * velocity.squaredNorm();
    if (body.kind == BodyKind::kRigid) energy += T(0.5) * body.inertia * v[body.offset + 2] * v[body.offset + 2];
    for (const GravityEffect<T>& g : model.gravity) {
      energy -= body.mass * g.acceleration.dot(Translation(body, model.dimension, q));
    }
  }
  for (const SpringEffect<T>& s : model.springs) {
    const T stretch = Between(MovePoint(model, s.a, q, v), MovePoint(model, s.b, q, v)).length - s.rest_length;
    energy += T(0.5) * s.stiffness * stretch * stretch;
  }
  return energy;
}

}  // namespace tether
