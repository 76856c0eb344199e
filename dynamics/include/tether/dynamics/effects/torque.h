// A world-frame torque on a rigid body (planar: about z, the value in z): constant `value`, or `schedule` when it
// is not empty. No potential energy.
#pragma once

#include "tether/dynamics/effects/schedule.h"
#include "tether/dynamics/model/bodies.h"

namespace tether {

template <typename T>
struct TorqueEffect {
  int scene_index = 0;
  int body = 0;
  Vec3<T> value = Vec3<T>::Zero();  // N m
  Schedule<Vec3<T>> schedule;

  template <typename U>
  TorqueEffect<U> Cast() const {
    return {scene_index, body, value.template cast<U>(), schedule.template Cast<U>()};
  }
  bool Conservative() const { return false; }

  template <typename Context>
  void AddForces(const Context& c, VecX<T>* f) const {
    c.AddTorque(body, schedule.empty() ? value : ScheduleValue(schedule, c.t), f);
  }
  template <typename Context>
  T Energy(const Context&) const {
    return T(0.0);
  }
};

}  // namespace tether
