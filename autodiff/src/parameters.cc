#include "tether/autodiff/parameters.h"

#include <algorithm>
#include <cstdlib>

#include "tether/dynamics/model/errors.h"

namespace tether {
namespace {

using nlohmann::json;

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

// The number a pointer names, with every pointer of its field; throws InputError naming the file and the pointer.
ParameterSet::Bound ParameterSet::Lookup(const Scene& scene, const std::string& pointer) {
  const auto fail = [&](const std::string& message) { throw InputError(scene.path + ": " + pointer + ": " + message); };
  json::json_pointer parsed;
  try {
    parsed = json::json_pointer(pointer);
  } catch (const json::exception&) {
    fail("not a JSON Pointer (it must look like /bodies/0/mass)");
  }
  bool found = false;
  try {  // an array index that is empty, not a number or past any size throws rather than answering no
    found = scene.document.contains(parsed);
  } catch (const json::exception&) {
  }
  if (!found) fail("is not in the scene file (a value left to its default must be written out to become a parameter)");
  const json& leaf = scene.document.at(parsed);
  if (!leaf.is_number()) fail("names " + std::string(leaf.type_name()) + ", not a number");
  const SceneNumber* number = scene.numbers.Find(pointer);
  if (!number) fail("is not a differentiable parameter");
  return {*number, scene.numbers.PointersOf(number->field)};
}

ParameterSet::ParameterSet(const Scene& scene, const std::vector<std::string>& given) {
  for (const std::string& pointer : Expanded(scene, given)) {
    Bound bound = Lookup(scene, pointer);
    for (size_t k = 0; k < numbers_.size(); ++k) {  // the same field twice, by the same pointer or its mirror
      if (numbers_[k].number.field != bound.number.field) continue;
      const std::string also = pointers_[k] == pointer ? "" : " (as " + pointers_[k] + ")";
      throw InputError(scene.path + ": " + pointer + ": named twice as a parameter" + also);
    }
    numbers_.push_back(std::move(bound));
    pointers_.push_back(pointer);
  }
}

std::vector<double> ParameterSet::Values(const Model<double>& model) const {
  std::vector<double> values;
  for (const Bound& bound : numbers_) values.push_back(bound.number.access(model));
  return values;
}

void ParameterSet::Tie(const Scene& scene, const std::vector<std::string>& ties, const std::string& flag) {
  const auto same = [](const Bound& a, const Bound& b) { return a.number.field == b.number.field; };
  for (const std::string& text : TiesExpanded(scene, ties, flag)) {
    const std::string source = flag + " '" + text + "'";
    const size_t equals = text.find('=');
    const std::string pointer = text.substr(0, equals);
    const auto resolve = [&](const std::string& p) {
      try {
        return Lookup(scene, p);
      } catch (const InputError& e) {
        throw InputError(source + ": " + e.what());
      }
    };
    TieRef tie{pointer, resolve(pointer), TieExpression(text.substr(equals + 1), source), {}};
    for (const Bound& parameter : numbers_) {
      if (same(parameter, tie.target)) throw InputError(source + ": " + pointer + " is a parameter (--param)");
    }
    for (const TieRef& earlier : ties_) {
      if (same(earlier.target, tie.target)) throw InputError(source + ": " + pointer + " is tied twice");
    }
    for (const std::string& reference : tie.expression.references()) {
      Bound field = resolve(reference);
      if (same(field, tie.target)) throw InputError(source + ": the expression names " + pointer + " itself");
      tie.references.push_back(std::move(field));
    }
    ties_.push_back(std::move(tie));
  }
  for (size_t i = 0; i < ties_.size(); ++i) {  // a tie may use what earlier ties set, not what later ones will
    for (size_t j = i + 1; j < ties_.size(); ++j) {
      for (const Bound& reference : ties_[i].references) {
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
    for (const Bound& reference : tie.references) values.push_back(reference.number.access(*model));
    tie.target.number.access(*model) = tie.expression.Evaluate(values);
  }
}

Model<Jet> ParameterSet::Seeded(const Model<double>& model, const std::vector<Seed>& seeds) const {
  std::vector<JetSeed> fields;
  for (const Seed& seed : seeds) fields.push_back({number(seed.parameter).access, seed.direction, seed.derivative});
  Model<Jet> out = SeededModel(model, fields);
  ApplyTies(&out);
  return out;
}

Model<Rev> ParameterSet::Recorded(const Model<double>& model, Tape* tape, std::vector<Rev>* inputs) const {
  std::vector<ModelField> fields;
  for (const Bound& bound : numbers_) fields.push_back(bound.number.access);
  Model<Rev> out = RecordedModel(model, fields, tape, inputs);
  ApplyTies(&out);
  return out;
}

void ParameterSet::Assign(const std::vector<double>& values, Model<double>* model) const {
  for (int i = 0; i < size(); ++i) Field(model, i) = values[i];
  ApplyTies(model);
}

namespace {

// A number written at every place of its field (a product of inertia at both of its places).
void WriteNumber(const std::vector<std::string>& places, double value, nlohmann::json* document) {
  for (const std::string& pointer : places) (*document)[nlohmann::json::json_pointer(pointer)] = value;
}

}  // namespace

void ParameterSet::WriteInto(const std::vector<double>& values, nlohmann::json* document) const {
  for (int i = 0; i < size(); ++i) WriteNumber(numbers_[i].places, values[i], document);
  for (const TieRef& tie : ties_) {
    std::vector<double> references;
    for (const std::string& pointer : tie.expression.references()) {
      references.push_back(document->at(nlohmann::json::json_pointer(pointer)).get<double>());
    }
    WriteNumber(tie.target.places, tie.expression.Evaluate(references), document);
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

}  // namespace tether
