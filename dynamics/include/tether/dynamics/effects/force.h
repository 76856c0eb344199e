// A world-frame force F at a body point (constant `value`, or `schedule` when it is not empty): f_x += F, and on a
// rigid body the torque a x F (a the point's world arm). No potential energy (it may do work).
#pragma once

#include "tether/dynamics/effects/schedule.h"
#include "tether/dynamics/model/bodies.h"

namespace tether {

template <typename T>
struct ForceEffect {
  int scene_index = 0;
  int body = 0;
  Vec3<T> point = Vec3<T>::Zero();  // body axes, m
  Vec3<T> value = Vec3<T>::Zero();  // N
  Schedule<Vec3<T>> schedule;

  template <typename U>
  ForceEffect<U> Cast() const {
    return {scene_index, body, point.template cast<U>(), value.template cast<U>(), schedule.template Cast<U>()};
  }
  bool Conservative() const { return false; }

  template <typename Context>
  void AddForces(const Context& c, VecX<T>* f) const {
    const auto p = c.Move(BodyPoint<T>{body, point}, false);
    c.AddForce(body, p, schedule.empty() ? value : ScheduleValue(schedule, c.t), f);
  }
  template <typename Context>
  T Energy(const Context&) const {
    return T(0.0);
  }
};

}  // namespace tether
