// The configuration space of a model: q and v have their own layouts (model.h), and only these functions move
// a configuration along a velocity (docs/architecture.md, principle 3; Pinocchio's integrate/difference).
//
//   Integrate(q, v, h)   q (+) h v: translations and planar angles add; a 3D body's orientation turns by the
//                        exponential map in its own frame, q_WB <- q_WB (x) Exp(h R_BP w_P) (rotation.h), and is
//                        normalised (which removes only rounding: the product of unit quaternions is one)
//   Difference(q0, q1)   the v-shaped d with Integrate(q0, d, 1) = q1: differences, and R_PB Log(q0^-1 (x) q1)
//                        for orientations (the shorter rotation)
//   DexpInv(theta, v)    the Runge-Kutta-Munthe-Kaas stage derivative: identity on translations and planar
//                        angles, DexpInv(theta_P, w_P) on a 3D body's rotation (theta_P in principal axes, where
//                        Exp(R_BP theta_P) = R_BP Exp(theta_P) R_PB)
// A 3D body's principal axes P are fixed in the model (R_BP), so the frame of w_P never changes during a run.
//
// The scene gives the initial state in its own form (positions, the quaternion as written, world-frame angular
// velocities); InitialState turns it into (q, v), normalising quaternions (smoothly: a derivative with respect to
// a component follows the rotation it names), and WithInitialState writes a (q, v) back into that form.
#pragma once

#include "tether/dynamics/model/model.h"

namespace tether {

template <typename T>
struct State {
  VecX<T> q;  // NumCoordinates()
  VecX<T> v;  // NumVelocities()
};

// *out = q (+) h v; out may alias neither q nor v.
template <typename T>
void Integrate(const Model<T>& model, const VecX<T>& q, const VecX<T>& v, double h, VecX<T>* out);

// *d = q1 (-) q0.
template <typename T>
void Difference(const Model<T>& model, const VecX<T>& q0, const VecX<T>& q1, VecX<T>* d);

// *k = dexp^-1 at the stage increment theta applied to v (see above); k may alias v.
template <typename T>
void DexpInv(const Model<T>& model, const VecX<T>& theta, const VecX<T>& v, VecX<T>* k);

template <typename T>
State<T> InitialState(const Model<T>& model);

// The model with its initial state set to (q, v).
template <typename T>
Model<T> WithInitialState(const Model<T>& model, const VecX<T>& q, const VecX<T>& v);

// A 3D body's orientation q_WB, its rotation R_WB and its angular velocity w_W in the world frame.
template <typename T>
Vec4<T> Orientation(const Body<T>& body, const VecX<T>& q) {
  return q.template segment<4>(body.q_offset + 3);
}
template <typename T>
Vec3<T> WorldAngularVelocity(const Body<T>& body, const VecX<T>& q, const VecX<T>& v);

// q' of a body's coordinates (N(q) v), written into rate[0 .. q_size), and, in second_order, the part of q''
// that does not depend on v' (zero but for a 3D body's quaternion: 1/2 q' (x) (0, w_B)).
// (kind, principal_axes and q_size as in Body.)
template <typename T>
void ConfigurationRate(BodyKind kind, const Vec4<double>& principal_axes, int q_size, const T* q, const T* v, T* rate,
                       T* second_order);

}  // namespace tether
