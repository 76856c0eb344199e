// The scalars tether is instantiated for, and the little glue every templated header needs.
//
// Every numerical routine is a template on the scalar T and is compiled for exactly two scalars:
//   double                               values;
//   Jet = ceres::Jet<double, kJetStride> values plus kJetStride directional derivatives.
// Value(x) is the double part of either; branches that must not be differentiated (step-size control,
// divergence checks, pivoting) look at Value(x) only.
#pragma once

#include <ceres/jet.h>

#include <Eigen/Core>

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
#if defined(__GNUC__)
#define TETHER_HOT_INLINE __attribute__((always_inline)) inline
#else
#define TETHER_HOT_INLINE inline
#endif

// Expands MACRO(T) once for every scalar the library is compiled for (explicit instantiation, see DESIGN.md).
#define TETHER_FOR_EACH_SCALAR(MACRO) \
  MACRO(double)                       \
  MACRO(::tether::Jet)
