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
//               b = -e min(u_n, 0) - k g^ where g < 0 and g^ < 0,  b = -g^ / h where g < 0 <= g^,
//               b = -g / h where g >= 0 (-e u_n where e > 0)
//   slip rows   |p_t| <= mu p_n;  u_t+ = 0 where |p_t| < mu p_n, else u_t+ = -c p_t with c >= 0
// (Coulomb's law at the impulse level: a contact sticks, or slides with the impulse mu p_n against its slip after).
// e is the side's restitution where it did not touch at the step before (Newton's law, spent once: a contact that
// persists is held, so a resting body does not hop), else 0; k = h beta / (1 + h alpha) is the Baumgarte law over
// one step, implicit in the rate (u+ = -h (alpha u+ + beta g^)), so that the scene's gains close an overlap g^;
// where the correction below leaves a gap g^ >= 0 instead, the side may close it over the next step (without that, a
// box resting on one edge holds the other up by the gap one step's fall opens, h^2 g: tilted for good).
// A side the impulses themselves drive into its surface within the step (a body landing on a limb pushes its other
// end down) joins them, and they are solved again (kMostImpulseRounds).
//
// The state then moves by the impulses' velocity change dv = A J^T p, and the configuration by the part of them
// that is a force the step did without, as the integrator would have moved it under that force spread over the
// step, so that a body resting or sticking on a slope does not creep:
//   v <- v + dv,  q <- q (+) w h A J^T (p - p_0),
// w the integrator's force position weight (integrator_descriptor.h), p_0 the impulses of the same problem with the
// rates at the step's start, J v_start (after the last step's impulses), where the side touched at the step before,
// else u: an impact's, what the approach the step found asks for (a body landing on the floor, and what its landing
// passes on to the other sides through the joints), which changes the velocity only. Both p and p_0 are functions
// of the state, which derivatives follow. The target's overlap left g^ = g - w h f u_n estimates the force's
// correction row by row: f = (J_n v_start - u_n) / -u_n, clamped to [0, 1], for a held side, else 0.
//
// The impulses solve Coulomb's problem by Newton's method on Alart and Curnier's function (coulomb_impulses.h),
// started from the last step's: Coulomb's problem itself, not a convex relaxation of it (Anitescu's cone
// complementarity would lift a sliding contact off at mu |u_t| per step). Where the contacts persist it takes one or
// two iterations; its solution meets the conditions to kImpulseTolerance of the largest rate, and its derivatives
// (Jets, the adjoint's replay) are the implicit function theorem's. Several contacts along one plane (a box's four
// corners, a humanoid's feet) make W singular: the motion is unique, the impulses are not, the solver's
// regularization picks small ones, and its solution is accepted to kImpulseAccuracy of the largest rate change the
// impulses make (a degenerate problem converges linearly). A run whose solves do not converge goes on with the last
// iterate (within the cones) and is warned of once.
#include <algorithm>
#include <cmath>
#include <sstream>
#include <type_traits>

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
// speed's), or to kImpulseAccuracy of the largest rate change W_rr p_r of the last impulses where W is singular
constexpr double kImpulseTolerance = 1e-10;
constexpr double kImpulseAccuracy = 1e-6;

// solves of one step's impulses at most: the first, and again where they drove sides apart into their surfaces
constexpr int kMostImpulseRounds = 3;

template <typename T>
T RowRate(const Model<T>& model, const ConstraintRow<T>& row, const VecX<T>& v) {
  return Dot(model, row.a, v) + Dot(model, row.b, v);
}

// the largest velocity component
template <typename T>
double Fastest(const VecX<T>& v) {
  double fastest = 0.0;
  for (Eigen::Index k = 0; k < v.size(); ++k) fastest = std::max(fastest, std::abs(Value(v[k])));
  return fastest;
}

