// Parameters: numeric leaves of a scene named by JSON Pointers (RFC 6901), bound to the model fields they set,
// so that a Model<T> can carry them as T (a Jet seeds their derivative directions, a Rev records them).
//
// A pointer is a parameter when the scene reader bound the number it names (io/scene_numbers.h): every number a
// model field holds, from a body's mass to a schedule's values; a product of inertia's two pointers name one
// field. Refused with a message naming the file and the pointer: pointers that are not in the scene file (a
// default must be written out to become a parameter), that name an array or object instead of a number, and
// numbers no field holds (names, types, the integrator, step, duration, tolerance, schedule times).
#pragma once

#include <string>
#include <vector>

#include "tether/autodiff/seeds.h"
#include "tether/autodiff/tie_expression.h"
#include "tether/dynamics/io/scene_reader.h"

namespace tether {

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
  // What the scene reader recorded of parameter i: its field, domain and schedule knot.
  const SceneNumber& number(int i) const { return numbers_[i].number; }

  // The model field of parameter i.
  template <typename T>
  T& Field(Model<T>* model, int i) const {
    return numbers_[i].number.access(*model);
  }

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

  // The model in Jets, parameter seeds[k].parameter carrying derivative seeds[k].derivative in direction
  // seeds[k].direction (seeds.h: 1 for the parameter itself, its value for its logarithm), the ties following.
  struct Seed {
    int parameter = 0;
    int direction = 0;
    double derivative = 1.0;
  };
  Model<Jet> Seeded(const Model<double>& model, const std::vector<Seed>& seeds) const;
  // The model in Revs with every parameter a new variable of the tape, in order (`inputs`), the ties recorded
  // from them.
  Model<Rev> Recorded(const Model<double>& model, Tape* tape, std::vector<Rev>* inputs) const;

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
  // A number and every pointer of its field (a product of inertia is written at both of its places).
  struct Bound {
    SceneNumber number;
    std::vector<std::string> places;
  };
  struct TieRef {
    std::string pointer;
    Bound target;
    TieExpression expression;
    std::vector<Bound> references;  // of expression.references()
  };
  // The number a pointer names; throws InputError naming the file and the pointer.
  static Bound Lookup(const Scene& scene, const std::string& pointer);

  std::vector<std::string> pointers_;
  std::vector<Bound> numbers_;
  std::vector<TieRef> ties_;
};

}  // namespace tether
