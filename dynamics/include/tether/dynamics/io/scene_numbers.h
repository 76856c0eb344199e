// SceneNumbers: the scene reader's record of every number it read that a model field holds, by JSON Pointer
// (RFC 6901): the field (ModelField), the number's domain, and, for a schedule's value, which knot it is. The
// parameter set (autodiff/parameters.h) looks pointers up here, so a number is a parameter as soon as the reader
// binds it: adding an effect adds its numbers where the reader reads them, and nowhere else.
//
// Not bound, so not parameters: names, types, body references, the dimension, the integrator, step, duration,
// tolerance and solver, the stabilization method, schedule times (a knot moves its neighbours' meaning).
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "tether/dynamics/model/model_field.h"

namespace tether {

// What the scene format allows a number: any finite value, >= 0, > 0 (these two fitted in log space: they are
// quantities like masses and stiffnesses), or [0, 1] (a restitution).
enum class NumberDomain { kAny, kNonNegative, kPositive, kUnitInterval };

// A value of a schedule (piecewise linear in time, effects/schedule.h): the knots of one schedule share its
// pointer; `fit` smooths consecutive knots of one component.
struct ScheduleKnot {
  std::string schedule;       // the schedule's JSON Pointer
  int knot = 0;               // which of its times
  int component = 0;          // which component of a vector value (0 for a number)
  std::vector<double> times;  // the schedule's times, s
};

struct SceneNumber {
  int field = 0;  // the model field's identity: the two pointers of a product of inertia (I_rc, I_cr) share one
  NumberDomain domain = NumberDomain::kAny;
  ModelField access;
  std::optional<ScheduleKnot> knot;
};

class SceneNumbers {
 public:
  // Records a number at `pointer` held by a field of its own, or by `field` (Add's answer for an earlier pointer).
  int Add(const std::string& pointer, NumberDomain domain, ModelField access, std::optional<ScheduleKnot> knot = {},
          int field = -1);
  // The number at `pointer`, or nullptr where the reader bound none there.
  const SceneNumber* Find(const std::string& pointer) const;
  // Every pointer that names this field, in order (a product of inertia has two).
  std::vector<std::string> PointersOf(int field) const;
  const std::map<std::string, SceneNumber>& all() const { return numbers_; }

 private:
  std::map<std::string, SceneNumber> numbers_;
  int fields_ = 0;
};

}  // namespace tether
