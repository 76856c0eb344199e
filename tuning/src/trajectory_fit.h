// Trajectory optimisation: fit with inequality targets (constraints) and several starts.
//
// Minimized: 1/2 sum r_i^2 over the data residuals (targets as keyframes, any columns) and the penalties
// (smoothing, effort: shooting_problem.h), subject to the inequality targets, sign (simulated - bound) <= 0 at
// their times, each met to kConstraintTolerance max(1, |bound|), and the box of the bounds. The solver is NLopt's
// SLSQP (sequential quadratic programming), chosen because it takes equality and inequality constraints with
// their Jacobians directly and meets them to tolerance at a local optimum; a penalty method (Ceres) would only
// approach them as its weights grow, and an augmented Lagrangian (AUGLAG) needs many more runs to close them.
//
// Each start runs as follows. Multiple shooting (segments K > 1): the segments' start states are unknowns and the
// continuity rows (end of segment k = start of segment k + 1) equality constraints, closed to
// kContinuityTolerance, so a motion whose end is sensitive to its beginning (a swing-up: an early error grows
// by 1e5) is found piece by piece. Then single shooting from the parameters found: one run of the scene's
// initial state, which is what a written scene does, polished until the constraints hold on it. Where the
// segments are left to fit (settings.segments 0), single shooting runs first and multiple shooting only when it
// does not meet the constraints, with AutomaticSegments segments.
//
// Starts: the scene's values, then starts - 1 random points (seeded): uniform within the bounds (in log space
// for the positive kinds), or, for a parameter unbounded on a side, up to |value| + 1 away from its value (a
// factor e for a positive kind). The hanging acrobot's zero torques are a stationary point (the hanging state
// minimizes the tip's height, so every gradient vanishes), which is why the other starts differ from them. Starts
// run in parallel on the cores; the kept result is the feasible one with the least cost (ties to the earlier
// start, so the result does not depend on the thread count), or, where none is feasible, the one with the
// least violation, reported as failed.
#pragma once

#include <vector>

#include "tether/tuning/identification.h"

namespace tether {

inline constexpr double kContinuityTolerance = 1e-8;

IdentifyResult FitTrajectory(const Model<double>& model, const ParameterSet& parameters,
                             const std::vector<Observations>& recordings, const IdentifySettings& settings);

// The segments fit chooses: about four knot intervals of the finest schedule among the parameters per segment
// (a segment's Jacobian then takes few knots), between 2 and 20; 10 without scheduled parameters.
int AutomaticSegments(const Model<double>& model, const ParameterSet& parameters,
                      const std::vector<Observations>& recordings, const IdentifySettings& settings);

}  // namespace tether
