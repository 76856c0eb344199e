// The names of contact_geometry.h's pairs and features, plain data that the constraint rows hold too.
#pragma once

#include <string>

namespace tether {

// Two shapes that may touch (their indices in model.shapes, in scene order) and their label "A|B".
struct ContactPair {
  int a = 0, b = 0;
  std::string label;
};

enum class GapForm { kVertexPlane, kClosest };

// One gap of a pair. kVertexPlane: vertex `vertex` of shape `first` against the plane `second`; kClosest: the
// closest points of the cores of `first` and `second` (first's core is the simpler: centre, segment, box).
struct ContactFeature {
  int pair = 0;
  GapForm form = GapForm::kVertexPlane;
  int first = 0, second = 0;
  int vertex = 0;
};

}  // namespace tether
