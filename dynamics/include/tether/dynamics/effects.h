// Applied forces: the generalized force f(t, q, q') of the declared effects, and the energy.
//
//   gravity  f_x += m g on every body
//   damping  f_x -= c x',  f_theta -= c_r theta'                 (listed bodies)
//   spring   tension s = k (l - l0) + d l', l = |p_B - p_A|, n = (p_B - p_A)/l: F_B = -s n, F_A = +s n
//   force    F at a body point (world frame): f_x += F, f_theta += perp(R r) . F
//   torque   f_theta += tau
// A point force enters the rotational coordinate through the lever perp(R r) (kinematics.h).
// Energy E = sum 1/2 m |x'|^2 + 1/2 I theta'^2 - sum m g . x + sum 1/2 k (l - l0)^2.
// Only the effects the model declares are visited; an empty list costs nothing.
#pragma once

#include "tether/dynamics/model.h"

namespace tether {

// f += the generalized force at time t and state (q, v).
template <typename T>
void AccumulateForces(const Model<T>& model, double t, const VecX<T>& q, const VecX<T>& v, VecX<T>* f);

// Kinetic + gravitational + spring potential energy, J.
template <typename T>
T Energy(const Model<T>& model, const VecX<T>& q, const VecX<T>& v);

}  // namespace tether