// whether two rows act on a common body (M^-1 couples nothing else)
template <typename T>
bool Shared(const ConstraintRow<T>& x, const ConstraintRow<T>& y) {
  const auto on = [&](int body) { return body != kWorld && (body == y.a.body || body == y.b.body); };
  return on(x.a.body) || on(x.b.body);
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
    NearPairs(model_, contacts_, ws.frames, q, 2.0 * step * Fastest(v) * (1.0 + LengthScale(model_)), &near_);
  }
  candidates_.clear();
  for (int i = 0; i < size(); ++i) {
    const Side& side = sides_[i];
    if (side.feature >= 0 && !near_[contacts_.features[side.feature].pair]) continue;  // every gap positive
    const Gap gap = GapAt(i, q, v, ws);
    const double g = Value(gap.g), closing = g + step * Value(gap.rate);
    if (g < 0.0 || closing < 0.0) {
      step_sides_.push_back(i);
      step_gaps_.push_back(gap);
    } else {
      candidates_.push_back({i, g});
    }
  }
}

template <typename T>
bool UnilateralEvents<T>::AddSidesClosedByImpulses(double step, const VecX<T>& q, const VecX<T>& v,
                                                   const Workspace<T>& ws) {
  const double reach = step * Fastest(v) * (1.0 + LengthScale(model_));  // no point moves farther over the step
  std::vector<int> sides;                                                // step_sides_ and the sides added, in order
  std::vector<Gap> gaps;
  std::vector<Candidate> left;
  size_t next = 0;
  for (const Candidate& candidate : candidates_) {
    const Gap gap = candidate.gap < reach ? GapAt(candidate.side, q, v, ws) : Gap{};
    if (candidate.gap >= reach || Value(gap.g) + step * Value(gap.rate) >= 0.0) {
      left.push_back(candidate);
      continue;
    }
    for (; next < step_sides_.size() && step_sides_[next] < candidate.side; ++next) {
      sides.push_back(step_sides_[next]);
      gaps.push_back(step_gaps_[next]);
    }
    sides.push_back(candidate.side);
    gaps.push_back(gap);  // its rate: the approach the impulses gave it
  }
  if (left.size() == candidates_.size()) return false;
  candidates_.swap(left);
  sides.insert(sides.end(), step_sides_.begin() + next, step_sides_.end());
  gaps.insert(gaps.end(), step_gaps_.begin() + next, step_gaps_.end());
  step_sides_.swap(sides);
  step_gaps_.swap(gaps);
  return true;
}

template <typename T>
void UnilateralEvents<T>::StepRows(double step, const VecX<T>& v_start, const VecX<T>& q, const VecX<T>& v,
                                   const Workspace<T>& ws) {
  const double w = Describe(model_.simulation.integrator).force_position_weight;
  const T k = step * ws.beta / (1.0 + step * ws.alpha);
  blocks_.clear();
  step_rows_.clear();
  std::vector<T> targets, rates, start;  // per row: b, u, and J v_start where the side touched at the step before
  for (size_t s = 0; s < step_sides_.size(); ++s) {
    const int i = step_sides_[s];
    const Side& side = sides_[i];
    StepBlock block;
    block.side = i;
    block.first_row = static_cast<Eigen::Index>(step_rows_.size());
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
    for (size_t r = static_cast<size_t>(block.first_row); r < step_rows_.size(); ++r) {
      rates.push_back(RowRate(model_, step_rows_[r], v));
      start.push_back(touching_[i] ? RowRate(model_, step_rows_[r], v_start) : rates.back());
    }
    const T& gap = step_gaps_[s].g;
    const T& rate = rates[block.first_row];
    const T e = touching_[i] ? T(0.0) : Restitution(side);
    if (Value(gap) >= 0.0) {  // closing within the next step: no faster than to touch at its end, or bouncing now
      const bool closing = Value(gap) + step * Value(rate) < 0.0;
      targets.push_back(Value(e) > 0.0 && closing ? T(-e * rate) : T(-gap / step));
    } else {
      // the overlap left once the held side's forces have moved the configuration: they cancel the approach the
      // step added to its rate, the fraction f of it
      T f(0.0);
      if (touching_[i] && Value(rate) < 0.0) {
        const T fraction = (start[block.first_row] - rate) / -rate;
        f = Value(fraction) <= 0.0 ? T(0.0) : Value(fraction) >= 1.0 ? T(1.0) : fraction;
      }
      const T left = gap - w * step * f * rate;  // g^
      if (Value(left) >= 0.0) {  // the force's correction leaves a gap: closing it over the next step is free
        targets.push_back(-left / step);
      } else {
        targets.push_back((Value(rate) < 0.0 ? -e * rate : T(0.0)) - k * left);
      }
    }
    for (int t = 1; t < block.rows; ++t) targets.push_back(T(0.0));
    blocks_.push_back(block);
  }
  const auto n = static_cast<Eigen::Index>(step_rows_.size());
  targets_ = Eigen::Map<VecX<T>>(targets.data(), n);
  free_rates_ = Eigen::Map<VecX<T>>(rates.data(), n);
  start_rates_ = Eigen::Map<VecX<T>>(start.data(), n);
}

