// Joint limits and contacts as unilateral constraints, resolved at events (docs/contract.md, "Joint limits,
// contact and impacts"; docs/contact.md).
//
// Each gap g >= 0 is a side: a declared side of a joint's range, g = s (x - bound) on the joint's coordinate x
// (s = +1 at the low bound, -1 at the high one), with g' = s x'; or a feature of a pair of shapes that may touch
// (contact_geometry.h: a vertex against a plane, the closest points of two cores). A side is inactive (no row, no
// cost) or active (one more KKT row of law kGap, constraint_rows.h, with pushing multiplier mu = -lambda >= 0).
// Between events the active
// set is fixed and the motion is smooth; the stepper (stepper.h) finds the first event inside a step by root
// finding on the integrator's own step map tau -> x(t + tau) (its continuous extension, so the event time is
// as accurate as the steps: order kept across events), on g for an inactive side and on mu for an active one,
// and takes the step up to the event, then Resolve:
//
//   impact   touching sides (|g| <= kTouching) that approach (g' < -kRestingSpeed) get an impulse P >= 0 along
//            their rows such that g'+ = -e g'- (Newton's law), with every equality row's velocity J v kept and
//            every active side held at g'+ = 0. Several sides touching at once (simultaneous impacts) are
//            solved together, S P = target - J v on the Schur complement of the rows involved; a side whose
//            impulse would pull (P < 0) is left out and the system solved again (active_set.h).
//   capture  a rebound whose free flight would close the gap again within kCaptureFlight of the step is not
//            followed (Zeno: the bounces of a ball coming to rest add up to a finite time): the side is held
//            with g' = 0 instead. The flight is estimated from the rebound speed and the gap's acceleration.
//   contact  sides that touch and rest (|g'| <= kRestingSpeed) are made active and the accelerations solved;
//            a side whose multiplier would pull (mu <= 0) is left out and the system solved again (active_set.h).
//            A side that was active and is left out releases (an event of its own when its mu crosses zero in a
//            step).
//   overlap  a side left out while it overlaps by its drift (the stabilization holds g near zero, not at it) is due
//            again only where its overlap deepens: its event function in a step is g(tau) - min(g(0), 0). Were
//            it due at g < 0, a side whose multiplier pulls would be captured and left out again at the same
//            instant without end.
//   grazing  an approach slower than kRestingSpeed is a touch, not an impact: no impulse. Below kGrazingSpeed an
//            impact's time sensitivity (g' in its denominator) is not taken, with a warning.
//
// Derivatives (Jets, and the adjoint's recorded replay) cross an impact through its time (the saltation
// matrix): with the event located on the values, dt* = -g / g' at the state just past it, its value removed (a zero
// carrying dt*/dtheta), moves the state along the motion before the event, x <- x + f- dt*; the impact and the new
// active set are resolved there; and the state moves back along the motion after it, x <- x - f+ dt*. To first order in
// the derivatives this is x+ = Xi x- with Xi = R + (f+ - R f-) grad(g)^T / (grad(g) . f-). A release needs nothing: the
// motion's vector field is continuous where the multiplier crosses zero. Doubles take the same moves by an exact zero,
// so that a double run and its Rev replay make the same KKT solves (adjoint.h).
#pragma once

#include <algorithm>
#include <string>
#include <vector>

#include "tether/dynamics/constraints/contact_geometry.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/solvers/coulomb_impulses.h"
#include "tether/dynamics/solvers/workspace.h"

namespace tether {

// gaps within this of zero touch (rad or m): the root finding leaves them at round-off
inline constexpr double kTouching = 1e-9;
// gap rates within this of zero rest (rad/s or m/s)
inline constexpr double kRestingSpeed = 1e-8;
// a rebound whose free flight would be shorter than this fraction of the step is captured
inline constexpr double kCaptureFlight = 1e-4;
// an impact slower than this (rad/s or m/s) grazes: its time's sensitivity is left out
inline constexpr double kGrazingSpeed = 1e-6;
// the kinetic energy an impact may gain by round-off, relative to 1 J + the energy before it, beyond the work of the
// impulses of the rows it keeps on their drift (their J v, which the stabilization is removing)
inline constexpr double kImpactEnergyRoundoff = 1e-9;

template <typename T>
class UnilateralEvents {
 public:
  struct Side {
    int joint = -1;      // a joint limit: index into model.joints
    int coordinate = 0;  //   index into JointCoordinates::references
    int side = 1;        //   +1 low, -1 high
    int feature = -1;    // a contact: index into contacts().features
    std::string label;   // the joint's name, or its pointer; a contact's pair "A|B"
  };

  // Every side of every joint range and every contact feature of the model, all inactive.
  explicit UnilateralEvents(const Model<T>& model);

