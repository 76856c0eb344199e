#include "tether/autodiff/parameters.h"

#include <cstdlib>

#include "tether/dynamics/errors.h"

namespace tether {
namespace {

using nlohmann::json;
using Kind = FieldRef::Kind;

// Resolves one pointer; `fail` throws with the pointer named.
class Resolver {
 public:
  Resolver(const Scene& scene, const std::string& pointer) : scene_(scene), pointer_(pointer) {}

  FieldRef Resolve() {
    json::json_pointer ptr;
    try {
      ptr = json::json_pointer(pointer_);
    } catch (const json::exception&) {
      Fail("not a JSON Pointer (it must look like /bodies/0/mass)");
    }
    if (!scene_.document.contains(ptr)) {
      Fail("is not in the scene file (a value left to its default must be written out to become a parameter)");
    }
    const json& leaf = scene_.document.at(ptr);
    if (!leaf.is_number()) Fail("names " + std::string(leaf.type_name()) + ", not a number");
    tokens_ = Tokens();
    const std::string& section = tokens_[0];
    if (section == "bodies") return Body();
    if (section == "constraints") return Constraint();
    if (section == "effects") return Effect();
    if (section == "stabilization") return Gain();
    return NotDifferentiable();
  }

 private:
  [[noreturn]] void Fail(const std::string& message) const {
    throw InputError(scene_.path + ": " + pointer_ + ": " + message);
  }
  [[noreturn]] FieldRef NotDifferentiable() const { Fail("is not a differentiable parameter"); }

  std::vector<std::string> Tokens() const {
    std::vector<std::string> out;
    size_t start = 1;
    while (start <= pointer_.size()) {
      const size_t slash = pointer_.find('/', start);
      std::string token = pointer_.substr(start, slash == std::string::npos ? std::string::npos : slash - start);
      for (size_t k; (k = token.find("~1")) != std::string::npos;) token.replace(k, 2, "/");
      for (size_t k; (k = token.find("~0")) != std::string::npos;) token.replace(k, 2, "~");
      out.push_back(token);
      if (slash == std::string::npos) break;
      start = slash + 1;
    }
    return out;
  }
  // token k as an index (the pointer exists, so array tokens are valid indices)
  int Index(size_t k) const { return std::atoi(tokens_.at(k).c_str()); }
  bool Is(size_t k, const char* key) const { return tokens_.size() > k && tokens_[k] == key; }

  FieldRef Body() const {
    const Model<double>& m = scene_.model;
    const int i = Index(1);
    const tether::Body<double>& body = m.bodies[i];
    if (Is(2, "mass")) return {Kind::kMass, i};
    if (Is(2, "inertia")) return {Kind::kInertia, i};
    if (Is(2, "position")) return {Kind::kInitialPosition, i, 0, body.offset + Index(3)};
    if (Is(2, "angle")) return {Kind::kInitialPosition, i, 0, body.offset + 2};
    if (Is(2, "velocity")) return {Kind::kInitialVelocity, i, 0, body.offset + Index(3)};
    if (Is(2, "angular_velocity")) return {Kind::kInitialVelocity, i, 0, body.offset + 2};
    return NotDifferentiable();
  }

  template <typename List>
  static int PositionOf(const List& list, int scene_index) {
    for (size_t k = 0; k < list.size(); ++k) {
      if (list[k].scene_index == scene_index) return static_cast<int>(k);
    }
    return -1;
  }

  FieldRef Constraint() const {
    const Model<double>& m = scene_.model;
    const int i = Index(1);
    const bool point = Is(2, "points");
    if (const int k = PositionOf(m.distances, i); k >= 0) {
      if (Is(2, "length")) return {Kind::kDistanceLength, k};
      if (point) return {Kind::kDistancePoint, k, Index(3), Index(4)};
    } else if (const int k = PositionOf(m.pins, i); k >= 0) {
      if (point) return {Kind::kPinPoint, k, Index(3), Index(4)};
    } else if (const int k = PositionOf(m.sliders, i); k >= 0) {
      if (point) return {Kind::kSliderPoint, k, Index(3), Index(4)};
      if (Is(2, "axis")) return {Kind::kSliderAxis, k, 0, Index(3)};
    }
    return NotDifferentiable();
  }

