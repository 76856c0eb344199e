// Rotations in 3D: unit quaternions q = (w, x, y, z) = (cos(phi/2), sin(phi/2) u), the exponential map of
// so(3) and its inverse, and the inverse of the differential of the exponential (Runge-Kutta-Munthe-Kaas).
//
//   R(q) r      = r + 2 w (v x r) + 2 v x (v x r),                       v = (x, y, z)
//   a (x) b     = (a_w b_w - a_v . b_v,  a_w b_v + b_w a_v + a_v x b_v)  (R(a (x) b) = R(a) R(b))
//   Exp(theta)  = (cos(|theta| / 2), sin(|theta| / 2) theta / |theta|)  (rotation by |theta| about theta)
//   Log(q)      = 2 atan2(|v|, w) v / |v|, taken for the sign of q with w >= 0 (the shorter rotation)
//   DexpInv(theta, w) = w + 1/2 theta x w + c(|theta|) theta x (theta x w),
//               c(s) = (1 - (s / 2) cot(s / 2)) / s^2 = 1/12 + s^2/720 + s^4/30240 + s^6/1209600 + ...
// DexpInv solves theta' for R(t) = R0 Exp(theta(t)) with R' = R [w]x (w the angular velocity in the body
// frame): Exp(theta)^-1 d/dt Exp(theta) = [dexp_{-theta} theta']x, so theta' = dexp_{-theta}^-1 w.
//
// Derivative-safe (docs/architecture.md, principle 9): near theta = 0 (and v = 0) the functions switch to their Taylor
// series on the value of |theta|^2, so that no sqrt or division is taken at zero and Jets get exact derivatives.
#pragma once

#include <Eigen/Geometry>  // cross products
#include <array>
#include <cmath>
#include <utility>

#include "tether/dynamics/scalars/scalar.h"

namespace tether {

template <typename T>
Vec3<T> VectorPart(const Vec4<T>& q) {
  return Vec3<T>(q[1], q[2], q[3]);
}

template <typename T>
Vec4<T> QuaternionProduct(const Vec4<T>& a, const Vec4<T>& b) {
  const Vec3<T> va = VectorPart(a), vb = VectorPart(b);
  const Vec3<T> v = a[0] * vb + b[0] * va + va.cross(vb);
  return Vec4<T>(a[0] * b[0] - va.dot(vb), v[0], v[1], v[2]);
}

template <typename T>
Vec4<T> Conjugate(const Vec4<T>& q) {
  return Vec4<T>(q[0], -q[1], -q[2], -q[3]);
}

// R(q) r for a unit quaternion q.
template <typename T>
Vec3<T> Rotate(const Vec4<T>& q, const Vec3<T>& r) {
  const Vec3<T> v = VectorPart(q);
  const Vec3<T> t = T(2.0) * v.cross(r);
  return r + q[0] * t + v.cross(t);
}

// The rotation by `angle` about z (a planar body's or shape's).
template <typename T>
Mat3<T> PlanarRotation(const T& angle) {
  using std::cos;
  using std::sin;
  const T c = cos(angle), s = sin(angle);
  Mat3<T> R = Mat3<T>::Identity();
  R(0, 0) = c;
  R(0, 1) = -s;
  R(1, 0) = s;
  R(1, 1) = c;
  return R;
}

template <typename T>
TETHER_HOT_INLINE Mat3<T> RotationMatrix(const Vec4<T>& q) {
  const T w = q[0], x = q[1], y = q[2], z = q[3];
  Mat3<T> R;
  R << T(1.0) - T(2.0) * (y * y + z * z), T(2.0) * (x * y - w * z), T(2.0) * (x * z + w * y), T(2.0) * (x * y + w * z),
      T(1.0) - T(2.0) * (x * x + z * z), T(2.0) * (y * z - w * x), T(2.0) * (x * z - w * y), T(2.0) * (y * z + w * x),
      T(1.0) - T(2.0) * (x * x + y * y);
  return R;
}

// q / |q| (q != 0): smooth in q, so a derivative with respect to a component of a scene's quaternion is that of
// the rotation it names.
template <typename T>
Vec4<T> Normalized(const Vec4<T>& q) {
  using std::sqrt;
  return q / sqrt(q.squaredNorm());
}

// Below |theta|^2 = kSeriesBelow, Exp and DexpInv take their Taylor series in |theta|^2, each written once here for
// the functions and for their derivatives' helpers below.
inline constexpr double kSeriesBelow = 1e-2;
inline constexpr std::array<double, 5> kExpCosineSeries = {1.0, -1.0 / 8, 1.0 / 384, -1.0 / 46080, 1.0 / 10321920};
inline constexpr std::array<double, 5> kExpSineSeries = {0.5, -1.0 / 48, 1.0 / 3840, -1.0 / 645120, 1.0 / 185794560};
inline constexpr std::array<double, 4> kDexpInvSeries = {1.0 / 12.0, 1.0 / 720.0, 1.0 / 30240.0, 1.0 / 1209600.0};

// sum_k a_k x^k by Horner's rule, a_0 + x (a_1 + x (a_2 + ...)), and its derivative sum_k k a_k x^(k - 1).
template <typename T, size_t N>
T Series(const std::array<double, N>& a, const T& x) {
  T sum = T(a[N - 1]);
  for (size_t k = N - 1; k-- > 0;) sum = T(a[k]) + x * sum;
  return sum;
}
template <size_t N>
double SeriesDerivative(const std::array<double, N>& a, double x) {
  double sum = static_cast<double>(N - 1) * a[N - 1];
  for (size_t k = N - 1; k-- > 1;) sum = static_cast<double>(k) * a[k] + x * sum;
  return sum;
}

template <typename T>
Vec4<T> Exp(const Vec3<T>& theta) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  const T squared = theta.squaredNorm();
  T c, s;                               // cos(|theta| / 2) and sin(|theta| / 2) / |theta|
  if (Value(squared) < kSeriesBelow) {  // the series to |theta|^8: the first term left out is below 3e-20
    c = Series(kExpCosineSeries, squared);
    s = Series(kExpSineSeries, squared);
  } else {
    const T angle = sqrt(squared);
    c = cos(T(0.5) * angle);
    s = sin(T(0.5) * angle) / angle;
  }
  return Vec4<T>(c, s * theta[0], s * theta[1], s * theta[2]);
}

