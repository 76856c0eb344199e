// The names of contact_geometry.h's pairs and features, plain data that the constraint rows hold too.
#pragma once

#include <string>

namespace tether {

// Two shapes that may touch (their indices in model.shapes, in scene order) and their label "A|B".
struct ContactPair {
  int a = 0, b = 0;
  std::string label;
};

// The forms of a gap (contact_geometry.h): a vertex of `first` against the plane `second`, against the box
// `second`, against the capsule `second`'s segment; the closest points of two round cores (sphere, capsule); the
// crossed edges of `first` (a capsule's segment or a box's edges) and of the box `second`.
enum class GapForm { kVertexPlane, kVertexBox, kVertexSegment, kClosest, kCrossedEdges };

// One gap of a pair: its form, its two shapes (the row's first body is second's, its second body first's:
// FeatureBodies) and which of its kind.
struct ContactFeature {
  int pair = 0;
  GapForm form = GapForm::kVertexPlane;
  int first = 0, second = 0;
  int vertex = 0;  // the vertex forms: which vertex of `first`; crossed edges: the rank of the crossing
};

}  // namespace tether
