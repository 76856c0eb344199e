#include "tether/dynamics/constraints/contact_geometry.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>

#include "tether/dynamics/constraints/constraint_rows_impl.h"
#include "tether/dynamics/constraints/core_witnesses.h"

namespace tether {
namespace {

// How simple a shape's core is: a centre, a segment, a box, a half-space.
int CoreRank(ShapeType type) {
  switch (type) {
    case ShapeType::kSphere:
      return 0;
    case ShapeType::kCapsule:
      return 1;
    case ShapeType::kBox:
      return 2;
    case ShapeType::kPlane:
      break;
  }
  return 3;
}

template <typename T>
int VertexCount(const Shape<T>& shape, int dimension) {
  if (shape.type == ShapeType::kCapsule) return 2;
  if (shape.type == ShapeType::kBox) return 1 << dimension;
  return 1;
}

// Vertex k of a shape's core in its frame S: a sphere's centre, a capsule's cap centre (0: -x, 1: +x), a box's
// corner (bit j of k: the sign along axis j).
template <typename T>
Vec3<T> VertexInShape(const Shape<T>& shape, int k, int dimension) {
  Vec3<T> x = Vec3<T>::Zero();
  if (shape.type == ShapeType::kCapsule) x[0] = T(k == 0 ? -0.5 : 0.5) * shape.length;
  if (shape.type == ShapeType::kBox) {
    for (int j = 0; j < dimension; ++j) x[j] = T((k >> j) & 1 ? 0.5 : -0.5) * shape.size[j];
  }
  return x;
}

// The body point at shape-frame coordinates x_S.
template <typename T>
BodyPoint<T> PointOfShape(const Shape<T>& shape, const Vec3<T>& x_S, int dimension) {
  return {shape.body, Vec3<T>(shape.position + ShapeRotation(shape, dimension) * x_S)};
}

// The line row of vertex point `vertex` (with radius r) against the plane through o_S with outward normal n_S of
// shape `plane` (both in its frame).
template <typename T>
LinePrimitive<T> AgainstPlane(const Shape<T>& plane, const Vec3<T>& o_S, const Vec3<T>& n_S, const BodyPoint<T>& vertex,
                              const T& r, int dimension, int scene_index) {
  LinePrimitive<T> line;
  line.scene_index = scene_index;
  line.a = PointOfShape(plane, o_S, dimension);
  line.b = vertex;
  line.rows = 1;
  line.normals[0] = ShapeRotation(plane, dimension) * n_S;
  line.offsets[0] = r;
  return line;
}

template <typename T>
WorldPose PoseOf(const Model<T>& model, const Shape<T>& shape, const BodyFrames<T>& frames, const VecX<T>& q) {
  const auto value = [](const T& x) { return Value(x); };
  const Mat3<double> R_BS = ShapeRotation(shape, model.dimension).unaryExpr(value);
  const Vec3<double> p_BS = shape.position.unaryExpr(value);
  if (shape.body == kWorld) return {p_BS, R_BS};
  const Body<T>& body = model.bodies[shape.body];
  Vec3<double> x = Vec3<double>::Zero();
  for (int k = 0; k < model.dimension; ++k) x[k] = Value(q[body.q_offset + k]);
  if (body.kind == BodyKind::kParticle) return {x + p_BS, R_BS};
  const Mat3<double> R_WB = frames[shape.body].R_WB.unaryExpr(value);
  return {x + R_WB * p_BS, R_WB * R_BS};
}

template <typename T>
Vec3<T> WitnessInShape(const Shape<T>& shape, const Witness& w) {
  Vec3<T> x = w.x.cast<T>();
  for (int j = 0; j < 3; ++j) {
    if (!w.on_end[j]) continue;
    const T half = shape.type == ShapeType::kCapsule ? T(0.5) * shape.length : T(0.5) * shape.size[j];
    x[j] = T(static_cast<double>(w.on_end[j])) * half;
  }
  return x;
}

}  // namespace

template <typename T>
ContactGeometry BuildContactGeometry(const Model<T>& model) {
  ContactGeometry geometry;
  std::set<std::pair<int, int>> apart;  // body pairs that never touch, smaller index first
  const auto never = [&apart](int a, int b) { apart.insert({std::min(a, b), std::max(a, b)}); };
  for (const Joint<T>& joint : model.joints) never(joint.a.body, joint.b.body);
  for (const UserConstraintInstance& c : model.user_constraints) never(c.body_a, c.body_b);
  for (const auto& [a, b] : model.contact.exclude) never(a, b);
  const std::vector<Shape<T>>& shapes = model.shapes;
  geometry.pair_of.assign(shapes.size() * shapes.size(), -1);
  for (size_t i = 0; i < shapes.size(); ++i) {
    for (size_t j = i + 1; j < shapes.size(); ++j) {
      const Shape<T>&si = shapes[i], &sj = shapes[j];
      if (!si.contact || !sj.contact || si.body == sj.body) continue;
      if (apart.count({std::min(si.body, sj.body), std::max(si.body, sj.body)})) continue;
      const bool i_first = CoreRank(si.type) <= CoreRank(sj.type);
      const int first = static_cast<int>(i_first ? i : j), second = static_cast<int>(i_first ? j : i);
      const ShapeType low = shapes[first].type, high = shapes[second].type;
      if (low == ShapeType::kPlane) continue;  // two planes: no floor between them
      const int pair = static_cast<int>(geometry.pairs.size());
      const auto vertices = [&](GapForm form, int of, int against) {
        for (int k = 0; k < VertexCount(shapes[of], model.dimension); ++k) {
          geometry.features.push_back({pair, form, of, against, k});
        }
      };
      if (high == ShapeType::kPlane) {
        vertices(GapForm::kVertexPlane, first, second);
      } else if (high == ShapeType::kBox) {
        vertices(GapForm::kVertexBox, first, second);
        if (low == ShapeType::kCapsule) vertices(GapForm::kVertexSegment, second, first);
        if (low == ShapeType::kBox) vertices(GapForm::kVertexBox, second, first);
        const int crossings = low == ShapeType::kBox ? kCrossedEdgesBoxBox : kCrossedEdgesCapsuleBox;
        for (int k = 0; low != ShapeType::kSphere && model.dimension == 3 && k < crossings; ++k) {
          geometry.features.push_back({pair, GapForm::kCrossedEdges, first, second, k});  // k: the rank
        }
      } else {
        geometry.features.push_back({pair, GapForm::kClosest, first, second, 0});
      }
      geometry.pair_of[i * shapes.size() + j] = pair;
      geometry.pairs.push_back({static_cast<int>(i), static_cast<int>(j), si.label + "|" + sj.label});
    }
  }
  return geometry;
}

template <typename T>
void NearPairs(const Model<T>& model, const ContactGeometry& geometry, const BodyFrames<T>& frames, const VecX<T>& q,
               double margin, std::vector<char>* near) {
  near->assign(geometry.pairs.size(), 0);
  const std::vector<Shape<T>>& shapes = model.shapes;
  const size_t n = shapes.size();
  struct Bound {
    Vec3<double> centre;
    double radius;
    int shape;
  };
  std::vector<Bound> spheres;
  std::vector<std::pair<int, WorldPose>> planes;
  for (size_t k = 0; k < n; ++k) {
    const Shape<T>& shape = shapes[k];
    if (!shape.contact) continue;
    const WorldPose pose = PoseOf(model, shape, frames, q);
    if (shape.type == ShapeType::kPlane) {
      planes.emplace_back(static_cast<int>(k), pose);
      continue;
    }
    double radius = Value(CoreRadius(shape));
    if (shape.type == ShapeType::kCapsule) radius += 0.5 * Value(shape.length);
    if (shape.type == ShapeType::kBox) radius = 0.5 * shape.size.unaryExpr([](const T& x) { return Value(x); }).norm();
    spheres.push_back({pose.origin, radius + margin, static_cast<int>(k)});
  }
  const auto mark = [&](int a, int b) {
    const int pair = geometry.pair_of[std::min(a, b) * n + std::max(a, b)];
    if (pair >= 0) (*near)[pair] = 1;
  };
  const int d = model.dimension;
  for (const auto& [plane, pose] : planes) {
    const Vec3<double> normal = pose.rotation.col(d == 3 ? 2 : 1);
    for (const Bound& sphere : spheres) {
      if (normal.dot(sphere.centre - pose.origin) <= sphere.radius) mark(plane, sphere.shape);
    }
  }
  std::sort(spheres.begin(), spheres.end(),
            [](const Bound& a, const Bound& b) { return a.centre.x() - a.radius < b.centre.x() - b.radius; });
  for (size_t i = 0; i < spheres.size(); ++i) {
    for (size_t j = i + 1; j < spheres.size(); ++j) {
      const Bound &a = spheres[i], &b = spheres[j];
      if (b.centre.x() - b.radius > a.centre.x() + a.radius) break;  // and every sphere after b
      if ((a.centre - b.centre).norm() <= a.radius + b.radius) mark(a.shape, b.shape);
    }
  }
}

namespace {

// The larger of two shapes' values of one law (each the shape's own where it gives one, else the scene's default).
template <typename T>
T Larger(const Model<T>& model, int shape_a, int shape_b, T Shape<T>::*value, bool Shape<T>::*given,
         T ContactSettings<T>::*fallback) {
  const Shape<T>&a = model.shapes[shape_a], &b = model.shapes[shape_b];
  const T x = a.*given ? a.*value : model.contact.*fallback, y = b.*given ? b.*value : model.contact.*fallback;
  return Value(x) >= Value(y) ? x : y;
}

}  // namespace

template <typename T>
T PairFriction(const Model<T>& model, int shape_a, int shape_b) {
  return Larger(model, shape_a, shape_b, &Shape<T>::friction, &Shape<T>::gives_friction, &ContactSettings<T>::friction);
}

template <typename T>
T PairRestitution(const Model<T>& model, int shape_a, int shape_b) {
  return Larger(model, shape_a, shape_b, &Shape<T>::restitution, &Shape<T>::gives_restitution,
                &ContactSettings<T>::restitution);
}

namespace {

// The direction in its body's frame along which a witness slides as the other shape moves: a capsule's axis where
// the witness is inside its segment, a box's free axis where it is on an edge (3D); zero at a centre or a corner.
template <typename T>
Vec3<T> SlideOf(const Shape<T>& shape, const Witness& w, int d) {
  int axis = -1;
  if (shape.type == ShapeType::kCapsule && !w.on_end[0]) axis = 0;
  if (shape.type == ShapeType::kBox && d == 3 &&
      std::abs(w.on_end[0]) + std::abs(w.on_end[1]) + std::abs(w.on_end[2]) == 2) {
    for (int j = 0; j < 3; ++j) axis = w.on_end[j] ? axis : j;
  }
  if (axis < 0) return Zero3<T>();
  return ShapeRotation(shape, d) * Vec3<T>::Unit(axis);
}

// The half sizes of a box shape, in double.
template <typename T>
BoxCore CoreOfBox(const Shape<T>& box, const WorldPose& pose, int dimension) {
  return {pose, Vec3<double>(0.5 * box.size.unaryExpr([](const T& x) { return Value(x); })), dimension};
}

// The gap of the point x_S of shape `of` (at x_W in the world, with radius r) against box `box`.
template <typename T>
GapPrimitive<T> PointAgainstBox(const Shape<T>& of, const Vec3<T>& x_S, const Vec3<double>& x_W, const T& r,
                                const Shape<T>& box, const WorldPose& box_pose, int d, int scene_index) {
  const BoxPoint closest = ClosestOfBox(CoreOfBox(box, box_pose, d), x_W);
  const BodyPoint<T> point = PointOfShape(of, x_S, d);
  GapPrimitive<T> gap;
  if (closest.face) {
    const Vec3<T> n_S = T(closest.sign) * Vec3<T>::Unit(closest.axis);
    gap.line = true;
    gap.plane = AgainstPlane(box, Vec3<T>(n_S * (T(0.5) * box.size[closest.axis])), n_S, point, r, d, scene_index);
    return gap;
  }
  gap.distance = {scene_index, PointOfShape(box, WitnessInShape(box, closest.witness), d), point, r};
  gap.slide_a = SlideOf(box, closest.witness, d);
  return gap;
}

}  // namespace

template <typename T>
GapPrimitive<T> MeasureFeature(const Model<T>& model, const ContactFeature& feature, const BodyFrames<T>& frames,
                               const VecX<T>& q) {
  const int d = model.dimension;
  const int scene_index = model.NumConstraints() + feature.pair;
  const Shape<T>&first = model.shapes[feature.first], &second = model.shapes[feature.second];
  GapPrimitive<T> gap;
  if (feature.form == GapForm::kVertexPlane) {
    const Vec3<T> normal_S = d == 3 ? Vec3<T>::UnitZ() : Vec3<T>::UnitY();
    gap.line = true;
    gap.plane = AgainstPlane(second, Vec3<T>(Vec3<T>::Zero()), normal_S,
                             PointOfShape(first, VertexInShape(first, feature.vertex, d), d), CoreRadius(first), d,
                             scene_index);
    return gap;
  }
  const WorldPose pose_a = PoseOf(model, first, frames, q), pose_b = PoseOf(model, second, frames, q);
  const auto value = [](const T& x) { return Value(x); };
  if (feature.form == GapForm::kVertexBox) {
    const Vec3<T> x_S = VertexInShape(first, feature.vertex, d);
    return PointAgainstBox(first, x_S, pose_a.ToWorld(x_S.unaryExpr(value)), CoreRadius(first), second, pose_b, d,
                           scene_index);
  }
  Witness wa, wb;
  if (feature.form == GapForm::kCrossedEdges) {
    const EdgeSource source{first.type == ShapeType::kBox, pose_a, Vec3<double>(0.5 * first.size.unaryExpr(value)),
                            Value(first.length)};
    const CrossedEdges edges = FindCrossedEdges(source, CoreOfBox(second, pose_b, d), feature.vertex);
    if (edges.found) {
      gap.line = true;
      gap.plane = AgainstPlane(second, WitnessInShape(second, edges.on_second), Vec3<T>(edges.normal_second.cast<T>()),
                               PointOfShape(first, WitnessInShape(first, edges.on_first), d), CoreRadius(first), d,
                               scene_index);
      gap.slide_a = SlideOf(second, edges.on_second, d);  // the two edges, whose cross product turns n
      gap.slide_b = SlideOf(first, edges.on_first, d);
      return gap;
    }
    gap.distance = {scene_index, PointOfShape(second, Vec3<T>(Vec3<T>::Zero()), d),
                    PointOfShape(first, Vec3<T>(Vec3<T>::Zero()), d), T(0.0)};  // apart: the origins' distance
    return gap;
  }
  if (feature.form == GapForm::kVertexSegment) {  // a box's corner: every coordinate its half size
    for (int j = 0; j < d; ++j) wa.on_end[j] = (feature.vertex >> j) & 1 ? 1 : -1;
    const auto [a, b] = SegmentOf(pose_b, Value(second.length));
    const Vec3<double> corner = pose_a.ToWorld(VertexInShape(first, feature.vertex, d).unaryExpr(value));
    wb = CapsuleWitness(ClosestOnSegment(a, b, corner), Value(second.length));
  } else if (first.type == ShapeType::kCapsule) {  // two capsules
    const auto [a1, b1] = SegmentOf(pose_a, Value(first.length));
    const auto [a2, b2] = SegmentOf(pose_b, Value(second.length));
    const auto [s, t] = ClosestOfSegments(a1, b1 - a1, a2, b2 - a2);
    wa = CapsuleWitness(2.0 * s - 1.0, Value(first.length));
    wb = CapsuleWitness(2.0 * t - 1.0, Value(second.length));
  } else if (second.type == ShapeType::kCapsule) {  // a sphere's centre and a capsule's segment
    const auto [a, b] = SegmentOf(pose_b, Value(second.length));
    wb = CapsuleWitness(ClosestOnSegment(a, b, pose_a.origin), Value(second.length));
  }  // two spheres: their centres
  gap.distance.scene_index = scene_index;
  gap.distance.a = PointOfShape(second, WitnessInShape(second, wb), d);
  gap.distance.b = PointOfShape(first, WitnessInShape(first, wa), d);
  gap.distance.length = CoreRadius(first) + CoreRadius(second);
  gap.slide_a = SlideOf(second, wb, d);
  gap.slide_b = SlideOf(first, wa, d);
  return gap;
}

namespace {

// A body-frame direction in the world, and a body's angular velocity (a particle's and the world's: none).
template <typename T>
Vec3<T> BodyToWorld(const Model<T>& model, const BodyFrames<T>& frames, int body, const Vec3<T>& x_B) {
  return body == kWorld || model.bodies[body].kind == BodyKind::kParticle ? x_B : Vec3<T>(frames[body].R_WB * x_B);
}

template <typename T>
Vec3<T> SpinOf(const Model<T>& model, const BodyFrames<T>& frames, int body) {
  return body == kWorld || model.bodies[body].kind == BodyKind::kParticle ? Zero3<T>() : frames[body].w_W;
}

// - m^T H^-1 m of the witnesses' slide (contact_geometry.h), at (q, v) with frames updated there.
template <typename T>
T SlideCorrection(const Model<T>& model, const BodyFrames<T>& frames, const GapPrimitive<T>& gap, const VecX<T>& q,
                  const VecX<T>& v) {
  const bool on_a = Value(gap.slide_a.squaredNorm()) > 0.0, on_b = Value(gap.slide_b.squaredNorm()) > 0.0;
  if (!on_a && !on_b) return T(0.0);
  const DistancePrimitive<T>& c = gap.distance;
  const PointMotion<T> pa = MovePoint(model, frames, c.a, q, v, true), pb = MovePoint(model, frames, c.b, q, v, true);
  const Segment<T> segment = Between(pa, pb);
  const Vec3<T> dv = pb.velocity - pa.velocity;
  const Vec3<T> u = BodyToWorld(model, frames, c.a.body, gap.slide_a);
  const Vec3<T> w = BodyToWorld(model, frames, c.b.body, gap.slide_b);
  const T m_a =
      on_a ? T(-u.dot(dv) * segment.inverse_length - segment.n.dot(SpinOf(model, frames, c.a.body).cross(u))) : T(0.0);
  const T m_b =
      on_b ? T(w.dot(dv) * segment.inverse_length + segment.n.dot(SpinOf(model, frames, c.b.body).cross(w))) : T(0.0);
  const T cosine = on_a && on_b ? T(u.dot(w)) : T(0.0), sine2 = T(1.0) - cosine * cosine;
  if (Value(sine2) < kParallelEdges * kParallelEdges) return T(0.0);  // parallel segments: no unique witnesses
  return -segment.length * (m_a * m_a + T(2.0) * cosine * m_a * m_b + m_b * m_b) / sine2;
}

// The turn of a crossed edges' normal that its line row leaves out (contact_geometry.h), at (q, v) with frames
// updated there: n = c / |c| with c = +-(e_1 x e_2) of the two edges' world directions, while the row turns n with
// its first body only (n_f' = w_1 x n). With d = x_2 - x_1 = (n . d) n, and n . n'' = -|n'|^2 for a unit vector,
//   g'' - (the row's) = 2 (n' - n_f') . d' + (n . d) (|n_f'|^2 - |n'|^2),
//   n' = (I - n n^T) c' / |c|,   c' = (w_1 x e_1) x e_2 + e_1 x (w_2 x e_2).
// Zero for the other line rows, which have no edges.
template <typename T>
T TurnCorrection(const Model<T>& model, const BodyFrames<T>& frames, const GapPrimitive<T>& gap, const VecX<T>& q,
                 const VecX<T>& v) {
  if (!(Value(gap.slide_a.squaredNorm()) > 0.0 && Value(gap.slide_b.squaredNorm()) > 0.0)) return T(0.0);
  const LinePrimitive<T>& line = gap.plane;
  const int body_1 = line.a.body, body_2 = line.b.body;
  const PointMotion<T> p1 = MovePoint(model, frames, line.a, q, v, true),
                       p2 = MovePoint(model, frames, line.b, q, v, true);
  const Vec3<T> n = BodyToWorld(model, frames, body_1, line.normals[0]);
  const Vec3<T> e1 = BodyToWorld(model, frames, body_1, gap.slide_a),
                e2 = BodyToWorld(model, frames, body_2, gap.slide_b);
  const Vec3<T> w1 = SpinOf(model, frames, body_1), w2 = SpinOf(model, frames, body_2);
  const Vec3<T> cross = e1.cross(e2);
  const T sign = Value(cross.dot(n)) < 0.0 ? T(-1.0) : T(1.0);
  const Vec3<T> cross_rate = sign * Vec3<T>(w1.cross(e1).cross(e2) + e1.cross(w2.cross(e2)));
  const Vec3<T> n_rate = (cross_rate - n * n.dot(cross_rate)) / cross.norm();
  const Vec3<T> n_fixed_rate = w1.cross(n);
  const Vec3<T> d = p2.position - p1.position, d_rate = p2.velocity - p1.velocity;
  return T(2.0) * (n_rate - n_fixed_rate).dot(d_rate) + n.dot(d) * (n_fixed_rate.squaredNorm() - n_rate.squaredNorm());
}

}  // namespace

template <typename T>
ConstraintRow<T>* EvaluateContactRow(const Model<T>& model, const ContactFeature& feature, const BodyFrames<T>& frames,
                                     const VecX<T>& q, const VecX<T>& v, bool velocity_terms, ConstraintRow<T>* row) {
  const GapPrimitive<T> gap = MeasureFeature(model, feature, frames, q);
  if (gap.line) {
    internal::EvaluateLineRows(model, frames, gap.plane, q, v, velocity_terms, row);
    if (velocity_terms) row->bias += TurnCorrection(model, frames, gap, q, v);
  } else {
    internal::EvaluateDistanceRow(model, frames, gap.distance, q, v, velocity_terms, row);
    if (velocity_terms) row->bias += SlideCorrection(model, frames, gap, q, v);
  }
  if (!(Value(row->value) < 0.0)) row->value = T(0.0);  // pushes where they overlap, never pulls
  return row + 1;
}

namespace {

// The feature's row at q (value: the gap, unclamped; no velocity product): v is not read.
template <typename T>
ConstraintRow<T> GapRow(const Model<T>& model, const ContactFeature& feature, const BodyFrames<T>& frames,
                        const VecX<T>& q) {
  const GapPrimitive<T> gap = MeasureFeature(model, feature, frames, q);
  ConstraintRow<T> row;
  if (gap.line) {
    internal::EvaluateLineRows(model, frames, gap.plane, q, q, false, &row);
  } else {
    internal::EvaluateDistanceRow(model, frames, gap.distance, q, q, false, &row);
  }
  return row;
}

}  // namespace

template <typename T>
GapAndRate<T> FeatureGap(const Model<T>& model, const ContactFeature& feature, const BodyFrames<T>& frames,
                         const VecX<T>& q, const VecX<T>& v) {
  const ConstraintRow<T> row = GapRow(model, feature, frames, q);
  return {row.value, Dot(model, row.a, v) + Dot(model, row.b, v)};
}

template <typename T>
T FeatureGapValue(const Model<T>& model, const ContactFeature& feature, const BodyFrames<T>& frames, const VecX<T>& q) {
  return GapRow(model, feature, frames, q).value;
}

#define TETHER_INSTANTIATE_CONTACT_GEOMETRY(T)                                                                       \
  template ContactGeometry BuildContactGeometry<T>(const Model<T>&);                                                 \
  template void NearPairs<T>(const Model<T>&, const ContactGeometry&, const BodyFrames<T>&, const VecX<T>&, double,  \
                             std::vector<char>*);                                                                    \
  template T PairFriction<T>(const Model<T>&, int, int);                                                             \
  template T PairRestitution<T>(const Model<T>&, int, int);                                                          \
  template GapPrimitive<T> MeasureFeature<T>(const Model<T>&, const ContactFeature&, const BodyFrames<T>&,           \
                                             const VecX<T>&);                                                        \
  template ConstraintRow<T>* EvaluateContactRow<T>(const Model<T>&, const ContactFeature&, const BodyFrames<T>&,     \
                                                   const VecX<T>&, const VecX<T>&, bool, ConstraintRow<T>*);         \
  template GapAndRate<T> FeatureGap<T>(const Model<T>&, const ContactFeature&, const BodyFrames<T>&, const VecX<T>&, \
                                       const VecX<T>&);                                                              \
  template T FeatureGapValue<T>(const Model<T>&, const ContactFeature&, const BodyFrames<T>&, const VecX<T>&);
TETHER_FOR_EACH_SCALAR(TETHER_INSTANTIATE_CONTACT_GEOMETRY)

}  // namespace tether
