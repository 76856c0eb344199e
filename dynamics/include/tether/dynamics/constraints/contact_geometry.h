// The narrow phase: which pairs of shapes may touch (the pair rules) and the gaps g(q) >= 0 between them
// (docs/contact.md). A pair has a fixed list of features, each one gap that is a smooth function of the
// configuration while the pair's shapes stay in one relative arrangement, so that an event on it (an impact, a
// release) can be located by root finding like a joint limit's (unilateral_events.h):
//
//   vertex against plane  a sphere's centre, a capsule's two cap centres, a box's 2^d corners, each a point p of
//                         its body with the shape's radius r (0 for a box), against a plane (o, n) of another:
//                           g = n . (p - o) - r                                      (a line row, constraint_rows.h)
//   closest points        sphere-sphere, sphere-capsule, capsule-capsule, sphere-box: the closest points p_A, p_B
//                         of the two cores (centre, segment, box), each found in double and fixed in its body as a
//                         witness, then
//                           g = |p_B - p_A| - r_A - r_B                              (a distance row)
//                         with a sphere's centre inside a box measured against the nearest face instead (a vertex
//                         against that face's plane, continuous with the outside form at the face).
//
// The witnesses are found in double and the gap is evaluated from them in the run's scalar (double, Jet, Rev):
// a witness is a closest point, so the distance is stationary in it and the gap's first derivatives (its Jacobian
// row and the derivatives with respect to the parameters) are exact. Where a witness sits on a capsule's end or a
// box's face its coordinate is the shape's dimension itself (size / 2, length / 2), so that dimensions are
// parameters of the gap. The second derivative misses the witness's slide along the core (the velocity product
// of a distance row between material points): a rolling capsule's row is held by the stabilization there.
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
// has none (they are unbounded: only a plane of the world is a floor). Throws InputError for a pair whose gap is
// not written yet (a capsule or a box against a box), naming both shapes.
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

// The primitive that measures a feature's gap at configuration q (frames updated there): a line row
// (vertex against plane: `line` true) or a distance row, whose value is the gap.
template <typename T>
struct GapPrimitive {
  bool line = false;
  LinePrimitive<T> plane;
  DistancePrimitive<T> distance;
};
template <typename T>
GapPrimitive<T> MeasureFeature(const Model<T>& model, const ContactFeature& feature, const BodyFrames<T>& frames,
                               const VecX<T>& q);

// The bodies of a feature's row, as its blocks hold them: (the plane's, the vertex's) for a vertex against a
// plane, (first's, second's) for closest points.
template <typename T>
std::pair<int, int> FeatureBodies(const Model<T>& model, const ContactFeature& feature) {
  const int first = model.shapes[feature.first].body, second = model.shapes[feature.second].body;
  return feature.form == GapForm::kVertexPlane ? std::pair<int, int>(second, first)
                                               : std::pair<int, int>(first, second);
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
