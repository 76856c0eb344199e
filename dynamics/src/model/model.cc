#include "tether/dynamics/model/model.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string_view>

#include "tether/dynamics/model/errors.h"

namespace tether {
namespace {

// The unit quaternion of a rotation matrix (Shepperd's method: the largest of the four squares first).
Vec4<double> QuaternionOf(const Mat3<double>& R) {
  const double trace = R.trace();
  Vec4<double> q;
  if (trace > R(0, 0) && trace > R(1, 1) && trace > R(2, 2)) {
    const double s = 2.0 * std::sqrt(1.0 + trace);
    q << 0.25 * s, (R(2, 1) - R(1, 2)) / s, (R(0, 2) - R(2, 0)) / s, (R(1, 0) - R(0, 1)) / s;
  } else if (R(0, 0) >= R(1, 1) && R(0, 0) >= R(2, 2)) {
    const double s = 2.0 * std::sqrt(1.0 + R(0, 0) - R(1, 1) - R(2, 2));
    q << (R(2, 1) - R(1, 2)) / s, 0.25 * s, (R(0, 1) + R(1, 0)) / s, (R(0, 2) + R(2, 0)) / s;
  } else if (R(1, 1) >= R(2, 2)) {
    const double s = 2.0 * std::sqrt(1.0 + R(1, 1) - R(0, 0) - R(2, 2));
    q << (R(0, 2) - R(2, 0)) / s, (R(0, 1) + R(1, 0)) / s, 0.25 * s, (R(1, 2) + R(2, 1)) / s;
  } else {
    const double s = 2.0 * std::sqrt(1.0 + R(2, 2) - R(0, 0) - R(1, 1));
    q << (R(1, 0) - R(0, 1)) / s, (R(0, 2) + R(2, 0)) / s, (R(1, 2) + R(2, 1)) / s, 0.25 * s;
  }
  return q / q.norm();
}

// R_BP for a symmetric tensor in body axes: identity when it is diagonal, else its eigenvectors (a proper
// rotation: the third column is the cross product of the first two).
Vec4<double> PrincipalAxes(const Mat3<double>& inertia) {
  const Mat3<double> off = inertia - Mat3<double>(inertia.diagonal().asDiagonal());
  if (off.cwiseAbs().maxCoeff() == 0.0) return Vec4<double>(1, 0, 0, 0);
  const Eigen::SelfAdjointEigenSolver<Mat3<double>> eigen(inertia);
  Mat3<double> R = eigen.eigenvectors();
  R.col(2) = R.col(0).cross(R.col(1));
  return QuaternionOf(R);
}

template <typename T>
int AppendBody(Model<T>* model, Body<T> body, int q_size, int v_size) {
  body.q_offset = model->NumCoordinates();
  body.v_offset = model->NumVelocities();
  body.q_size = q_size;
  body.v_size = v_size;
  const int index = static_cast<int>(model->bodies.size());
  if (body.kind != BodyKind::kParticle) model->rigid_bodies.push_back(index);
  if (body.kind == BodyKind::kRigid3d) model->spatial_bodies.push_back(index);
  model->bodies.push_back(std::move(body));
  return index;
}

}  // namespace

const char* ShapeTypeName(ShapeType type) {
  switch (type) {
    case ShapeType::kSphere:
      return "sphere";
    case ShapeType::kCapsule:
      return "capsule";
    case ShapeType::kBox:
      return "box";
    case ShapeType::kPlane:
      return "plane";
  }
  return "?";
}

std::int64_t StepCount(const SimulationSettings& simulation) {
  const double steps = std::ceil(simulation.duration / simulation.step - 1e-9);
  if (!(steps <= static_cast<double>(kMaxSteps))) return kMaxSteps + 1;  // NaN too
  return std::max<std::int64_t>(1, static_cast<std::int64_t>(steps));
}

void CheckStepCount(const SimulationSettings& simulation, const std::string& where) {
  if (StepCount(simulation) <= kMaxSteps) return;
  std::ostringstream out;
  out << where << ": a duration of " << simulation.duration << " s at a step of " << simulation.step << " s is "
      << simulation.duration / simulation.step << " steps, more than a run may take (" << kMaxSteps << ")";
  throw InputError(out.str());
}

template <typename U>
Model<U> CastModel(const Model<double>& m) {
  Model<U> out;
  out.dimension = m.dimension;
  out.rigid_bodies = m.rigid_bodies;
  out.spatial_bodies = m.spatial_bodies;
  for (const Body<double>& b : m.bodies) {
    Body<U> c;
    c.name = b.name;
    c.kind = b.kind;
    c.mass = U(b.mass);
    c.inertia = U(b.inertia);
    c.inertia_tensor = b.inertia_tensor.cast<U>();
    c.principal_axes = b.principal_axes;
    c.position = b.position.cast<U>();
    c.angle = U(b.angle);
    c.orientation = b.orientation.cast<U>();
    c.velocity = b.velocity.cast<U>();
    c.angular_velocity = b.angular_velocity.cast<U>();
    c.q_offset = b.q_offset;
    c.q_size = b.q_size;
    c.v_offset = b.v_offset;
    c.v_size = b.v_size;
    out.bodies.push_back(std::move(c));
  }
  for (const Joint<double>& j : m.joints) {
    const JointRange<double>& r = j.range;
    out.joints.push_back({j.scene_index,
                          j.type,
                          j.name,
                          j.a.template Cast<U>(),
                          j.b.template Cast<U>(),
                          j.axis.cast<U>(),
                          j.axis_b.cast<U>(),
                          U(j.length),
                          U(j.angle),
                          {r.has_low, r.has_high, U(r.low), U(r.high), U(r.restitution)}});
  }
  out.user_constraints = m.user_constraints;
  for (const Marker<double>& k : m.markers) out.markers.push_back({k.name, k.point.template Cast<U>()});
  for (const Shape<double>& shape : m.shapes) out.shapes.push_back(shape.template Cast<U>());
  out.contact = m.contact.template Cast<U>();
  ForEachEffectList(
      [](auto& to, const auto& from) {
        for (const auto& effect : from) to.push_back(effect.template Cast<U>());
      },
      out, m);
  out.simulation = m.simulation;
  out.stabilization = {m.stabilization.method, U(m.stabilization.alpha), U(m.stabilization.beta),
                       m.stabilization.gains_from_rule};
  return out;
}

template <typename T>
int AddBody(Model<T>* model, const std::string& name, BodyKind kind, const T& mass, const T& inertia,
            const Vec3<T>& position, const T& angle, const Vec3<T>& velocity, const T& angular_velocity) {
  const int d = model->dimension;
  Body<T> body;
  body.name = name;
  body.kind = kind;
  body.mass = mass;
  body.position.head(d) = position.head(d);
  body.velocity.head(d) = velocity.head(d);
  const int size = kind == BodyKind::kPlanar ? 3 : d;
  if (kind == BodyKind::kPlanar) {
    body.inertia = inertia;
    body.angle = angle;
    body.angular_velocity[2] = angular_velocity;
  }
  return AppendBody(model, std::move(body), size, size);
}

template <typename T>
int AddRigidBody3d(Model<T>* model, const std::string& name, const T& mass, const Mat3<T>& inertia,
                   const Vec3<T>& position, const Vec4<T>& orientation, const Vec3<T>& velocity,
                   const Vec3<T>& angular_velocity) {
  Body<T> body;
  body.name = name;
  body.kind = BodyKind::kRigid3d;
  body.mass = mass;
  body.inertia_tensor = inertia;
  Mat3<double> value;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) value(r, c) = Value(inertia(r, c));
  }
  body.principal_axes = PrincipalAxes(value);
  body.position = position;
  body.orientation = orientation;
  body.velocity = velocity;
  body.angular_velocity = angular_velocity;
  return AppendBody(model, std::move(body), 7, 6);
}

