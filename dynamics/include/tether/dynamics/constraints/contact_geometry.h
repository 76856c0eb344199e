// The narrow phase: which pairs of shapes may touch (the pair rules) and the gaps g(q) >= 0 between them
// (docs/contact.md). A pair has a fixed list of features, each one gap that is a smooth function of the
// configuration while the pair's shapes stay in one relative arrangement, so that an event on it (an impact, a
// release) can be located by root finding like a joint limit's (unilateral_events.h). A core is what a shape is
// the points within its radius r of (core_witnesses.h: a centre, a segment, a box with r = 0):
//
//   vertex against plane    a sphere's centre, a capsule's two cap centres, a box's 2^d corners, each a point p of
//                           its body with its shape's radius r, against a plane (o, n) of another:
//                             g = n . (p - o) - r                                    (a line row, constraint_rows.h)
//   vertex against box      a sphere's centre, a capsule's cap centres or a box's corners against a box: the box's
//                           point x closest to p, found in double and fixed in the box as a witness, then
//                             g = |p - x| - r                                        (a distance row)
//                           and with p inside the box, against the face nearest it (a vertex against that face's
//                           plane, continuous with the outside form at the face)
//   vertex against segment  a box's corners against a capsule: g = |p - x| - r_capsule, x on its segment
//   closest points          sphere-sphere, sphere-capsule, capsule-capsule: the closest points x_A, x_B of the two
//                           cores, witnesses, then  g = |x_B - x_A| - r_A - r_B
//   crossed edges           (3D) a capsule's segment or a box's edges against a box's: the pair of edges whose
//                           separation along their common normal n is the contact (core_witnesses.h), a line row
//                             g = n . (x_A - x_B) - r_A    (n and x_B fixed in the box B, x_A in A)
//                           and, where no pair of edges touches, the distance of the two shapes' origins (a gap
//                           that stays positive, as that feature is then apart).
// These lists are complete: two convex cores touch at a vertex of one (a corner, a cap centre) or, in 3D, at
// crossed edges; faces and parallel edges touch where their corners do.
//
// The witnesses are found in double and the gap is evaluated from them in the run's scalar (double, Jet, Rev):
// a witness is a closest point, so the distance is stationary in it and the gap's first derivatives (its Jacobian
// row and the derivatives with respect to the parameters) are exact; for crossed edges x_A - x_B is along n, which
// is normal to both edges, so the slide of either witness and the turn of n leave the gap unchanged to first
// order. Where a witness sits on a capsule's end or a box's face or edge its coordinate is the shape's dimension
// itself (size / 2, length / 2), so that dimensions are parameters of the gap. The second derivative of a distance
// row between material points misses the witnesses' slide along their segment or edge: with f(q, s) the distance
// at slide parameters s (unit speed along the directions u_k), g = f(q, s*(q)) and f_s = 0 there, so
//   g'' = f'' - m^T H^-1 m,   m = d/dt f_s at fixed s,   H = f_ss
// (for one witness on the row's first body sliding along u: m = -u . d'/|d| - n . (w_a x u), H = 1/|d|; for two,
// H = [[1, -c], [-c, 1]] / |d| with c = u_a . u_b), which EvaluateContactRow adds to the row's velocity product: a
// ball sliding along a capsule then has the gap acceleration of a point along a line, not of two material points
// drawing apart. Segments closer to parallel than 1e-3 (their witnesses not unique) get no correction. A crossed
// edges' line row turns n with B only; the true n = +-(e_A x e_B)/|e_A x e_B| turns with both edges, and since
// n . (x_A - x_B) is the same for any points of the two lines, that turn is all the row misses:
//   g'' = (the row's) + 2 (n' - n_B') . d' + (n . d) (|n_B'|^2 - |n'|^2),   d = x_A - x_B,  n_B' = w_B x n
// (n . n'' = -|n'|^2 for a unit vector), which EvaluateContactRow adds too.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "tether/dynamics/constraints/constraint_rows.h"
#include "tether/dynamics/constraints/contact_features.h"

