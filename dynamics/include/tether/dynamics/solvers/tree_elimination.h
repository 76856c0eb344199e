// The KKT system of a tree of 3D rigid bodies, solved body by body in the joints' free directions (Featherstone's
// articulated-body algorithm, written over tether's rows in maximal coordinates).
//
// Each body C of the tree hangs from its parent P (another body, or the world) by the rows of one body pair,
//   J_P a_P + J_C a_C = gamma,     gamma = -(Jdot v + alpha J v + beta C)       (m rows, J_C of rank m <= 6),
// with a = v' over the body's velocities (world translation, rotation in its principal axes). Every a_C that keeps
// them is
//   a_C = T a_P + S qdd + b,       J_C S = 0 (S: 6 x k, k = 6 - m),   J_C T = -J_P,   J_C b = gamma,
// for the k free accelerations qdd. A body's equation M_C a_C = f_C - J_C^T lambda_C - sum over its children c of
// J_Pc^T lambda_c, projected on S, loses its own joint's reaction (S^T J_C^T = 0); a child's reaction on it is
// -J_Pc^T lambda_c = T_c^T J_Cc^T lambda_c = T_c^T (p_c - I_c a_c). So, with I the articulated inertia and p the
// articulated force of a body (its M and f, plus its children's shares):
//   backward, children first:  z = p - I b,   U = I S,   D = S^T U = L L^T,   W = U L^-T,   y = L^-1 S^T z,
//                              I_P += T^T (I - W W^T) T,   p_P += T^T (z - W y)   (nothing for the world);
//   forward, parents first:    qdd = L^-T (y - W^T T a_P),   a_C = T a_P + S qdd + b   (a_P = 0 for the world).
// In exact arithmetic this is the Schur path's acceleration (schur_system.h): the same unique solution of the KKT
// system, in O(bodies) with 6 x 6 blocks and k unknowns a joint instead of m multipliers, and no multipliers at all.
//
// The elimination runs in world-aligned coordinates: a body's angular velocity, acceleration and torque and the
// rotational blocks of its inertia are turned from its principal axes R to the world's (omega_W = R omega,
// I = diag(m 1, R J R^T), and back for a_C at the end), and its joint's rows are taken in the world's axes from their
// primitives (constraint_rows.h), not from the rows the Schur path evaluates. There every joint can take a rigid
// following
//   T = X = [1 -[d]x; 0 1]
// with J_C X = -J_P. For a double hinge, d = c_C - c_P (the bodies' centres of mass): its rows are unchanged by a
// rigid motion of both bodies together. A point part's rows x_C - x_P (the two anchors) turn with such a motion when
// they are not zero, so there d = r_P - r_C, the anchors' arms from their centres, = c_C - c_P - (x_C - x_P), which
// keeps them as evaluated, violated or not; angle rows are unchanged either way. Any other T that keeps the rows
// differs from X by S Z (J_C (X - T) = 0), and (I - W W^T) S = 0, S^T (z - W y) = 0 make the parent's shares and a_C
// the same for both. So I_P += X^T (I - W W^T) X takes cross products with d, p_P gains [f; d x f + tau],
// X a_P = [a - d x alpha; alpha], and a joint needs only S and b, from its child's rows.
//
// The joints it takes are made of a point part (three rows x_b - x_a, translations -e_k on the first body and e_k on
// the second) and 0 to 3 angle rows (no translation): hinges, balls, universal joints and welds. With s = 1 where the
// child is the rows' second body (-1 where it is the first) and r_C the child's anchor from its centre, the point
// rows' rotational blocks on the child are X_C = s [r_C]x^T (row k: s (r_C x e_k)); an angle row u . w (u turning with
// the first body, w with the second) has -s (u x w) there, the rows of Y_C. With c = Y_C^+ gamma_angle
// (Y_C^+ = Y_C^T (Y_C Y_C^T)^-1) and N a basis of Y_C's null space,
//   S = [-s X_C N; N] = [r_C x N; N],   b = [s (gamma_point - X_C c); c] = [s gamma_point + r_C x c; c],
// where gamma_point = -(w_b x (w_b x r_b) - w_a x (w_a x r_a) + beta (x_b - x_a) + alpha (x_b' - x_a')) from the
// anchors' motions (w: the bodies' angular velocities, r: the anchors' arms).
//
// A double hinge's four rows (a distance, two lines whose normals turn with their bodies, one or two angles between
// body-fixed axes) are unchanged by each hinge's screw (its world axis a_i through its world point x_i) moving the
// child alone:
//   S = [a_i x (c_C - x_i); a_i] (i = 1, 2),   b = J_C^T (J_C J_C^T)^-1 gamma (J_C in the world's axes).
// (Lines and distances of other joints keep the Schur path. Served from their rows as they are, with a right inverse
// and a null space of J_C from a QR factorization, then from a Cholesky factorization of J_C J_C^T with general
// 6 x 6 transports, they made humanoid.xml's step 7 to 10% slower than the Schur path's; docs/performance.md, "The
// tree elimination".)
//
// Where a joint's rows are close to dependent (a universal joint near its gimbal lock: a pivot of Y_C Y_C^T, or of a
// double hinge's J_C J_C^T, below kTreePivot times max(1, its largest diagonal)), the evaluation fails and the Schur
// path, which regularizes such rows (schur_solver.h), takes it.
//
// The plan is made once per row layout (SchurShape); a layout is a tree when every body is a 3D rigid body, every
// row is an equality (no active limit or contact), the body pairs that rows join form a forest rooted at the world,
// and each pair's rows are one such joint's: one point primitive's three and all of one angle primitive's, or a
// double hinge's four.
#pragma once

