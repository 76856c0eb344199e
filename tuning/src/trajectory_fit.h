// Trajectory optimisation: fit with inequality targets (constraints) and several starts.
//
// Minimized: 1/2 sum r_i^2 over the data residuals (targets as keyframes, any columns) and the penalties
// (smoothing, effort: shooting_problem.h), subject to the inequality targets, sign (simulated - bound) <= 0 at
// their times, each met to kConstraintTolerance max(1, |bound|) on one run of the scene from its initial state,
// and the box of the bounds.
//
// Each start runs in three steps.
//   reach (multiple shooting, segments K > 1)  the constraints alone, as a least-squares feasibility problem
//       solved by Levenberg-Marquardt (Ceres): the continuity rows (end of segment k = start of segment k + 1,
//       and each start on the scene's constraints: ShootingProblem::StartRows) and the inequality rows where they
//       come within kMargin tolerances of their bound, plus how far each unknown lies outside its bound. A motion whose end is sensitive to its beginning (a swing-up: an early
//       error grows by 1e5) is found piece by piece, and the joints close to about 1e-10.
//   reach (single shooting)  the same from there on one run, which parts from the joined segments by their gaps
//       grown along the motion; Gauss-Newton closes that from nearby, with steps far below 1e-8 of the unknowns.
//   polish  the cost minimized subject to the constraints by NLopt's SLSQP (sequential quadratic programming, with
//       the constraints' Jacobians), on a quarter of the budget; the best feasible point it sees is kept.
// SLSQP is chosen for the polish because it takes the constraints and their Jacobians directly and stays on them
// while lowering the cost; it is not the first step because from a random start (and with multiple shooting's
// continuity as equalities) it wanders off: measured on the acrobot, it ended with gaps of 1 to 7 rad between the
// segments where Levenberg-Marquardt closed them. Where the segments are left to fit (settings.segments 0),
// single shooting runs first, on an eighth of the budget; where it meets the constraints, it is polished again on
// the whole budget from there, and where it does not, multiple shooting (AutomaticSegments) runs from the start.
//
// Starts: the scene's values, then starts - 1 random points (seeded): uniform within kStartSpread of each bounded
// box's half-width about its middle (in log space for the positive kinds), or, for a parameter unbounded on a
// side, within kStartSpread (|value| + 1) of its value (a factor e^kStartSpread for a positive kind). The hanging
// acrobot's zero torques are a stationary point (the hanging state minimizes the tip's height, so every gradient
// vanishes), which is why the other starts differ from them. Starts run in parallel on the cores; the kept result
// is the feasible one with the least cost (ties to the earlier start, so the result does not depend on the thread
// count), or, where none is feasible, the one with the least violation, reported as failed.
#pragma once

#include <vector>

#include "tether/tuning/identification.h"

namespace tether {

inline constexpr double kContinuityTolerance = 1e-8;

IdentifyResult FitTrajectory(const Model<double>& model, const ParameterSet& parameters,
                             const std::vector<Observations>& recordings, const IdentifySettings& settings);

// The targets with each interval (a path constraint) replaced by one target at every integrator step of `step`
// seconds within it; (*origin)[j] is the index of the target that result j comes from. InputError naming the flag
// when an interval leaves the run [0, duration] or holds no step.
std::vector<InequalityTarget> AtEveryStep(const std::vector<InequalityTarget>& targets, double step,
                                          double duration, std::vector<int>* origin);

// The segments fit chooses: about four knot intervals of the finest schedule among the parameters per segment
// (a segment's Jacobian then takes few knots), between 2 and 20; 10 without scheduled parameters.
int AutomaticSegments(const ParameterSet& parameters, const std::vector<Observations>& recordings,
                      const IdentifySettings& settings);

}  // namespace tether
