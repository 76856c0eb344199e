// Quadratic air drag at a body point: F = -1/2 rho C_d A |v| v, v the point's world velocity (rho the fluid's
// density, C_d the drag coefficient, A the reference area), applied at the point: on a rigid body it also turns the
// body, by a x F. Dissipative: no potential energy.
//
// Derivative-safe at rest: |v| v is differentiable at v = 0 (its derivative is 0 there) where |v| alone is not, so
// the force is zero there without taking the square root.
#pragma once

#include <cmath>

#include "tether/dynamics/model/bodies.h"

namespace tether {

template <typename T>
struct DragEffect {
  int scene_index = 0;
  int body = 0;
  Vec3<T> point = Vec3<T>::Zero();  // body axes, m
  T density = T(1.225);             // rho, kg/m^3 (air at sea level by default)
  T drag_coefficient = T(0.0);      // C_d
  T area = T(0.0);                  // A, m^2

  template <typename U>
  DragEffect<U> Cast() const {
    return {scene_index, body, point.template cast<U>(), U(density), U(drag_coefficient), U(area)};
  }
  bool Conservative() const { return false; }

  template <typename Context>
  void AddForces(const Context& c, VecX<T>* f) const {
    using std::sqrt;
    const auto p = c.Move(BodyPoint<T>{body, point}, true);
    const T speed_squared = p.velocity.squaredNorm();
    if (!(Value(speed_squared) > 0.0)) return;
    const T scale = T(-0.5) * density * drag_coefficient * area * sqrt(speed_squared);
    c.AddForce(body, p, Vec3<T>(scale * p.velocity), f);
  }
  template <typename Context>
  T Energy(const Context&) const {
    return T(0.0);
  }
};

}  // namespace tether