// W from its factors: per row r, x_r = M^-1 J_r^T (a unit impulse's velocity change were there no equality rows),
// z_r = G x_r (what it does to the equality rows' rates) and s_r = S^-1 z_r (their impulses' answer), so that
//   W_rc = J_r x_c - z_r . s_c,   A J^T p = X p - M^-1 G^T S^-1 G X p.
// In double z_r . s_c is y_r . y_c with y = F^-1 z, S = F F^T (SchurSolver::HalfSolveInPlace): half a solve a row.
template <typename T>
bool UnilateralEvents<T>::Delassus(bool factor, Workspace<T>* ws) {
  const Eigen::Index n = static_cast<Eigen::Index>(step_rows_.size()), m = static_cast<Eigen::Index>(ws->rows.size());
  free_moves_.resize(std::max(free_moves_.size(), step_rows_.size()));
  couplings_.resize(m, n);
  reactions_.resize(m, n);
  bool halves = std::is_same_v<T, double>;
  for (Eigen::Index c = 0; c < n; ++c) {
    VecX<T>& x = free_moves_[c];
    x.setZero(model_.NumVelocities());
    AddScaled(model_, step_rows_[c].a, T(1.0), &x);
    AddScaled(model_, step_rows_[c].b, T(1.0), &x);
    ApplyInverseMass(model_, ws->inverse_mass, x, &x);
    if (m == 0) continue;
    CouplingOf(c, *ws, &ws->kkt.rhs);
    if (factor && c == 0 && !ws->solver->Solve(ws->kkt.schur, ws->kkt.rhs, &ws->kkt.lambda, SchurSourceOf(*ws)))
      return false;
    if constexpr (std::is_same_v<T, double>) {
      halves = halves && ws->solver->HalfSolveInPlace(&ws->kkt.rhs);
      if (halves) {
        couplings_.col(c) = ws->kkt.rhs;  // y_c
        continue;
      }
      CouplingOf(c, *ws, &ws->kkt.rhs);
    }
    couplings_.col(c) = ws->kkt.rhs;
    if (!ws->solver->SolveAgain(ws->kkt.schur, ws->kkt.rhs, &ws->kkt.lambda, SchurSourceOf(*ws))) return false;
    reactions_.col(c) = ws->kkt.lambda;
  }
  if (halves && m > 0) {
    delassus_.noalias() = -couplings_.transpose().lazyProduct(couplings_);  // y_r . y_c: y fills in
  } else {
    delassus_.setZero(n, n);
  }
  for (Eigen::Index c = 0; c < n; ++c) {  // W is symmetric (A is): its upper triangle, mirrored
    for (Eigen::Index r = 0; r <= c; ++r) {
      if (Shared(step_rows_[r], step_rows_[c])) delassus_(r, c) += RowRate(model_, step_rows_[r], free_moves_[c]);
      for (Eigen::Index i = 0; !halves && i < m; ++i) {  // z_r . s_c over z_r's nonzeros (CouplingOf)
        if (Shared(ws->rows[i], step_rows_[r])) delassus_(r, c) -= couplings_(i, r) * reactions_(i, c);
      }
      delassus_(c, r) = delassus_(r, c);
    }
  }
  solved_reactions_ = !halves;
  return true;
}

