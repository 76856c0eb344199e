// Applied forces: the generalized force f(t, q, v) of the declared effects (v-shaped: forces on translation,
// torques on rotation in each body's velocity frame), and the energy.
//
//   gravity       f_x += m g on every body
//   damping       f_x -= c x',  torque -c_r w                        (listed bodies)
//   spring        tension s = k (l - l0) + d l', l = |p_B - p_A|, n = (p_B - p_A)/l: F_B = -s n, F_A = +s n
//   force         F at a body point (world frame): f_x += F, torque a x F (a the point's world arm)
//   torque        tau (world frame; planar bodies: about z)
//   joint_torque  tau on the joint's coordinate: f += tau dq'/dv (joint_coordinates.h)
//   joint_spring  the same with tau = -k (q - rest) - d q'
//   gyroscopic    3D rigid bodies, always: torque -w_P x (I_P w_P) in principal axes (Euler's equations)
// A world-frame torque enters a body's rotation as R_PW tau (kinematics.h). I_P = R_PB I_B R_BP is the scene's
// tensor (its upper triangle mirrored) seen in principal axes: diagonal at the values the scene was loaded with, and a
// full symmetric matrix where a parameter (a product of inertia, or a Jet's derivative part) moves it off the diagonal.
// Energy E = sum 1/2 m |x'|^2 + 1/2 I theta'^2 + 1/2 w_P . I_P w_P - sum m g . x + sum 1/2 k (l - l0)^2
//            + sum 1/2 k (q - rest)^2 over joint springs.
// Only the effects the model declares are visited; an empty list costs nothing.
#pragma once

#include "tether/dynamics/constraints/joint_coordinates.h"

namespace tether {

// I_P of a 3D rigid body (kg m^2, principal axes): R_BP^T I_B R_BP, I_B symmetric with its products of
// inertia in the upper triangle of `inertia_tensor` (parameters.h).
template <typename T>
Mat3<T> PrincipalInertia(const Mat3<T>& inertia_tensor, const Vec4<double>& principal_axes);
template <typename T>
Mat3<T> PrincipalInertia(const Body<T>& body) {
  return PrincipalInertia(body.inertia_tensor, body.principal_axes);
}

// Rev: a torque `value` on coordinate k when it is a 3D joint's angle, f += value dtheta'/dv, as one recorded
// operation (joint_torque_adjoint.cc); false, and nothing done, for the other coordinates.
bool RecordAngleTorque(const Model<Rev>& model, const JointCoordinates<Rev>& coordinates, int k,
                       const BodyFrames<Rev>& frames, const Rev& value, VecX<Rev>* f);

// Rev: f_P -= w_P x (I_P w_P) on every 3D body, each body's torque one recorded operation (gyroscopic_adjoint.cc).
void RecordGyroscopicTorques(const Model<Rev>& model, const VecX<Rev>& v, VecX<Rev>* f);

// f += the generalized force at time t and state (q, v); frames updated there with velocities.
template <typename T>
void AccumulateForces(const Model<T>& model, const JointCoordinates<T>& coordinates, const BodyFrames<T>& frames,
                      double t, const VecX<T>& q, const VecX<T>& v, VecX<T>* f);

// Kinetic + gravitational + spring and joint-spring potential energy, J; frames updated at q.
template <typename T>
T Energy(const Model<T>& model, const JointCoordinates<T>& coordinates, const BodyFrames<T>& frames, const VecX<T>& q,
         const VecX<T>& v);

}  // namespace tether