  bool empty() const { return sides_.empty(); }
  // The scene's "contact": "stepping": no event is located and no side is ever active; StepContacts resolves them
  // all by impulses at every step's end.
  bool stepping() const { return stepping_; }
  static constexpr int kImpulseStride = 3;
  int size() const { return static_cast<int>(sides_.size()); }
  bool active(int i) const { return active_[i] != 0; }
  // An active contact's friction (kNone for a limit or an inactive side).
  Friction friction(int i) const { return active_[i] ? static_cast<Friction>(active_[i] - 1) : Friction::kNone; }
  const Side& side(int i) const { return sides_[i]; }
  // Per side: 0 inactive, else 1 + its Friction; and the sliding directions held (3 numbers a side).
  const std::vector<char>& active_set() const { return active_; }
  const std::vector<double>& held_slips() const { return held_slips_; }
  const std::vector<int>& active_order() const { return active_order_; }  // the active sides in row order
  // Restores an active set and its held directions (a saved carry): the workspace's rows follow.
  void SetActiveSet(const std::vector<char>& active, const std::vector<double>& held_slips, Workspace<T>* ws);

  const ContactGeometry& contacts() const { return contacts_; }

  // Appends to *due every inactive side whose gap is negative at q (a limit's from the tracked coordinate values,
  // JointCoordinates::last).
  void Overlapping(const VecX<T>& q, Workspace<T>* ws, std::vector<int>* due) const;
  // The pushing multipliers mu of the active sides at (t, q, v), in side order (one KKT solve); false when the
  // system could not be solved.
  bool Multipliers(double t, const VecX<T>& q, const VecX<T>& v, Workspace<T>* ws, std::vector<double>* mu);
  // The event function of side i at (t, q, v) after a step: g when inactive, mu when active (an event where it
  // turns negative); a friction event's (below).
  double EventValue(int i, double t, const VecX<T>& q, const VecX<T>& v, Workspace<T>* ws);

  // Impacts, then the active set and its friction, at time t (above); side `capture` (or -1) is captured at once:
  // its gap closes again within kCaptureFlight of the step; `event` is the event located there (or -1: at the
  // start, or at a time step's end), which a friction event's pair follows whatever the sign of its function's
  // round-off there. Events are appended to report->events.
  void Resolve(double t, double step, int capture, int event, VecX<T>* q, VecX<T>* v, Workspace<T>* ws,
               RunReport* report);

  // Friction events (unilateral_friction.cc) are numbered size() + i, i the first active side of their pair: a
  // sticking pair's when its tangential force leaves the cone (mu N - |F_t| turns negative), a sliding pair's
  // when its slip stops (the slip along the direction held turns negative).
  bool IsFrictionEvent(int event) const { return event >= size(); }
  // Appends the friction events due at (t, q, v); `solved`: the workspace holds the KKT solve there already
  // (Multipliers), which a sticking pair's cone reads.
  void FrictionDue(double t, const VecX<T>& q, const VecX<T>& v, Workspace<T>* ws, std::vector<int>* due, bool solved);
  // A sliding pair's held direction follows its mean slip where its friction changes the slip by less than the
  // slip itself over a step of `step` (at the start of every step, t; contact_friction.h): the slip across the
  // direction then decays without overshoot.
  void FollowSlips(double t, double step, const VecX<T>& q, const VecX<T>& v, Workspace<T>* ws);

  // Time stepping (unilateral_stepping.cc): after a step of `step` from the velocity v_start that ended at t in
  // (q, v), impulses on the sides that overlap there or would close within the next step, and the configuration
  // moved by what the integrator makes of a lasting contact's (integrator_descriptor.h).
  void StepContacts(double t, double step, const VecX<T>& v_start, VecX<T>* q, VecX<T>* v, Workspace<T>* ws,
                    RunReport* report);
  // The sides that touched at the last step's end (time stepping): their restitution is spent; and their impulses
  // there (kImpulseStride numbers a side: the gap row's, then the slip rows'), where the next step's solve starts.
  const std::vector<char>& touching() const { return touching_; }
  const std::vector<double>& last_impulses() const { return last_impulses_; }
  void SetTouching(const std::vector<char>& touching, const std::vector<double>& impulses) {
    touching_ = touching;
    last_impulses_ = impulses;
  }

 private:
  struct GapState {
    double g = 0.0, rate = 0.0;
  };
  struct Gap {
    T g, rate;
  };

