// The seam between the templated core and the reverse-mode scalar Rev (reverse.h): the operations whose adjoint is
// written out by hand, each a customization point. The template below is what every scalar does (nothing: the
// templated code that calls it computes the operation itself, and a Rev run records it elementary operation by
// elementary operation); the overload for Rev records the whole operation as one node whose adjoint its own file
// writes out, which is what makes the adjoint fast. The core calls these and tests no scalar type: this is the
// one place that knows Rev is special. Each Rev overload sits beside the templated code it mirrors (its file is
// named below), and tests/recorded_kernels_test.cc compares each with that code on random inputs, value and
// adjoint against Jets.
//
// Each returns whether it did the work (always false but for Rev).
#pragma once

#include <vector>

#include "tether/dynamics/adjoint/reverse.h"
#include "tether/dynamics/model/scalar.h"

namespace tether {

template <typename T>
struct Model;
template <typename T>
struct BodyFrame;
template <typename T>
struct JointCoordinates;

// f += value dtheta'/dv for joint coordinate k when it is a 3D joint's angle (effects/joint_torque.h;
// dynamics/src/effects/joint_torque_adjoint.cc).
template <typename T>
bool RecordedAngleTorque(const Model<T>&, const JointCoordinates<T>&, int, const std::vector<BodyFrame<T>>&, const T&,
                         VecX<T>*) {
  return false;
}
bool RecordedAngleTorque(const Model<Rev>& model, const JointCoordinates<Rev>& coordinates, int k,
                         const std::vector<BodyFrame<Rev>>& frames, const Rev& value, VecX<Rev>* f);

// f_P -= w_P x (I_P w_P) on every 3D body, each body's torque one node (effects/effects_impl.h;
// dynamics/src/effects/gyroscopic_adjoint.cc).
template <typename T>
bool RecordedGyroscopicTorques(const Model<T>&, const VecX<T>&, VecX<T>*) {
  return false;
}
bool RecordedGyroscopicTorques(const Model<Rev>& model, const VecX<Rev>& v, VecX<Rev>* f);

}  // namespace tether
