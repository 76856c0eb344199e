// The residuals of identification and fitting as functions of the unknowns (identification.h has the problem).
//
// Unknowns x: the parameters (positive kinds as log p, the others as p), then for multiple shooting the start
// state of every segment after the first: an offset d from its reference, q = q_ref (+) d, and the velocity v.
// Residuals, in this order:
//   data         simulated - observed, every observed cell of every recording, segment by segment;
//   continuity   end state of segment k (-) start state of segment k + 1 (configuration, then velocity), for
//                every k; then, with kOnTheConstraints, for every segment after the first its start state (-)
//                that state moved onto the constraints (without these rows a trajectory fit's steps drift off the
//                constraints, where moving a state onto them can jump between branches: on the acrobot 2 of 8
//                starts reached the upright without, 5 with; identification keeps without, its starts come from
//                the data). With kOnTheConstraints the end state is itself moved onto the constraints first: a
//                stabilized run ends off them by its drift, and a start both on them and equal to that end would
//                be asked for twice what cannot be (on the acrobot the gaps stalled at 1e-5 m, the drift, and
//                the reach ran out its 500 iterations); the run from the scene's initial state, which is not
//                moved there, then parts from the joined segments by the drifts, which single shooting closes;
//   penalties    smoothing sqrt(W_s) (s_{j+1} - s_j) of consecutive schedule values; effort, the integral
//                W_e int_0^D tau(t)^2 dt of every joint motor's torque, exact for its piecewise linear schedule
//                (held at its end values): over a piece of length L from a to b, W_e L (a^2 + a b + b^2) / 3 =
//                1/2 (r1^2 + r2^2) with r1 = c (a + b / 2), r2 = c (sqrt(3) / 2) b, c = sqrt(2 W_e L / 3);
//   constraints  simulated - bound of every inequality target (fit's --at-least / --at-most).
// The segments' boundaries lie on the integrator's step grid (the K-th parts of [0, last target time], rounded),
// so that the joined segments step exactly as one run of the scene does.
// A segment after the first starts from its unknown state moved onto the constraints (as every run starts), and
// continues the joint coordinates of the whole run (a joint's angle is measured from the scene's initial state; a
// 3D hinge's angle takes the branch nearest its value at the previous segment's end, so that it turns continuously
// however far the segment's start has moved from the first guess).
//
// Jacobian by Jets, segment by segment: segment k's residuals depend on the parameters that act within it (a
// schedule value only between its neighbouring knots; any other parameter, and all of them when ties are
// declared, everywhere) and on its own start state, so each segment is run once per kJetStride of those rather
// than once per kJetStride of all unknowns.
#pragma once

#include <Eigen/Core>
#include <string>
#include <utility>
#include <vector>

#include "tether/autodiff/observations.h"
#include "tether/autodiff/parameters.h"
#include "tether/dynamics/scalars/scalar.h"
#include "tether/tuning/identification.h"
#include "tether/tuning/task_threads.h"

namespace tether {

// Throws InputError when a parameter's value lies outside its bound (settings.bounds), naming --bound.
void CheckStartWithinBounds(const ParameterSet& parameters, const std::vector<double>& values,
                            const IdentifySettings& settings);

// Whether parameter i is fitted as log p: a quantity the scene format keeps positive (or non-negative), whose
// value and lower bound are positive.
bool FittedInLogSpace(const ParameterSet& parameters, int i, double value, const IdentifySettings& settings);

class ShootingProblem {
 public:
  // Whether the continuity rows hold each segment's start state to the constraints as well (see above).
  enum class StartRows { kContinuityOnly, kOnTheConstraints };
  // settings.segments >= 1 (Identify resolves an automatic choice before). With `idle`, a Jacobian's Jet runs
  // spread over the cores it holds (task_threads.h).
  ShootingProblem(const Model<double>& model, const ParameterSet& parameters,
                  const std::vector<Observations>& recordings, const IdentifySettings& settings,
                  StartRows start_rows = StartRows::kContinuityOnly, IdleCores* idle = nullptr);

  int Unknowns() const { return parameters_.size() + (Segments() - 1) * state_size_; }
  int Segments() const { return static_cast<int>(boundaries_.size()) - 1; }
  bool LogSpace(int i) const { return log_space_[i]; }
  int DataCount() const { return segment_rows_.back(); }
  int ContinuityCount() const { return (on_the_constraints_ ? 2 : 1) * (Segments() - 1) * state_size_; }
  int PenaltyCount() const { return penalty_count_; }
  int ConstraintCount() const { return static_cast<int>(targets_.size()); }
  // The constraint rows: the first and how each bounds its residual (+1: r <= 0, at most; -1: r >= 0, at least).
  int FirstConstraintRow() const { return DataCount() + ContinuityCount() + PenaltyCount(); }
  double ConstraintSign(int c) const { return settings_.inequalities[c].at_least ? -1.0 : 1.0; }

