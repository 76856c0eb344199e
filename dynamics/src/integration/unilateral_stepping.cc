// Time stepping: the scene's "contact": "stepping" (docs/contact.md, "Time stepping"), Moreau's velocity-level
// scheme with Coulomb's exact cone, first order.
//
// Every step is taken by the scene's integrator with no side active (the equality rows alone: one row layout for
// the whole run, nothing located, nothing to analyze again). At its end (q, v) the sides that overlap (g < 0), and
// those whose gap would close within the next step at its rate (0 <= g < -h g': speculative contacts, so that a
// landing body does not sink: without restitution it ends the next step touching, with restitution it bounces at
// this step's end, up to one step's travel above the surface rather than as far into it), get impulses p along
// their rows J: with A = M^-1 less what the equality rows take away (an impulse's velocity change keeps every
// equality row's J v) and the Delassus matrix W = J A J^T, the rates after are u+ = u + W p, and
//   gap row     p_n >= 0,  u_n+ >= b,  p_n (u_n+ - b) = 0,
//               b = -e min(u_n, 0) - k min(g^, 0) where g < 0,  b = -g / h where g >= 0 (-e u_n where e > 0)
//   slip rows   |p_t| <= mu p_n;  u_t+ = 0 where |p_t| < mu p_n, else u_t+ = -c p_t with c >= 0
// (Coulomb's law at the impulse level: a contact sticks, or slides with the impulse mu p_n against its slip after).
// e is the side's restitution where it did not touch at the step before (Newton's law, spent once: a contact that
// persists is held, so a resting body does not hop), else 0; k = h beta / (1 + h alpha) is the Baumgarte law over
// one step, implicit in the rate (u+ = -h (alpha u+ + beta g^)), so that the scene's gains close an overlap g^. The
// state then moves by the impulses' velocity change dv = A J^T p, and the sides that touched at the step before
// and overlap (held contacts, whose impulse is a force the step did without) move the configuration as the integrator
// would have under that force spread over the step:
//   v <- v + dv,  q <- q (+) w h dv_held,  g^ = g - w h f u_n (the overlap left for u_n+ = 0),
// w the integrator's force position weight (integrator_descriptor.h), so that a body resting or sticking on a slope
// does not creep. A held side's impulse counts as a force for the fraction that cancels what the step added to its
// approach, f = (J_n v_start - u_n) / -u_n (clamped to [0, 1]) with J_n v_start its rate at the step's start, after
// the last step's impulses (its row at the step's end: f is a function of the state, which derivatives follow); the
// rest of it, and a new contact's impulse, are an impact's: they change the velocity only.
//
// The impulses solve Coulomb's problem by Newton's method on Alart and Curnier's function (coulomb_impulses.h),
// started from the last step's: Coulomb's problem itself, not a convex relaxation of it (Anitescu's cone
// complementarity would lift a sliding contact off at mu |u_t| per step). Where the contacts persist it takes one or
// two iterations; its solution meets the conditions to kImpulseTolerance of the largest rate, and its derivatives
// (Jets, the adjoint's replay) are the implicit function theorem's. Several contacts along one plane (a box's four
// corners) make W singular: the motion is unique, the impulses are not, and the solver's regularization picks the
// least ones. A run whose solves do not converge goes on with the last iterate (within the cones) and is warned of
// once.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "tether/dynamics/constraints/contact_friction.h"
#include "tether/dynamics/effects/effects.h"
#include "tether/dynamics/integration/integrator_descriptor.h"
#include "tether/dynamics/integration/simulator.h"
#include "tether/dynamics/integration/unilateral_events.h"
#include "tether/dynamics/model/configuration_space.h"
#include "tether/dynamics/model/errors.h"

