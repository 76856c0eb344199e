#include "tether/dynamics/integration/controls.h"

#include <algorithm>
#include <cmath>

#include "tether/dynamics/model/errors.h"

namespace tether {
namespace {

// Every control of the model, as a pointer /effects/K and the joint it acts on, in the scene's order.
struct Named {
  Control control;
  int scene_index = 0;
  std::string pointer, joint;
};

std::vector<Named> AllControls(const Model<double>& model) {
  std::vector<Named> all;
  const auto add = [&](Control::Kind kind, size_t k, int scene_index, int joint) {
    Named n;
    n.control.kind = kind;
    n.control.index = static_cast<int>(k);
    n.scene_index = scene_index;
    n.pointer = "/effects/" + std::to_string(scene_index);
    n.joint = model.joints[joint].name;
    all.push_back(n);
  };
  for (size_t k = 0; k < model.joint_torques.size(); ++k) {
    add(Control::Kind::kJointTorque, k, model.joint_torques[k].scene_index, model.joint_torques[k].joint);
  }
  for (size_t k = 0; k < model.joint_servos.size(); ++k) {
    add(Control::Kind::kServoTarget, k, model.joint_servos[k].scene_index, model.joint_servos[k].joint);
  }
  std::sort(all.begin(), all.end(), [](const Named& a, const Named& b) { return a.scene_index < b.scene_index; });
  return all;
}

std::string Describe(const Named& n) {
  return n.pointer +
         (n.control.kind == Control::Kind::kJointTorque ? " (the joint_torque on '" : " (the joint_servo on '") +
         n.joint + "')";
}

}  // namespace

Control FindControl(const Model<double>& model, const std::string& name) {
  const std::vector<Named> all = AllControls(model);
  std::vector<const Named*> matches;
  for (const Named& n : all) {
    if (n.pointer == name || (!n.joint.empty() && n.joint == name)) matches.push_back(&n);
  }
  if (matches.size() == 1) {
    Control control = matches.front()->control;
    control.name = name;
    return control;
  }
  std::string choices;
  for (const Named& n : all) choices += (choices.empty() ? "" : ", ") + Describe(n);
  if (matches.empty()) {
    throw InputError(
        "no control '" + name + "': a control is a joint_torque's value or a joint_servo's target, " +
        (all.empty() ? std::string("and the scene has none") : "named by its joint or /effects/K: " + choices));
  }
  std::string found;
  for (const Named* n : matches) found += (found.empty() ? "" : ", ") + Describe(*n);
  throw InputError("'" + name + "' names several controls (" + found + "): name one by its pointer");
}

void SetControl(const Control& control, double value, Model<double>* model) {
  if (!std::isfinite(value)) {
    throw InputError("control '" + control.name + "': expected a finite number, got " + std::to_string(value));
  }
  if (control.kind == Control::Kind::kJointTorque) {
    auto& e = model->joint_torques[control.index];
    e.value = value;
    e.schedule = {};
  } else {
    auto& e = model->joint_servos[control.index];
    e.target = value;
    e.schedule = {};
  }
}

double ControlValue(const Control& control, const Model<double>& model, double t) {
  if (control.kind == Control::Kind::kJointTorque) {
    const auto& e = model.joint_torques[control.index];
    return e.schedule.empty() ? e.value : ScheduleValue(e.schedule, t);
  }
  return model.joint_servos[control.index].Target(t);
}

ControlSettings SaveControls(const Model<double>& model) { return {model.joint_torques, model.joint_servos}; }

void RestoreControls(const ControlSettings& settings, Model<double>* model) {
  model->joint_torques = settings.joint_torques;
  model->joint_servos = settings.joint_servos;
}

}  // namespace tether
