// The closest features of two shapes' cores, found in double (contact_geometry.h evaluates the gaps from them in
// the run's scalar). A core is what a shape is the points within its radius of: a centre (sphere), a segment along
// the shape's x axis (capsule), a box |x_k| <= h_k (radius 0). In a shape's frame S:
//
//   point and segment  the clamped projection u = clamp((p - a) . (b - a) / |b - a|^2, 0, 1)
//   two segments       Ericson, Real-Time Collision Detection 5.1.9 (the parallel case: the start of the overlap)
//   point and box      x_k = clamp(p_k, -h_k, h_k); a point beyond one face only, or inside or on the box, is
//                      measured against that face's plane instead (inside: the face nearest it, the least
//                      h_k - |p_k|), the outside form's value and first derivative at that face
//   crossed edges      an edge E_A of the first core (a capsule's segment or one of a box's 12 edges) and an edge
//                      E_B of a box whose lines' closest points p_A, p_B lie inside both edges, with the unit normal
//                      n = +-(e_A x e_B) / |e_A x e_B| pointing out of B. The pair is a contact candidate when n
//                      lies in B's outward normal cone at E_B (n . f >= 0 for both faces at the edge) and -n in
//                      A's (a box's; every direction normal to a segment is in its cone); its gap is the separation
//                      of the cores along n, s = n . (p_A - p_B) (then p_A - p_B = s n). Where s >= 0 the cores are
//                      apart, and s is their distance (a distance between points of the surfaces, and no more than
//                      the separation along any axis); where s < 0 the edges have crossed, which is only a contact
//                      with p_A inside B and p_B inside A. The candidate with the largest s is a contact (the
//                      separating-axis rule: the least overlap), and so are the others whose normal is within 30
//                      degrees of its n, in order of decreasing s: a capsule lying across a box's face, or a box
//                      across a box's (a layer of a Jenga tower), touches at several crossings with one normal,
//                      while a crossing along another axis overlaps more and is not where the shapes touch (a
//                      segment sunk into a box's ridge also crosses the ridge's end faces' edges, sideways).
#pragma once

#include <array>
#include <utility>

#include "tether/dynamics/model/kinematics.h"

namespace tether {

// A shape's pose in the world, in double: x_W = origin + rotation x_S.
struct WorldPose {
  Vec3<double> origin = Vec3<double>::Zero();
  Mat3<double> rotation = Mat3<double>::Identity();
  Vec3<double> ToShape(const Vec3<double>& x_W) const { return rotation.transpose() * (x_W - origin); }
  Vec3<double> ToWorld(const Vec3<double>& x_S) const { return origin + rotation * x_S; }
};

// A closest point of a core in its shape's frame: each coordinate either its value (a stationary point of the
// distance: its derivative does not matter) or, where it sits on the core's end or face, the shape's half dimension
// with its sign (on_end), so that the dimension is a parameter of the gap.
struct Witness {
  Vec3<double> x = Vec3<double>::Zero();
  int on_end[3] = {0, 0, 0};  // -1, +1: at the negative or positive half dimension along that axis
};

// The parameter in [-1, 1] of the point of the segment (-1: a, +1: b) closest to p.
double ClosestOnSegment(const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& p);

// The parameters in [0, 1] of the closest points of segments p1 + s d1 and p2 + t d2.
std::pair<double, double> ClosestOfSegments(const Vec3<double>& p1, const Vec3<double>& d1, const Vec3<double>& p2,
                                            const Vec3<double>& d2);

// A capsule's witness at segment parameter u in [-1, 1], and its segment's ends in the world.
Witness CapsuleWitness(double u, double length);
std::pair<Vec3<double>, Vec3<double>> SegmentOf(const WorldPose& pose, double length);

// A box core: its pose, half sizes h (the first `dimension` axes) and dimension.
struct BoxCore {
  WorldPose pose;
  Vec3<double> half = Vec3<double>::Zero();
  int dimension = 3;
};

// What a point x_W is measured against on a box core: a face (axis, sign: the outward unit normal sign e_axis in
// the box's frame) where x_W is beyond the box along that axis only, or inside or on the box (the face nearest
// it); else the clamped point, on an edge or at a corner. A face is a plane, whose gap has an exact second
// derivative; a clamped point slides along its edge as x_W moves, which a row between material points leaves out.
struct BoxPoint {
  bool face = false;
  int axis = 0;
  double sign = 1.0;
  Witness witness;  // not a face: the clamped point
};
BoxPoint ClosestOfBox(const BoxCore& box, const Vec3<double>& x_W);

// The first core of a crossed-edges search: a capsule's segment (length) or a box.
struct EdgeSource {
  bool box = false;
  WorldPose pose;
  Vec3<double> half = Vec3<double>::Zero();  // a box's half sizes
  double length = 0.0;                       // a capsule's
};

// The contact of crossed edges of `first` against box `second` (3D) of the given rank among the candidates (0: the
// largest separation), when there are that many: the witnesses on both edges in their shapes' frames, and n in
// second's frame.
struct CrossedEdges {
  bool found = false;
  Witness on_first, on_second;
  Vec3<double> normal_second = Vec3<double>::Zero();
};
CrossedEdges FindCrossedEdges(const EdgeSource& first, const BoxCore& second, int rank);

// How many crossed-edge contacts a pair carries: a box against a box touches at up to 4 (two faces across each
// other), a capsule against a box at up to 2 (the segment across a face).
inline constexpr int kCrossedEdgesBoxBox = 4, kCrossedEdgesCapsuleBox = 2;
// The cosine of the largest angle between the normals of two crossings of one contact (30 degrees).
inline constexpr double kCrossingsAlong = 0.866;

// Edges closer to parallel than this (the sine of their angle) are not a pair: their lines' closest points are
// ill-conditioned, and the corners at their ends carry their contact.
inline constexpr double kParallelEdges = 1e-3;

}  // namespace tether
