// The scalars tether is instantiated for, and the little glue every templated header needs.
//
// Every numerical routine is a template on the scalar T and is compiled for exactly three scalars:
//   double                               values;
//   Jet = ceres::Jet<double, kJetStride> values plus kJetStride directional derivatives (forward mode);
//   Rev                                  values recorded for reverse mode (reverse.h).
// Value(x) is the double part of either; branches that must not be differentiated (step-size control,
// divergence checks, pivoting) look at Value(x) only.
#pragma once

#include <ceres/jet.h>

#include <Eigen/Core>

#include "tether/dynamics/scalars/reverse.h"

namespace tether {

// Derivative directions carried by one Jet; more parameters are handled in chunks of this many.
inline constexpr int kJetStride = 4;
using Jet = ceres::Jet<double, kJetStride>;

template <typename T>
struct IsJet : std::false_type {};
template <typename S, int N>
struct IsJet<ceres::Jet<S, N>> : std::true_type {};

inline double Value(double x) { return x; }
template <int N>
double Value(const ceres::Jet<double, N>& x) {
  return x.a;
}

template <typename T>
using Vec3 = Eigen::Matrix<T, 3, 1>;
template <typename T>
using Vec4 = Eigen::Matrix<T, 4, 1>;  // a quaternion (w, x, y, z)
template <typename T>
using Mat3 = Eigen::Matrix<T, 3, 3>;
template <typename T>
using VecX = Eigen::Matrix<T, Eigen::Dynamic, 1>;

}  // namespace tether

// Small functions on the hot path of a step (a point's motion, a Jacobian block's dot product) that the compiler
// must inline although their switch over body kinds makes it hesitate (Eigen's EIGEN_STRONG_INLINE does the same).
// TETHER_FLATTEN asks for everything a hot function calls to be inlined into it: with Jets the compiler otherwise
// leaves Eigen's small 3-vector copies out of line, a call each. Not under AddressSanitizer, where g++ takes
// minutes to compile the flattened, instrumented function (and speed does not matter).
#if defined(__GNUC__)
#define TETHER_HOT_INLINE __attribute__((always_inline)) inline
#else
#define TETHER_HOT_INLINE inline
#endif
#if defined(__GNUC__) && !defined(__SANITIZE_ADDRESS__)
#define TETHER_FLATTEN __attribute__((flatten))
#else
#define TETHER_FLATTEN
#endif

namespace tether {

// A zero 3-vector for the hot path, element by element: Eigen's Zero() goes through its expression evaluator,
// which for a Jet scalar the compiler leaves out of line, a call per vector.
template <typename T>
TETHER_HOT_INLINE Eigen::Matrix<T, 3, 1> Zero3() {
  Eigen::Matrix<T, 3, 1> v;
  v[0] = T(0.0);
  v[1] = T(0.0);
  v[2] = T(0.0);
  return v;
}

}  // namespace tether

// Expands MACRO(T) once for every scalar the library is compiled for (explicit instantiation: docs/architecture.md,
// principle 10).
#define TETHER_FOR_EACH_SCALAR(MACRO) \
  MACRO(double)                       \
  MACRO(::tether::Jet)                \
  MACRO(::tether::Rev)
