// Joint coordinates (docs/contract.md): a hinge's angle, a prismatic joint's displacement, both for a cylindrical
// joint, the angle of a 2D pin between planar rigid bodies; with their rates and their gradients with respect to
// v, which is how motors and joint springs act (a torque tau on the coordinate is the generalized force
// tau dq'/dv, equal and opposite on the two bodies, so it does no net work on the pair but through the joint).
//
//   hinge (3D)   theta = theta_0 + atan2((n_A x n_B) . a, n_A . n_B), n_A a normal of A's axis a (A's frame),
//                n_B its image in B at the start, all turned into the world; continuous (the branch nearest the
//                last value), theta' = (w_B - w_A) . a
//   pin (2D)     theta = theta_0 + (theta_B - theta_A) - (theta_B - theta_A)_start,   theta' = w_B - w_A
//   displacement s = u . (p_B - p_A), u = R_WA a / |a|:  s' = u . (p_B' - p_A') + w_A . (u x (p_B - p_A))
// and, for a joint limit's row (unilateral_events.h), the velocity product of the second derivative,
// coordinate'' = (dq'/dv) v' + bias:
//   hinge        bias = (w_B - w_A) . (w_A x a_W)          pin (2D)  bias = 0
//   displacement bias = u . (c_B - c_A) + 2 (w_A x u) . d' + (w_A x (w_A x u)) . d   (d = p_B - p_A, c the
//                points' centripetal accelerations: the line row's of constraint_rows.h with n = u)
// theta_0 is the joint's "angle" key; "the start" is the state the references are built at (the assembled
// initial state).
#pragma once

#include <vector>

#include "tether/dynamics/model/kinematics.h"

namespace tether {

template <typename T>
struct CoordinateReference {
  int joint = 0;  // index into Model::joints
  JointCoordinate coordinate = JointCoordinate::kAngle;
  Vec3<T> axis = Vec3<T>::UnitZ();     // unit, A's frame
  Vec3<T> normal_a = Vec3<T>::Zero();  // hinge: a unit normal of the axis, A's frame
  Vec3<T> normal_b = Vec3<T>::Zero();  // hinge: the same vector in B's frame at the start
  T offset = T(0.0);                   // angle: theta_0 (3D), theta_0 - (theta_B - theta_A)_start (2D)
};

// Value, rate and gradient (dq'/dv on each body) of one coordinate at a state.
template <typename T>
struct CoordinateRow {
  T value = T(0.0);
  T rate = T(0.0);
  BodyVector<T> a, b;
};

// Whether a joint's coordinates are tracked: a named joint's (its CSV columns) and a limited one's.
template <typename T>
bool TracksCoordinates(const Joint<T>& joint) {
  return !joint.name.empty() || joint.range.declared();
}

template <typename T>
struct JointCoordinates {
  // every coordinate of every tracked joint, in scene order, the angle before the displacement
  std::vector<CoordinateReference<T>> references;
  std::vector<double> last;  // the last value of each (picks the branch of an angle)

  // The position in `references` of a joint's coordinate, -1 if it has none.
  int Find(int joint, JointCoordinate coordinate) const;
};

// The position of a joint's coordinate among the references BuildJointCoordinates makes, -1 if it has none.
template <typename T>
int CoordinateIndex(const Model<T>& model, int joint, JointCoordinate coordinate);

template <typename T>
JointCoordinates<T> BuildJointCoordinates(const Model<T>& model, const VecX<T>& q);

// Coordinate k at (q, v), frames updated there (velocities too when `velocities`). Without `value`, an angle's value
// is left zero and its arctangent not taken (a motor, or a spring without stiffness, reads only the direction and
// the rate).
template <typename T>
CoordinateRow<T> EvaluateCoordinate(const Model<T>& model, const JointCoordinates<T>& coordinates, int k,
                                    const BodyFrames<T>& frames, const VecX<T>& q, const VecX<T>& v, bool velocities,
                                    bool value = true);

// The same for any reference, the branch of an angle taken nearest `branch`.
template <typename T>
CoordinateRow<T> EvaluateCoordinateAt(const Model<T>& model, const CoordinateReference<T>& reference, double branch,
                                      const BodyFrames<T>& frames, const VecX<T>& q, const VecX<T>& v, bool velocities,
                                      bool value = true);

// The coordinate's velocity product `bias` above at (q, v), frames updated there with velocities.
template <typename T>
T CoordinateBias(const Model<T>& model, const CoordinateReference<T>& reference, const BodyFrames<T>& frames,
                 const VecX<T>& q, const VecX<T>& v);

// Moves every `last` to the coordinates' values at (q, v) (after an accepted step).
template <typename T>
void TrackCoordinates(const Model<T>& model, const BodyFrames<T>& frames, const VecX<T>& q, const VecX<T>& v,
                      JointCoordinates<T>* coordinates);

}  // namespace tether
