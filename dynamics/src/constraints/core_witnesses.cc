#include "tether/dynamics/constraints/core_witnesses.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tether {

double ClosestOnSegment(const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& p) {
  const Vec3<double> d = b - a;
  const double dd = d.squaredNorm();
  const double s = dd > 0.0 ? std::clamp((p - a).dot(d) / dd, 0.0, 1.0) : 0.0;
  return 2.0 * s - 1.0;
}

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

Witness CapsuleWitness(double u, double length) {
  Witness w;
  w.x[0] = 0.5 * u * length;
  if (u <= -1.0) w.on_end[0] = -1;
  if (u >= 1.0) w.on_end[0] = 1;
  return w;
}

std::pair<Vec3<double>, Vec3<double>> SegmentOf(const WorldPose& pose, double length) {
  const Vec3<double> half = pose.rotation.col(0) * (0.5 * length);
  return {pose.origin - half, pose.origin + half};
}

BoxPoint ClosestOfBox(const BoxCore& box, const Vec3<double>& x_W) {
  const Vec3<double> c = box.pose.ToShape(x_W);
  BoxPoint closest;
  int beyond = 0;
  double least = std::numeric_limits<double>::infinity();
  for (int j = 0; j < box.dimension; ++j) {
    const double half = box.half[j];
    closest.witness.x[j] = std::clamp(c[j], -half, half);
    const double depth = half - std::abs(c[j]);
    if (depth < 0.0) {
      closest.witness.on_end[j] = c[j] < 0.0 ? -1 : 1;
      ++beyond;
    }
    if (depth < least) {  // the face nearest inside; beyond one face only, that face
      least = depth;
      closest.axis = j;
      closest.sign = c[j] >= 0.0 ? 1.0 : -1.0;
    }
  }
  closest.face = beyond <= 1;
  return closest;
}

