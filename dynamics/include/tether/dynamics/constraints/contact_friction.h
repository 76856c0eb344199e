// Coulomb friction at an active contact feature (docs/contact.md, "Friction"): the contact point, its tangent
// plane and the rows that hold or resist the slip there.
//
// The contact point c lies on the surfaces where they touch, with the normal n along which the gap grows (from
// the row's first body a to its second b, contact_geometry.h):
//   vertex against plane   c = p_b - r n,        c' = v_b(p_b) - r n',   n' = w_a x n
//   closest points         c = p_a + r_a n,      c' = v_a(p_a) + r_a n', n' = (1 - n n^T)(v_b(p_b) - v_a(p_a)) / |d|
// The slip is u = v_b(c) - v_a(c) with v_X(c) = v_X + w_X x (c - x_X), the velocity of the point of body X at c;
// its tangential part u_t = u - n (n . u).
//   sticking   d - 1 rows t_k . u = 0 (t_k an orthonormal basis of the tangent plane: axis_normals of n), held at
//              the velocity level (value 0: there is no position to return to). Where u = 0 their velocity product
//              is  t . (w_b x (c' - v_b) - w_a x (c' - v_a))  (d/dt of v_X(c) = v_X' + w_X' x (c - x_X) +
//              w_X x (c' - v_X)).
//   sliding    the contact's normal force N >= 0 comes with the force mu N against the pair's sliding direction
//              s, so its generalized force is that of the row  s . u  times -mu N: the normal row's force
//              direction is J_n - mu J_s (constrained_dynamics.h solves the KKT system with it). s is one direction
//              for all the contacts of a pair, held over each step (unilateral_events.h): the direction of the
//              pair's mean slip at the step's start where its friction changes the slip by less than the slip
//              itself over the step, else the one held before (at the instant a contact starts to slide: against the
//              force that sticking needed). Coulomb's direction u_t / |u_t| followed within the step would be a stiff
//              equation for the slip across s (a rate mu N / (m |u_t|) that no explicit step resolves as |u_t| goes to
//              zero); held, a straight slide is exact and a curving one first order in the step.
#pragma once

#include "tether/dynamics/constraints/constraint_rows.h"

namespace tether {

// Where an active feature touches, at (q, v) with frames updated there (with `velocities` false v is not read, and
// the velocities are zero).
template <typename T>
struct ContactPoint {
  Vec3<T> normal = Vec3<T>::Zero();          // n, unit, world
  PointMotion<T> on_a, on_b;                 // the points of a and of b at c: arm c - x, velocity v_X(c)
  Vec3<T> point_velocity = Vec3<T>::Zero();  // c'
  int body_a = kWorld, body_b = kWorld;
};
template <typename T>
ContactPoint<T> ContactPointOf(const Model<T>& model, const ContactFeature& feature, const BodyFrames<T>& frames,
                               const VecX<T>& q, const VecX<T>& v, bool velocities);

// The slip u_t at the contact point; in double.
template <typename T>
Vec3<T> SlipOf(const ContactPoint<T>& contact);
template <typename T>
Vec3<double> TangentialSlip(const ContactPoint<T>& contact);

// The row t . u at the contact (t a unit world direction in its tangent plane); with velocity_terms, its velocity
// product where u = 0 (above). Its value is 0.
template <typename T>
void SlipRow(const Model<T>& model, const BodyFrames<T>& frames, const ContactPoint<T>& contact, const Vec3<T>& t,
             bool velocity_terms, ConstraintRow<T>* row);

// The unit tangents t_1 (and t_2 in 3D) of a contact with normal n.
template <typename T>
int Tangents(int dimension, const Vec3<T>& n, Vec3<T> t[2]);

// A slip slower than this (m/s) gives no direction.
inline constexpr double kSlipDirectionSpeed = 1e-8;

// A sliding contact's part of the KKT system: its normal row and mu J_s, the row s . u times its friction
// coefficient (the normal row's force direction is J_n - mu J_s).
template <typename T>
struct SlidingRow {
  int row = 0;
  BodyVector<T> a, b;
};

// The sliding contacts of `set` at (q, v), frames updated there; `rows` is the number of rows of the set
// (DescribeRows), whose contacts' normal rows come before the sticking contacts' slip rows, last.
template <typename T>
void EvaluateSliding(const Model<T>& model, const ConstraintSet<T>& set, const BodyFrames<T>& frames, const VecX<T>& q,
                     const VecX<T>& v, int rows, std::vector<SlidingRow<T>>* sliding);

// The number of slip rows of the sticking contacts in `set`.
template <typename T>
int SlipRowCount(const Model<T>& model, const ConstraintSet<T>& set) {
  int count = 0;
  for (const ContactPrimitive& c : set.contacts) count += c.friction == Friction::kStick ? model.dimension - 1 : 0;
  return count;
}

}  // namespace tether