namespace tether {

struct ContactGeometry {
  std::vector<ContactPair> pairs;
  std::vector<ContactFeature> features;
  std::vector<int> pair_of;  // shapes a < b -> the index of their pair, or -1: pair_of[a * shapes + b]
};

// The pairs the rules let touch (docs/contract.md: shapes with contact on different bodies, not two world shapes,
// not two bodies joined directly by a constraint, not an excluded pair) and their features. A pair of two planes
// has none (they are unbounded: only a plane of the world is a floor).
template <typename T>
ContactGeometry BuildContactGeometry(const Model<T>& model);

// The broad phase: near[p] = 1 for every pair p whose shapes' bounding spheres (the sphere about a shape's origin
// that holds it: radius r, r + length / 2, half the box's diagonal) overlap at configuration q, frames updated
// there (positions), or, for a plane, whose other shape's sphere reaches below it; 0 otherwise, where every
// feature's gap is then positive. Spheres are swept along the world x axis (sorted by their lowest x), so N shapes
// cost N log N and the pairs whose intervals overlap, not N^2. Each sphere is grown by `margin` (time stepping's
// reach over a step: pairs still apart that may touch within it).
template <typename T>
void NearPairs(const Model<T>& model, const ContactGeometry& geometry, const BodyFrames<T>& frames, const VecX<T>& q,
               double margin, std::vector<char>* near);

// The friction and restitution of the pair of shapes a and b: the larger of the two shapes' (each the shape's own,
// else the scene's default).
template <typename T>
T PairFriction(const Model<T>& model, int a, int b);
template <typename T>
T PairRestitution(const Model<T>& model, int a, int b);

// The primitive that measures a feature's gap at configuration q (frames updated there): a line row (`line` true)
// or a distance row, whose value is the gap. Its first body is second's, its second body first's.
// A distance row's witnesses may slide: along a capsule's segment, or a box's edge (slide_a, slide_b: the unit
// direction in the body frame of the row's first and second body, zero where the witness is a centre or a corner).
template <typename T>
struct GapPrimitive {
  bool line = false;
  LinePrimitive<T> plane;
  DistancePrimitive<T> distance;
  Vec3<T> slide_a = Zero3<T>(), slide_b = Zero3<T>();
};
template <typename T>
GapPrimitive<T> MeasureFeature(const Model<T>& model, const ContactFeature& feature, const BodyFrames<T>& frames,
                               const VecX<T>& q);

// The bodies of a feature's row, as its blocks hold them: (second's, first's).
template <typename T>
std::pair<int, int> FeatureBodies(const Model<T>& model, const ContactFeature& feature) {
  return {model.shapes[feature.second].body, model.shapes[feature.first].body};
}

// The radius of a shape about its core: a sphere's or capsule's, 0 for a box or a plane.
template <typename T>
T CoreRadius(const Shape<T>& shape) {
  return shape.type == ShapeType::kSphere || shape.type == ShapeType::kCapsule ? shape.radius : T(0.0);
}

// The row of an active feature at (q, v), frames updated there: the gap's Jacobian and velocity product, its value
// min(g, 0) (constraint_rows.h). Returns the row after it.
template <typename T>
ConstraintRow<T>* EvaluateContactRow(const Model<T>& model, const ContactFeature& feature, const BodyFrames<T>& frames,
                                     const VecX<T>& q, const VecX<T>& v, bool velocity_terms, ConstraintRow<T>* row);

// A feature's gap g and its rate g' at (q, v), frames updated there (velocities included).
template <typename T>
struct GapAndRate {
  T g, rate;
};
template <typename T>
GapAndRate<T> FeatureGap(const Model<T>& model, const ContactFeature& feature, const BodyFrames<T>& frames,
                         const VecX<T>& q, const VecX<T>& v);
// The gap alone at q, frames updated there (positions only).
template <typename T>
T FeatureGapValue(const Model<T>& model, const ContactFeature& feature, const BodyFrames<T>& frames, const VecX<T>& q);

}  // namespace tether
