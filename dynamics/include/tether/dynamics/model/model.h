// Model<T>: the immutable description of a scene in maximal coordinates.
//
// Configuration q and velocity v stack every body's own in scene order, each with its own layout
// (configuration_space.h):
//   particle           q = p_W (d numbers)                      v = p_W' (d)
//   planar rigid body  q = (x, y, theta)                        v = (x', y', theta')
//   3D rigid body      q = (p_WBo, q_WB) (3 + a unit quaternion) v = (p_WBo', w_WB_P) (3 + 3)
// where w_WB_P is the body's angular velocity expressed in its principal axes P. The mass matrix is therefore
// diagonal: m on translation, I on a planar angle, the principal moments on w_WB_P. A full inertia tensor from
// the scene is diagonalised once, at load: R_BP (the principal axes in body axes) is fixed in the model, and
// the tensor, which stays a parameter, is seen in P at the start of every run (constrained_dynamics.h).
//
// Fields mirror the scene file (CONTRACT.md) one to one, which is what lets a JSON Pointer name any of them:
// the initial state is held as the scene gives it (world-frame angular velocity, the quaternion as written),
// and turned into (q, v) at the start of a run (InitialState in configuration_space.h). Constraints and effects
// are stored by kind, so evaluation loops run only over what the scene declares.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "tether/dynamics/constraints/joint_kinds.h"
#include "tether/dynamics/model/scalar.h"

