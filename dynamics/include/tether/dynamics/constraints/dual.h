// Dual<S>: a forward-mode dual number v + d eps with eps^2 = 0, over any scalar S (double, ceres::Jet, or
// another Dual). It exists because ceres::Jet cannot be nested in Ceres 2.1 (its scalar constructors are
// explicit), and the automatic derivation of a user constraint needs second derivatives of a residual whose
// scalar may itself be a Jet:
//   C(q + eps e_j)                        -> d = dC/dq_j                 (a Jacobian column)
//   C(q + eps1 q' + eps2 q') over Dual<Dual<S>> -> d.d = q'^T (d^2C/dq^2) q' = Jdot q'
// Supported: + - * / (with Dual, S and double), comparisons (by value), sqrt, sin, cos, tan, asin, acos, atan,
// atan2, exp, log, pow, abs, hypot.
#pragma once

#include <cmath>
#include <type_traits>

namespace tether {

template <typename S>
struct Dual {
  S v;  // value
  S d;  // derivative along the seeded direction

  Dual() : v(0.0), d(0.0) {}
  Dual(double value) : v(value), d(0.0) {}  // NOLINT: constants enter expressions implicitly, as with Jets
  Dual(const S& value, const S& derivative) : v(value), d(derivative) {}
  template <typename U = S, typename = std::enable_if_t<!std::is_same_v<U, double>>>
  explicit Dual(const S& value) : v(value), d(0.0) {}

  Dual& operator+=(const Dual& o) { return *this = *this + o; }
  Dual& operator-=(const Dual& o) { return *this = *this - o; }
  Dual& operator*=(const Dual& o) { return *this = *this * o; }
  Dual& operator/=(const Dual& o) { return *this = *this / o; }

  friend Dual operator+(const Dual& x) { return x; }
  friend Dual operator-(const Dual& x) { return {-x.v, -x.d}; }
  friend Dual operator+(const Dual& x, const Dual& y) { return {x.v + y.v, x.d + y.d}; }
  friend Dual operator-(const Dual& x, const Dual& y) { return {x.v - y.v, x.d - y.d}; }
  friend Dual operator*(const Dual& x, const Dual& y) { return {x.v * y.v, x.d * y.v + x.v * y.d}; }
  friend Dual operator/(const Dual& x, const Dual& y) {
    const S q = x.v / y.v;
    return {q, (x.d - q * y.d) / y.v};
  }
  // Mixed with the underlying scalar S itself. Templates, so that only an exact S matches: a double goes through
  // the implicit Dual(double) above, and Dual<Dual<..>> * 2.0 stays unambiguous.
  template <typename U, typename = std::enable_if_t<std::is_same_v<U, S> && !std::is_same_v<S, double>>>
  friend Dual operator+(const Dual& x, const U& y) {
    return {x.v + y, x.d};
  }
  template <typename U, typename = std::enable_if_t<std::is_same_v<U, S> && !std::is_same_v<S, double>>>
  friend Dual operator+(const U& y, const Dual& x) {
    return {y + x.v, x.d};
  }
  template <typename U, typename = std::enable_if_t<std::is_same_v<U, S> && !std::is_same_v<S, double>>>
  friend Dual operator-(const Dual& x, const U& y) {
    return {x.v - y, x.d};
  }
  template <typename U, typename = std::enable_if_t<std::is_same_v<U, S> && !std::is_same_v<S, double>>>
  friend Dual operator-(const U& y, const Dual& x) {
    return {y - x.v, -x.d};
  }
  template <typename U, typename = std::enable_if_t<std::is_same_v<U, S> && !std::is_same_v<S, double>>>
  friend Dual operator*(const Dual& x, const U& y) {
    return {x.v * y, x.d * y};
  }
  template <typename U, typename = std::enable_if_t<std::is_same_v<U, S> && !std::is_same_v<S, double>>>
  friend Dual operator*(const U& y, const Dual& x) {
    return {y * x.v, y * x.d};
  }
  template <typename U, typename = std::enable_if_t<std::is_same_v<U, S> && !std::is_same_v<S, double>>>
  friend Dual operator/(const Dual& x, const U& y) {
    return {x.v / y, x.d / y};
  }
  template <typename U, typename = std::enable_if_t<std::is_same_v<U, S> && !std::is_same_v<S, double>>>
  friend Dual operator/(const U& y, const Dual& x) {
    return Dual(y) / x;
  }

  friend bool operator<(const Dual& x, const Dual& y) { return x.v < y.v; }
  friend bool operator>(const Dual& x, const Dual& y) { return x.v > y.v; }
  friend bool operator<=(const Dual& x, const Dual& y) { return x.v <= y.v; }
  friend bool operator>=(const Dual& x, const Dual& y) { return x.v >= y.v; }
  friend bool operator==(const Dual& x, const Dual& y) { return x.v == y.v; }
  friend bool operator!=(const Dual& x, const Dual& y) { return x.v != y.v; }

  // Elementary functions: f(v + d eps) = f(v) + f'(v) d eps. `using std::f` keeps S = double working, and
  // argument-dependent lookup finds ceres' and tether's overloads for Jets and nested Duals.
  friend Dual sqrt(const Dual& x) {
    using std::sqrt;
    const S r = sqrt(x.v);
    return {r, x.d / (S(2.0) * r)};
  }
  friend Dual sin(const Dual& x) {
    using std::cos;
    using std::sin;
    return {sin(x.v), cos(x.v) * x.d};
  }
  friend Dual cos(const Dual& x) {
    using std::cos;
    using std::sin;
    return {cos(x.v), -sin(x.v) * x.d};
  }
  friend Dual tan(const Dual& x) {
    using std::tan;
    const S t = tan(x.v);
    return {t, (S(1.0) + t * t) * x.d};
  }
  friend Dual asin(const Dual& x) {
    using std::asin;
    using std::sqrt;
    return {asin(x.v), x.d / sqrt(S(1.0) - x.v * x.v)};
  }
  friend Dual acos(const Dual& x) {
    using std::acos;
    using std::sqrt;
    return {acos(x.v), -x.d / sqrt(S(1.0) - x.v * x.v)};
  }
  friend Dual atan(const Dual& x) {
    using std::atan;
    return {atan(x.v), x.d / (S(1.0) + x.v * x.v)};
  }
  friend Dual atan2(const Dual& y, const Dual& x) {
    using std::atan2;
    return {atan2(y.v, x.v), (x.v * y.d - y.v * x.d) / (x.v * x.v + y.v * y.v)};
  }
  friend Dual exp(const Dual& x) {
    using std::exp;
    const S e = exp(x.v);
    return {e, e * x.d};
  }
  friend Dual log(const Dual& x) {
    using std::log;
    return {log(x.v), x.d / x.v};
  }
  friend Dual pow(const Dual& x, double p) {
    using std::pow;
    return {pow(x.v, p), S(p) * pow(x.v, p - 1.0) * x.d};
  }
  friend Dual abs(const Dual& x) { return x.v < S(0.0) ? -x : x; }
  friend Dual hypot(const Dual& x, const Dual& y) { return sqrt(x * x + y * y); }
};

}  // namespace tether
