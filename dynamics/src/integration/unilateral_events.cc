#include "tether/dynamics/integration/unilateral_events.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <type_traits>

#include "tether/dynamics/constraints/active_set.h"
#include "tether/dynamics/constraints/contact_friction.h"
#include "tether/dynamics/effects/effects.h"
#include "tether/dynamics/model/configuration_space.h"
#include "tether/dynamics/model/errors.h"
#include "tether/dynamics/solvers/constrained_dynamics.h"

namespace tether {

template <typename T>
UnilateralEvents<T>::UnilateralEvents(const Model<T>& model)
    : model_(model), stepping_(model.simulation.contact == ContactMode::kStepping) {
  for (size_t j = 0; j < model.joints.size(); ++j) {
    const Joint<T>& joint = model.joints[j];
    if (!joint.range.declared()) continue;
    const JointKind& kind = JointKindOf(joint.type);
    const int k = kind.limitable ? CoordinateIndex(model, static_cast<int>(j), LimitedCoordinate(kind)) : -1;
    if (k < 0) {  // the scene reader refuses it; a model built in code may not have been through it
      throw InputError("constraint /constraints/" + std::to_string(joint.scene_index) +
                       " has a range but no coordinate to limit (hinge, prismatic, or a 2D pin between planar bodies)");
    }
    const std::string label = joint.name.empty() ? "/constraints/" + std::to_string(joint.scene_index) : joint.name;
    if (joint.range.has_low) sides_.push_back({static_cast<int>(j), k, 1, -1, label});
    if (joint.range.has_high) sides_.push_back({static_cast<int>(j), k, -1, -1, label});
  }
  if (!model.shapes.empty()) contacts_ = BuildContactGeometry(model);
  for (size_t f = 0; f < contacts_.features.size(); ++f) {
    sides_.push_back({-1, 0, 1, static_cast<int>(f), contacts_.pairs[contacts_.features[f].pair].label});
  }
  active_.assign(sides_.size(), 0);
  touching_.assign(sides_.size(), 0);
  last_impulses_.assign(kImpulseStride * sides_.size(), 0.0);
  held_slips_.assign(3 * sides_.size(), 0.0);
  acceleration_.setZero(model.NumVelocities());
}

template <typename T>
T UnilateralEvents<T>::Bound(const Side& side) const {
  const JointRange<T>& range = model_.joints[side.joint].range;
  return side.side > 0 ? range.low : range.high;
}

template <typename T>
T UnilateralEvents<T>::Restitution(const Side& side) const {
  if (side.feature < 0) return model_.joints[side.joint].range.restitution;
  const ContactFeature& feature = contacts_.features[side.feature];
  return PairRestitution(model_, feature.first, feature.second);
}

// The active sides' rows: the limits' first, then the contacts' (constraint_rows.h), each in side order.
template <typename T>
void UnilateralEvents<T>::Apply(Workspace<T>* ws) {
  std::vector<LimitPrimitive<T>> limits;
  std::vector<ContactPrimitive> contacts;
  active_order_.clear();
  for (size_t i = 0; i < sides_.size(); ++i) {
    if (!active_[i]) continue;
    const Side& side = sides_[i];
    active_order_.push_back(static_cast<int>(i));
    if (side.feature >= 0) {
      const ContactFeature& feature = contacts_.features[side.feature];
      const auto [a, b] = FeatureBodies(model_, feature);
      contacts.push_back({model_.NumConstraints() + feature.pair, a, b, feature, friction(static_cast<int>(i)),
                          HeldSlip(static_cast<int>(i))});
      continue;
    }
    const Joint<T>& joint = model_.joints[side.joint];
    limits.push_back({joint.scene_index, joint.a.body, joint.b.body, ws->coordinates.references[side.coordinate],
                      side.side, Bound(side)});
  }
  std::vector<int> key;  // the active sides and their friction: what the rows' layout depends on
  for (int i : active_order_) key.push_back(4 * i + active_[i]);
  ws->SetActiveGaps(model_, limits, contacts, key);
}

template <typename T>
void UnilateralEvents<T>::SetActiveSet(const std::vector<char>& active, const std::vector<double>& held_slips,
                                       Workspace<T>* ws) {
  if (active == active_ && held_slips == held_slips_) return;
  held_slips_ = held_slips;
  if (active == active_) return SyncHeldSlips(ws);
  active_ = active;
  Apply(ws);
}

template <typename T>
void UnilateralEvents<T>::SyncHeldSlips(Workspace<T>* ws) const {
  auto contact = ws->constraints.contacts.begin();
  for (int i : active_order_) {
    if (sides_[i].feature < 0) continue;
    contact->held_slip = HeldSlip(static_cast<int>(i));
    ++contact;
  }
}

template <typename T>
void UnilateralEvents<T>::Overlapping(const VecX<T>& q, Workspace<T>* ws, std::vector<int>* due) const {
  bool frames = false;  // updated at q, and the near pairs found, for the first contact
  for (int i = 0; i < size(); ++i) {
    if (active_[i]) continue;
    const Side& side = sides_[i];
    double gap = 0.0;
    if (side.feature < 0) {
      gap = TrackedGap(side, *ws);
    } else {
      if (!frames) {
        UpdateFrames(model_, q, q, false, &ws->frames);
        NearPairs(model_, contacts_, ws->frames, q, 0.0, &near_);
      }
      frames = true;
      const ContactFeature& feature = contacts_.features[side.feature];
      if (!near_[feature.pair]) continue;  // its bounding spheres are apart: every gap of the pair is positive
      gap = Value(FeatureGapValue(model_, feature, ws->frames, q));
    }
    if (gap < 0.0) due->push_back(i);
  }
}

template <typename T>
std::vector<typename UnilateralEvents<T>::GapState> UnilateralEvents<T>::Measure(const VecX<T>& q, const VecX<T>& v,
                                                                                 Workspace<T>* ws) const {
  UpdateFrames(model_, q, v, true, &ws->frames);
  std::vector<GapState> gaps(sides_.size());
  for (int i = 0; i < size(); ++i) {
    const Gap gap = GapAt(i, q, v, *ws);
    gaps[i] = {Value(gap.g), Value(gap.rate)};
  }
  return gaps;
}

template <typename T>
bool UnilateralEvents<T>::Multipliers(double t, const VecX<T>& q, const VecX<T>& v, Workspace<T>* ws,
                                      std::vector<double>* mu) {
  mu->clear();
  if (!ComputeAcceleration(model_, t, q, v, ws, &acceleration_)) return false;
  const size_t first = FirstGapRow(*ws);
  for (size_t j = 0; j < active_order_.size(); ++j) mu->push_back(-Value(ws->kkt.lambda[first + j]));
  return true;
}

template <typename T>
double UnilateralEvents<T>::EventValue(int i, double t, const VecX<T>& q, const VecX<T>& v, Workspace<T>* ws) {
  if (IsFrictionEvent(i)) return FrictionEventValue(i - size(), t, q, v, ws);
  if (!active_[i]) {
    const Side& side = sides_[i];
    if (side.feature < 0) return TrackedGap(side, *ws);
    UpdateFrames(model_, q, v, false, &ws->frames);
    return Value(FeatureGapValue(model_, contacts_.features[side.feature], ws->frames, q));
  }
  std::vector<double> mu;
  if (!Multipliers(t, q, v, ws, &mu)) return 0.0;
  const auto position = ActivePosition(i);
  return mu[position];
}

template <typename T>
double UnilateralEvents<T>::GapAcceleration(int i, double t, const VecX<T>& q, const VecX<T>& v, Workspace<T>* ws) {
  if (!ComputeAcceleration(model_, t, q, v, ws, &acceleration_)) return 0.0;
  const Side& side = sides_[i];
  if (side.feature >= 0) {
    ConstraintRow<T> row;
    EvaluateContactRow(model_, contacts_.features[side.feature], ws->frames, q, v, true, &row);
    return Value(Dot(model_, row.a, acceleration_) + Dot(model_, row.b, acceleration_) + row.bias);
  }
  const CoordinateRow<T> x = EvaluateCoordinate(model_, ws->coordinates, side.coordinate, ws->frames, q, v, true);
  const T rate = Dot(model_, x.a, acceleration_) + Dot(model_, x.b, acceleration_) +
                 CoordinateBias(model_, ws->coordinates.references[side.coordinate], ws->frames, q, v);
  return side.side * Value(rate);
}

template <typename T>
typename UnilateralEvents<T>::Gap UnilateralEvents<T>::GapOf(int i, const VecX<T>& q, const VecX<T>& v,
                                                             Workspace<T>* ws) const {
  UpdateFrames(model_, q, v, true, &ws->frames);
  return GapAt(i, q, v, *ws);
}

template <typename T>
typename UnilateralEvents<T>::Gap UnilateralEvents<T>::GapAt(int i, const VecX<T>& q, const VecX<T>& v,
                                                             const Workspace<T>& ws) const {
  const Side& side = sides_[i];
  if (side.feature >= 0) {
    const GapAndRate<T> gap = FeatureGap(model_, contacts_.features[side.feature], ws.frames, q, v);
    return {gap.g, gap.rate};
  }
  const CoordinateRow<T> x = EvaluateCoordinate(model_, ws.coordinates, side.coordinate, ws.frames, q, v, true);
  const T s(static_cast<double>(side.side));
  return {s * (x.value - Bound(side)), s * x.rate};
}

template <typename T>
void UnilateralEvents<T>::MoveAlongMotion(double t, const T& dt, VecX<T>* q, VecX<T>* v, Workspace<T>* ws) {
  if (!ComputeAcceleration(model_, t, *q, *v, ws, &acceleration_)) return;
  const VecX<T> increment = *v * dt;
  VecX<T> moved(q->size());
  Integrate(model_, *q, increment, 1.0, &moved);
  *q = moved;
  *v += acceleration_ * dt;
}

template <typename T>
T UnilateralEvents<T>::EventTimeSensitivity(double t, int i, VecX<T>* q, VecX<T>* v, Workspace<T>* ws,
                                            RunReport* report) {
  const Gap gap = GapOf(i, *q, *v, ws);
  if (std::abs(Value(gap.rate)) < kGrazingSpeed) {
    if constexpr (std::is_same_v<T, double>) return T(0.0);  // nothing is differentiated
    std::ostringstream out;
    out << "a grazing impact on " << sides_[i].label << " at t = " << t << " s (approach speed " << Value(gap.rate)
        << ", below " << kGrazingSpeed << "): the derivatives leave out its time's dependence on the parameters";
    report->warnings.push_back(out.str());
    return T(0.0);
  }
  T dt = -gap.g / gap.rate;
  dt -= T(Value(dt));
  MoveAlongMotion(t, dt, q, v, ws);
  return dt;
}

template <typename T>
std::vector<double> UnilateralEvents<T>::Impulse(const std::vector<int>& impacting, const std::vector<T>& target,
                                                 bool capture, const VecX<T>& q, VecX<T>* v, Workspace<T>* ws) {
  const std::vector<char> held = active_;
  std::vector<T> wanted(sides_.size(), T(0.0));  // g'+ of every side in the solve
  std::vector<char> kept(sides_.size(), 0);      // a capture's sides hold whatever their impulse
  for (size_t k = 0; k < impacting.size(); ++k) {
    active_[impacting[k]] = 1;
    wanted[impacting[k]] = target[k];
    kept[impacting[k]] = capture;
  }
  std::vector<char> struck(sides_.size(), 0);
  for (int i : impacting) struck[i] = 1;
  std::vector<char> set = active_;
  std::vector<double> drift;  // J v of the rows kept
  double work = 0.0;
  std::vector<double> of_side(sides_.size(), 0.0);
  const bool solved = SolveActiveSet(
      &set, kept, false,
      [&](const std::vector<char>& candidate, std::vector<int>* sides, std::vector<double>* impulses) {
        active_ = candidate;
        Apply(ws);
        EvaluateRows(model_, q, *v, false, ws);
        MultiplyJacobian(model_, *v, ws);
        const size_t first = FirstGapRow(*ws), end = first + active_order_.size();
        drift.assign(ws->rows.size(), 0.0);
        for (size_t r = 0; r < ws->rows.size(); ++r) {  // other rows keep J v; sides leave at their target rate
          const bool side = r >= first && r < end;
          if (!side || !struck[active_order_[r - first]]) drift[r] = Value(ws->kkt.rhs[r]);  // held: its drift
          ws->kkt.rhs[r] = side ? wanted[active_order_[r - first]] - ws->kkt.rhs[r] : T(0.0);
        }
        AssembleSchur(ws);
        if (!ws->solver->Solve(ws->kkt.schur, ws->kkt.rhs, &ws->kkt.lambda, SchurSourceOf(*ws))) return false;
        work = 0.0;  // what the kept rows' impulses do on their drift J v: energy they may add
        for (size_t r = 0; r < drift.size(); ++r) work += std::abs(Value(ws->kkt.lambda[r]) * drift[r]);
        *sides = active_order_;
        impulses->clear();
        std::fill(of_side.begin(), of_side.end(), 0.0);
        for (size_t j = 0; j < active_order_.size(); ++j) {
          impulses->push_back(Value(ws->kkt.lambda[first + j]));
          of_side[active_order_[j]] = impulses->back();
        }
        return true;
      });
  drift_work_ += work;
  if (solved) {  // the last solve is the active set's: v+ = v + M^-1 J^T P
    ApplyReaction(model_, ws, &ws->reaction);
    *v += ws->reaction;
  }
  active_ = held;
  Apply(ws);
  return of_side;
}

template <typename T>
RunEvent UnilateralEvents<T>::EventAt(double t, const char* kind, int i, double before, double after, double impulse,
                                      const VecX<T>& q, const Workspace<T>& ws) const {
  RunEvent event{t, kind, sides_[i].label, before, after};
  event.impulse = impulse;
  const Side& side = sides_[i];
  if (side.feature >= 0) {
    const ContactPoint<T> contact = ContactPointOf(model_, contacts_.features[side.feature], ws.frames, q, q, false);
    event.point = contact.on_a.position.unaryExpr([](const T& x) { return Value(x); });
    event.normal = contact.normal.unaryExpr([](const T& x) { return Value(x); });
  } else {
    const VecX<T> none;  // not read without velocities
    event.point =
        MovePoint(model_, ws.frames, model_.joints[side.joint].b, q, none, false).position.unaryExpr([](const T& x) {
          return Value(x);
        });
  }
  return event;
}

template <typename T>
void UnilateralEvents<T>::Resolve(double t, double step, int capture, int event, VecX<T>* q, VecX<T>* v,
                                  Workspace<T>* ws, RunReport* report) {
  const std::vector<char> was_active = active_;
  const int located = IsFrictionEvent(event) ? contacts_.features[sides_[event - size()].feature].pair : -1;
  if (located >= 0 && friction(event - size()) == Friction::kSlide) {  // a slip stops: no impact, no release
    const T stop = SlipStopSensitivity(t, located, q, v, ws);
    ChooseFriction(t, located, *q, *v, ws, report);
    MoveAlongMotion(t, -stop, q, v, ws);
    return;
  }
  std::vector<GapState> gaps = Measure(*q, *v, ws);
  if (capture >= 0) {  // held where it touches, at rest
    const double impulse = Impulse({capture}, {T(0.0)}, true, *q, v, ws)[capture];
    gaps = Measure(*q, *v, ws);
    report->events.push_back(EventAt(t, "impact", capture, gaps[capture].rate, 0.0, impulse, *q, *ws));
  }
  std::vector<int> impacting;
  for (int i = 0; i < size(); ++i) {
    if (!active_[i] && gaps[i].g <= kTouching && gaps[i].rate < -kRestingSpeed) impacting.push_back(i);
  }
  if (impacting.empty()) {
    HoldTouching(t, gaps, *q, *v, ws);
    ChooseFriction(t, located, *q, *v, ws, report);
  } else {
    // derivatives cross the impact through its time: the state is moved along the motion before it by the time's
    // sensitivity dt* (a zero value), resolved, and moved back along the motion after it (the saltation matrix);
    // doubles take the same steps with a zero that is exactly zero, one sequence of KKT solves for every scalar,
    // which the adjoint's replay of a double run relies on
    const T event_time = EventTimeSensitivity(t, impacting.front(), q, v, ws, report);
    gaps = Impacts(t, step, impacting, gaps, *q, v, ws, report);
    HoldTouching(t, gaps, *q, *v, ws);
    ChooseFriction(t, located, *q, *v, ws, report);
    MoveAlongMotion(t, -event_time, q, v, ws);
  }
  for (int i = 0; i < size(); ++i) {
    if (was_active[i] && !active_[i]) {
      report->events.push_back(EventAt(t, "release", i, gaps[i].rate, gaps[i].rate, 0.0, *q, *ws));
    }
  }
}

template <typename T>
std::vector<typename UnilateralEvents<T>::GapState> UnilateralEvents<T>::Impacts(double t, double step,
                                                                                 const std::vector<int>& impacting,
                                                                                 const std::vector<GapState>& before,
                                                                                 const VecX<T>& q, VecX<T>* v,
                                                                                 Workspace<T>* ws, RunReport* report) {
  std::vector<T> target;  // Newton's law, g'+ = -e g'-
  for (int i : impacting) target.push_back(-Restitution(sides_[i]) * GapOf(i, q, *v, ws).rate);
  const double energy = Value(KineticEnergy(model_, *v));
  drift_work_ = 0.0;
  std::vector<double> impulses = Impulse(impacting, target, false, q, v, ws);
  std::vector<GapState> after = Measure(q, *v, ws);
  for (int i : impacting) {  // a rebound that would land again within a sliver of the step is captured
    if (!(after[i].rate > kRestingSpeed)) continue;
    const double fall = GapAcceleration(i, t, q, *v, ws);
    if (fall < 0.0 && 2.0 * after[i].rate / -fall < kCaptureFlight * step) {
      const std::vector<double> capture = Impulse({i}, {T(0.0)}, true, q, v, ws);
      for (size_t k = 0; k < impulses.size(); ++k) impulses[k] += capture[k];
    }
  }
  after = Measure(q, *v, ws);
  // no impact gains energy (e <= 1, pushing impulses): a gain beyond round-off is a defect, reported as such
  const double gained = Value(KineticEnergy(model_, *v)) - energy;
  if (gained > drift_work_ + kImpactEnergyRoundoff * (1.0 + energy)) {
    std::ostringstream out;
    out << "the impact on " << sides_[impacting.front()].label << " at t = " << t << " s gained " << gained
        << " J of kinetic energy (a defect of the impact's solve: please report the scene)";
    throw SimulationDiverged(out.str(), t, -1);
  }
  for (int i : impacting) {
    report->events.push_back(EventAt(t, "impact", i, before[i].rate, after[i].rate, impulses[i], q, *ws));
  }
  return after;
}

template <typename T>
void UnilateralEvents<T>::HoldTouching(double t, const std::vector<GapState>& gaps, const VecX<T>& q, const VecX<T>& v,
                                       Workspace<T>* ws) {
  std::vector<char> candidate(sides_.size(), 0);  // touching sides at rest, and the held ones that stay
  for (int i = 0; i < size(); ++i) {
    const bool resting = std::abs(gaps[i].rate) <= kRestingSpeed;
    const bool held = gaps[i].rate <= kRestingSpeed;
    candidate[i] = active_[i] ? (held ? active_[i] : 0) : gaps[i].g <= kTouching && resting;
  }
  const std::vector<char> none(sides_.size(), 0);  // less those whose multiplier would pull, or is zero
  SolveActiveSet(&candidate, none, true,
                 [&](const std::vector<char>& set, std::vector<int>* sides, std::vector<double>* mu) {
                   SetActiveSet(set, held_slips_, ws);
                   *sides = active_order_;
                   return active_order_.empty() ? (mu->clear(), true) : Multipliers(t, q, v, ws, mu);
                 });
}

#define TETHER_INSTANTIATE_LIMIT_EVENTS(T) template class UnilateralEvents<T>;
TETHER_FOR_EACH_SCALAR(TETHER_INSTANTIATE_LIMIT_EVENTS)

}  // namespace tether