template <typename T>
int AddJoint(Model<T>* model, const Joint<T>& joint) {
  model->joints.push_back(joint);
  return static_cast<int>(model->joints.size()) - 1;
}

template <typename T>
int JointIndex(const Model<T>& model, int scene_index) {
  for (size_t k = 0; k < model.joints.size(); ++k) {
    if (model.joints[k].scene_index == scene_index) return static_cast<int>(k);
  }
  return -1;
}

template <typename T>
bool HasCoordinate(const Model<T>& model, const Joint<T>& joint, JointCoordinate coordinate) {
  const JointKind& kind = JointKindOf(joint.type);
  if (coordinate == JointCoordinate::kDisplacement) return HasDisplacement(kind);
  if (kind.coordinates != CoordinateSet::kPlanarAngle) return HasAngle(kind);
  auto planar_or_world = [&model](int body) { return body == kWorld || model.bodies[body].kind == BodyKind::kPlanar; };
  return model.dimension == 2 && planar_or_world(joint.a.body) && planar_or_world(joint.b.body);
}

const JointKind* FindJointKind(std::string_view name) {
  for (const JointKind& kind : kJointKinds) {
    if (name == kind.name) return &kind;
  }
  return nullptr;
}

std::string JointTypeList() {
  std::vector<std::string> names;
  for (const JointKind& kind : kJointKinds) names.push_back(kind.name);
  return ListWithOr(names);
}

#define TETHER_INSTANTIATE_MODEL(T)                                                                              \
  template Model<T> CastModel<T>(const Model<double>&);                                                          \
  template int AddBody<T>(Model<T>*, const std::string&, BodyKind, const T&, const T&, const Vec3<T>&, const T&, \
                          const Vec3<T>&, const T&);                                                             \
  template int AddRigidBody3d<T>(Model<T>*, const std::string&, const T&, const Mat3<T>&, const Vec3<T>&,        \
                                 const Vec4<T>&, const Vec3<T>&, const Vec3<T>&);                                \
  template int AddJoint<T>(Model<T>*, const Joint<T>&);                                                          \
  template int JointIndex<T>(const Model<T>&, int);                                                              \
  template bool HasCoordinate<T>(const Model<T>&, const Joint<T>&, JointCoordinate);
TETHER_FOR_EACH_SCALAR(TETHER_INSTANTIATE_MODEL)

}  // namespace tether