  FieldRef Effect() const {
    const Model<double>& m = scene_.model;
    const int i = Index(1);
    if (const int k = PositionOf(m.gravity, i); k >= 0) {
      if (Is(2, "acceleration")) return {Kind::kGravity, k, 0, Index(3)};
    } else if (const int k = PositionOf(m.damping, i); k >= 0) {
      if (Is(2, "coefficient")) return {Kind::kDampingCoefficient, k};
      if (Is(2, "angular_coefficient")) return {Kind::kDampingAngular, k};
    } else if (const int k = PositionOf(m.springs, i); k >= 0) {
      if (Is(2, "stiffness")) return {Kind::kSpringStiffness, k};
      if (Is(2, "rest_length")) return {Kind::kSpringRestLength, k};
      if (Is(2, "damping")) return {Kind::kSpringDamping, k};
      if (Is(2, "points")) return {Kind::kSpringPoint, k, Index(3), Index(4)};
    } else if (const int k = PositionOf(m.forces, i); k >= 0) {
      if (Is(2, "value")) return {Kind::kForceValue, k, 0, Index(3)};
      if (Is(2, "point")) return {Kind::kForcePoint, k, 0, Index(3)};
      if (Is(2, "schedule") && Is(3, "values")) return {Kind::kForceSchedule, k, Index(4), Index(5)};
    } else if (const int k = PositionOf(m.torques, i); k >= 0) {
      if (Is(2, "value")) return {Kind::kTorqueValue, k};
      if (Is(2, "schedule") && Is(3, "values")) return {Kind::kTorqueSchedule, k, Index(4)};
    }
    return NotDifferentiable();
  }

  FieldRef Gain() const {
    if (Is(1, "alpha")) return {Kind::kAlpha};
    if (Is(1, "beta")) return {Kind::kBeta};
    return NotDifferentiable();
  }

  const Scene& scene_;
  const std::string& pointer_;
  std::vector<std::string> tokens_;
};

// The field of a Model<T> (const or not) that f names.
template <typename M>
auto& FieldOf(M* m, const FieldRef& f) {
  auto point = [&f](auto& element) -> auto& { return f.slot == 0 ? element.a.local : element.b.local; };
  switch (f.kind) {
    case Kind::kMass: return m->bodies[f.index].mass;
    case Kind::kInertia: return m->bodies[f.index].inertia;
    case Kind::kInitialPosition: return m->q0[f.component];
    case Kind::kInitialVelocity: return m->v0[f.component];
    case Kind::kDistanceLength: return m->distances[f.index].length;
    case Kind::kDistancePoint: return point(m->distances[f.index])[f.component];
    case Kind::kPinPoint: return point(m->pins[f.index])[f.component];
    case Kind::kSliderPoint: return point(m->sliders[f.index])[f.component];
    case Kind::kSliderAxis: return m->sliders[f.index].axis[f.component];
    case Kind::kGravity: return m->gravity[f.index].acceleration[f.component];
    case Kind::kDampingCoefficient: return m->damping[f.index].coefficient;
    case Kind::kDampingAngular: return m->damping[f.index].angular_coefficient;
    case Kind::kSpringStiffness: return m->springs[f.index].stiffness;
    case Kind::kSpringRestLength: return m->springs[f.index].rest_length;
    case Kind::kSpringDamping: return m->springs[f.index].damping;
    case Kind::kSpringPoint: return point(m->springs[f.index])[f.component];
    case Kind::kForceValue: return m->forces[f.index].value[f.component];
    case Kind::kForcePoint: return m->forces[f.index].point[f.component];
    case Kind::kForceSchedule: return m->forces[f.index].schedule.values[f.slot][f.component];
    case Kind::kTorqueValue: return m->torques[f.index].value;
    case Kind::kTorqueSchedule: return m->torques[f.index].schedule.values[f.slot];
    case Kind::kAlpha: return m->stabilization.alpha;
    case Kind::kBeta: return m->stabilization.beta;
  }
  return m->stabilization.beta;  // unreachable: the switch covers every kind
}

}  // namespace

ParameterSet::ParameterSet(const Scene& scene, const std::vector<std::string>& pointers) {
  for (const std::string& pointer : pointers) {
    for (const std::string& seen : pointers_) {
      if (seen == pointer) throw InputError(scene.path + ": " + pointer + ": named twice as a parameter");
    }
    fields_.push_back(Resolver(scene, pointer).Resolve());
    pointers_.push_back(pointer);
  }
}

template <typename T>
T& ParameterSet::Field(Model<T>* model, int i) const {
  return FieldOf(model, fields_[i]);
}

std::vector<double> ParameterSet::Values(const Model<double>& model) const {
  std::vector<double> values;
  for (const FieldRef& f : fields_) values.push_back(FieldOf(&model, f));
  return values;
}

void ParameterSet::Assign(const std::vector<double>& values, Model<double>* model) const {
  for (int i = 0; i < size(); ++i) Field(model, i) = values[i];
}

void ParameterSet::WriteInto(const std::vector<double>& values, nlohmann::json* document) const {
  for (int i = 0; i < size(); ++i) (*document)[nlohmann::json::json_pointer(pointers_[i])] = values[i];
}

template double& ParameterSet::Field<double>(Model<double>*, int) const;
template Jet& ParameterSet::Field<Jet>(Model<Jet>*, int) const;

}  // namespace tether
