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
// Fields mirror the scene file (docs/contract.md) one to one: the scene reader records which JSON Pointer lands in
// which field (scene_reader.h), the parameters are looked up there. The initial state is held as the scene gives
// it (world-frame angular velocity, the quaternion as written), and turned into (q, v) at the start of a run
// (InitialState in configuration_space.h). Constraints and effects are stored by kind, so evaluation loops run
// only over what the scene declares; each effect is a header of its own in effects/ (docs/architecture.md, "Add
// an effect"), and ForEachEffectList below is the one list of them.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "tether/dynamics/constraints/joint_kinds.h"
#include "tether/dynamics/effects/damping.h"
#include "tether/dynamics/effects/drag.h"
#include "tether/dynamics/effects/force.h"
#include "tether/dynamics/effects/gravity.h"
#include "tether/dynamics/effects/joint_servo.h"
#include "tether/dynamics/effects/joint_spring.h"
#include "tether/dynamics/effects/joint_torque.h"
#include "tether/dynamics/effects/spring.h"
#include "tether/dynamics/effects/torque.h"
#include "tether/dynamics/model/bodies.h"
#include "tether/dynamics/model/shapes.h"

namespace tether {

class UserConstraint;

enum class Integrator { kEuler, kSymplecticEuler, kRk4, kRk45 };
enum class Stabilization { kNone, kBaumgarte, kProjection };
// kAuto is kSparse, the faster path at every size, unless the factor is one dense block of a hub body's rows (see
// schur_solver.h).
enum class KktSolver { kAuto, kDense, kSparse };

// A joint's limits on its coordinate (hinge, prismatic, 2D hinge pin): the gaps coordinate - low >= 0 and
// high - coordinate >= 0, each side present or open; Newton's restitution e at an impact on either
// (unilateral_events.h).
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

struct SimulationSettings {
  Integrator integrator = Integrator::kRk4;
  double step = 1e-3;       // s
  double duration = 1.0;    // s
  double tolerance = 1e-8;  // rk45's local error tolerance (absolute and relative)
  KktSolver solver = KktSolver::kAuto;
  ContactMode contact = ContactMode::kEvents;  // how contacts are resolved (docs/contact.md)
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
  std::vector<Shape<T>> shapes;  // in scene order
  ContactSettings<T> contact;

  // the effects, a list per kind (ForEachEffectList below visits them all)
  std::vector<GravityEffect<T>> gravity;
  std::vector<DampingEffect<T>> damping;
  std::vector<SpringEffect<T>> springs;
  std::vector<ForceEffect<T>> forces;
  std::vector<TorqueEffect<T>> torques;
  std::vector<JointTorqueEffect<T>> joint_torques;
  std::vector<JointSpringEffect<T>> joint_springs;
  std::vector<JointServoEffect<T>> joint_servos;
  std::vector<DragEffect<T>> drag;

  SimulationSettings simulation;
  StabilizationSettings<T> stabilization;

  int NumCoordinates() const { return bodies.empty() ? 0 : bodies.back().q_offset + bodies.back().q_size; }
  int NumVelocities() const { return bodies.empty() ? 0 : bodies.back().v_offset + bodies.back().v_size; }
  int NumConstraints() const { return static_cast<int>(joints.size() + user_constraints.size()); }
};

// f(list, ...) for every list of effects of one or more models, the same kind's lists side by side: the one place
// that names them all (casting, forces, energy and the checks below follow from it).
template <typename F, typename... Models>
void ForEachEffectList(F&& f, Models&... models) {
  f(models.gravity...);
  f(models.damping...);
  f(models.springs...);
  f(models.forces...);
  f(models.torques...);
  f(models.joint_torques...);
  f(models.joint_springs...);
  f(models.joint_servos...);
  f(models.drag...);
}

// Whether the scene's energy is conserved by its effects (each says whether it is: no damping of its own or in a
// spring, no applied force, torque or motor). Energy drift measures an integrator's error only then.
template <typename T>
bool ConservesEnergy(const Model<T>& model) {
  bool conserves = true;
  ForEachEffectList(
      [&conserves](const auto& list) {
        for (const auto& effect : list) conserves = conserves && effect.Conservative();
      },
      model);
  return conserves;
}

// Whether any joint has a range (joint limits, unilateral_events.h).
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
