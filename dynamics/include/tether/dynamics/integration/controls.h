// Controls: the numbers a controller sets between the steps of a run it takes itself (docs/stepping.md). A
// control is a `joint_torque`'s value or a `joint_servo`'s target, named by its joint's name (when exactly one
// such effect acts on that joint) or by the effect's JSON Pointer, /effects/K. Setting a control writes the
// model the stepper reads (Stepper holds the model by reference, and the effects are read at every evaluation),
// so the next step sees it: a held value, like a zero-order hold, that replaces the effect's schedule, if any,
// from then on. Nothing else changes, so a run whose controls are never set is the run Simulate makes.
#pragma once

#include <string>
#include <vector>

#include "tether/dynamics/model/model.h"

namespace tether {

struct Control {
  enum class Kind { kJointTorque, kServoTarget };
  Kind kind = Kind::kJointTorque;
  int index = 0;     // into Model::joint_torques or Model::joint_servos
  std::string name;  // as asked, for messages
};

// The control called `name`; InputError naming the controls there are when none or several match.
Control FindControl(const Model<double>& model, const std::string& name);

// Holds `value` (N m or N for a torque, rad or m for a target) from now on; a non-finite value is an InputError.
void SetControl(const Control& control, double value, Model<double>* model);

// The control's value at time t (its schedule's there, when it still has one).
double ControlValue(const Control& control, const Model<double>& model, double t);

// What the controls of a model hold (every joint_torque and joint_servo, schedules included), to put back with
// the state a controller saved (a reset, a rollout).
struct ControlSettings {
  std::vector<JointTorqueEffect<double>> joint_torques;
  std::vector<JointServoEffect<double>> joint_servos;
};
ControlSettings SaveControls(const Model<double>& model);
void RestoreControls(const ControlSettings& settings, Model<double>* model);

}  // namespace tether
