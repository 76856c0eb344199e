// Model<T>: the immutable description of a scene in maximal coordinates.
//
// Coordinates q stack every body's own coordinates in scene order: a particle has its position (d numbers,
// d = 2 or 3), a planar rigid body has (x, y, angle) of its centre of mass. The mass matrix is therefore
// diagonal: m for each translational coordinate, the inertia I about the centre of mass for an angle.
// Constraints and effects are stored by kind, so evaluation loops run only over what the scene declares.
// Fields mirror the scene file (CONTRACT.md) one to one, which is what lets a JSON Pointer name any of them.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "tether/dynamics/scalar.h"

namespace tether {

class UserConstraint;

enum class BodyKind { kParticle, kRigid };
enum class Integrator { kEuler, kSymplecticEuler, kRk4, kRk45 };
enum class Stabilization { kNone, kBaumgarte, kProjection };
// kAuto is kSparse, the faster path at every size (see schur_solver.h).
enum class KktSolver { kAuto, kDense, kSparse };

// Body index of the fixed ground frame.
inline constexpr int kWorld = -1;

template <typename T>
struct Body {
  std::string name;
  BodyKind kind = BodyKind::kParticle;
  T mass = T(1.0);     // kg, > 0
  T inertia = T(0.0);  // kg m^2 about the centre of mass; planar rigid bodies only
  int offset = 0;      // index of the body's first coordinate in q
  int size = 0;        // d for a particle, 3 (x, y, angle) for a planar rigid body
};

// A point fixed in a body, in body-local coordinates (world coordinates when body == kWorld).
// Components beyond the scene's dimension are zero.
template <typename T>
struct BodyPoint {
  int body = kWorld;
  Vec3<T> local = Vec3<T>::Zero();
};

// |p_B - p_A| = length.
template <typename T>
struct DistanceConstraint {
  int scene_index = 0;
  BodyPoint<T> a, b;
  T length = T(1.0);  // m, > 0
};

// p_B = p_A: a revolute joint in 2D, a ball joint in 3D.
template <typename T>
struct PinConstraint {
  int scene_index = 0;
  BodyPoint<T> a, b;
};

// p_B stays on the line through p_A along `axis` (given in A's frame, any non-zero length).
template <typename T>
struct SliderConstraint {
  int scene_index = 0;
  BodyPoint<T> a, b;
  Vec3<T> axis = Vec3<T>::UnitX();
};

// A constraint given as a residual function of two bodies' coordinates (see user_constraint.h).
struct UserConstraintInstance {
  int scene_index = 0;
  int body_a = kWorld;
  int body_b = kWorld;
  std::shared_ptr<const UserConstraint> residual;
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

// A torque on a planar rigid body: constant `value`, or `schedule` when it is not empty.
template <typename T>
struct TorqueEffect {
  int scene_index = 0;
  int body = 0;
  T value = T(0.0);
  Schedule<T> schedule;
};

struct SimulationSettings {
  Integrator integrator = Integrator::kRk4;
  double step = 1e-3;       // s
  double duration = 1.0;    // s
  double tolerance = 1e-8;  // rk45's local error tolerance (absolute and relative)
  KktSolver solver = KktSolver::kAuto;
};

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
  VecX<T> q0;  // initial coordinates, laid out by Body::offset and Body::size
  VecX<T> v0;  // initial velocities, same layout

  std::vector<DistanceConstraint<T>> distances;
  std::vector<PinConstraint<T>> pins;
  std::vector<SliderConstraint<T>> sliders;
  std::vector<UserConstraintInstance> user_constraints;

  std::vector<GravityEffect<T>> gravity;
  std::vector<DampingEffect<T>> damping;
  std::vector<SpringEffect<T>> springs;
  std::vector<ForceEffect<T>> forces;
  std::vector<TorqueEffect<T>> torques;

  SimulationSettings simulation;
  StabilizationSettings<T> stabilization;

  int NumCoordinates() const { return static_cast<int>(q0.size()); }
  int NumConstraints() const {
    return static_cast<int>(distances.size() + pins.size() + sliders.size() + user_constraints.size());
  }
};

// Model<double> -> Model<U>: every quantity converted, derivatives (if any) zero.
template <typename U>
Model<U> CastModel(const Model<double>& model);

// Appends a body and its initial state; returns its index. `position` holds d numbers, and for a rigid body
// (dimension 2 only) `angle` and `angular_velocity` are used.
template <typename T>
int AddBody(Model<T>* model, const std::string& name, BodyKind kind, const T& mass, const T& inertia,
            const Vec3<T>& position, const T& angle, const Vec3<T>& velocity, const T& angular_velocity);

}  // namespace tether
