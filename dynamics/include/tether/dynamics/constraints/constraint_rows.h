// Constraint primitives and the rows C_i(q) = 0 they produce, with the Jacobian rows J_i (C_i' = J_i v) and the
// velocity-product terms Jdot_i v (C_i'' = J_i v' + Jdot_i v). Every built-in joint is a list of primitives
// (Jolt's constraint parts); d = p_B - p_A, c the centripetal parts of the points' accelerations, w the world
// angular velocities (kinematics.h):
//
//   distance   C = |d| - L,   n = d/|d|:  J v = n . d',   Jdot v = (|d'|^2 - (n . d')^2)/|d| + n . (c_B - c_A)
//   point      C_k = e_k . d for each world axis e_k (d rows):       Jdot v = e_k . (c_B - c_A)
//   line       C_k = n_k . d - c_k, n_k = R_WA n_k^A (1 or 2 rows; c_k = 0 and n_k normal to A's axis for a
//              point on A's line, d - 1 rows); n_k turns with A:
//              J v = n . d' + w_A . (n x d),
//              Jdot v = n . (c_B - c_A) + 2 (w_A x n) . d' + (w_A x (w_A x n)) . d
//   angle      C_k = u_k . w_k - c_k, u_k = R_WA u_k^A, w_k = R_WB w_k^B (1 to 3 rows, radians for small errors):
//              J v = (w_A - w_B) . (u x w),
//              Jdot v = (w_A - w_B) . ((w_A x u) x w + u x (w_B x w))
//   user       any residual of two bodies' coordinates, derived automatically (user_constraint.h)
//   limit      an active joint limit (unilateral_events.h), one-sided: the gap g = s (x - bound) >= 0 of a joint
//              coordinate x (s = +1 at the low bound, -1 at the high one), J = s dx'/dv, Jdot v = s bias
//              (joint_coordinates.h); its value is min(g, 0), the violation, so that the stabilization pushes
//              the bodies apart where they overlap and never pulls them together
//   contact    an active contact feature (contact_geometry.h): a line row (a vertex against a plane) or a
//              distance row (closest points) whose value is the gap g, one-sided and clamped like a limit's;
//              a sticking contact adds d - 1 slip rows (contact_friction.h)
//
// The joints' parts (joint_kinds.h, which lists each joint's) as primitives; "at the start" is the state the set
// is built at:
//   common axis: angle (n_1 . a_B, n_2 . a_B; n_k normal to A's axis, a_B A's axis as seen in B at the start)
//   crossed axes: angle (u_A . u_B - its start value)
//   frozen orientation: angle rows (e_1 . f_2, e_2 . f_3, e_3 . f_1), e_k A's axes, f_k their images in B at the
//   start (so that C = 0 there and the three rows are independent).
//   double hinge (A turns a massless link K about a_1 through o_1, K turns B about a_2 through o_2; a_1, o_1, a_2
//   and o_2 are all fixed in K, d = o_2 - o_1): distance (|d|) + line (a_1 . d, normal a_1 on A) + line (a_2 . d
//   from B's side, normal a_2 on B) + angle (a_1 . a_2), each as at the start. These four invariants of K are
//   independent unless the axis lines meet (then the joint is a universal at their meeting point; the scene
//   reader refuses it); with parallel axes the last two are replaced by the hinge's two common-axis rows. Locally
//   their zero set is the link's two-parameter family of relative poses: it contains it, and has its dimension.
// Every row touches at most two bodies, so J is stored as two BodyVector blocks per row: the sparse structure is
// explicit.
#pragma once

#include <vector>

#include "tether/dynamics/constraints/contact_features.h"
#include "tether/dynamics/constraints/joint_coordinates.h"
#include "tether/dynamics/model/kinematics.h"

