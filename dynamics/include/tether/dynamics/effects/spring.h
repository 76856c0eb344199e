// A spring between two body points: tension s = k (l - l0) + d l' along the line between them, l = |p_B - p_A|,
// n = (p_B - p_A) / l: F_A = +s n, F_B = -s n. Potential energy 1/2 k (l - l0)^2.
#pragma once

#include "tether/dynamics/model/bodies.h"

namespace tether {

template <typename T>
struct SpringEffect {
  int scene_index = 0;
  BodyPoint<T> a, b;
  T stiffness = T(0.0);    // k, N/m
  T rest_length = T(0.0);  // l0, m
  T damping = T(0.0);      // d, N s/m

  template <typename U>
  SpringEffect<U> Cast() const {
    return {scene_index, a.template Cast<U>(), b.template Cast<U>(), U(stiffness), U(rest_length), U(damping)};
  }
  bool Conservative() const { return damping == T(0.0); }

  template <typename Context>
  void AddForces(const Context& c, VecX<T>* f) const {
    const auto pa = c.Move(a, true), pb = c.Move(b, true);
    const auto segment = c.Between(pa, pb);
    const T tension = stiffness * (segment.length - rest_length) + damping * segment.n.dot(pb.velocity - pa.velocity);
    c.AddForce(a.body, pa, segment.n, tension, f);
    c.AddForce(b.body, pb, segment.n, T(-tension), f);
  }
  template <typename Context>
  T Energy(const Context& c) const {
    const T stretch = c.Between(c.Move(a, false), c.Move(b, false)).length - rest_length;
    return T(0.5) * stiffness * stretch * stretch;
  }
};

}  // namespace tether
