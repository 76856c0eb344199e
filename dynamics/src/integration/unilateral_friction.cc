// UnilateralEvents' friction (unilateral_events.h, contact_friction.h; docs/contact.md, "Friction").
//
// Coulomb's law is applied to a pair of shapes as a whole: the active features of a touching pair (a box's corners
// on a floor) stick together or slide together, and the cone bounds the pair's total tangential force by mu times
// its total normal force. Several coplanar contacts share their forces in ways the motion does not fix (the
// solver's least-norm multipliers, schur_solver.h): a test corner by corner would read one of those sharings (a
// box resting on a slope would slip at its unloaded corners while the pair holds); the pair's totals do not
// depend on it. A sliding pair's features each take mu times their own normal force against the pair's one
// sliding direction (contact_friction.h).
#include <algorithm>
#include <cmath>
#include <sstream>

#include "tether/dynamics/integration/unilateral_events.h"
#include "tether/dynamics/model/errors.h"
#include "tether/dynamics/solvers/constrained_dynamics.h"

namespace tether {

template <typename T>
std::vector<std::vector<int>> UnilateralEvents<T>::ActiveByPair() const {
  std::vector<std::vector<int>> by_pair(contacts_.pairs.size());
  for (int i : active_order_) {
    if (sides_[i].feature >= 0) by_pair[contacts_.features[sides_[i].feature].pair].push_back(i);
  }
  return by_pair;
}

template <typename T>
Vec3<double> UnilateralEvents<T>::StickingForce(const std::vector<int>& sides, const VecX<T>& q, const VecX<T>& v,
                                                Workspace<T>* ws) const {
  // the slip rows follow the gap rows, d - 1 for each sticking contact in row order
  size_t row = FirstGapRow(*ws) + active_order_.size();
  Vec3<double> force = Vec3<double>::Zero();
  const int tangents = model_.dimension - 1;
  for (int i : active_order_) {
    if (friction(i) != Friction::kStick) continue;
    if (std::find(sides.begin(), sides.end(), i) != sides.end()) {
      const ContactPoint<T> contact =
          ContactPointOf(model_, contacts_.features[sides_[i].feature], ws->frames, q, v, false);
      Vec3<T> t[2];
      Tangents(model_.dimension, contact.normal, t);
      for (int k = 0; k < tangents; ++k) {  // the rows' force on b: -J^T lambda
        force -= Value(ws->kkt.lambda[row + k]) * t[k].unaryExpr([](const T& x) { return Value(x); });
      }
    }
    row += tangents;
  }
  return force;
}

template <typename T>
double UnilateralEvents<T>::ConeMargin(const std::vector<int>& sides, const VecX<T>& q, const VecX<T>& v,
                                       Workspace<T>* ws) const {
  const ContactFeature& feature = contacts_.features[sides_[sides.front()].feature];
  const double mu = Value(PairFriction(model_, feature.first, feature.second));
  const size_t first = FirstGapRow(*ws);
  double normal = 0.0;
  for (int i : sides) {
    const size_t position = ActivePosition(i);
    normal -= Value(ws->kkt.lambda[first + position]);
  }
  return mu * normal - StickingForce(sides, q, v, ws).norm();
}

template <typename T>
double UnilateralEvents<T>::SlipAlongHeld(const std::vector<int>& sides, const VecX<T>& q, const VecX<T>& v,
                                          Workspace<T>* ws) const {
  UpdateFrames(model_, q, v, true, &ws->frames);
  double along = 0.0;
  for (int i : sides) {
    const ContactPoint<T> contact =
        ContactPointOf(model_, contacts_.features[sides_[i].feature], ws->frames, q, v, true);
    along += TangentialSlip(contact).dot(HeldSlip(static_cast<int>(i)));
  }
  return along;
}

template <typename T>
double UnilateralEvents<T>::FrictionEventValue(int side, double t, const VecX<T>& q, const VecX<T>& v,
                                               Workspace<T>* ws) {
  const std::vector<int> sides = ActiveByPair()[contacts_.features[sides_[side].feature].pair];
  if (sides.empty()) return 1.0;  // released meanwhile: no friction event
  if (friction(sides.front()) == Friction::kSlide) return SlipAlongHeld(sides, q, v, ws);
  std::vector<double> mu;
  if (!Multipliers(t, q, v, ws, &mu)) return 0.0;
  return ConeMargin(sides, q, v, ws);
}

template <typename T>
void UnilateralEvents<T>::FrictionDue(double t, const VecX<T>& q, const VecX<T>& v, Workspace<T>* ws,
                                      std::vector<int>* due, bool solved) {
  for (const std::vector<int>& sides : ActiveByPair()) {
    if (sides.empty() || friction(sides.front()) == Friction::kNone) continue;
    double value = 0.0;
    if (friction(sides.front()) == Friction::kSlide) {
      value = SlipAlongHeld(sides, q, v, ws);
    } else {
      std::vector<double> mu;
      if (!solved && !Multipliers(t, q, v, ws, &mu)) continue;
      solved = true;
      value = ConeMargin(sides, q, v, ws);
    }
    if (value < 0.0) due->push_back(size() + sides.front());
  }
}

template <typename T>
void UnilateralEvents<T>::FollowSlips(double t, double step, const VecX<T>& q, const VecX<T>& v, Workspace<T>* ws) {
  bool solved = false;
  for (const std::vector<int>& sides : ActiveByPair()) {
    if (sides.empty() || friction(sides.front()) != Friction::kSlide) continue;
    if (!solved && !ComputeAcceleration(model_, t, q, v, ws, &acceleration_)) return;
    solved = true;
    Vec3<double> mean = Vec3<double>::Zero();  // the pair's mean slip, and its rate along it
    std::vector<ContactPoint<T>> contacts;
    for (int i : sides) {
      contacts.push_back(ContactPointOf(model_, contacts_.features[sides_[i].feature], ws->frames, q, v, true));
      mean += TangentialSlip(contacts.back()) / static_cast<double>(sides.size());
    }
    if (!(mean.norm() > kSlipDirectionSpeed)) continue;
    // the slip's deceleration by the pair's friction alone, at its first contact: mu sum_j N_j J_1 M^-1 J_j^T
    // (J_j the row s . u of contact j); across s the slip is steered at that rate over |u_t|
    const Vec3<double> s = mean / mean.norm();
    std::vector<ConstraintRow<T>> rows(sides.size());
    for (size_t j = 0; j < sides.size(); ++j)
      SlipRow(model_, ws->frames, contacts[j], Vec3<T>(s.cast<T>()), false, &rows[j]);
    const ContactFeature& feature = contacts_.features[sides_[sides.front()].feature];
    const double mu = Value(PairFriction(model_, feature.first, feature.second));
    VecX<T> force = VecX<T>::Zero(v.size()), response(v.size());
    for (size_t j = 0; j < sides.size(); ++j) {
      const size_t position = ActivePosition(sides[j]);
      const T normal(-mu * Value(ws->kkt.lambda[FirstGapRow(*ws) + position]));
      AddScaled(model_, rows[j].a, normal, &force);
      AddScaled(model_, rows[j].b, normal, &force);
    }
    ApplyInverseMass(model_, ws->inverse_mass, force, &response);
    const double deceleration = std::abs(Value(Dot(model_, rows[0].a, response) + Dot(model_, rows[0].b, response)));
    if (!(step * deceleration <= mean.norm())) continue;  // too slow a slip to steer by
    for (int i : sides) Hold(i, s);
  }
  if (solved) SyncHeldSlips(ws);
}

template <typename T>
T UnilateralEvents<T>::SlipStopSensitivity(double t, int pair, VecX<T>* q, VecX<T>* v, Workspace<T>* ws) {
  if (!ComputeAcceleration(model_, t, *q, *v, ws, &acceleration_)) return T(0.0);
  T slip(0.0), rate(0.0);
  const std::vector<int> sides = ActiveByPair()[pair];
  for (int i : sides) {
    const ContactPoint<T> contact =
        ContactPointOf(model_, contacts_.features[sides_[i].feature], ws->frames, *q, *v, true);
    ConstraintRow<T> row;
    const Vec3<double> held = HeldSlip(i);
    SlipRow(model_, ws->frames, contact, Vec3<T>(held.cast<T>()), true, &row);
    slip += Dot(model_, row.a, *v) + Dot(model_, row.b, *v);
    rate += Dot(model_, row.a, acceleration_) + Dot(model_, row.b, acceleration_) + row.bias;
  }
  if (!(std::abs(Value(rate)) > 0.0)) return T(0.0);
  T dt = -slip / rate;
  dt -= T(Value(dt));
  MoveAlongMotion(t, dt, q, v, ws);
  return dt;
}

template <typename T>
void UnilateralEvents<T>::ChooseFriction(double t, int located, const VecX<T>& q, const VecX<T>& v, Workspace<T>* ws,
                                         RunReport* report) {
  const std::vector<std::vector<int>> by_pair = ActiveByPair();
  const std::vector<char> before = active_;
  const auto set = [this](const std::vector<int>& sides, Friction f) {
    for (int i : sides) active_[i] = static_cast<char>(1 + static_cast<int>(f));
  };
  UpdateFrames(model_, q, v, true, &ws->frames);
  bool any = false;
  std::vector<size_t> slipping;  // the located pair whose force left the cone
  for (size_t pair = 0; pair < by_pair.size(); ++pair) {
    const std::vector<int>& sides = by_pair[pair];
    if (sides.empty()) continue;
    const ContactFeature& feature = contacts_.features[sides_[sides.front()].feature];
    if (!(Value(PairFriction(model_, feature.first, feature.second)) > 0.0)) {
      set(sides, Friction::kNone);
      continue;
    }
    any = true;
    double fastest = 0.0, along_held = 0.0;
    Vec3<double> mean = Vec3<double>::Zero();  // the pair's slip: its direction is the pair's
    for (int i : sides) {
      const Vec3<double> slip =
          TangentialSlip(ContactPointOf(model_, contacts_.features[sides_[i].feature], ws->frames, q, v, true));
      fastest = std::max(fastest, slip.norm());
      along_held += slip.dot(HeldSlip(static_cast<int>(i)));
      mean += slip / static_cast<double>(sides.size());
    }
    if (mean.norm() > kSlipDirectionSpeed) {
      for (int i : sides) Hold(i, mean / mean.norm());
    }
    // a pair slipping no faster than a resting speed may stick; so may one whose slip has turned back (a stop
    // located just past it)
    const Friction was = friction(sides.front());
    const bool stopped = was == Friction::kSlide && (along_held <= 0.0 || static_cast<int>(pair) == located);
    set(sides, fastest <= kRestingSpeed || stopped ? Friction::kStick : Friction::kSlide);
    if (static_cast<int>(pair) == located && was == Friction::kStick) slipping.push_back(pair);
  }
  if (!any) {
    if (active_ != before) Apply(ws);
    return;
  }
  Apply(ws);
  std::vector<double> mu;
  const auto solve = [&]() {
    if (Multipliers(t, q, v, ws, &mu)) return;
    if (ws->painleve >= 0) {
      const int row = ws->painleve;
      std::ostringstream out;
      out << "the simulation diverged at t = " << t << " s: Painleve's paradox at the contact "
          << contacts_.pairs[ws->infos[row].scene_index - model_.NumConstraints()].label
          << ": its sliding friction admits no consistent accelerations (the normal force would have to pull); a "
             "smaller friction coefficient, or the time-stepping mode, avoids it";
      throw SimulationDiverged(out.str(), t, ws->infos[row].scene_index);
    }
  };
  solve();
  bool switched = false;  // sticking pairs whose force leaves the cone slide, against it
  for (size_t pair = 0; pair < by_pair.size(); ++pair) {
    const std::vector<int>& sides = by_pair[pair];
    if (sides.empty() || friction(sides.front()) != Friction::kStick) continue;
    const bool left = std::find(slipping.begin(), slipping.end(), pair) != slipping.end();
    if (!left && ConeMargin(sides, q, v, ws) >= 0.0) continue;
    const Vec3<double> force = StickingForce(sides, q, v, ws);
    for (int i : sides) Hold(i, -force / force.norm());
    set(sides, Friction::kSlide);
    switched = true;
  }
  if (switched) {
    Apply(ws);
    solve();
  }
  for (const std::vector<int>& sides : by_pair) {  // a touching pair that changes is an event
    if (sides.empty()) continue;
    const int i = sides.front();
    const Friction was = before[i] ? static_cast<Friction>(before[i] - 1) : Friction::kNone;
    if (!before[i] || was == Friction::kNone || was == friction(i)) continue;
    const Gap gap = GapOf(i, q, v, ws);
    report->events.push_back(EventAt(t, friction(i) == Friction::kStick ? "stick" : "slip", i, Value(gap.rate),
                                     Value(gap.rate), 0.0, q, *ws));
  }
}

#define TETHER_INSTANTIATE_UNILATERAL_FRICTION(T)                                                                      \
  template std::vector<std::vector<int>> UnilateralEvents<T>::ActiveByPair() const;                                    \
  template Vec3<double> UnilateralEvents<T>::StickingForce(const std::vector<int>&, const VecX<T>&, const VecX<T>&,    \
                                                           Workspace<T>*) const;                                       \
  template double UnilateralEvents<T>::ConeMargin(const std::vector<int>&, const VecX<T>&, const VecX<T>&,             \
                                                  Workspace<T>*) const;                                                \
  template double UnilateralEvents<T>::SlipAlongHeld(const std::vector<int>&, const VecX<T>&, const VecX<T>&,          \
                                                     Workspace<T>*) const;                                             \
  template double UnilateralEvents<T>::FrictionEventValue(int, double, const VecX<T>&, const VecX<T>&, Workspace<T>*); \
  template void UnilateralEvents<T>::FrictionDue(double, const VecX<T>&, const VecX<T>&, Workspace<T>*,                \
                                                 std::vector<int>*, bool);                                             \
  template void UnilateralEvents<T>::FollowSlips(double, double, const VecX<T>&, const VecX<T>&, Workspace<T>*);       \
  template void UnilateralEvents<T>::ChooseFriction(double, int, const VecX<T>&, const VecX<T>&, Workspace<T>*,        \
                                                    RunReport*);                                                       \
  template T UnilateralEvents<T>::SlipStopSensitivity(double, int, VecX<T>*, VecX<T>*, Workspace<T>*);
TETHER_FOR_EACH_SCALAR(TETHER_INSTANTIATE_UNILATERAL_FRICTION)

}  // namespace tether
