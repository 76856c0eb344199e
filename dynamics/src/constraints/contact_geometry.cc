#include "tether/dynamics/constraints/contact_geometry.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>

#include "tether/dynamics/constraints/constraint_rows_impl.h"
#include "tether/dynamics/model/errors.h"

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
T Radius(const Shape<T>& shape) {
  return shape.type == ShapeType::kSphere || shape.type == ShapeType::kCapsule ? shape.radius : T(0.0);
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

// A shape's pose in the world at the current state, in double: x_W = origin + rotation x_S.
struct WorldPose {
  Vec3<double> origin;
  Mat3<double> rotation;
  Vec3<double> ToShape(const Vec3<double>& x_W) const { return rotation.transpose() * (x_W - origin); }
};

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

// A closest point of a core in its shape's frame, found in double: each coordinate either its value there (a
// stationary point of the distance: its derivative does not matter) or, where it sits on the core's end or face,
// the shape's half dimension with its sign (so that the dimension is a parameter of the gap).
struct Witness {
  Vec3<double> x = Vec3<double>::Zero();
  int on_end[3] = {0, 0, 0};  // -1, +1: at the negative or positive half dimension along that axis
};

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

// The parameter in [-1, 1] of the point of the segment (-1: a, +1: b) closest to p.
double ClosestOnSegment(const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& p) {
  const Vec3<double> d = b - a;
  const double dd = d.squaredNorm();
  const double s = dd > 0.0 ? std::clamp((p - a).dot(d) / dd, 0.0, 1.0) : 0.0;
  return 2.0 * s - 1.0;
}

// The parameters in [0, 1] of the closest points of segments p1 + s d1 and p2 + t d2 (Ericson, Real-Time Collision
// Detection, 5.1.9); for parallel segments the one with s at the start of their overlap.
std::pair<double, double> ClosestOfSegments(const Vec3<double>& p1, const Vec3<double>& d1, const Vec3<double>& p2,
                                            const Vec3<double>& d2) {
  const Vec3<double> r = p1 - p2;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  if (a <= 0.0 && e <= 0.0) return {0.0, 0.0};
  if (a <= 0.0) return {0.0, std::clamp(f / e, 0.0, 1.0)};
  const double c = d1.dot(r);
  if (e <= 0.0) return {std::clamp(-c / a, 0.0, 1.0), 0.0};
  const double b = d1.dot(d2), denominator = a * e - b * b;
  double s = denominator > 1e-14 * a * e ? std::clamp((b * f - c * e) / denominator, 0.0, 1.0) : 0.0;
  double t = (b * s + f) / e;
  if (t < 0.0) {
    t = 0.0;
    s = std::clamp(-c / a, 0.0, 1.0);
  } else if (t > 1.0) {
    t = 1.0;
    s = std::clamp((b - c) / a, 0.0, 1.0);
  }
  return {s, t};
}

// A capsule's witness at segment parameter u in [-1, 1].
Witness CapsuleWitness(double u, double length) {
  Witness w;
  w.x[0] = 0.5 * u * length;
  if (u <= -1.0) w.on_end[0] = -1;
  if (u >= 1.0) w.on_end[0] = 1;
  return w;
}

// A capsule's segment ends in the world.
std::pair<Vec3<double>, Vec3<double>> SegmentOf(const WorldPose& pose, double length) {
  const Vec3<double> half = pose.rotation.col(0) * (0.5 * length);
  return {pose.origin - half, pose.origin + half};
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
      if (high == ShapeType::kPlane) {
        for (int k = 0; k < VertexCount(shapes[first], model.dimension); ++k) {
          geometry.features.push_back({pair, GapForm::kVertexPlane, first, second, k});
        }
      } else if (low == ShapeType::kSphere || (low == ShapeType::kCapsule && high == ShapeType::kCapsule)) {
        geometry.features.push_back({pair, GapForm::kClosest, first, second, 0});
      } else {
        throw InputError("the shapes /shapes/" + std::to_string(first) + " (" + ShapeTypeName(low) + ") and /shapes/" +
                         std::to_string(second) + " (" + ShapeTypeName(high) +
                         ") may touch, and contact between a capsule or a box and a box is not simulated yet: "
                         "exclude the pair (\"contact\": {\"exclude\": [[A, B]]}) or set \"contact\": false on one");
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
    double radius = Value(Radius(shape));
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

template <typename T>
GapPrimitive<T> MeasureFeature(const Model<T>& model, const ContactFeature& feature, const BodyFrames<T>& frames,
                               const VecX<T>& q) {
  const int d = model.dimension;
  const int scene_index = model.NumConstraints() + feature.pair;
  const Shape<T>&first = model.shapes[feature.first], &second = model.shapes[feature.second];
  GapPrimitive<T> gap;
  const Vec3<T> normal_S = d == 3 ? Vec3<T>::UnitZ() : Vec3<T>::UnitY();
  if (feature.form == GapForm::kVertexPlane) {
    gap.line = true;
    gap.plane =
        AgainstPlane(second, Vec3<T>(Vec3<T>::Zero()), normal_S,
                     PointOfShape(first, VertexInShape(first, feature.vertex, d), d), Radius(first), d, scene_index);
    return gap;
  }
  const WorldPose pose_a = PoseOf(model, first, frames, q), pose_b = PoseOf(model, second, frames, q);
  Witness wa, wb;
  if (first.type == ShapeType::kSphere && second.type == ShapeType::kBox) {
    const Vec3<double> c = pose_b.ToShape(pose_a.origin);  // the sphere's centre in the box's frame
    int deepest = -1;
    double least = 0.0;  // inside: the face nearest the centre
    for (int j = 0; j < d; ++j) {
      const double half = 0.5 * Value(second.size[j]);
      wb.x[j] = std::clamp(c[j], -half, half);
      if (c[j] <= -half) wb.on_end[j] = -1;
      if (c[j] >= half) wb.on_end[j] = 1;
      const double depth = half - std::abs(c[j]);
      if (depth > 0.0 && (deepest < 0 || depth < least)) {
        deepest = j;
        least = depth;
      }
    }
    if (wb.x == c && deepest >= 0) {  // the centre is inside: measured against the nearest face
      const T sign(c[deepest] >= 0.0 ? 1.0 : -1.0);
      const Vec3<T> n_S = sign * Vec3<T>::Unit(deepest);
      gap.line = true;
      gap.plane = AgainstPlane(second, Vec3<T>(n_S * (T(0.5) * second.size[deepest])), n_S,
                               PointOfShape(first, Vec3<T>(Vec3<T>::Zero()), d), first.radius, d, scene_index);
      return gap;
    }
  } else if (first.type == ShapeType::kSphere && second.type == ShapeType::kCapsule) {
    const auto [a, b] = SegmentOf(pose_b, Value(second.length));
    wb = CapsuleWitness(ClosestOnSegment(a, b, pose_a.origin), Value(second.length));
  } else if (first.type == ShapeType::kCapsule) {
    const auto [a1, b1] = SegmentOf(pose_a, Value(first.length));
    const auto [a2, b2] = SegmentOf(pose_b, Value(second.length));
    const auto [s, t] = ClosestOfSegments(a1, b1 - a1, a2, b2 - a2);
    wa = CapsuleWitness(2.0 * s - 1.0, Value(first.length));
    wb = CapsuleWitness(2.0 * t - 1.0, Value(second.length));
  }
  gap.distance.scene_index = scene_index;
  gap.distance.a = PointOfShape(first, WitnessInShape(first, wa), d);
  gap.distance.b = PointOfShape(second, WitnessInShape(second, wb), d);
  gap.distance.length = Radius(first) + Radius(second);
  return gap;
}

template <typename T>
ConstraintRow<T>* EvaluateContactRow(const Model<T>& model, const ContactFeature& feature, const BodyFrames<T>& frames,
                                     const VecX<T>& q, const VecX<T>& v, bool velocity_terms, ConstraintRow<T>* row) {
  const GapPrimitive<T> gap = MeasureFeature(model, feature, frames, q);
  if (gap.line) {
    internal::EvaluateLineRows(model, frames, gap.plane, q, v, velocity_terms, row);
  } else {
    internal::EvaluateDistanceRow(model, frames, gap.distance, q, v, velocity_terms, row);
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
