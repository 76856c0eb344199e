#include "tether/autodiff/parameters.h"

#include <algorithm>
#include <cstdlib>

#include "tether/dynamics/model/errors.h"

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
    bool found = false;
    try {  // an array index that is empty, not a number or past any size throws rather than answering no
      found = scene_.document.contains(ptr);
    } catch (const json::exception&) {
    }
    if (!found) {
      Fail("is not in the scene file (a value left to its default must be written out to become a parameter)");
    }
    const json& leaf = scene_.document.at(ptr);
    if (!leaf.is_number()) Fail("names " + std::string(leaf.type_name()) + ", not a number");
    tokens_ = Tokens();
    const std::string& section = tokens_[0];
    if (section == "bodies") return Body();
    if (section == "constraints") return Constraint();
    if (section == "effects") return Effect();
    if (section == "markers") return Marker();
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
    const bool planar_angular = m.bodies[i].kind == BodyKind::kPlanar;
    if (Is(2, "mass")) return {Kind::kMass, i};
    if (Is(2, "inertia") && tokens_.size() == 3) return {Kind::kInertia, i};
    if (Is(2, "inertia") && tokens_.size() == 4) return {Kind::kInertiaMoment, i, Index(3), Index(3)};
    if (Is(2, "inertia")) {  // a tensor entry: the diagonal, or the product of inertia I_rc = I_cr (upper entry)
      const int r = std::min(Index(3), Index(4)), c = std::max(Index(3), Index(4));
      return {r == c ? Kind::kInertiaMoment : Kind::kInertiaProduct, i, r, c};
    }
    if (Is(2, "position")) return {Kind::kPosition, i, 0, Index(3)};
    if (Is(2, "angle")) return {Kind::kAngle, i};
    if (Is(2, "orientation")) return {Kind::kOrientation, i, 0, Index(3)};
    if (Is(2, "velocity")) return {Kind::kVelocity, i, 0, Index(3)};
    if (Is(2, "angular_velocity")) return {Kind::kAngularVelocity, i, 0, planar_angular ? 2 : Index(3)};
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
    const int k = JointIndex(m, Index(1));
    if (k < 0) return NotDifferentiable();
    if (Is(2, "length")) return {Kind::kJointLength, k};
    if (Is(2, "points")) return {Kind::kJointPoint, k, Index(3), Index(4)};
    if (Is(2, "axis")) return {Kind::kJointAxis, k, 0, Index(3)};
    if (Is(2, "axes")) return {Index(3) == 0 ? Kind::kJointAxis : Kind::kJointAxisB, k, 0, Index(4)};
    if (Is(2, "angle")) return {Kind::kJointAngle, k};
    if (Is(2, "range")) return {Kind::kJointRange, k, Index(3)};
    if (Is(2, "restitution")) return {Kind::kJointRestitution, k};
    return NotDifferentiable();
  }

  FieldRef Marker() const {
    if (Is(2, "point")) return {Kind::kMarkerPoint, Index(1), 0, Index(3)};
    return NotDifferentiable();
  }

  FieldRef Effect() const {
    const Model<double>& m = scene_.model;
    const int i = Index(1);
    const bool scheduled = Is(2, "schedule") && Is(3, "values");
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
      if (scheduled) return {Kind::kForceSchedule, k, Index(4), Index(5)};
    } else if (const int k = PositionOf(m.torques, i); k >= 0) {
      const bool planar = m.dimension == 2;  // a planar torque is the z component
      if (Is(2, "value")) return {Kind::kTorqueValue, k, 0, planar ? 2 : Index(3)};
      if (scheduled) return {Kind::kTorqueSchedule, k, Index(4), planar ? 2 : Index(5)};
    } else if (const int k = PositionOf(m.joint_torques, i); k >= 0) {
      if (Is(2, "value")) return {Kind::kJointTorqueValue, k};
      if (scheduled) return {Kind::kJointTorqueSchedule, k, Index(4)};
    } else if (const int k = PositionOf(m.joint_springs, i); k >= 0) {
      if (Is(2, "stiffness")) return {Kind::kJointSpringStiffness, k};
      if (Is(2, "rest")) return {Kind::kJointSpringRest, k};
      if (Is(2, "damping")) return {Kind::kJointSpringDamping, k};
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
    case Kind::kInertiaMoment:
    case Kind::kInertiaProduct: return m->bodies[f.index].inertia_tensor(f.slot, f.component);
    case Kind::kPosition: return m->bodies[f.index].position[f.component];
    case Kind::kAngle: return m->bodies[f.index].angle;
    case Kind::kOrientation: return m->bodies[f.index].orientation[f.component];
    case Kind::kVelocity: return m->bodies[f.index].velocity[f.component];
    case Kind::kAngularVelocity: return m->bodies[f.index].angular_velocity[f.component];
    case Kind::kJointLength: return m->joints[f.index].length;
    case Kind::kJointPoint: return point(m->joints[f.index])[f.component];
    case Kind::kJointAxis: return m->joints[f.index].axis[f.component];
    case Kind::kJointAxisB: return m->joints[f.index].axis_b[f.component];
    case Kind::kJointAngle: return m->joints[f.index].angle;
    case Kind::kJointRange: return f.slot == 0 ? m->joints[f.index].range.low : m->joints[f.index].range.high;
    case Kind::kJointRestitution: return m->joints[f.index].range.restitution;
    case Kind::kMarkerPoint: return m->markers[f.index].point.local[f.component];
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
    case Kind::kTorqueValue: return m->torques[f.index].value[f.component];
    case Kind::kTorqueSchedule: return m->torques[f.index].schedule.values[f.slot][f.component];
    case Kind::kJointTorqueValue: return m->joint_torques[f.index].value;
    case Kind::kJointTorqueSchedule: return m->joint_torques[f.index].schedule.values[f.slot];
    case Kind::kJointSpringStiffness: return m->joint_springs[f.index].stiffness;
    case Kind::kJointSpringRest: return m->joint_springs[f.index].rest;
    case Kind::kJointSpringDamping: return m->joint_springs[f.index].damping;
    case Kind::kAlpha: return m->stabilization.alpha;
    case Kind::kBeta: return m->stabilization.beta;
  }
  return m->stabilization.beta;  // unreachable: the switch covers every kind
}

