// Applied forces: the generalized force f(t, q, v) of a model's effects, and its energy. Each effect is a header of
// its own (gravity.h, damping.h, spring.h, force.h, torque.h, joint_torque.h, joint_spring.h, joint_servo.h,
// drag.h), which states its law; here they are summed over the model's lists (ForEachEffectList, model.h),
// through the view of the state that effect_context.h gives them:
//   f = sum over the effects of their force  +  the gyroscopic torque -w_P x (I_P w_P) of every 3D rigid body
//   E = sum 1/2 m |x'|^2 + 1/2 I theta'^2 + 1/2 w_P . I_P w_P  +  sum over the effects of their potential energy
// (v-shaped: forces on translation, torques on rotation in each body's velocity frame; Euler's equations in
// principal axes). I_P = R_PB I_B R_BP is the scene's tensor (its upper triangle mirrored) seen in principal axes:
// diagonal at the values the scene was loaded with, and a full symmetric matrix where a parameter (a product of
// inertia, or a Jet's derivative part) moves it off the diagonal. Only the effects the model declares are
// visited; an empty list costs nothing.
#pragma once

#include <vector>

#include "tether/dynamics/constraints/joint_coordinates.h"

namespace tether {

// I_P of a 3D rigid body (kg m^2, principal axes): R_BP^T I_B R_BP, I_B symmetric with its products of
// inertia in the upper triangle of `inertia_tensor` (the scene reader binds both of a product's pointers there).
template <typename T>
Mat3<T> PrincipalInertia(const Mat3<T>& inertia_tensor, const Vec4<double>& principal_axes);
template <typename T>
Mat3<T> PrincipalInertia(const Body<T>& body) {
  return PrincipalInertia(body.inertia_tensor, body.principal_axes);
}

// PrincipalInertia of every body (zero for those that are not 3D rigid bodies): taken once per run, as M^-1 is,
// so that an evaluation's gyroscopic torques do not turn each body's tensor into its principal axes again.
template <typename T>
std::vector<Mat3<T>> PrincipalInertias(const Model<T>& model);

// f += the generalized force at time t and state (q, v); frames updated there with velocities; principal_inertia
// as PrincipalInertias(model).
template <typename T>
void AccumulateForces(const Model<T>& model, const JointCoordinates<T>& coordinates,
                      const std::vector<Mat3<T>>& principal_inertia, const BodyFrames<T>& frames, double t,
                      const VecX<T>& q, const VecX<T>& v, VecX<T>* f);

// 1/2 v^T M v, J.
template <typename T>
T KineticEnergy(const Model<T>& model, const VecX<T>& v);

// Kinetic + the effects' potential energy, J; frames updated at q.
template <typename T>
T Energy(const Model<T>& model, const JointCoordinates<T>& coordinates, const BodyFrames<T>& frames, const VecX<T>& q,
         const VecX<T>& v);

}  // namespace tether