namespace tether {

class UserConstraint;

enum class BodyKind { kParticle, kPlanar, kRigid3d };
enum class Integrator { kEuler, kSymplecticEuler, kRk4, kRk45 };
enum class Stabilization { kNone, kBaumgarte, kProjection };
// kAuto is kSparse, the faster path at every size, unless the factor is one dense block of a hub body's rows (see
// schur_solver.h).
enum class KktSolver { kAuto, kDense, kSparse };

// Body index of the fixed ground frame.
inline constexpr int kWorld = -1;

template <typename T>
struct Body {
  std::string name;
  BodyKind kind = BodyKind::kParticle;
  T mass = T(1.0);                                         // kg, > 0
  T inertia = T(0.0);                                      // planar: kg m^2 about the centre of mass
  Mat3<T> inertia_tensor = Mat3<T>::Zero();                // 3D: kg m^2 about the centre of mass, body axes, symmetric
  Vec4<double> principal_axes = Vec4<double>(1, 0, 0, 0);  // 3D: R_BP, fixed at load (identity when the
                                                           // scene gives principal moments)
  // the initial state as the scene gives it
  Vec3<T> position = Vec3<T>::Zero();                             // m, world (components beyond the dimension are zero)
  T angle = T(0.0);                                               // planar: rad
  Vec4<T> orientation = Vec4<T>(T(1.0), T(0.0), T(0.0), T(0.0));  // 3D: q_WB, normalised at the start of a run
  Vec3<T> velocity = Vec3<T>::Zero();                             // m/s
  Vec3<T> angular_velocity = Vec3<T>::Zero();                     // rad/s, world frame (planar: z only)
  // where the body's numbers sit in q and in v
  int q_offset = 0, q_size = 0;
  int v_offset = 0, v_size = 0;
};

// A point fixed in a body, in body axes from the centre of mass (world coordinates when body == kWorld).
// Components beyond the scene's dimension are zero.
template <typename T>
struct BodyPoint {
  int body = kWorld;
  Vec3<T> local = Vec3<T>::Zero();
};

// A joint's limits on its coordinate (hinge, prismatic, 2D hinge pin): the gaps coordinate - low >= 0 and
// high - coordinate >= 0, each side present or open; Newton's restitution e at an impact on either (limit_events.h).
template <typename T>
struct JointRange {
  bool has_low = false, has_high = false;
  T low = T(0.0), high = T(0.0);  // rad or m
  T restitution = T(0.0);         // 0 <= e <= 1
  bool declared() const { return has_low || has_high; }
};

// A joint of the scene; its type's parts, keys and coordinates are in joint_kinds.h.
template <typename T>
struct Joint {
  int scene_index = 0;
  JointType type = JointType::kPin;
  std::string name;  // empty when the scene names none
  BodyPoint<T> a, b;
  Vec3<T> axis = Vec3<T>::UnitX();    // in A's frame, any non-zero length
  Vec3<T> axis_b = Vec3<T>::UnitY();  // universal, double_hinge: B's axis in B's frame
  T length = T(1.0);                  // distance: m, > 0
  T angle = T(0.0);                   // hinge, cylindrical, 2D hinge pin: the angle coordinate at the start
  JointRange<T> range;                // hinge, prismatic, 2D hinge pin: limits on the coordinate
};

// A constraint given as a residual function of two bodies' coordinates (see user_constraint.h).
struct UserConstraintInstance {
  int scene_index = 0;
  int body_a = kWorld;
  int body_b = kWorld;
  std::shared_ptr<const UserConstraint> residual;
};

// A named point of a body: output columns, data and targets.
template <typename T>
struct Marker {
  std::string name;
  BodyPoint<T> point;
};

// Piecewise linear in time through (times[k], values[k]), held at the end values outside [times.front(),
// times.back()]. Empty means "not scheduled".
template <typename V>
struct Schedule {
  std::vector<double> times;
  std::vector<V> values;
  bool empty() const { return times.empty(); }
};

template <typename T>
struct GravityEffect {
  int scene_index = 0;
  Vec3<T> acceleration = Vec3<T>::Zero();  // m/s^2
};

// Force -c v on every listed body, torque -c_r omega on the rigid ones.
template <typename T>
struct DampingEffect {
  int scene_index = 0;
  T coefficient = T(0.0);          // N s/m
  T angular_coefficient = T(0.0);  // N m s/rad
  std::vector<int> bodies;
};

// Tension k (l - l0) + d l' along the line between the two points, l = |p_B - p_A|.
template <typename T>
struct SpringEffect {
  int scene_index = 0;
  BodyPoint<T> a, b;
  T stiffness = T(0.0);    // N/m
  T rest_length = T(0.0);  // m
  T damping = T(0.0);      // N s/m
};

// A world-frame force applied at a body point: constant `value`, or `schedule` when it is not empty.
template <typename T>
struct ForceEffect {
  int scene_index = 0;
  int body = 0;
  Vec3<T> point = Vec3<T>::Zero();
  Vec3<T> value = Vec3<T>::Zero();
  Schedule<Vec3<T>> schedule;
};

// A world-frame torque on a rigid body (planar: about z, the value in z): constant or scheduled.
template <typename T>
struct TorqueEffect {
  int scene_index = 0;
  int body = 0;
  Vec3<T> value = Vec3<T>::Zero();
  Schedule<Vec3<T>> schedule;
};

// A motor: torque (or force) `value` on B along the joint's coordinate, and its reaction on A.
template <typename T>
struct JointTorqueEffect {
  int scene_index = 0;
  int joint = 0;  // index into Model::joints
  JointCoordinate coordinate = JointCoordinate::kAngle;
  T value = T(0.0);
  Schedule<T> schedule;
};

// -k (coordinate - rest) - d coordinate' along the joint's coordinate.
template <typename T>
struct JointSpringEffect {
  int scene_index = 0;
  int joint = 0;
  JointCoordinate coordinate = JointCoordinate::kAngle;
  T stiffness = T(0.0);  // N m/rad or N/m
  T rest = T(0.0);       // rad or m
  T damping = T(0.0);    // N m s/rad or N s/m
};

struct SimulationSettings {
  Integrator integrator = Integrator::kRk4;
  double step = 1e-3;       // s
  double duration = 1.0;    // s
  double tolerance = 1e-8;  // rk45's local error tolerance (absolute and relative)
  KktSolver solver = KktSolver::kAuto;
};

// A run's number of steps, ceil(duration / step) and at least one, saturating above kMaxSteps: the most a run
// may take (a pendulum needs about an hour for them), beyond which a request is refused up front rather than
// overflowing a count.
inline constexpr std::int64_t kMaxSteps = 1'000'000'000;
std::int64_t StepCount(const SimulationSettings& simulation);
// Throws InputError, naming `where` (a JSON Pointer or the flags), when the settings ask for more than kMaxSteps.
void CheckStepCount(const SimulationSettings& simulation, const std::string& where);

template <typename T>
struct StabilizationSettings {
  Stabilization method = Stabilization::kBaumgarte;
  T alpha = T(0.0);  // 1/s, C'' + alpha C' + beta C = 0
  T beta = T(0.0);   // 1/s^2
  // True when the scene named no gains: alpha and beta then follow DefaultGains() for the integrator and step.
  bool gains_from_rule = true;
};

template <typename T>
struct Model {
  int dimension = 2;
  std::vector<Body<T>> bodies;
  // The indices of the planar and 3D rigid bodies, and of the 3D ones, kept by AddBody and AddRigidBody3d (the
  // only ways to add a body), so that a step visits frames and gyroscopic torques only where there are some.
  std::vector<int> rigid_bodies, spatial_bodies;

