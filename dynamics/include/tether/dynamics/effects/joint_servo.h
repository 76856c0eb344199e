// A servo on a joint's coordinate x (joint_coordinates.h): MuJoCo's position and velocity actuators in one,
//   u = kp (r - x) + kd (r' - x'),   tau = u, or with a `limit` L > 0: tau = L tanh(u / L)
// on B along the coordinate and its reaction on A, r the `target` (constant, or piecewise linear in time: its
// `schedule`) and r' the `target_rate` (constant). The saturation is tanh because it is smooth: slope 1 at u = 0,
// |tau| < L, every derivative continuous, so gradients through a saturated servo are exact (a clamp's would vanish
// where it saturates and jump where it starts to). N m (N) for kp per rad (m), kd per rad/s (m/s).
// Potential energy, of the position term alone: 1/2 kp (x - r)^2, or (L^2 / kp) log cosh(kp (x - r) / L) with a
// limit; the servo conserves it only without kd, a target rate or a schedule.
#pragma once

#include <cmath>

#include "tether/dynamics/constraints/joint_kinds.h"
#include "tether/dynamics/effects/schedule.h"
#include "tether/dynamics/scalars/scalar.h"

namespace tether {

template <typename T>
struct JointServoEffect {
  int scene_index = 0;
  int joint = 0;  // index into Model::joints
  JointCoordinate coordinate = JointCoordinate::kAngle;
  T kp = T(0.0);           // N m/rad or N/m
  T kd = T(0.0);           // N m s/rad or N s/m
  T target = T(0.0);       // r, rad or m (when `schedule` is empty)
  T target_rate = T(0.0);  // r', rad/s or m/s
  T limit = T(0.0);        // L, N m or N; 0: no saturation
  Schedule<T> schedule;

  template <typename U>
  JointServoEffect<U> Cast() const {
    return {
        scene_index, joint, coordinate, U(kp), U(kd), U(target), U(target_rate), U(limit), schedule.template Cast<U>()};
  }
  bool Conservative() const { return kd == T(0.0) && target_rate == T(0.0) && schedule.empty(); }

  T Target(double t) const { return schedule.empty() ? target : ScheduleValue(schedule, t); }

  template <typename Context>
  void AddForces(const Context& c, VecX<T>* f) const {
    const auto row = c.Coordinate(joint, coordinate, true);
    const T u = kp * (Target(c.t) - row.value) + kd * (target_rate - row.rate);
    using std::tanh;
    c.AddAlong(row, Saturated() ? T(limit * tanh(u / limit)) : u, f);
  }
  template <typename Context>
  T Energy(const Context& c) const {
    const T error = c.Coordinate(joint, coordinate, false).value - Target(c.t);
    if (!Saturated()) return T(0.5) * kp * error * error;
    if (!(Value(kp) > 0.0)) return T(0.0);
    using std::abs;
    using std::exp;
    using std::log1p;
    const T z = abs(kp * error / limit);  // log cosh z = |z| + log(1 + e^(-2|z|)) - log 2, without overflow
    return limit * limit / kp * (z + log1p(exp(T(-2.0) * z)) - T(std::log(2.0)));
  }

 private:
  bool Saturated() const { return Value(limit) > 0.0; }
};

}  // namespace tether