// An orientation turned by turn_P, given in the principal axes P of its body (R_BP from principal_axes):
// q_WB (x) Exp(R_BP turn_P), normalised (configuration_space.h's Integrate).
template <typename T>
Vec4<T> TurnedOrientation(const Vec4<T>& q_WB, const Vec4<double>& principal_axes, const Vec3<T>& turn_P) {
  const bool principal = principal_axes == Vec4<double>(1, 0, 0, 0);
  const Vec3<T> turn_B = principal ? turn_P : Rotate(Vec4<T>(principal_axes.template cast<T>()), turn_P);
  // the product of unit quaternions is one; normalising removes the rounding that would otherwise accumulate
  return Normalized(QuaternionProduct(q_WB, Exp(turn_B)));
}

// Exp's coefficients as functions of sq = |theta|^2, with their derivatives, in double and by the branch Exp takes
// (the recorded Integrate's adjoint, configuration_adjoint.cc): c = cos(|theta| / 2), s = sin(|theta| / 2) /
// |theta|, dc/dsq = -s / 4 and ds/dsq = (c / 2 - s) / (2 sq), or the derivatives of the series.
struct ExpCoefficients {
  double c, s, dc, ds;
};
inline ExpCoefficients ExpCoefficientsAt(double sq) {
  if (sq < kSeriesBelow) {
    return {Series(kExpCosineSeries, sq), Series(kExpSineSeries, sq), SeriesDerivative(kExpCosineSeries, sq),
            SeriesDerivative(kExpSineSeries, sq)};
  }
  const double angle = std::sqrt(sq);
  const double c = std::cos(0.5 * angle), s = std::sin(0.5 * angle) / angle;
  return {c, s, -0.25 * s, (0.5 * c - s) / (2.0 * sq)};
}

template <typename T>
Vec3<T> Log(const Vec4<T>& quaternion) {
  using std::atan2;
  using std::sqrt;
  const Vec4<T> q = Value(quaternion[0]) < 0.0 ? Vec4<T>(-quaternion) : quaternion;
  const Vec3<T> v = VectorPart(q);
  const T squared = v.squaredNorm();
  const T w = q[0];
  T scale;  // 2 atan2(|v|, w) / |v|
  if (Value(squared) < 1e-8 * Value(w) * Value(w)) {
    const T ratio = squared / (w * w);
    scale = T(2.0) / w * (T(1.0) - ratio / T(3.0) + ratio * ratio / T(5.0));
  } else {
    const T norm = sqrt(squared);
    scale = T(2.0) * atan2(norm, w) / norm;
  }
  return scale * v;
}

// DexpInv's c(s2) and its derivative dc/ds2, in double and by the branch DexpInv takes (its adjoint):
// with s = sqrt(s2) and f = 1 - (s / 2) cot(s / 2), c = f / s2 and dc/ds2 = (f' / s - 2 c) / (2 s2),
// f' = (s / 2 csc^2(s / 2) - cot(s / 2)) / 2; or the derivative of the series.
inline std::pair<double, double> DexpInvCoefficientAt(double s2) {
  if (s2 < kSeriesBelow) return {Series(kDexpInvSeries, s2), SeriesDerivative(kDexpInvSeries, s2)};
  const double s = std::sqrt(s2), half = 0.5 * s;
  const double cot = 1.0 / std::tan(half), csc = 1.0 / std::sin(half);
  const double c = (1.0 - half * cot) / s2;
  const double f_prime = 0.5 * (half * csc * csc - cot);
  return {c, (f_prime / s - 2.0 * c) / (2.0 * s2)};
}

template <typename T>
Vec3<T> DexpInv(const Vec3<T>& theta, const Vec3<T>& w) {
  using std::sqrt;
  using std::tan;
  const T s2 = theta.squaredNorm();
  T c;
  if (Value(s2) < kSeriesBelow) {
    c = Series(kDexpInvSeries, s2);
  } else {
    const T s = sqrt(s2);
    c = (T(1.0) - T(0.5) * s / tan(T(0.5) * s)) / s2;
  }
  const Vec3<T> cross = theta.cross(w);
  return w + T(0.5) * cross + c * theta.cross(cross);
}

}  // namespace tether
