// Gravity: f_x += m g on every body; potential energy -sum m g . x.
#pragma once

#include "tether/dynamics/model/bodies.h"

namespace tether {

template <typename T>
struct GravityEffect {
  int scene_index = 0;
  Vec3<T> acceleration = Vec3<T>::Zero();  // g, m/s^2

  template <typename U>
  GravityEffect<U> Cast() const {
    return {scene_index, acceleration.template cast<U>()};
  }
  bool Conservative() const { return true; }

  template <typename Context>
  void AddForces(const Context& c, VecX<T>* f) const {
    for (const Body<T>& body : c.model.bodies) {
      for (int k = 0; k < c.dimension(); ++k) (*f)[body.v_offset + k] += body.mass * acceleration[k];
    }
  }
  template <typename Context>
  T Energy(const Context& c) const {
    T energy(0.0);
    for (const Body<T>& body : c.model.bodies) energy -= body.mass * acceleration.dot(c.CentreOf(body));
    return energy;
  }
};

}  // namespace tether