template <typename T>
void UnilateralEvents<T>::CouplingOf(Eigen::Index c, const Workspace<T>& ws, VecX<T>* z) const {
  z->setZero(static_cast<Eigen::Index>(ws.rows.size()));
  for (size_t i = 0; i < ws.rows.size(); ++i) {  // the equality rows that share a body with row c
    if (!Shared(ws.rows[i], step_rows_[c])) continue;
    (*z)[i] = RowRate(model_, ws.rows[i], free_moves_[c]);
  }
}

template <typename T>
VecX<T> UnilateralEvents<T>::VelocityChange(const VecX<T>& impulses, Workspace<T>* ws) const {
  VecX<T> dv = VecX<T>::Zero(model_.NumVelocities());
  for (Eigen::Index c = 0; c < impulses.size(); ++c) dv += free_moves_[c] * impulses[c];
  if (ws->rows.empty()) return dv;
  if (solved_reactions_) {
    ws->kkt.lambda = reactions_ * impulses;
  } else {  // S^-1 G X p
    MultiplyJacobian(model_, dv, ws);
    ws->solver->SolveAgain(ws->kkt.schur, ws->kkt.rhs, &ws->kkt.lambda, SchurSourceOf(*ws));
  }
  ApplyReaction(model_, ws, &ws->reaction);
  return dv - ws->reaction;
}

template <typename T>
bool UnilateralEvents<T>::SolveImpulses(const VecX<T>& rates, bool warm, VecX<T>* impulses) {
  impulses->setZero(rates.size());
  impulse_blocks_.assign(blocks_.begin(), blocks_.end());
  for (const StepBlock& block : blocks_) {  // from the impulses of the step before, where the side touched then
    for (int r = 0; warm && r < block.rows; ++r)
      (*impulses)[block.first_row + r] = T(last_impulses_[kImpulseStride * block.side + r]);
  }
  // the rates' largest, and the largest change the impulses of the step before (or this step's whole impulses)
  // make to their own rows
  double fastest = kRestingSpeed, change = 0.0;
  const VecX<T>& reference = warm ? *impulses : impulses_;
  for (Eigen::Index r = 0; r < rates.size(); ++r) {
    fastest = std::max(fastest, std::abs(Value(rates[r])));
    change = std::max(change, std::abs(Value(delassus_(r, r)) * Value(reference[r])));
  }
  return impulse_solver_.Solve(delassus_, rates, targets_, impulse_blocks_, kImpulseTolerance * fastest, impulses,
                               kImpulseAccuracy * change, &degenerate_[warm ? 0 : 1]);
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
  VecX<T> dv = VecX<T>::Zero(model_.NumVelocities()), held = dv;  // all the impulses', their forces'
  if (!step_sides_.empty()) {
    if (!ws->rows.empty()) AssembleSchur(ws);
    // the impulses of one side can drive another that was apart into its surface within the step (a body landing
    // on a limb pushes its other end down): such sides join, and the impulses are solved again
    for (int round = 0;; ++round) {
      StepRows(step, v_start, *q, *v, *ws);
      StepImpulses(t, round == 0, ws, report);
      dv = VelocityChange(impulses_, ws);
      if (round + 1 == kMostImpulseRounds || !AddSidesClosedByImpulses(step, *q, VecX<T>(*v + dv), *ws)) break;
    }
    // the impulses' forces: less those that the rates at the step's start alone would have asked for (an impact's,
    // the whole impulse of a side that did not touch at the step before)
    if (!SolveImpulses(start_rates_, false, &impact_impulses_)) WarnUnsolved(t, report);
    held = VelocityChange(VecX<T>(impulses_ - impact_impulses_), ws);
  }
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
    report->events.push_back(EventAt(t, "release", i, rate, rate, 0.0, *q, *ws));
  }
  if (step_sides_.empty()) return;
  CheckEnergy(t, dv);
  *v += dv;
  VecX<T> moved(q->size());
  Integrate(model_, *q, held, Describe(model_.simulation.integrator).force_position_weight * step, &moved);
  q->swap(moved);
  const VecX<T>& measured = moved;               // the step's configuration, where the frames are
  for (size_t b = 0; b < blocks_.size(); ++b) {  // a side touches where it overlaps or its impulse pushes
    const StepBlock& block = blocks_[b];
    const int i = block.side;
    const double rate = Value(step_gaps_[b].rate);  // its approach: at the step's end, or after other sides' impulses
    const double after = Value(free_rates_[block.first_row] + delassus_.row(block.first_row).dot(impulses_));
    for (int r = 0; r < block.rows; ++r) last_impulses_[kImpulseStride * i + r] = Value(impulses_[block.first_row + r]);
    const bool touches = Value(step_gaps_[b].g) < 0.0 || Value(impulses_[block.first_row]) > 0.0;
    if (touches && !touching_[i] && rate < -kRestingSpeed) {
      const double impulse = Value(impulses_[block.first_row]);
      report->events.push_back(EventAt(t, "impact", i, rate, after, impulse, measured, *ws));
    } else if (!touches && touching_[i]) {
      report->events.push_back(EventAt(t, "release", i, rate, rate, 0.0, measured, *ws));
    }
    touching_[i] = touches;
  }
}

