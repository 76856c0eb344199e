// A run of a model: assemble the initial state onto the constraints, step on the grid t_k = k h (the last
// step shortened to land on the duration), stabilize, watch for divergence, and hand output rows to an
// observer.
//
// Divergence: the run stops with SimulationDiverged when the state becomes non-finite, the Schur system
// cannot be factored, rk45's step collapses, or a constraint is violated by more than the scene's length
// scale (the largest of its initial coordinates, constraint lengths and point offsets, at least 1 mm): a
// constraint that is off by the size of the whole scene no longer describes the mechanism.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "tether/dynamics/model.h"

namespace tether {

template <typename T>
struct Sample {
  double t;
  const VecX<T>& q;
  const VecX<T>& v;
  double constraint_error;  // largest geometric violation over the constraints, m
  T energy;                 // kinetic + gravity + spring potential, J
};

struct RunOptions {
  int every = 1;  // output every k-th step (the first and the last state are always output)
};

struct RunReport {
  int steps = 0;
  std::vector<std::string> warnings;  // e.g. that the initial state was moved onto the constraints
};

// Throws InputError when the initial state cannot be assembled onto the constraints, and
// SimulationDiverged when the run diverges.
template <typename T>
RunReport Simulate(const Model<T>& model, const RunOptions& options,
                   const std::function<void(const Sample<T>&)>& observer);

// The length scale above, m.
template <typename T>
double LengthScale(const Model<T>& model);

// "constraint /constraints/3 (distance world-bob)": how messages name a constraint.
template <typename T>
std::string DescribeConstraint(const Model<T>& model, int scene_index);

}  // namespace tether