namespace tether {

// A double hinge whose unit axes are closer to parallel than this at the start (the sine of the angle between
// them) takes the parallel form of its rows (above), whose common-axis rows hold A's axis as seen in B.
inline constexpr double kParallelAxes = 1e-6;

template <typename T>
struct ConstraintRow {
  T value = T(0.0);  // C_i(q): metres for points and lengths, the sine of an angle for angle rows
  T bias = T(0.0);   // Jdot_i v
  BodyVector<T> a;   // J_i restricted to the first body
  BodyVector<T> b;   // J_i restricted to the second body
};

// A row's law (docs/architecture.md, principle 4): an equality C = 0, or a one-sided gap g >= 0 whose multiplier may
// push, never pull.
enum class RowLaw { kEquality, kGap };

// A row's translational Jacobian blocks where they are known before any evaluation, so that the assembly of S
// skips their products (schur_system.h): zero on both bodies (angle rows), or a point row's world axis e_k
// (-e_k on the first body, +e_k on the second). kEvaluated: whatever the evaluation gives.
enum class RowTranslation : signed char { kEvaluated, kZero, kAxisX, kAxisY, kAxisZ };
inline RowTranslation AxisTranslation(int k) {
  return static_cast<RowTranslation>(static_cast<int>(RowTranslation::kAxisX) + k);
}
inline int TranslationAxis(RowTranslation translation) {  // k for kAxisX + k
  return static_cast<int>(translation) - static_cast<int>(RowTranslation::kAxisX);
}

// The kind of primitive a row comes from, in the order rows are laid out (ConstraintSet); kSlip: a sticking
// contact's slip rows.
enum class RowPrimitive : signed char { kDistance, kPoint, kLine, kAngle, kUser, kLimit, kContact, kSlip };

// What is known about a row before any evaluation: the constraint it belongs to, the bodies it touches, its law
// and its translational Jacobian. Rows of one primitive are consecutive; `part` counts the primitives, so that a
// constraint's violation is the largest norm over its primitives (metres and radians are not added).
struct RowInfo {
  int scene_index = 0;
  int body_a = kWorld;
  int body_b = kWorld;
  int part = 0;
  RowLaw law = RowLaw::kEquality;
  RowTranslation translation = RowTranslation::kEvaluated;
  RowPrimitive kind = RowPrimitive::kUser;  // the primitive the row comes from
  int primitive = 0;                        // its index among the set's (or the model's) primitives of that kind
};

template <typename T>
struct DistancePrimitive {
  int scene_index = 0;
  BodyPoint<T> a, b;
  T length = T(1.0);
};

template <typename T>
struct PointPrimitive {
  int scene_index = 0;
  BodyPoint<T> a, b;
};

template <typename T>
struct LinePrimitive {
  int scene_index = 0;
  BodyPoint<T> a, b;
  int rows = 0;
  Vec3<T> normals[2] = {Zero3<T>(), Zero3<T>()};  // unit, in A's frame
  T offsets[2] = {T(0.0), T(0.0)};  // c_k, m
};

template <typename T>
struct AnglePrimitive {
  int scene_index = 0;
  int body_a = kWorld, body_b = kWorld;
  int rows = 0;
  Vec3<T> u[3], w[3];  // unit, in A's and in B's frame
  T c[3];
};

// One side of a joint's range: the gap g = side (coordinate - bound) >= 0.
template <typename T>
struct LimitPrimitive {
  int scene_index = 0;
  int body_a = kWorld, body_b = kWorld;
  CoordinateReference<T> coordinate;  // the joint's coordinate (joint_coordinates.h)
  int side = 1;                       // +1: the low bound, -1: the high one
  T bound = T(0.0);                   // rad or m
};

// How an active contact's friction acts (contact_friction.h): not at all (mu = 0), holding it (d - 1 more rows), or
// against its slip (the normal row's force turned by mu).
enum class Friction : char { kNone, kStick, kSlide };

// An active contact feature: the gap g >= 0 between two shapes (contact_geometry.h), and its friction.
struct ContactPrimitive {
  int scene_index = 0;  // model.NumConstraints() + the pair's index: past the constraints (DescribeConstraint)
  int body_a = kWorld, body_b = kWorld;
  ContactFeature feature;
  Friction friction = Friction::kNone;
  Vec3<double> held_slip = Vec3<double>::Zero();  // kSlide: the direction held where the slip is too slow to give one
};

// A run's constraint primitives, stored by kind; rows are laid out in this order, then the user constraints,
// then the active limits and contacts (set by the run as they engage and release: unilateral_events.h), then the
// slip rows of the sticking contacts.
template <typename T>
struct ConstraintSet {
  std::vector<DistancePrimitive<T>> distances;
  std::vector<PointPrimitive<T>> points;
  std::vector<LinePrimitive<T>> lines;
  std::vector<AnglePrimitive<T>> angles;
  std::vector<LimitPrimitive<T>> limits;
  std::vector<ContactPrimitive> contacts;
};

// The primitives of the model's constraints, with the quantities fixed at the start taken at configuration q.
template <typename T>
ConstraintSet<T> BuildConstraintSet(const Model<T>& model, const VecX<T>& q);

// Rows in evaluation order.
template <typename T>
std::vector<RowInfo> DescribeRows(const Model<T>& model, const ConstraintSet<T>& set);

// Fills rows (sized as DescribeRows) at state (q, v), with frames already updated at (q, v). With
// velocity_terms false, `bias` is not computed and v is not read (position-only uses: projection, output).
template <typename T>
void EvaluateConstraintRows(const Model<T>& model, const ConstraintSet<T>& set, const BodyFrames<T>& frames,
                            const VecX<T>& q, const VecX<T>& v, bool velocity_terms,
                            std::vector<ConstraintRow<T>>* rows);

// The row of an active limit at (q, v), frames updated there: s x' on the joint's coordinate x, its value
// min(g, 0) with g = s (x - bound).
template <typename T>
void EvaluateLimitRow(const Model<T>& model, const LimitPrimitive<T>& limit, const BodyFrames<T>& frames,
                      const VecX<T>& q, const VecX<T>& v, bool velocity_terms, ConstraintRow<T>* row);

// The largest geometric violation over the constraints (per constraint, the largest Euclidean norm over its
// primitives' rows), and the scene index of the constraint where it occurs (-1 when there are none).
struct Violation {
  double largest = 0.0;
  int scene_index = -1;
};
template <typename T>
Violation LargestViolation(const std::vector<RowInfo>& infos, const std::vector<ConstraintRow<T>>& rows);

// Unit normals of an axis: in 2D perp(axis); in 3D two vectors completing the unit axis to a right-handed frame
// (u, n1, n2) (the coordinate axis least aligned with it fixes the first).
template <typename T>
void AxisNormals(int dimension, const Vec3<T>& axis, Vec3<T>* n1, Vec3<T>* n2);

}  // namespace tether
