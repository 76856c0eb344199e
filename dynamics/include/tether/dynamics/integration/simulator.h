// A run of a model: assemble the initial state onto the constraints, step on the grid t_k = k h (the last
// step shortened to land on the duration, and steps split at requested stop times), stabilize, watch for
// divergence, and hand output rows and stop samples to an observer.
//
// Divergence: the run stops with SimulationDiverged when the state becomes non-finite, the Schur system
// cannot be factored, rk45's step collapses, or a constraint is violated by more than the scene's length
// scale (the largest of its initial coordinates, constraint lengths and point offsets, at least 1 mm): a
// constraint that is off by the size of the whole scene no longer describes the mechanism. The violation is
// checked after every step and at every sample, the last one included. A run longer than kMaxSteps steps
// (model.h) is refused with InputError before it starts.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "tether/dynamics/constraints/constraint_rows.h"
#include "tether/dynamics/model/configuration_space.h"

namespace tether {

template <typename T>
struct Sample {
  double t;
  const VecX<T>& q;                           // configuration (model.h's layout)
  const VecX<T>& v;                           // velocity
  double constraint_error;                    // largest geometric violation over the constraints, m (rad for angles)
  T energy;                                   // kinetic + gravity + spring potential, J (RunOptions::energy)
  const VecX<T>& coordinates;                 // every named joint's coordinates (joint_coordinates.h's order)
  const VecX<T>& coordinate_rates;            // and their rates
  const BodyFrames<T>& frames;                // the bodies' frames at (q, v)
  const std::vector<ConstraintRow<T>>& rows;  // the constraint rows at q (values and Jacobian blocks; no bias)
  bool output = true;                         // a row of the output grid (every k-th step, the first and the last)
  int stop = -1;                              // index into RunOptions::stops when the sample is at a stop time, else -1
};

struct RunOptions {
  int every = 1;  // output every k-th step (the first and the last state are always output)
  // Time of the initial state (the bodies' initial state in the model): the run covers [start_time, start_time +
  // duration] on the grid start_time + k h. Time-dependent effects (schedules) see these times.
  double start_time = 0.0;
  // Times (strictly increasing, within the run's interval) at which the run must sample its state exactly: the
  // step that would cross a stop is split there, so observations need no interpolation. A stop within 1e-9 h
  // of a grid time is served by it, and one past the end by no more than 1e-12 of the duration (the rounding
  // of a time written in a file) by the end state.
  std::vector<double> stops;
  // Test oracle and benchmark only: factor the Schur matrix of Jets itself instead of applying the implicit
  // function theorem to its value part (schur_solver.h).
  bool factor_jet_matrices = false;
  // Whether the samples carry the energy (Sample::energy, NaN otherwise): a run whose observer never reads it
  // (a loss on other columns, ObservesEnergy) skips evaluating it, which recorded (the adjoint's replay) adds
  // a node per term.
  bool energy = true;
};

// An event of a unilateral constraint (unilateral_events.h): the rows of `tether simulate --events`.
struct RunEvent {
  double t = 0.0;
  std::string kind;                              // "impact" or "release"
  std::string constraint;                        // the joint's name (or its pointer, /constraints/K, when it has none)
  double speed_before = 0.0, speed_after = 0.0;  // the gap's rate g' just before and after
  // Where, in the world: a contact's point and its normal n (unit, from the label's second shape towards its first,
  // on whose body the impulse pushes along n); a limit's joint point on its second body and n zero. An impact's
  // impulse (N s along n; a limit's N m s or N s along its coordinate), else 0.
  Vec3<double> point = Vec3<double>::Zero(), normal = Vec3<double>::Zero();
  double impulse = 0.0;
};

struct RunReport {
  std::int64_t steps = 0;
  std::int64_t retaken_steps = 0;     // steps retaken in substeps near a singular pass (schur_solver.h)
  std::vector<std::string> warnings;  // e.g. that the initial state was moved onto the constraints
  std::vector<RunEvent> events;       // in time order
  std::string drift;                  // when the constraints drifted past 1% of the length scale: that warning
};

// The state a run starts from: the model's initial state moved onto its constraints (the mass-weighted nearest
// state, projection.h) with its velocities projected, and a warning in `report` for each that moved. Throws
// InputError when it cannot be assembled: Simulate's first step, which `tether check` reports too.
template <typename T>
State<T> AssembledInitialState(const Model<T>& model, RunReport* report);

// Throws InputError when the initial state cannot be assembled onto the constraints, and
// SimulationDiverged when the run diverges.
template <typename T>
RunReport Simulate(const Model<T>& model, const RunOptions& options,
                   const std::function<void(const Sample<T>&)>& observer);

// The length scale above, m (from the initial positions, lengths and point offsets).
template <typename T>
double LengthScale(const Model<T>& model);

// "constraint /constraints/3 (distance world-bob)": how messages name a constraint.
template <typename T>
std::string DescribeConstraint(const Model<T>& model, int scene_index);

}  // namespace tether
