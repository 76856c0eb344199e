#include "tether/dynamics/constraints/contact_friction.h"

#include <cmath>

#include "tether/dynamics/constraints/constraint_rows_impl.h"
#include "tether/dynamics/constraints/contact_geometry.h"

namespace tether {
namespace {

// The point of `body` at world position c: its arm c - x and its velocity v + w x (c - x) (a particle's arm is
// zero: it has no rotation).
template <typename T>
PointMotion<T> BodyPointAt(const Model<T>& model, const BodyFrames<T>& frames, int body, const Vec3<T>& c,
                           const VecX<T>& q, const VecX<T>& v, bool velocities) {
  PointMotion<T> m;
  m.position = c;
  if (body == kWorld) return m;
  const Body<T>& b = model.bodies[body];
  if (velocities) m.velocity = Translation(model.dimension, v.data() + b.v_offset);
  if (b.kind == BodyKind::kParticle) return m;
  m.arm = c - Translation(model.dimension, q.data() + b.q_offset);
  if (velocities) m.velocity += frames[body].w_W.cross(m.arm);
  return m;
}

template <typename T>
Vec3<T> AngularVelocity(const Model<T>& model, const BodyFrames<T>& frames, int body) {
  return body == kWorld || model.bodies[body].kind == BodyKind::kParticle ? Vec3<T>(Vec3<T>::Zero()) : frames[body].w_W;
}

}  // namespace

template <typename T>
ContactPoint<T> ContactPointOf(const Model<T>& model, const ContactFeature& feature, const BodyFrames<T>& frames,
                               const VecX<T>& q, const VecX<T>& v, bool velocities) {
  const GapPrimitive<T> gap = MeasureFeature(model, feature, frames, q);
  ContactPoint<T> contact;
  Vec3<T> c;
  if (gap.line) {
    const LinePrimitive<T>& line = gap.plane;
    contact.body_a = line.a.body;
    contact.body_b = line.b.body;
    const PointMotion<T> vertex = MovePoint(model, frames, line.b, q, v, velocities);
    const bool turns = line.a.body != kWorld && model.bodies[line.a.body].kind != BodyKind::kParticle;
    contact.normal = turns ? Vec3<T>(frames[line.a.body].R_WB * line.normals[0]) : line.normals[0];
    const T r = line.offsets[0];
    c = vertex.position - r * contact.normal;
    if (velocities) {
      const Vec3<T> w_a = AngularVelocity(model, frames, line.a.body);
      contact.point_velocity = vertex.velocity - r * w_a.cross(contact.normal);
    }
  } else {
    const DistancePrimitive<T>& distance = gap.distance;
    contact.body_a = distance.a.body;
    contact.body_b = distance.b.body;
    const PointMotion<T> pa = MovePoint(model, frames, distance.a, q, v, velocities);
    const PointMotion<T> pb = MovePoint(model, frames, distance.b, q, v, velocities);
    const Segment<T> segment = Between(pa, pb);
    contact.normal = segment.n;
    const T r_a = CoreRadius(model.shapes[feature.second]);  // the distance row runs from second's core to first's
    c = pa.position + r_a * contact.normal;
    const Vec3<T> dv = pb.velocity - pa.velocity;
    const Vec3<T> turning = (dv - contact.normal * contact.normal.dot(dv)) * segment.inverse_length;
    contact.point_velocity = pa.velocity + r_a * turning;
  }
  contact.on_a = BodyPointAt(model, frames, contact.body_a, c, q, v, velocities);
  contact.on_b = BodyPointAt(model, frames, contact.body_b, c, q, v, velocities);
  return contact;
}

template <typename T>
Vec3<T> SlipOf(const ContactPoint<T>& contact) {
  const Vec3<T> u = contact.on_b.velocity - contact.on_a.velocity;
  return u - contact.normal * contact.normal.dot(u);
}

template <typename T>
Vec3<double> TangentialSlip(const ContactPoint<T>& contact) {
  return SlipOf(contact).unaryExpr([](const T& x) { return Value(x); });
}

template <typename T>
void SlipRow(const Model<T>& model, const BodyFrames<T>& frames, const ContactPoint<T>& contact, const Vec3<T>& t,
             bool velocity_terms, ConstraintRow<T>* row) {
  row->value = T(0.0);
  row->a = PointGradient(model, frames, contact.body_a, Vec3<T>(-t), contact.on_a);
  row->b = PointGradient(model, frames, contact.body_b, t, contact.on_b);
  if (!velocity_terms) return;
  const Vec3<T> w_a = AngularVelocity(model, frames, contact.body_a);
  const Vec3<T> w_b = AngularVelocity(model, frames, contact.body_b);
  const Vec3<T> centre_a = contact.on_a.velocity - w_a.cross(contact.on_a.arm);  // v_X
  const Vec3<T> centre_b = contact.on_b.velocity - w_b.cross(contact.on_b.arm);
  row->bias = t.dot(Vec3<T>(w_b.cross(Vec3<T>(contact.point_velocity - centre_b)) -
                            w_a.cross(Vec3<T>(contact.point_velocity - centre_a))));
}

template <typename T>
int Tangents(int dimension, const Vec3<T>& n, Vec3<T> t[2]) {
  AxisNormals(dimension, n, &t[0], &t[1]);
  return dimension - 1;
}

template <typename T>
void EvaluateSliding(const Model<T>& model, const ConstraintSet<T>& set, const BodyFrames<T>& frames, const VecX<T>& q,
                     const VecX<T>& v, int rows, std::vector<SlidingRow<T>>* sliding) {
  sliding->clear();
  const int first = rows - static_cast<int>(set.contacts.size()) - SlipRowCount(model, set);
  for (size_t k = 0; k < set.contacts.size(); ++k) {
    const ContactPrimitive& c = set.contacts[k];
    if (c.friction != Friction::kSlide) continue;
    const ContactPoint<T> contact = ContactPointOf(model, c.feature, frames, q, v, true);
    const T mu = PairFriction(model, c.feature.first, c.feature.second);
    ConstraintRow<T> row;
    SlipRow(model, frames, contact, Vec3<T>(c.held_slip.cast<T>()), false, &row);
    for (BodyVector<T>* block : {&row.a, &row.b}) {
      block->translation *= mu;
      block->rotation *= mu;
    }
    sliding->push_back({first + static_cast<int>(k), row.a, row.b});
  }
}

#define TETHER_INSTANTIATE_CONTACT_FRICTION(T)                                                                     \
  template ContactPoint<T> ContactPointOf<T>(const Model<T>&, const ContactFeature&, const BodyFrames<T>&,         \
                                             const VecX<T>&, const VecX<T>&, bool);                                \
  template Vec3<double> TangentialSlip<T>(const ContactPoint<T>&);                                                 \
  template void SlipRow<T>(const Model<T>&, const BodyFrames<T>&, const ContactPoint<T>&, const Vec3<T>&, bool,    \
                           ConstraintRow<T>*);                                                                     \
  template int Tangents<T>(int, const Vec3<T>&, Vec3<T>[2]);                                                       \
  template Vec3<T> SlipOf<T>(const ContactPoint<T>&);                                                              \
  template void EvaluateSliding<T>(const Model<T>&, const ConstraintSet<T>&, const BodyFrames<T>&, const VecX<T>&, \
                                   const VecX<T>&, int, std::vector<SlidingRow<T>>*);
TETHER_FOR_EACH_SCALAR(TETHER_INSTANTIATE_CONTACT_FRICTION)

}  // namespace tether