#include <array>
#include <optional>
#include <utility>
#include <vector>

#include "tether/dynamics/constraints/constraint_rows.h"
#include "tether/dynamics/solvers/schur_system.h"

namespace tether {

inline constexpr double kTreePivot = 1e-12;

// One body of the tree and the rows that hang it from its parent.
struct TreeJoint {
  int child = 0;                       // the body
  int parent = kWorld;                 // its parent body, or kWorld
  int parent_joint = -1;               // the parent's index in TreePlan::joints(), -1 for the world
  int child_v = 0;                     // the child's first velocity
  int parent_v = 0;                    // the parent's (unused for the world)
  bool child_second = true;            // the child is its rows' second body (b)
  int angles = 0;                      // angle rows, 0 to 3
  std::array<int, 6> rows{};           // the point rows along x, y and z, then the angle rows
  int double_hinge = -1;               // the model's joint where the rows are a double hinge's four (rows[0..3])
  // the primitives the rows come from, in row order: a point and an angle (none for a ball), or a double hinge's
  // distance, lines and angle; their rows are all the joint's
  std::array<std::pair<RowPrimitive, int>, 4> primitives{};
  int primitive_count = 0;
};

// For each scene index, the model joint with that index when it is a double hinge, -1 for every other constraint:
// how TreePlan::Of tells a double hinge's rows.
template <typename T>
std::vector<int> DoubleHingesByScene(const std::vector<Joint<T>>& joints) {
  std::vector<int> out;
  for (size_t j = 0; j < joints.size(); ++j) {
    if (joints[j].type != JointType::kDoubleHinge) continue;
    const size_t scene = static_cast<size_t>(joints[j].scene_index);
    if (scene >= out.size()) out.resize(scene + 1, -1);
    out[scene] = static_cast<int>(j);
  }
  return out;
}

class TreePlan {
 public:
  // The plan of a row layout, or none when it is not a tree (above).
  static std::optional<TreePlan> Of(const std::vector<RowInfo>& infos, const std::vector<BodyLayout>& layout,
                                    const std::vector<int>& double_hinges);

  const std::vector<TreeJoint>& joints() const { return joints_; }      // parents before their children
  const std::vector<int>& free_bodies() const { return free_bodies_; }  // bodies no row touches: a = M^-1 f

 private:
  std::vector<TreeJoint> joints_;
  std::vector<int> free_bodies_;
};

template <typename T>
using Vec6 = Eigen::Matrix<T, 6, 1>;  // a body's velocities' shape: translation (world), rotation (principal axes)

// What one elimination computes into, per joint (TreeAcceleration sizes it to the plan's joints).
template <typename T>
struct TreeJointWork {
  Eigen::Matrix<T, 6, 6> inertia;     // I, articulated (world-aligned, as above): its lower triangle until eliminated
  Vec6<T> force;                      // p, then z
  Vec3<T> arm;                        // d (X = [1 -[d]x; 0 1])
  int free = 0;                       // k
  Eigen::Matrix<T, 6, 3> directions;  // S
  Eigen::Matrix<T, 6, 3> w;           // W = U L^-T
  Mat3<T> l;                          // L, its diagonal inverted (as Cholesky leaves it)
  Vec3<T> y;                          // y = L^-1 S^T z
  Vec6<T> offset;                     // b
  Vec6<T> acceleration;               // a_C
};

template <typename T>
using TreeWork = std::vector<TreeJointWork<T>>;

// v' for the plan's bodies at (q, v) from the constraint primitives, the frames (updated at (q, v)), the generalized
// force f, the bodies' masses and principal inertias, M^-1 (InverseMass's diagonal and rotational blocks, for the
// bodies no row touches) and the gains; the rows' values C into (*rows)[i].value (their blocks and biases are not
// written). False (with *a untouched) where a joint's rows are close to dependent (above).
template <typename T>
bool TreeAcceleration(const Model<T>& model, const TreePlan& plan, const ConstraintSet<T>& set,
                      const BodyFrames<T>& frames, const std::vector<Mat3<T>>& principal_inertia,
                      const VecX<T>& inverse_diagonal, const std::vector<Mat3<T>>& inverse_rotational, const VecX<T>& q,
                      const VecX<T>& v, const T& alpha, const T& beta, const VecX<T>& force, TreeWork<T>* work,
                      std::vector<ConstraintRow<T>>* rows, VecX<T>* a);

}  // namespace tether
