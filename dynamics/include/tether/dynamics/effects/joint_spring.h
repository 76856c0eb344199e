// A spring on a joint's coordinate: tau = -k (q - rest) - d q' along it (joint_coordinates.h). Potential energy
// 1/2 k (q - rest)^2.
#pragma once

#include <type_traits>

#include "tether/dynamics/constraints/joint_kinds.h"
#include "tether/dynamics/scalars/scalar.h"

namespace tether {

template <typename T>
struct JointSpringEffect {
  int scene_index = 0;
  int joint = 0;  // index into Model::joints
  JointCoordinate coordinate = JointCoordinate::kAngle;
  T stiffness = T(0.0);  // k, N m/rad or N/m
  T rest = T(0.0);       // rad or m
  T damping = T(0.0);    // d, N m s/rad or N s/m

  template <typename U>
  JointSpringEffect<U> Cast() const {
    return {scene_index, joint, coordinate, U(stiffness), U(rest), U(damping)};
  }
  bool Conservative() const { return damping == T(0.0); }

  template <typename Context>
  void AddForces(const Context& c, VecX<T>* f) const {
    bool stretch = true;  // a double zero stiffness needs no angle; a Jet or Rev zero can still carry derivatives
    if constexpr (std::is_same_v<T, double>) stretch = stiffness != 0.0;
    const auto row = c.Coordinate(joint, coordinate, true, stretch);
    c.AddAlong(row, T(-stiffness * (row.value - rest) - damping * row.rate), f);
  }
  template <typename Context>
  T Energy(const Context& c) const {
    const T stretch = c.Coordinate(joint, coordinate, false).value - rest;
    return T(0.5) * stiffness * stretch * stretch;
  }
};

}  // namespace tether