  // The first row of the active sides (the sticking contacts' slip rows follow them).
  size_t FirstGapRow(const Workspace<T>& ws) const {
    return ws.rows.size() - active_order_.size() - SlipRowCount(model_, ws.constraints);
  }
  T Bound(const Side& side) const;
  // A limit side's gap from the tracked coordinate values (JointCoordinates::last).
  double TrackedGap(const Side& side, const Workspace<T>& ws) const {
    return side.side * (ws.coordinates.last[side.coordinate] - Value(Bound(side)));
  }
  // Side i's held sliding direction, read and set.
  Vec3<double> HeldSlip(int i) const {
    return Vec3<double>(held_slips_[3 * i], held_slips_[3 * i + 1], held_slips_[3 * i + 2]);
  }
  void Hold(int i, const Vec3<double>& direction) {
    for (int k = 0; k < 3; ++k) held_slips_[3 * i + k] = direction[k];
  }
  // Where active side i stands among the active sides (its row after FirstGapRow).
  size_t ActivePosition(int i) const {
    return std::find(active_order_.begin(), active_order_.end(), i) - active_order_.begin();
  }
  T Restitution(const Side& side) const;
  std::vector<GapState> Measure(const VecX<T>& q, const VecX<T>& v, Workspace<T>* ws) const;
  void Apply(Workspace<T>* ws);
  // The held directions into the workspace's contact rows (the set unchanged).
  void SyncHeldSlips(Workspace<T>* ws) const;
  // Impulses on the equality rows, the active sides and the sides in `impacting` so that each impacting side
  // leaves at its target rate; a side whose impulse would pull is left out, unless `capture` (the sides in
  // `impacting` are then held at their target, a capture's last, tiny pull).
  // Returns every side's impulse (zero for those not in the solve).
  std::vector<double> Impulse(const std::vector<int>& impacting, const std::vector<T>& target, bool capture,
                              const VecX<T>& q, VecX<T>* v, Workspace<T>* ws);
  // The event `kind` on side i at (t, q) (frames updated at q), with its place and `impulse` (RunEvent).
  RunEvent EventAt(double t, const char* kind, int i, double before, double after, double impulse, const VecX<T>& q,
                   const Workspace<T>& ws) const;
  // Newton's law on the sides in `impacting` (their gaps `before`), rebounds too slow to follow captured, the
  // events reported; returns the gaps after.
  std::vector<GapState> Impacts(double t, double step, const std::vector<int>& impacting,
                                const std::vector<GapState>& before, const VecX<T>& q, VecX<T>* v, Workspace<T>* ws,
                                RunReport* report);
  // The active set at (q, v): the touching sides at rest and the held ones still at rest, less those whose
  // multiplier would pull.
  void HoldTouching(double t, const std::vector<GapState>& gaps, const VecX<T>& q, const VecX<T>& v, Workspace<T>* ws);
  // g and g' of side i at (q, v), in T; GapAt with the frames already updated there.
  Gap GapOf(int i, const VecX<T>& q, const VecX<T>& v, Workspace<T>* ws) const;
  Gap GapAt(int i, const VecX<T>& q, const VecX<T>& v, const Workspace<T>& ws) const;
  // (q, v) <- (q (+) v dt, v + v' dt) with the current active set.
  void MoveAlongMotion(double t, const T& dt, VecX<T>* q, VecX<T>* v, Workspace<T>* ws);
  // dt* of an impact on side i (a zero value; zero when it grazes, with a warning), the state moved by it.
  T EventTimeSensitivity(double t, int i, VecX<T>* q, VecX<T>* v, Workspace<T>* ws, RunReport* report);
  // The gap's acceleration g'' of side i with the current active set (one KKT solve).
  double GapAcceleration(int i, double t, const VecX<T>& q, const VecX<T>& v, Workspace<T>* ws);

  // friction (unilateral_friction.cc)
  // The active sides of each pair (empty for pairs not touching).
  std::vector<std::vector<int>> ActiveByPair() const;
  // Each touching pair's friction at (t, q, v): none (mu = 0), sticking where it slips no faster than
  // kRestingSpeed (or its slip turned back) and the force it needs lies in the cone, else sliding; changes of
  // touching pairs reported as stick or slip events. Throws SimulationDiverged at Painleve's paradox.
  // `located` is the pair of the friction event located there, or -1: a sticking one slides, a sliding one sticks
  // unless its force leaves the cone.
  void ChooseFriction(double t, int located, const VecX<T>& q, const VecX<T>& v, Workspace<T>* ws, RunReport* report);
  // dt* of the stop of sliding pair `pair`'s slip (a zero value; the sum h of its slips along the held directions
  // and its rate: dt* = -h / h'), the state moved by it along the sliding motion: the vector field changes there
  // (the sliding force gives way to the sticking one), so the derivatives cross it as they cross an impact.
  T SlipStopSensitivity(double t, int pair, VecX<T>* q, VecX<T>* v, Workspace<T>* ws);
  // A sticking pair's cone margin mu N - |F_t| from the last solve (its normal and slip rows' multipliers).
  double ConeMargin(const std::vector<int>& sides, const VecX<T>& q, const VecX<T>& v, Workspace<T>* ws) const;
  // The force F_t that a sticking pair's slip rows exert on its second bodies, world, from the last solve.
  Vec3<double> StickingForce(const std::vector<int>& sides, const VecX<T>& q, const VecX<T>& v, Workspace<T>* ws) const;
  // A sliding pair's slip along its held directions, summed over its sides.
  double SlipAlongHeld(const std::vector<int>& sides, const VecX<T>& q, const VecX<T>& v, Workspace<T>* ws) const;
  double FrictionEventValue(int side, double t, const VecX<T>& q, const VecX<T>& v, Workspace<T>* ws);

