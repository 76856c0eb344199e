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

#include <optional>
#include <vector>

#include "tether/dynamics/scalars/reverse.h"
#include "tether/dynamics/scalars/scalar.h"

namespace tether {

template <typename T>
struct Model;
template <typename T>
struct BodyFrame;
template <typename T>
struct JointCoordinates;
template <typename T>
struct ConstraintRow;
template <typename T>
struct DistancePrimitive;
template <typename T>
struct PointPrimitive;
template <typename T>
struct AnglePrimitive;
template <typename T>
struct Workspace;

// The frames of the 3D bodies (model.spatial_bodies) at (q, v) (model/kinematics.h: UpdateFrames;
// dynamics/src/model/frames_adjoint.cc).
template <typename T>
bool RecordedSpatialFrames(const Model<T>&, const VecX<T>&, const VecX<T>&, bool, std::vector<BodyFrame<T>>*) {
  return false;
}
bool RecordedSpatialFrames(const Model<Rev>& model, const VecX<Rev>& q, const VecX<Rev>& v, bool velocities,
                           std::vector<BodyFrame<Rev>>* frames);

// Integrate and DexpInv of a model with 3D bodies, every body at once (model/configuration_space.h;
// dynamics/src/model/configuration_adjoint.cc); DexpInv maps k's 3D rotations in place (k holds v).
template <typename T>
bool RecordedSpatialIntegrate(const Model<T>&, const VecX<T>&, const VecX<T>&, double, VecX<T>*) {
  return false;
}
bool RecordedSpatialIntegrate(const Model<Rev>& model, const VecX<Rev>& q, const VecX<Rev>& v, double h,
                              VecX<Rev>* out);
template <typename T>
bool RecordedSpatialDexpInv(const Model<T>&, const VecX<T>&, VecX<T>*) {
  return false;
}
bool RecordedSpatialDexpInv(const Model<Rev>& model, const VecX<Rev>& theta, VecX<Rev>* k);

// The rows of the distance, point and angle primitives into `rows` and on (constraints/constraint_rows_impl.h:
// EvaluateConstraintRows; dynamics/src/constraints/distance_adjoint.cc and rigid_rows_adjoint.cc). Each returns the
// row after them, or nullptr where it did not do them. The distance rows between particles (or a particle and the
// world) are one node, the others node by node; the point and angle rows of a 3D scene one node each.
template <typename T>
ConstraintRow<T>* RecordedDistanceRows(const Model<T>&, const std::vector<DistancePrimitive<T>>&,
                                       const std::vector<BodyFrame<T>>&, const VecX<T>&, const VecX<T>&, bool,
                                       ConstraintRow<T>*) {
  return nullptr;
}
ConstraintRow<Rev>* RecordedDistanceRows(const Model<Rev>& model, const std::vector<DistancePrimitive<Rev>>& distances,
                                         const std::vector<BodyFrame<Rev>>& frames, const VecX<Rev>& q,
                                         const VecX<Rev>& v, bool velocity_terms, ConstraintRow<Rev>* rows);
template <typename T>
ConstraintRow<T>* RecordedPointRows(const Model<T>&, const std::vector<PointPrimitive<T>>&,
                                    const std::vector<BodyFrame<T>>&, const VecX<T>&, const VecX<T>&, bool,
                                    ConstraintRow<T>*) {
  return nullptr;
}
ConstraintRow<Rev>* RecordedPointRows(const Model<Rev>& model, const std::vector<PointPrimitive<Rev>>& points,
                                      const std::vector<BodyFrame<Rev>>& frames, const VecX<Rev>& q, const VecX<Rev>& v,
                                      bool velocity_terms, ConstraintRow<Rev>* rows);
template <typename T>
ConstraintRow<T>* RecordedAngleRows(const Model<T>&, const std::vector<AnglePrimitive<T>>&,
                                    const std::vector<BodyFrame<T>>&, bool, ConstraintRow<T>*) {
  return nullptr;
}
ConstraintRow<Rev>* RecordedAngleRows(const Model<Rev>& model, const std::vector<AnglePrimitive<Rev>>& angles,
                                      const std::vector<BodyFrame<Rev>>& frames, bool velocity_terms,
                                      ConstraintRow<Rev>* rows);

// The KKT part of a derivative evaluation, v' from the workspace's rows, force and gains, a node per velocity
// (solvers/constrained_dynamics.h: SolveKkt; dynamics/src/solvers/kkt_adjoint.cc): whether S could be factored,
// or nothing where it did not do it.
template <typename T>
std::optional<bool> RecordedKktAcceleration(const Model<T>&, const VecX<T>&, Workspace<T>*, VecX<T>*) {
  return std::nullopt;
}
std::optional<bool> RecordedKktAcceleration(const Model<Rev>& model, const VecX<Rev>& v, Workspace<Rev>* ws,
                                            VecX<Rev>* a);

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
