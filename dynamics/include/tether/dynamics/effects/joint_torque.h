// A motor: torque (or force) tau on B along the joint's coordinate, and its reaction on A: f += tau dq'/dv
// (joint_coordinates.h). Constant `value`, or `schedule` when it is not empty. No potential energy.
#pragma once

#include "tether/dynamics/constraints/joint_kinds.h"
#include "tether/dynamics/effects/schedule.h"
#include "tether/dynamics/scalars/scalar.h"

namespace tether {

template <typename T>
struct JointTorqueEffect {
  int scene_index = 0;
  int joint = 0;  // index into Model::joints
  JointCoordinate coordinate = JointCoordinate::kAngle;
  T value = T(0.0);  // N m or N
  Schedule<T> schedule;

  template <typename U>
  JointTorqueEffect<U> Cast() const {
    return {scene_index, joint, coordinate, U(value), schedule.template Cast<U>()};
  }
  bool Conservative() const { return false; }

  template <typename Context>
  void AddForces(const Context& c, VecX<T>* f) const {
    c.AddAlongCoordinate(joint, coordinate, schedule.empty() ? value : ScheduleValue(schedule, c.t), f);
  }
  template <typename Context>
  T Energy(const Context&) const {
    return T(0.0);
  }
};

}  // namespace tether