template <typename T>
void UnilateralEvents<T>::StepImpulses(double t, bool factor, Workspace<T>* ws, RunReport* report) {
  if (!Delassus(factor, ws)) {
    throw SimulationDiverged("the simulation diverged at t = " + std::to_string(t) +
                                 " s: the constraint system became singular or non-finite",
                             t, -1);
  }
  if (!SolveImpulses(free_rates_, true, &impulses_)) WarnUnsolved(t, report);
}

template <typename T>
void UnilateralEvents<T>::WarnUnsolved(double t, RunReport* report) {
  if (unsolved_warned_) return;
  unsolved_warned_ = true;
  std::ostringstream out;
  out << "t = " << t << " s: the contact impulses did not converge (" << impulse_solver_.newton_iterations()
      << " Newton iterations, " << impulse_solver_.sweeps()
      << " Gauss-Seidel sweeps); the run goes on with the last ones (within the friction cones)";
  report->warnings.push_back(out.str());
}

#define TETHER_INSTANTIATE_UNILATERAL_STEPPING(T)                                                                    \
  template void UnilateralEvents<T>::StepContacts(double, double, const VecX<T>&, VecX<T>*, VecX<T>*, Workspace<T>*, \
                                                  RunReport*);                                                       \
  template void UnilateralEvents<T>::StepSides(double, const VecX<T>&, const VecX<T>&, const Workspace<T>&);         \
  template void UnilateralEvents<T>::StepRows(double, const VecX<T>&, const VecX<T>&, const VecX<T>&,                \
                                              const Workspace<T>&);                                                  \
  template bool UnilateralEvents<T>::Delassus(bool, Workspace<T>*);                                                  \
  template VecX<T> UnilateralEvents<T>::VelocityChange(const VecX<T>&, Workspace<T>*) const;                         \
  template void UnilateralEvents<T>::CouplingOf(Eigen::Index, const Workspace<T>&, VecX<T>*) const;                  \
  template bool UnilateralEvents<T>::SolveImpulses(const VecX<T>&, bool, VecX<T>*);                                  \
  template void UnilateralEvents<T>::StepImpulses(double, bool, Workspace<T>*, RunReport*);                          \
  template void UnilateralEvents<T>::WarnUnsolved(double, RunReport*);                                               \
  template bool UnilateralEvents<T>::AddSidesClosedByImpulses(double, const VecX<T>&, const VecX<T>&,                \
                                                              const Workspace<T>&);                                  \
  template void UnilateralEvents<T>::CheckEnergy(double, const VecX<T>&) const;
TETHER_FOR_EACH_SCALAR(TETHER_INSTANTIATE_UNILATERAL_STEPPING)

}  // namespace tether