namespace {

// An edge of a core in the world, start + s direction for s in [0, 1], with what its witness and its normal cone
// need: the shape axis along it, the signs of the other coordinates and the outward normals of the two faces at
// it (a box's; a segment has none).
struct Edge {
  Vec3<double> start, direction;
  double length = 0.0;
  int axis = 0;
  int signs[3] = {0, 0, 0};
  Vec3<double> faces[2];
};

struct Edges {
  std::array<Edge, 12> edge;
  int count = 0;
};

Edges EdgesOf(const EdgeSource& core) {
  Edges edges;
  if (!core.box) {
    const auto [a, b] = SegmentOf(core.pose, core.length);
    edges.edge[0].start = a;
    edges.edge[0].direction = b - a;
    edges.edge[0].length = core.length;
    edges.count = 1;
    return edges;
  }
  for (int k = 0; k < 3; ++k) {
    const int a = (k + 1) % 3, b = (k + 2) % 3;
    for (int corner = 0; corner < 4; ++corner) {
      Edge& edge = edges.edge[edges.count++];
      edge.axis = k;
      edge.signs[a] = corner & 1 ? 1 : -1;
      edge.signs[b] = corner & 2 ? 1 : -1;
      Vec3<double> start_S = Vec3<double>::Zero();
      start_S[k] = -core.half[k];
      start_S[a] = edge.signs[a] * core.half[a];
      start_S[b] = edge.signs[b] * core.half[b];
      edge.start = core.pose.ToWorld(start_S);
      edge.length = 2.0 * core.half[k];
      edge.direction = core.pose.rotation.col(k) * edge.length;
      edge.faces[0] = core.pose.rotation.col(a) * edge.signs[a];
      edge.faces[1] = core.pose.rotation.col(b) * edge.signs[b];
    }
  }
  return edges;
}

// Whether x_W is inside a box or on its surface (to round-off: a crossing of edges whose normal is one face's lies
// in the plane of the other).
bool Inside(const EdgeSource& core, const Vec3<double>& x_W) {
  const Vec3<double> c = core.pose.ToShape(x_W);
  return (c.array().abs() <= core.half.array() * (1.0 + 1e-9)).all();
}

// The witness at parameter s of an edge.
Witness EdgeWitness(const EdgeSource& core, const Edge& edge, double s) {
  if (!core.box) return CapsuleWitness(2.0 * s - 1.0, core.length);
  Witness w;
  for (int j = 0; j < 3; ++j) {
    w.on_end[j] = edge.signs[j];
    w.x[j] = edge.signs[j] * core.half[j];
  }
  w.x[edge.axis] = (2.0 * s - 1.0) * core.half[edge.axis];
  return w;
}

// The cones hold to round-off: a box lying flat across another has its crossings' normals on the cones' borders.
constexpr double kConeTolerance = 1e-9;

// The sign (+1, -1) that puts +-g in the outward normal cone of a box's edge (both faces' normals within 90 degrees
// of it), g normal to the edge with |g| = size; 0 when neither does.
int ConeSign(const Edge& edge, const Vec3<double>& g, double size) {
  const double x = g.dot(edge.faces[0]), y = g.dot(edge.faces[1]), tolerance = kConeTolerance * size;
  if (x >= -tolerance && y >= -tolerance) return 1;
  if (x <= tolerance && y <= tolerance) return -1;
  return 0;
}

// The crossings of first's edges and box's that are contacts, in order (core_witnesses.h).
struct Crossings {
  struct Candidate {
    double separation, s, t;
    int a, b;
    Vec3<double> n;
  };
  std::array<Candidate, 12 * 12> candidate;
  int count = 0;
  Edges edges_a, edges_b;  // the edges the candidates index
};

Crossings FindCrossings(const EdgeSource& first, const EdgeSource& box) {
  Crossings found;
  found.edges_a = EdgesOf(first);
  found.edges_b = EdgesOf(box);
  const Edges &edges_a = found.edges_a, &edges_b = found.edges_b;
  for (int ia = 0; ia < edges_a.count; ++ia) {
    const Edge& ea = edges_a.edge[ia];
    for (int ib = 0; ib < edges_b.count; ++ib) {
      const Edge& eb = edges_b.edge[ib];
      const Vec3<double> cross = ea.direction.cross(eb.direction);
      const double size = cross.norm();
      if (!(size > kParallelEdges * ea.length * eb.length)) continue;
      const int sign = ConeSign(eb, cross, size);                                    // n in B's cone at eb: out of B
      if (sign == 0 || (first.box && ConeSign(ea, cross, size) != -sign)) continue;  // and -n in A's
      const auto [s, t] = ClosestOfSegments(ea.start, ea.direction, eb.start, eb.direction);
      if (s <= 0.0 || s >= 1.0 || t <= 0.0 || t >= 1.0) continue;  // an end is closest: a corner's contact
      const Vec3<double> pa = ea.start + s * ea.direction, pb = eb.start + t * eb.direction;
      const Vec3<double> n = cross * (sign / size);
      const double separation = n.dot(pa - pb);
      if (separation < 0.0 && !(Inside(box, pa) && (!first.box || Inside(first, pb)))) continue;
      found.candidate[found.count++] = {separation, s, t, ia, ib, n};
    }
  }
  std::stable_sort(found.candidate.begin(), found.candidate.begin() + found.count,
                   [](const auto& x, const auto& y) { return x.separation > y.separation; });
  int along = 0;  // those along the first's normal, in order
  for (int k = 0; k < found.count; ++k) {
    if (found.candidate[k].n.dot(found.candidate[0].n) >= kCrossingsAlong)
      found.candidate[along++] = found.candidate[k];
  }
  found.count = along;
  return found;
}

bool SameCore(const EdgeSource& x, const EdgeSource& y) {
  return x.box == y.box && x.pose.origin == y.pose.origin && x.pose.rotation == y.pose.rotation && x.half == y.half &&
         x.length == y.length;
}

}  // namespace

CrossedEdges FindCrossedEdges(const EdgeSource& first, const BoxCore& second, int rank) {
  const EdgeSource box{true, second.pose, second.half, 0.0};
  // a pair's ranks are asked for in turn at one configuration: the last search is kept (per thread)
  thread_local EdgeSource last_first, last_box;
  thread_local Crossings last;
  thread_local bool searched = false;
  if (!searched || !SameCore(first, last_first) || !SameCore(box, last_box)) {
    last = FindCrossings(first, box);
    last_first = first;
    last_box = box;
    searched = true;
  }
  if (rank >= last.count) return {};
  const Crossings::Candidate& c = last.candidate[rank];
  return {true, EdgeWitness(first, last.edges_a.edge[c.a], c.s), EdgeWitness(box, last.edges_b.edge[c.b], c.t),
          second.pose.rotation.transpose() * c.n};
}

}  // namespace tether