namespace tether {
namespace {

// the impulses' conditions hold to this fraction of the largest rate at the step's end (and at least a resting
// speed's)
constexpr double kImpulseTolerance = 1e-10;

template <typename T>
T RowRate(const Model<T>& model, const ConstraintRow<T>& row, const VecX<T>& v) {
  return Dot(model, row.a, v) + Dot(model, row.b, v);
}

}  // namespace

template <typename T>
void UnilateralEvents<T>::StepSides(double step, const VecX<T>& q, const VecX<T>& v, const Workspace<T>& ws) {
  step_sides_.clear();
  step_gaps_.clear();
  if (!contacts_.features.empty()) {
    // the bounding spheres grown by how far a point may move over the next step: a point r from its body's origin
    // moves at |v| + |w| r <= c (1 + r / 1 m), c the largest velocity component, r at most the length scale; twice
    // that, for two shapes closing on each other
    double fastest = 0.0;
    for (Eigen::Index k = 0; k < v.size(); ++k) fastest = std::max(fastest, std::abs(Value(v[k])));
    NearPairs(model_, contacts_, ws.frames, q, 2.0 * step * fastest * (1.0 + LengthScale(model_)), &near_);
  }
  for (int i = 0; i < size(); ++i) {
    const Side& side = sides_[i];
    if (side.feature >= 0 && !near_[contacts_.features[side.feature].pair]) continue;  // every gap positive
    const Gap gap = GapAt(i, q, v, ws);
    const double g = Value(gap.g), closing = g + step * Value(gap.rate);
    if (g < 0.0 || closing < 0.0) {
      step_sides_.push_back(i);
      step_gaps_.push_back(gap.g);
    }
  }
}

template <typename T>
void UnilateralEvents<T>::StepRows(double step, const VecX<T>& v_start, const VecX<T>& q, const VecX<T>& v,
                                   const Workspace<T>& ws) {
  const double w = Describe(model_.simulation.integrator).force_position_weight;
  const T k = step * ws.beta / (1.0 + step * ws.alpha);
  blocks_.clear();
  step_rows_.clear();
  targets_.resize(0);
  std::vector<T> targets;
  for (size_t s = 0; s < step_sides_.size(); ++s) {
    const int i = step_sides_[s];
    const Side& side = sides_[i];
    StepBlock block;
    block.side = i;
    block.first_row = static_cast<int>(step_rows_.size());
    ConstraintRow<T> row;
    if (side.feature < 0) {
      const Joint<T>& joint = model_.joints[side.joint];
      const LimitPrimitive<T> limit{joint.scene_index, joint.a.body,
                                    joint.b.body,      ws.coordinates.references[side.coordinate],
                                    side.side,         Bound(side)};
      EvaluateLimitRow(model_, limit, ws.frames, q, v, false, &row);
      step_rows_.push_back(row);
    } else {
      const ContactFeature& feature = contacts_.features[side.feature];
      EvaluateContactRow(model_, feature, ws.frames, q, v, false, &row);
      step_rows_.push_back(row);
      block.friction = PairFriction(model_, feature.first, feature.second);
      if (Value(block.friction) > 0.0) {
        const ContactPoint<T> contact = ContactPointOf(model_, feature, ws.frames, q, v, false);
        Vec3<T> tangents[2];
        block.rows += Tangents(model_.dimension, contact.normal, tangents);
        for (int t = 1; t < block.rows; ++t) {
          SlipRow(model_, ws.frames, contact, tangents[t - 1], false, &row);
          step_rows_.push_back(row);
        }
      }
    }
    const T& gap = step_gaps_[s];
    const T rate = RowRate(model_, step_rows_[block.first_row], v);
    const T e = touching_[i] ? T(0.0) : Restitution(side);
    if (Value(gap) >= 0.0) {  // closing within the next step: no faster than to touch at its end, or bouncing now
      targets.push_back(Value(e) > 0.0 ? T(-e * rate) : T(-gap / step));
    } else {
      // a held side's impulse is a force for the part that cancels the approach the step added to its rate
      if (touching_[i] && Value(rate) < 0.0) {
        const T force = (RowRate(model_, step_rows_[block.first_row], v_start) - rate) / -rate;
        block.force = Value(force) <= 0.0 ? T(0.0) : Value(force) >= 1.0 ? T(1.0) : force;
      }
      const T left = gap - w * step * block.force * rate;  // g^
      targets.push_back((Value(rate) < 0.0 ? -e * rate : T(0.0)) - (Value(left) < 0.0 ? k * left : T(0.0)));
    }
    for (int t = 1; t < block.rows; ++t) targets.push_back(T(0.0));
    blocks_.push_back(block);
  }
  targets_ = Eigen::Map<VecX<T>>(targets.data(), static_cast<Eigen::Index>(targets.size()));
  free_rates_.resize(static_cast<Eigen::Index>(step_rows_.size()));
  for (size_t r = 0; r < step_rows_.size(); ++r) free_rates_[r] = RowRate(model_, step_rows_[r], v);
}

template <typename T>
bool UnilateralEvents<T>::Response(const ConstraintRow<T>& row, bool first, Workspace<T>* ws, VecX<T>* dv) {
  dv->setZero(model_.NumVelocities());
  AddScaled(model_, row.a, T(1.0), dv);
  AddScaled(model_, row.b, T(1.0), dv);
  ApplyInverseMass(model_, ws->inverse_mass, *dv, dv);
  if (ws->rows.empty()) return true;
  MultiplyJacobian(model_, *dv, ws);
  const bool solved = first ? ws->solver->Solve(ws->kkt.schur, ws->kkt.rhs, &ws->kkt.lambda)
                            : ws->solver->SolveAgain(ws->kkt.schur, ws->kkt.rhs, &ws->kkt.lambda);
  if (!solved) return false;
  ApplyReaction(model_, ws, &ws->reaction);
  *dv -= ws->reaction;
  return true;
}

template <typename T>
bool UnilateralEvents<T>::SolveImpulses() {
  impulses_.setZero(free_rates_.size());
  impulse_blocks_.clear();
  for (const StepBlock& block : blocks_) {  // from the impulses of the step before, where the side touched then
    impulse_blocks_.push_back({block.first_row, block.rows, block.friction});
    for (int r = 0; r < block.rows; ++r)
      impulses_[block.first_row + r] = T(last_impulses_[kImpulseStride * block.side + r]);
  }
  double fastest = kRestingSpeed;
  for (Eigen::Index r = 0; r < free_rates_.size(); ++r) fastest = std::max(fastest, std::abs(Value(free_rates_[r])));
  return impulse_solver_.Solve(delassus_, free_rates_, targets_, impulse_blocks_, kImpulseTolerance * fastest,
                               &impulses_);
}

// The kinetic energy the impulses add, p^T u + p^T W p / 2 (= v^T M dv + dv^T M dv / 2 less the work of the equality
// rows' impulses on their drift J v, which the stabilization is removing), is at most the work of the
// stabilization's push out of the overlaps: Newton's law with e <= 1 and Coulomb's friction add none.
template <typename T>
void UnilateralEvents<T>::CheckEnergy(double t, const VecX<T>& dv) const {
  double pushed = 0.0;
  for (const StepBlock& block : blocks_) {
    const double rate = Value(free_rates_[block.first_row]);
    const double newton = rate < 0.0 ? -Value(Restitution(sides_[block.side])) * rate : 0.0;
    pushed += Value(impulses_[block.first_row]) * std::max(Value(targets_[block.first_row]) - newton, 0.0);
  }
  const double kinetic = Value(KineticEnergy(model_, dv));  // p^T W p / 2
  const double work = Value(impulses_.dot(free_rates_));    // p^T u
  const double gained = work + kinetic;
  if (gained > pushed + kImpactEnergyRoundoff * (1.0 + kinetic + std::abs(work))) {
    std::ostringstream out;
    out << "the contact impulses at t = " << t << " s gained " << gained
        << " J of kinetic energy (a defect of the impulse solve: please report the scene)";
    throw SimulationDiverged(out.str(), t, -1);
  }
}

template <typename T>
void UnilateralEvents<T>::StepContacts(double t, double step, const VecX<T>& v_start, VecX<T>* q, VecX<T>* v,
                                       Workspace<T>* ws, RunReport* report) {
  EvaluateRows(model_, *q, *v, true, ws);  // the equality rows and the frames (velocities too) at the step's end
  StepSides(step, *q, *v, *ws);
  size_t next = 0;                    // step_sides_ is in the sides' order
  for (int i = 0; i < size(); ++i) {  // sides left out: no impulse to start from; released if they touched
    if (next < step_sides_.size() && step_sides_[next] == i) {
      ++next;
      continue;
    }
    std::fill_n(last_impulses_.begin() + kImpulseStride * i, kImpulseStride, 0.0);
    if (!touching_[i]) continue;
    touching_[i] = 0;
    const double rate = Value(GapAt(i, *q, *v, *ws).rate);
    report->events.push_back({t, "release", sides_[i].label, rate, rate});
  }
  if (step_sides_.empty()) return;
  if (!ws->rows.empty()) AssembleSchur(ws);
  StepRows(step, v_start, *q, *v, *ws);
  const size_t n = step_rows_.size();
  responses_.resize(std::max(responses_.size(), n));
  for (size_t r = 0; r < n; ++r) {
    if (!Response(step_rows_[r], r == 0, ws, &responses_[r])) {
      throw SimulationDiverged("the simulation diverged at t = " + std::to_string(t) +
                                   " s: the constraint system became singular or non-finite",
                               t, -1);
    }
  }
  delassus_.resize(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
  for (size_t c = 0; c < n; ++c) {  // W is symmetric (A is): its upper triangle, mirrored
    for (size_t r = 0; r <= c; ++r) {
      delassus_(r, c) = RowRate(model_, step_rows_[r], responses_[c]);
      delassus_(c, r) = delassus_(r, c);
    }
  }
  if (!SolveImpulses() && !unsolved_warned_) {
    unsolved_warned_ = true;
    std::ostringstream out;
    out << "t = " << t << " s: the contact impulses did not converge (" << impulse_solver_.newton_iterations()
        << " Newton iterations, " << impulse_solver_.sweeps()
        << " Gauss-Seidel sweeps); the run goes on with the last ones (within the friction cones)";
    report->warnings.push_back(out.str());
  }
  VecX<T> dv = VecX<T>::Zero(model_.NumVelocities()), held = dv;  // all the impulses', their forces'
  for (size_t b = 0; b < blocks_.size(); ++b) {
    const StepBlock& block = blocks_[b];
    for (int r = block.first_row; r < block.first_row + block.rows; ++r) {
      dv += responses_[r] * impulses_[r];
      if (Value(block.force) > 0.0) held += responses_[r] * (impulses_[r] * block.force);
    }
  }
  CheckEnergy(t, dv);
  *v += dv;
  VecX<T> moved(q->size());
  Integrate(model_, *q, held, Describe(model_.simulation.integrator).force_position_weight * step, &moved);
  q->swap(moved);
  for (size_t b = 0; b < blocks_.size(); ++b) {  // a side touches where it overlaps or its impulse pushes
    const StepBlock& block = blocks_[b];
    const int i = block.side;
    const double rate = Value(free_rates_[block.first_row]);
    const double after = rate + Value(delassus_.row(block.first_row).dot(impulses_));
    for (int r = 0; r < block.rows; ++r) last_impulses_[kImpulseStride * i + r] = Value(impulses_[block.first_row + r]);
    const bool touches = Value(step_gaps_[b]) < 0.0 || Value(impulses_[block.first_row]) > 0.0;
    if (touches && !touching_[i] && rate < -kRestingSpeed) {
      report->events.push_back({t, "impact", sides_[i].label, rate, after});
    } else if (!touches && touching_[i]) {
      report->events.push_back({t, "release", sides_[i].label, rate, rate});
    }
    touching_[i] = touches;
  }
}

#define TETHER_INSTANTIATE_UNILATERAL_STEPPING(T)                                                                    \
  template void UnilateralEvents<T>::StepContacts(double, double, const VecX<T>&, VecX<T>*, VecX<T>*, Workspace<T>*, \
                                                  RunReport*);                                                       \
  template void UnilateralEvents<T>::StepSides(double, const VecX<T>&, const VecX<T>&, const Workspace<T>&);         \
  template void UnilateralEvents<T>::StepRows(double, const VecX<T>&, const VecX<T>&, const VecX<T>&,                \
                                              const Workspace<T>&);                                                  \
  template bool UnilateralEvents<T>::Response(const ConstraintRow<T>&, bool, Workspace<T>*, VecX<T>*);               \
  template bool UnilateralEvents<T>::SolveImpulses();                                                                \
  template void UnilateralEvents<T>::CheckEnergy(double, const VecX<T>&) const;
TETHER_FOR_EACH_SCALAR(TETHER_INSTANTIATE_UNILATERAL_STEPPING)

}  // namespace tether
