// Elementwise linear maps of vectors, the integrators' stage arithmetic (integrators.h, configuration_space.h):
//
//   out_i = f(x1_i, ..., xN_i),   f linear and homogeneous:  f(x) = sum_j c_j x_j,  c_j = f(e_j)
//
// (e_j the j-th unit vector: the coefficient is what f computes for it). f is one expression written once, for
// example [c](auto v, auto k) { return v + c * k; }, evaluated on every scalar's values by the same arithmetic,
// so a Rev replay reproduces the double run value for value. With Rev the whole vector is one recorded
// operation (reverse.h): its backward sweep adds  xbar_j += c_j outbar  element by element, where recording f
// node by node would cost a node per product and per sum (the Runge-Kutta stages made most of a step's record).
// `out` takes the inputs' size and may be one of them (each element is read before it is written).
#pragma once

#include <algorithm>
#include <array>
#include <memory>
#include <tuple>
#include <utility>
#include <vector>

#include "tether/dynamics/scalars/scalar.h"

namespace tether {

template <typename T, typename F, typename... X>
void Elementwise(VecX<T>* out, F f, const VecX<X>&... x) {
  const int n = static_cast<int>(std::get<0>(std::forward_as_tuple(x...)).size());
  out->resize(n);
  for (int i = 0; i < n; ++i) (*out)[i] = f(x[i]...);
}

namespace internal {

// f(e_j): f's coefficient of its j-th argument.
template <typename F, size_t... I>
double Coefficient(F f, size_t j, std::index_sequence<I...>) {
  return f((I == j ? 1.0 : 0.0)...);
}

}  // namespace internal

template <typename F, typename... X>
void Elementwise(VecX<Rev>* out, F f, const VecX<X>&... x) {
  constexpr size_t kInputs = sizeof...(X);
  const int n = static_cast<int>(std::get<0>(std::forward_as_tuple(x...)).size());
  out->resize(n);
  const auto any_recorded = [n](const VecX<Rev>& input) {
    for (int i = 0; i < n; ++i) {
      if (input[i].index >= 0) return true;
    }
    return false;
  };
  if (!(any_recorded(x) || ...)) {
    for (int i = 0; i < n; ++i) (*out)[i] = Rev(f(x[i].a...));
    return;
  }
  std::array<double, kInputs> coefficients;
  for (size_t j = 0; j < kInputs; ++j) coefficients[j] = internal::Coefficient(f, j, std::index_sequence_for<X...>());
  // the inputs' nodes, input by input
  Tape* tape = ActiveTape();
  const std::shared_ptr<std::vector<int>> nodes = tape->Reusable<std::vector<int>>();
  nodes->resize(kInputs * n);
  int* slot = nodes->data();
  ((std::transform(x.data(), x.data() + n, slot, [](const Rev& r) { return r.index; }), slot += n), ...);
  const int first = tape->RecordExternal(n, [nodes, coefficients, n](const double* out_bar, Tape* tape) {
    for (size_t j = 0; j < kInputs; ++j) {
      const int* input = nodes->data() + j * n;
      for (int i = 0; i < n; ++i) tape->AddAdjoint(input[i], coefficients[j] * out_bar[i]);
    }
  });
  for (int i = 0; i < n; ++i) (*out)[i] = Rev(f(x[i].a...), first + i);
}

}  // namespace tether