// The pointers with every one that ends in "/*" replaced by the pointers of its array's elements, in order.
std::vector<std::string> Expanded(const Scene& scene, const std::vector<std::string>& pointers) {
  std::vector<std::string> out;
  for (const std::string& pointer : pointers) {
    if (!EndsInWildcard(pointer)) {
      out.push_back(pointer);
      continue;
    }
    const std::vector<std::string> elements = WildcardElements(scene.document, pointer);
    if (elements.empty()) {
      const std::string array = pointer.substr(0, pointer.size() - 2);
      throw InputError(scene.path + ": " + pointer + ": '/*' stands for the elements of an array, and " +
                       (array.empty() ? std::string("the document") : array) + " is not a non-empty array");
    }
    out.insert(out.end(), elements.begin(), elements.end());
  }
  return out;
}

// The ties with every one whose pointer ends in "/*" replaced by a tie per element k of its array, "/*}" in its
// expression read as "/k}" (element k of the named array: one knot list following another, element by element).
std::vector<std::string> TiesExpanded(const Scene& scene, const std::vector<std::string>& ties,
                                      const std::string& flag) {
  std::vector<std::string> out;
  for (const std::string& text : ties) {
    const size_t equals = text.find('=');
    if (equals == std::string::npos) throw InputError(flag + " '" + text + "': expected PTR=EXPR");
    const std::string pointer = text.substr(0, equals), expression = text.substr(equals + 1);
    if (!EndsInWildcard(pointer)) {
      out.push_back(text);
      continue;
    }
    std::vector<std::string> elements;
    try {
      elements = Expanded(scene, {pointer});
    } catch (const InputError& e) {
      throw InputError(flag + " '" + text + "': " + e.what());
    }
    for (size_t k = 0; k < elements.size(); ++k) {
      std::string element_expression = expression;
      const std::string index = "/" + std::to_string(k) + "}";
      for (size_t at = element_expression.find("/*}"); at != std::string::npos;
           at = element_expression.find("/*}", at + index.size())) {
        element_expression.replace(at, 3, index);
      }
      out.push_back(elements[k] + "=" + element_expression);
    }
  }
  return out;
}

}  // namespace

bool EndsInWildcard(const std::string& pointer) {
  return pointer.size() >= 2 && pointer.compare(pointer.size() - 2, 2, "/*") == 0;
}

std::vector<std::string> WildcardElements(const nlohmann::json& document, const std::string& pointer) {
  const std::string array = pointer.substr(0, pointer.size() - 2);
  const json* elements = nullptr;
  try {
    elements = &document.at(json::json_pointer(array));
  } catch (const json::exception&) {
    return {};  // a malformed or missing prefix
  }
  std::vector<std::string> out;
  if (!elements->is_array()) return out;
  for (size_t k = 0; k < elements->size(); ++k) out.push_back(array + "/" + std::to_string(k));
  return out;
}

