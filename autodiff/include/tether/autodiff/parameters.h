// Parameters: numeric leaves of a scene named by JSON Pointers (RFC 6901), bound to the model fields they set,
// so that a Model<T> can carry them as T (a Jet seeds their derivative directions).
//
// Differentiable: /bodies/i/{mass, inertia (planar), inertia/k (3D principal moment), inertia/r/c (3D tensor:
// a product of inertia names both I_rc and I_cr, which follow it together), position/k, angle, orientation/k,
// velocity/k, angular_velocity[/k]}; /constraints/i/{length, points/j/k, axis/k, axes/j/k, angle};
// /markers/i/point/k; /effects/i/{acceleration/k (gravity), coefficient, angular_coefficient (damping),
// stiffness, rest_length, damping, points/j/k (spring), value[/k], point/k, schedule/values/j[/k] (force,
// torque, joint_torque), stiffness, rest, damping (joint_spring)}; /stabilization/{alpha, beta}.
// Refused with a message naming the file and the pointer: pointers that are not in the scene file (a default
// must be written out to become a parameter), that name an array or object instead of a number, and leaves
// that are not differentiable (names, types, the integrator, step, duration, tolerance, schedule times).
#pragma once

#include <string>
#include <vector>

#include "tether/autodiff/tie_expression.h"
#include "tether/dynamics/io/scene_reader.h"

namespace tether {

// Where a parameter lives in a Model<T>.
struct FieldRef {
  enum class Kind {
    kMass, kInertia, kInertiaMoment, kInertiaProduct,
    kPosition, kAngle, kOrientation, kVelocity, kAngularVelocity,
    kJointLength, kJointPoint, kJointAxis, kJointAxisB, kJointAngle, kJointRange, kJointRestitution, kMarkerPoint,
    kGravity, kDampingCoefficient, kDampingAngular,
    kSpringStiffness, kSpringRestLength, kSpringDamping, kSpringPoint,
    kForceValue, kForcePoint, kForceSchedule, kTorqueValue, kTorqueSchedule,
    kJointTorqueValue, kJointTorqueSchedule, kJointSpringStiffness, kJointSpringRest, kJointSpringDamping,
    kAlpha, kBeta
  };
  Kind kind = Kind::kMass;
  int index = 0;      // body, marker, or position in the model's list of that kind of constraint or effect
  int slot = 0;       // which point (0: first body's, 1: second's), which schedule value, or a tensor's row
  int component = 0;  // vector component, or a tensor's column
};

// Whether a pointer ends in "/*": it stands for every element of the array before it (ParameterSet, bounds).
bool EndsInWildcard(const std::string& pointer);
// The pointers of the elements of the array that a pointer ending in "/*" names, in order; none where it names no
// non-empty array (the callers refuse it, naming their own file and entry).
std::vector<std::string> WildcardElements(const nlohmann::json& document, const std::string& pointer);

class ParameterSet {
 public:
  ParameterSet() = default;
  // Resolves every pointer against the scene; one that ends in "/*" stands for every element of the array it
  // ends in (/effects/2/schedule/values/* is /effects/2/schedule/values/0, /1, ...), and pointers() lists them so.
  // Throws InputError naming the file and the pointer.
  ParameterSet(const Scene& scene, const std::vector<std::string>& pointers);

  int size() const { return static_cast<int>(pointers_.size()); }
  const std::vector<std::string>& pointers() const { return pointers_; }
  const FieldRef& field(int i) const { return fields_[i]; }

  // The model field of parameter i.
  template <typename T>
  T& Field(Model<T>* model, int i) const;

  // Ties (`--tie PTR=EXPR`, tie_expression.h): each PTR follows its expression of other scene numbers
  // (parameters or not) instead of being an unknown, in the order given: a tie may name the pointers earlier ties
  // set, not its own nor a later one's. Throws InputError naming `flag` (and the scene file where a pointer does
  // not resolve): an unknown or non-differentiable pointer, a tied pointer that is also a parameter or tied twice,
  // and ties whose values at the scene's own numbers the scene format refuses (a mass tied to -1).
  void Tie(const Scene& scene, const std::vector<std::string>& ties, const std::string& flag = "--tie");
  bool tied() const { return !ties_.empty(); }
  // Sets the tied fields from the others; every place that sets the parameters in a model calls it after them.
  template <typename T>
  void ApplyTies(Model<T>* model) const;

  std::vector<double> Values(const Model<double>& model) const;
  // Sets the parameters, then the ties.
  void Assign(const std::vector<double>& values, Model<double>* model) const;
  // Writes the values into a scene document at their pointers, then the tied pointers' values from them (for
  // writing a scene back).
  void WriteInto(const std::vector<double>& values, nlohmann::json* document) const;
  // The scene with `values` (and the ties' values from them) written in and read again, through every check of
  // the scene format: one validation for every number that reaches a scene this way (a tie, an estimate written
  // back). Throws the reader's InputError, naming the pointer, when the format refuses it.
  Scene SceneWith(const Scene& scene, const std::vector<double>& values) const;

 private:
  struct TieRef {
    std::string pointer;
    FieldRef target;
    TieExpression expression;
    std::vector<FieldRef> references;  // of expression.references()
  };
  std::vector<std::string> pointers_;
  std::vector<FieldRef> fields_;
  std::vector<TieRef> ties_;
};

}  // namespace tether
