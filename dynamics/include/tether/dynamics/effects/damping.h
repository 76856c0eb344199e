// Damping: force -c x' on every listed body, torque -c_r w on the rigid ones (in the frame of their angular
// velocity in v). No potential energy.
#pragma once

#include <vector>

#include "tether/dynamics/model/bodies.h"

namespace tether {

template <typename T>
struct DampingEffect {
  int scene_index = 0;
  T coefficient = T(0.0);          // c, N s/m
  T angular_coefficient = T(0.0);  // c_r, N m s/rad
  std::vector<int> bodies;

  template <typename U>
  DampingEffect<U> Cast() const {
    return {scene_index, U(coefficient), U(angular_coefficient), bodies};
  }
  bool Conservative() const { return false; }

  template <typename Context>
  void AddForces(const Context& c, VecX<T>* f) const {
    for (int index : bodies) {
      const Body<T>& body = c.model.bodies[index];
      for (int k = 0; k < c.dimension(); ++k) (*f)[body.v_offset + k] -= coefficient * c.v[body.v_offset + k];
      if (body.kind == BodyKind::kPlanar) (*f)[body.v_offset + 2] -= angular_coefficient * c.v[body.v_offset + 2];
      if (body.kind == BodyKind::kRigid3d) {
        for (int k = 3; k < 6; ++k) (*f)[body.v_offset + k] -= angular_coefficient * c.v[body.v_offset + k];
      }
    }
  }
  template <typename Context>
  T Energy(const Context&) const {
    return T(0.0);
  }
};

}  // namespace tether
