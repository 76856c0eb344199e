// ModelField: one number of a Model<T> (a body's mass, a spring's stiffness, a component of a force's point), to
// read and set for every scalar the library is compiled for. It is made from one generic accessor,
//   [k](auto& model) -> auto& { return model.springs[k].stiffness; }
// which the scene reader writes where it reads the number (io/scene_numbers.h): the parameters, ties and sweeps
// reach the model through it, and nothing else needs to know where a JSON key lands.
#pragma once

#include <functional>
#include <tuple>

#include "tether/dynamics/model/model.h"

namespace tether {

class ModelField {
 public:
  ModelField() = default;
  template <typename Access>
  explicit ModelField(Access access)
      : access_(Accessor<double>(access), Accessor<Jet>(access), Accessor<Rev>(access)) {}

  template <typename T>
  T& operator()(Model<T>& model) const {
    return std::get<Accessor<T>>(access_)(model);
  }
  template <typename T>
  T operator()(const Model<T>& model) const {
    return std::get<Accessor<T>>(access_)(const_cast<Model<T>&>(model));  // read only
  }

 private:
  template <typename T>
  using Accessor = std::function<T&(Model<T>&)>;
  // one accessor per scalar of TETHER_FOR_EACH_SCALAR (scalar.h)
  std::tuple<Accessor<double>, Accessor<Jet>, Accessor<Rev>> access_;
};

}  // namespace tether
