#include "tether/dynamics/model.h"

namespace tether {
namespace {

template <typename U>
Vec3<U> CastVec(const Vec3<double>& v) {
  return v.cast<U>();
}

template <typename U>
BodyPoint<U> CastPoint(const BodyPoint<double>& p) {
  return {p.body, CastVec<U>(p.local)};
}

template <typename U>
Schedule<U> CastSchedule(const Schedule<double>& s) {
  Schedule<U> out{s.times, {}};
  for (double v : s.values) out.values.push_back(U(v));
  return out;
}

template <typename U>
Schedule<Vec3<U>> CastSchedule(const Schedule<Vec3<double>>& s) {
  Schedule<Vec3<U>> out{s.times, {}};
  for (const Vec3<double>& v : s.values) out.values.push_back(CastVec<U>(v));
  return out;
}

}  // namespace

template <typename U>
Model<U> CastModel(const Model<double>& m) {
  Model<U> out;
  out.dimension = m.dimension;
  for (const Body<double>& b : m.bodies) out.bodies.push_back({b.name, b.kind, U(b.mass), U(b.inertia), b.offset, b.size});
  out.q0 = m.q0.cast<U>();
  out.v0 = m.v0.cast<U>();
  for (const auto& c : m.distances) out.distances.push_back({c.scene_index, CastPoint<U>(c.a), CastPoint<U>(c.b), U(c.length)});
  for (const auto& c : m.pins) out.pins.push_back({c.scene_index, CastPoint<U>(c.a), CastPoint<U>(c.b)});
  for (const auto& c : m.sliders) {
    out.sliders.push_back({c.scene_index, CastPoint<U>(c.a), CastPoint<U>(c.b), CastVec<U>(c.axis)});
  }
  out.user_constraints = m.user_constraints;
  for (const auto& e : m.gravity) out.gravity.push_back({e.scene_index, CastVec<U>(e.acceleration)});
  for (const auto& e : m.damping) {
    out.damping.push_back({e.scene_index, U(e.coefficient), U(e.angular_coefficient), e.bodies});
  }
  for (const auto& e : m.springs) {
    out.springs.push_back({e.scene_index, CastPoint<U>(e.a), CastPoint<U>(e.b), U(e.stiffness), U(e.rest_length),
                           U(e.damping)});
  }
  for (const auto& e : m.forces) {
    out.forces.push_back({e.scene_index, e.body, CastVec<U>(e.point), CastVec<U>(e.value), CastSchedule<U>(e.schedule)});
  }
  for (const auto& e : m.torques) out.torques.push_back({e.scene_index, e.body, U(e.value), CastSchedule<U>(e.schedule)});
  out.simulation = m.simulation;
  out.stabilization = {m.stabilization.method, U(m.stabilization.alpha), U(m.stabilization.beta),
                       m.stabilization.gains_from_rule};
  return out;
}

template <typename T>
int AddBody(Model<T>* model, const std::string& name, BodyKind kind, const T& mass, const T& inertia,
            const Vec3<T>& position, const T& angle, const Vec3<T>& velocity, const T& angular_velocity) {
  const int d = model->dimension;
  const int size = kind == BodyKind::kRigid ? 3 : d;
  const int offset = model->NumCoordinates();
  model->bodies.push_back({name, kind, mass, inertia, offset, size});
  model->q0.conservativeResize(offset + size);
  model->v0.conservativeResize(offset + size);
  model->q0.segment(offset, d) = position.head(d);
  model->v0.segment(offset, d) = velocity.head(d);
  if (kind == BodyKind::kRigid) {
    model->q0[offset + 2] = angle;
    model->v0[offset + 2] = angular_velocity;
  }
  return static_cast<int>(model->bodies.size()) - 1;
}

#define TETHER_INSTANTIATE_MODEL(T)                                                                         \
  template Model<T> CastModel<T>(const Model<double>&);                                                     \
  template int AddBody<T>(Model<T>*, const std::string&, BodyKind, const T&, const T&, const Vec3<T>&, const T&, \
                          const Vec3<T>&, const T&);
TETHER_FOR_EACH_SCALAR(TETHER_INSTANTIATE_MODEL)

}  // namespace tether