  // unknowns <-> parameters (in their own units)
  double ToUnknown(int i, double p) const;
  double ToParameter(int i, double x) const;
  // The parameters (in their own units) at unknowns x.
  std::vector<double> Parameters(const std::vector<double>& x) const;

  // The box on the unknowns from settings.bounds, in the unknowns' units (the start states are unbounded).
  void Box(std::vector<double>* lower, std::vector<double>* upper) const;

  // The starting unknowns: the scene's parameters and, for multiple shooting, the segments' start states as
  // offsets from their references (zero) and velocities.
  std::vector<double> Start() const;

  // Residuals at unknowns x, and their Jacobian when asked. False where a run diverges or a start cannot run.
  bool Evaluate(const std::vector<double>& x, Eigen::VectorXd* r, Eigen::MatrixXd* jacobian) const;

  // The cost 1/2 sum rho(r_i^2) at x over the data and penalty residuals, and its gradient with respect to x, by
  // the adjoint: single shooting without constraints, whose unknowns are the parameters. False where the run
  // diverges.
  bool CostGradient(const std::vector<double>& x, const RobustLoss& loss, double* cost,
                    std::vector<double>* gradient) const;

  // The data residuals at x grouped per recording and column, for the report.
  std::vector<ResidualStatistics> Statistics(const std::vector<double>& x) const;

 private:
  // Which unknowns a Jet run seeds: unknown seeded[j] in derivative slot j.
  struct Seeds {
    std::vector<int> unknowns;
    int Slot(int unknown) const;
  };
  // What a run of one segment gives: its data residuals (group: recording x column, as in Statistics) in
  // recording, row, column order; its constraint residuals by target; its end state.
  template <typename T>
  struct SegmentOutput {
    std::vector<std::pair<size_t, T>> data;
    std::vector<std::pair<int, T>> constraints;
    State<T> end;
    std::vector<double> end_coordinates;  // the joint coordinates at the end (joint_coordinates.h's order)
    State<T> start;  // after the first segment: the start state as the run moved it onto the constraints
  };

  Model<double> WithParameters(const std::vector<double>& x) const;
  template <typename T>
  Model<T> Seeded(const Model<double>& model, const Seeds& seeds) const;
  // Segment k's run; `hint`: the joint coordinates at the previous segment's end, which this one continues.
  template <typename T>
  SegmentOutput<T> RunSegment(const Model<T>& model, const std::vector<double>& x, int k, const Seeds& seeds,
                              const std::vector<double>& hint) const;
  template <typename T>
  State<T> SegmentStart(const Model<T>& model, const std::vector<double>& x, int k, const Seeds& seeds) const;
  // Sets the joint angles of a segment's model (their values at its start, joint_coordinates.h) so that its joint
  // coordinates continue those of the whole run from the scene's initial state; `hint` (the previous segment's
  // end) picks a 3D angle's branch.
  template <typename T>
  void ContinueCoordinates(const Model<T>& model, const VecX<T>& q_start, const std::vector<double>& hint,
                           Model<T>* segment) const;
  template <typename T>
  void Penalties(Model<T> model, std::vector<T>* out) const;
  // Whether observation time t belongs to segment k: (begin, end], and t = 0 to the first.
  bool InSegment(double t, int k) const;
  // Whether parameter i acts within segment k.
  bool ActsWithin(int i, int k) const;
  std::vector<State<double>> SegmentStarts();
  void ReplaceByData(double t, VecX<double>* q, VecX<double>* v) const;

  const Model<double>& model_;
  const ParameterSet& parameters_;
  const std::vector<Observations>& recordings_;
  const IdentifySettings& settings_;
  bool on_the_constraints_ = false;  // StartRows::kOnTheConstraints
  IdleCores* idle_ = nullptr;
  std::vector<Observations> targets_;  // one per inequality target: its column at its time, the bound as value
  std::vector<const Observations*> observed_;  // the recordings, then the targets
  size_t data_groups_ = 0;                      // columns over the recordings
  std::vector<bool> log_space_;
  std::vector<double> boundaries_;
  std::vector<int> segment_rows_;         // the first data row of each segment, and the data count last
  int state_size_ = 0;                    // unknowns per segment start: an offset d and a velocity (2 nv)
  std::vector<State<double>> references_;  // the start states the offsets are taken from
  std::vector<std::pair<int, int>> smooth_pairs_;
  int penalty_count_ = 0;  // rows of Penalties: the smoothing pairs and the effort pieces
};

}  // namespace tether