ParameterSet::ParameterSet(const Scene& scene, const std::vector<std::string>& given) {
  for (const std::string& pointer : Expanded(scene, given)) {
    const FieldRef field = Resolver(scene, pointer).Resolve();
    for (size_t k = 0; k < fields_.size(); ++k) {  // the same field twice, by the same pointer or its mirror
      const FieldRef& seen = fields_[k];
      if (seen.kind == field.kind && seen.index == field.index && seen.slot == field.slot &&
          seen.component == field.component) {
        const std::string also = pointers_[k] == pointer ? "" : " (as " + pointers_[k] + ")";
        throw InputError(scene.path + ": " + pointer + ": named twice as a parameter" + also);
      }
    }
    fields_.push_back(field);
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

void ParameterSet::Tie(const Scene& scene, const std::vector<std::string>& ties, const std::string& flag) {
  const auto same = [](const FieldRef& a, const FieldRef& b) {
    return a.kind == b.kind && a.index == b.index && a.slot == b.slot && a.component == b.component;
  };
  for (const std::string& text : TiesExpanded(scene, ties, flag)) {
    const std::string source = flag + " '" + text + "'";
    const size_t equals = text.find('=');
    const std::string pointer = text.substr(0, equals);
    const auto resolve = [&](const std::string& p) {
      try {
        return Resolver(scene, p).Resolve();
      } catch (const InputError& e) {
        throw InputError(source + ": " + e.what());
      }
    };
    TieRef tie{pointer, resolve(pointer), TieExpression(text.substr(equals + 1), source), {}};
    for (size_t k = 0; k < fields_.size(); ++k) {
      if (same(fields_[k], tie.target)) throw InputError(source + ": " + pointer + " is a parameter (--param)");
    }
    for (const TieRef& earlier : ties_) {
      if (same(earlier.target, tie.target)) throw InputError(source + ": " + pointer + " is tied twice");
    }
    for (const std::string& reference : tie.expression.references()) {
      const FieldRef field = resolve(reference);
      if (same(field, tie.target)) throw InputError(source + ": the expression names " + pointer + " itself");
      tie.references.push_back(field);
    }
    ties_.push_back(std::move(tie));
  }
  for (size_t i = 0; i < ties_.size(); ++i) {  // a tie may use what earlier ties set, not what later ones will
    for (size_t j = i + 1; j < ties_.size(); ++j) {
      for (const FieldRef& reference : ties_[i].references) {
        if (same(reference, ties_[j].target)) {
          throw InputError(flag + " '" + ties_[i].pointer + "': names " + ties_[j].pointer +
                           ", which a later tie sets (give that tie first)");
        }
      }
    }
  }
  if (ties_.empty()) return;
  try {
    SceneWith(scene, Values(scene.model));
  } catch (const InputError& e) {
    throw InputError(flag + ": at the scene's values the ties give a number the scene format refuses: " + e.what());
  }
}

template <typename T>
void ParameterSet::ApplyTies(Model<T>* model) const {
  std::vector<T> values;
  for (const TieRef& tie : ties_) {
    values.clear();
    for (const FieldRef& reference : tie.references) values.push_back(FieldOf(model, reference));
    const T value = tie.expression.Evaluate(values);
    FieldOf(model, tie.target) = value;
    if (tie.target.kind == Kind::kInertiaProduct) {  // the tensor stays symmetric
      model->bodies[tie.target.index].inertia_tensor(tie.target.component, tie.target.slot) = value;
    }
  }
}

void ParameterSet::Assign(const std::vector<double>& values, Model<double>* model) const {
  for (int i = 0; i < size(); ++i) Field(model, i) = values[i];
  ApplyTies(model);
}

namespace {

// A number written at its pointer (a product of inertia at both of its places).
void WriteNumber(const std::string& pointer, const FieldRef& f, double value, nlohmann::json* document) {
  (*document)[nlohmann::json::json_pointer(pointer)] = value;
  if (f.kind == Kind::kInertiaProduct) {  // the tensor stays symmetric
    auto& tensor = (*document)["bodies"][f.index]["inertia"];
    tensor[f.slot][f.component] = value;
    tensor[f.component][f.slot] = value;
  }
}

}  // namespace

void ParameterSet::WriteInto(const std::vector<double>& values, nlohmann::json* document) const {
  for (int i = 0; i < size(); ++i) WriteNumber(pointers_[i], fields_[i], values[i], document);
  for (const TieRef& tie : ties_) {
    std::vector<double> references;
    for (const std::string& pointer : tie.expression.references()) {
      references.push_back(document->at(nlohmann::json::json_pointer(pointer)).get<double>());
    }
    WriteNumber(tie.pointer, tie.target, tie.expression.Evaluate(references), document);
  }
}

Scene ParameterSet::SceneWith(const Scene& scene, const std::vector<double>& values) const {
  nlohmann::json document = scene.document;
  WriteInto(values, &document);
  return ParseScene(document, scene.path);
}

template void ParameterSet::ApplyTies<double>(Model<double>*) const;
template void ParameterSet::ApplyTies<Jet>(Model<Jet>*) const;
template void ParameterSet::ApplyTies<Rev>(Model<Rev>*) const;
template double& ParameterSet::Field<double>(Model<double>*, int) const;
template Jet& ParameterSet::Field<Jet>(Model<Jet>*, int) const;
template Rev& ParameterSet::Field<Rev>(Model<Rev>*, int) const;

}  // namespace tether
