// The constraint rows C_i(q) = 0 of a model, with their Jacobian rows J_i = dC_i/dq and the velocity-product
// term Jdot_i q' (so that C_i'' = J_i q'' + Jdot_i q').
//
//   distance  C = |d| - L,   d = p_B - p_A,  n = d/|d|
//             J q'' = n . (d'' without velocity products),  Jdot q' = (|d'|^2 - (n . d')^2)/|d| + n . (c_B - c_A)
//   pin       C_k = (p_B - p_A)_k for each axis k;          Jdot q' = (c_B - c_A)_k
//   slider    C_k = n_k . d with n_k normal to the axis (one row in 2D, two in 3D), n turning with body A:
//             Jdot q' = -w_A^2 n . d + 2 w_A perp(n) . d' + n . (c_B - c_A)        (w_A = 0 in 3D)
//   user      any residual of two bodies' coordinates, derived automatically (user_constraint.h)
// where c is the centripetal part of a point's acceleration (kinematics.h). Every row touches at most two
// bodies, so J is stored as two BodyVector blocks per row: the sparse structure is explicit.
#pragma once

#include <vector>

#include "tether/dynamics/kinematics.h"

namespace tether {

template <typename T>
struct ConstraintRow {
  T value = T(0.0);  // C_i(q), metres for the built-in constraints
  T bias = T(0.0);   // Jdot_i q'
  BodyVector<T> a;   // J_i restricted to the first body
  BodyVector<T> b;   // J_i restricted to the second body
};

// What is known about a row before any evaluation: the constraint it belongs to and the bodies it touches.
struct RowInfo {
  int scene_index = 0;
  int body_a = kWorld;
  int body_b = kWorld;
};

// Rows in evaluation order (distances, pins, sliders, user constraints).
template <typename T>
std::vector<RowInfo> DescribeRows(const Model<T>& model);

// Fills rows (sized as DescribeRows) at state (q, v). With velocity_terms false, `bias` is not computed and v
// is not read (position-only uses: projection, output).
template <typename T>
void EvaluateConstraintRows(const Model<T>& model, const VecX<T>& q, const VecX<T>& v, bool velocity_terms,
                            std::vector<ConstraintRow<T>>* rows);

// The largest geometric violation over the constraints (the Euclidean norm of each constraint's rows), and
// the scene index of the constraint where it occurs (-1 when there are none).
struct Violation {
  double largest = 0.0;
  int scene_index = -1;
};
template <typename T>
Violation LargestViolation(const std::vector<RowInfo>& infos, const std::vector<ConstraintRow<T>>& rows);

}  // namespace tether