  std::vector<Joint<T>> joints;
  std::vector<UserConstraintInstance> user_constraints;
  std::vector<Marker<T>> markers;

  std::vector<GravityEffect<T>> gravity;
  std::vector<DampingEffect<T>> damping;
  std::vector<SpringEffect<T>> springs;
  std::vector<ForceEffect<T>> forces;
  std::vector<TorqueEffect<T>> torques;
  std::vector<JointTorqueEffect<T>> joint_torques;
  std::vector<JointSpringEffect<T>> joint_springs;

  SimulationSettings simulation;
  StabilizationSettings<T> stabilization;

  int NumCoordinates() const { return bodies.empty() ? 0 : bodies.back().q_offset + bodies.back().q_size; }
  int NumVelocities() const { return bodies.empty() ? 0 : bodies.back().v_offset + bodies.back().v_size; }
  int NumConstraints() const { return static_cast<int>(joints.size() + user_constraints.size()); }
};

// Whether the scene's energy is conserved by its effects: no damping (of its own or in a spring), no applied
// force, torque or motor. Energy drift measures an integrator's error only then.
template <typename T>
bool ConservesEnergy(const Model<T>& model) {
  for (const auto& s : model.springs) {
    if (s.damping != T(0.0)) return false;
  }
  for (const auto& s : model.joint_springs) {
    if (s.damping != T(0.0)) return false;
  }
  return model.damping.empty() && model.forces.empty() && model.torques.empty() && model.joint_torques.empty();
}

// Whether any joint has a range (joint limits, limit_events.h).
template <typename T>
bool HasJointLimits(const Model<T>& model) {
  for (const Joint<T>& joint : model.joints) {
    if (joint.range.declared()) return true;
  }
  return false;
}

// Model<double> -> Model<U>: every quantity converted, derivatives (if any) zero.
template <typename U>
Model<U> CastModel(const Model<double>& model);

// Appends a particle or a planar rigid body (model->dimension 2 only) with its initial state; returns its
// index. `angle`, `angular_velocity` and `inertia` are used by planar rigid bodies only.
template <typename T>
int AddBody(Model<T>* model, const std::string& name, BodyKind kind, const T& mass, const T& inertia,
            const Vec3<T>& position, const T& angle, const Vec3<T>& velocity, const T& angular_velocity);

// Appends a 3D rigid body (model->dimension 3) with its inertia tensor about the centre of mass in body axes,
// its orientation q_WB and its world-frame angular velocity; R_BP is worked out from the tensor (identity when
// it is diagonal). Returns its index.
template <typename T>
int AddRigidBody3d(Model<T>* model, const std::string& name, const T& mass, const Mat3<T>& inertia,
                   const Vec3<T>& position, const Vec4<T>& orientation, const Vec3<T>& velocity,
                   const Vec3<T>& angular_velocity);

// Appends a built-in constraint; returns its index in model->joints. scene_index is its position among all
// constraints.
template <typename T>
int AddJoint(Model<T>* model, const Joint<T>& joint);

// The index in model.joints of the constraint with this scene index, or -1.
template <typename T>
int JointIndex(const Model<T>& model, int scene_index);

// Whether a joint has a coordinate (its kind's, joint_kinds.h; a 2D pin's angle only between planar rigid bodies,
// or one and the world).
template <typename T>
bool HasCoordinate(const Model<T>& model, const Joint<T>& joint, JointCoordinate coordinate);

}  // namespace tether
