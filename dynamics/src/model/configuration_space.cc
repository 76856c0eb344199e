#include "tether/dynamics/model/configuration_space.h"

#include "tether/dynamics/adjoint/recorded.h"
#include "tether/dynamics/model/elementwise.h"
#include "tether/dynamics/model/rotation.h"

namespace tether {
namespace {

template <typename T>
Vec4<T> PrincipalAxes(const Body<T>& body) {
  return body.principal_axes.template cast<T>();
}

}  // namespace

template <typename T>
TETHER_FLATTEN void Integrate(const Model<T>& model, const VecX<T>& q, const VecX<T>& v, double h, VecX<T>* out) {
  if (model.spatial_bodies.empty()) {  // q and v share one layout (h = 1: h v is v exactly)
    Elementwise(
        out, [h](const auto& x, const auto& y) { return x + h * y; }, q, v);
    return;
  }
  if (RecordedSpatialIntegrate(model, q, v, h, out)) return;
  for (const Body<T>& body : model.bodies) {
    const T* qb = q.data() + body.q_offset;
    const T* vb = v.data() + body.v_offset;
    T* ob = out->data() + body.q_offset;
    if (body.kind != BodyKind::kRigid3d) {
      for (int k = 0; k < body.q_size; ++k) ob[k] = qb[k] + h * vb[k];
      continue;
    }
    for (int k = 0; k < 3; ++k) ob[k] = qb[k] + h * vb[k];
    const Vec3<T> turn_P(T(h) * vb[3], T(h) * vb[4], T(h) * vb[5]);
    const Vec4<T> turned = TurnedOrientation(Vec4<T>(qb[3], qb[4], qb[5], qb[6]), body.principal_axes, turn_P);
    for (int k = 0; k < 4; ++k) ob[3 + k] = turned[k];
  }
}

template <typename T>
void Difference(const Model<T>& model, const VecX<T>& q0, const VecX<T>& q1, VecX<T>* d) {
  if (model.spatial_bodies.empty()) {  // q and v share one layout
    d->noalias() = q1 - q0;
    return;
  }
  for (const Body<T>& body : model.bodies) {
    const T* a = q0.data() + body.q_offset;
    const T* b = q1.data() + body.q_offset;
    T* out = d->data() + body.v_offset;
    if (body.kind != BodyKind::kRigid3d) {
      for (int k = 0; k < body.q_size; ++k) out[k] = b[k] - a[k];
      continue;
    }
    for (int k = 0; k < 3; ++k) out[k] = b[k] - a[k];
    const Vec4<T> relative =
        QuaternionProduct(Conjugate(Vec4<T>(a[3], a[4], a[5], a[6])), Vec4<T>(b[3], b[4], b[5], b[6]));
    const Vec3<T> turn_P = Rotate(Conjugate(PrincipalAxes(body)), Log(relative));
    for (int k = 0; k < 3; ++k) out[3 + k] = turn_P[k];
  }
}

template <typename T>
TETHER_FLATTEN void DexpInv(const Model<T>& model, const VecX<T>& theta, const VecX<T>& v, VecX<T>* k) {
  if (k != &v) *k = v;
  if (model.spatial_bodies.empty()) return;
  if (RecordedSpatialDexpInv(model, theta, k)) return;
  for (const Body<T>& body : model.bodies) {
    if (body.kind != BodyKind::kRigid3d) continue;
    const int r = body.v_offset + 3;
    const Vec3<T> rate = DexpInv(Vec3<T>(theta.template segment<3>(r)), Vec3<T>(v.template segment<3>(r)));
    k->template segment<3>(r) = rate;
  }
}

template <typename T>
Vec3<T> WorldAngularVelocity(const Body<T>& body, const VecX<T>& q, const VecX<T>& v) {
  switch (body.kind) {
    case BodyKind::kParticle:
      return Vec3<T>::Zero();
    case BodyKind::kPlanar:
      return Vec3<T>(T(0.0), T(0.0), v[body.v_offset + 2]);
    case BodyKind::kRigid3d:
      break;
  }
  const Vec4<T> q_WP = QuaternionProduct(Orientation(body, q), PrincipalAxes(body));
  return Rotate(q_WP, Vec3<T>(v.template segment<3>(body.v_offset + 3)));
}

template <typename T>
State<T> InitialState(const Model<T>& model) {
  State<T> s;
  s.q.setZero(model.NumCoordinates());
  s.v.setZero(model.NumVelocities());
  const int d = model.dimension;
  for (const Body<T>& body : model.bodies) {
    s.q.segment(body.q_offset, d) = body.position.head(d);
    s.v.segment(body.v_offset, d) = body.velocity.head(d);
    if (body.kind == BodyKind::kPlanar) {
      s.q[body.q_offset + 2] = body.angle;
      s.v[body.v_offset + 2] = body.angular_velocity[2];
    } else if (body.kind == BodyKind::kRigid3d) {
      const Vec4<T> q_WB = Normalized(body.orientation);
      s.q.template segment<4>(body.q_offset + 3) = q_WB;
      const Vec4<T> q_PW = Conjugate(QuaternionProduct(q_WB, PrincipalAxes(body)));
      s.v.template segment<3>(body.v_offset + 3) = Rotate(q_PW, body.angular_velocity);
    }
  }
  return s;
}

template <typename T>
Model<T> WithInitialState(const Model<T>& model, const VecX<T>& q, const VecX<T>& v) {
  Model<T> out = model;
  const int d = model.dimension;
  for (Body<T>& body : out.bodies) {
    body.position.head(d) = q.segment(body.q_offset, d);
    body.velocity.head(d) = v.segment(body.v_offset, d);
    if (body.kind == BodyKind::kPlanar) {
      body.angle = q[body.q_offset + 2];
      body.angular_velocity[2] = v[body.v_offset + 2];
    } else if (body.kind == BodyKind::kRigid3d) {
      body.orientation = Orientation(body, q);
      body.angular_velocity = WorldAngularVelocity(body, q, v);
    }
  }
  return out;
}

template <typename T>
void ConfigurationRate(BodyKind kind, const Vec4<double>& principal_axes, int q_size, const T* q, const T* v, T* rate,
                       T* second_order) {
  const int translation = kind == BodyKind::kRigid3d ? 3 : q_size;
  for (int k = 0; k < translation; ++k) {
    rate[k] = v[k];
    second_order[k] = T(0.0);
  }
  if (kind != BodyKind::kRigid3d) return;
  // q_WB' = 1/2 q_WB (x) (0, w_B), and with w_B' = 0 its derivative 1/2 q_WB' (x) (0, w_B)
  const Vec3<T> w_B = Rotate(Vec4<T>(principal_axes.template cast<T>()), Vec3<T>(v[3], v[4], v[5]));
  const Vec4<T> spin(T(0.0), w_B[0], w_B[1], w_B[2]);
  const Vec4<T> first = T(0.5) * QuaternionProduct(Vec4<T>(q[3], q[4], q[5], q[6]), spin);
  const Vec4<T> second = T(0.5) * QuaternionProduct(first, spin);
  for (int k = 0; k < 4; ++k) {
    rate[3 + k] = first[k];
    second_order[3 + k] = second[k];
  }
}

#define TETHER_INSTANTIATE_CONFIGURATION_SPACE(T)                                                \
  template void Integrate<T>(const Model<T>&, const VecX<T>&, const VecX<T>&, double, VecX<T>*); \
  template void Difference<T>(const Model<T>&, const VecX<T>&, const VecX<T>&, VecX<T>*);        \
  template void DexpInv<T>(const Model<T>&, const VecX<T>&, const VecX<T>&, VecX<T>*);           \
  template Vec3<T> WorldAngularVelocity<T>(const Body<T>&, const VecX<T>&, const VecX<T>&);      \
  template State<T> InitialState<T>(const Model<T>&);                                            \
  template Model<T> WithInitialState<T>(const Model<T>&, const VecX<T>&, const VecX<T>&);        \
  template void ConfigurationRate<T>(BodyKind, const Vec4<double>&, int, const T*, const T*, T*, T*);
TETHER_FOR_EACH_SCALAR(TETHER_INSTANTIATE_CONFIGURATION_SPACE)

}  // namespace tether