  // time stepping (unilateral_stepping.cc)
  // The sides an impulse may act on at (q, v), frames updated there (velocities too): those that overlap, and those
  // whose gap would close within the next step at its rate; into step_sides_, step_gaps_.
  void StepSides(double step, const VecX<T>& q, const VecX<T>& v, const Workspace<T>& ws);
  // Their rows: per side its gap row, then for a contact with friction its tangents' slip rows; their friction
  // coefficients, targets, rates, and rates at the step's start (where the side touched at the step before).
  void StepRows(double step, const VecX<T>& v_start, const VecX<T>& q, const VecX<T>& v, const Workspace<T>& ws);
  // Where the impulses' velocity change moves sides left out of them (candidates_) into their surfaces within the
  // step (v: after the impulses), those sides join step_sides_; false when none does.
  bool AddSidesClosedByImpulses(double step, const VecX<T>& q, const VecX<T>& v, const Workspace<T>& ws);
  // W and the impulses of step_rows_ (`factor`: the KKT matrix is factored with the first row's response), a
  // warning where they did not converge.
  void StepImpulses(double t, bool factor, Workspace<T>* ws, RunReport* report);
  // The run's one warning that impulses did not converge, at t.
  void WarnUnsolved(double t, RunReport* report);
  // W = J A J^T over step_rows_ into delassus_, with its factors (`factor`: the KKT matrix is factored with the
  // first row's); false where the KKT solve fails.
  bool Delassus(bool factor, Workspace<T>* ws);
  // z = G M^-1 J_c^T for step row c (free_moves_[c] filled): the equality rows' rates a unit impulse on it makes.
  void CouplingOf(Eigen::Index c, const Workspace<T>& ws, VecX<T>* z) const;
  // The velocity change A J^T p of impulses p on step_rows_ (after Delassus).
  VecX<T> VelocityChange(const VecX<T>& impulses, Workspace<T>* ws) const;
  // The impulses (coulomb_impulses.h) for the rows' `rates` before them, into `impulses`, from the last step's where
  // `warm` (else from none); false when they did not converge.
  bool SolveImpulses(const VecX<T>& rates, bool warm, VecX<T>* impulses);
  // Throws SimulationDiverged where the impulses' velocity change dv gained kinetic energy (below).
  void CheckEnergy(double t, const VecX<T>& dv) const;

  const Model<T>& model_;
  bool stepping_;
  ContactGeometry contacts_;
  std::vector<Side> sides_;
  std::vector<char> active_;        // per side
  std::vector<double> held_slips_;  // per side, 3 numbers: a sliding contact's direction held (contact_friction.h)
  std::vector<int> active_order_;
  VecX<T> acceleration_;
  double drift_work_ = 0.0;  // of the last impulse (Impulse)
  mutable std::vector<char> near_;  // the broad phase's pairs (Overlapping)

  // time stepping's
  struct StepBlock : ImpulseBlock<T> {  // its rows: the gap row, then d - 1 slip rows where it has friction
    int side = 0;
  };
  std::vector<char> touching_;         // per side
  std::vector<double> last_impulses_;  // kImpulseStride per side
  std::vector<int> step_sides_;
  std::vector<Gap> step_gaps_;  // g and g' of step_sides_ (g': after other sides' impulses, for a side they drove in)
  struct Candidate {  // a side near enough to be measured, apart and not closing at its rate before the impulses
    int side = 0;
    double gap = 0.0;
  };
  std::vector<Candidate> candidates_;
  std::vector<StepBlock> blocks_;
  std::vector<ConstraintRow<T>> step_rows_;
  std::vector<VecX<T>> free_moves_;  // per row r, M^-1 J_r^T (Delassus)
  // per row, G M^-1 J_r^T and S^-1 of it, or F^-1 of it alone (solved_reactions_ false: Delassus)
  Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> couplings_, reactions_;
  bool solved_reactions_ = true;
  Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> delassus_;  // W = J A J^T over the rows
  VecX<T> free_rates_, start_rates_, targets_, impulses_, impact_impulses_;
  std::vector<ImpulseBlock<T>> impulse_blocks_;
  CoulombImpulses<T> impulse_solver_;
  bool degenerate_[2] = {false, false};  // whether the last step's impulses, and its impacts', were (SolveImpulses)
  bool unsolved_warned_ = false;
};

}  // namespace tether
