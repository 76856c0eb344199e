// Dual numbers (dual.h): arithmetic and every listed function for Dual<double> (first derivatives) and
// Dual<Dual<double>> (second derivatives, seeded at both levels as the user-constraint derivation does) against
// analytic derivatives; Dual<Jet> carries the Jet's derivative parts through value and derivative.
#include "tether/dynamics/constraints/dual.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "tether/dynamics/scalars/scalar.h"

namespace tether {
namespace {

using D1 = Dual<double>;
using D2 = Dual<Dual<double>>;

constexpr double kTolerance = 1e-13;  // relative to max(1, |exact|)

void ExpectClose(double actual, double exact, const std::string& what) {
  EXPECT_NEAR(actual, exact, kTolerance * std::max(1.0, std::abs(exact))) << what;
}

// x + eps1 + eps2: value f(x), both first-level parts f'(x), the second-level part f''(x).
D2 SeedTwice(double x) { return D2(D1(x, 1.0), D1(1.0, 0.0)); }

// A function of one variable given three ways: on D1, on D2, and its analytic value, f' and f''.
struct Case {
  std::string name;
  double x;
  std::function<D1(const D1&)> f1;
  std::function<D2(const D2&)> f2;
  double value, first, second;
};

void Check(const Case& c) {
  SCOPED_TRACE(c.name + " at x = " + std::to_string(c.x));
  const D1 y1 = c.f1(D1(c.x, 1.0));
  ExpectClose(y1.v, c.value, "value");
  ExpectClose(y1.d, c.first, "first derivative");
  const D2 y2 = c.f2(SeedTwice(c.x));
  ExpectClose(y2.v.v, c.value, "value (nested)");
  ExpectClose(y2.v.d, c.first, "first derivative (inner level)");
  ExpectClose(y2.d.v, c.first, "first derivative (outer level)");
  ExpectClose(y2.d.d, c.second, "second derivative");
}

// The same generic lambda for both levels.
#define TETHER_CASE(name, x, expression, value, first, second)                                                         \
  Case {                                                                                                               \
    name, x, [](const D1& t) -> D1 { return expression; }, [](const D2& t) -> D2 { return expression; }, value, first, \
        second                                                                                                         \
  }

TEST(Dual, ArithmeticMatchesAnalyticDerivatives) {
  const double x = 1.7;
  const std::vector<Case> cases = {
      TETHER_CASE("x * x * x", x, t * t * t, x * x * x, 3 * x * x, 6 * x),
      TETHER_CASE("1 / x", x, 1.0 / t, 1 / x, -1 / (x * x), 2 / (x * x * x)),
      TETHER_CASE("x / (x + 2)", x, t / (t + 2.0), x / (x + 2), 2 / ((x + 2) * (x + 2)),
                  -4 / ((x + 2) * (x + 2) * (x + 2))),
      TETHER_CASE("(3 - x) * 2 - x / 4 + (-x)", x, (3.0 - t) * 2.0 - t / 4.0 + (-t), (3 - x) * 2 - x / 4 - x, -3.25,
                  0.0),
      TETHER_CASE("+x - 5 + x * x", x, +t - 5.0 + t * t, x - 5 + x * x, 1 + 2 * x, 2.0),
  };
  for (const Case& c : cases) Check(c);
}

TEST(Dual, CompoundAssignmentAndComparisons) {
  D1 y(2.0, 1.0);     // y = x at x = 2
  y += D1(3.0);       // x + 3
  y *= D1(2.0, 1.0);  // (x + 3) x
  y -= 1.0;           // (x + 3) x - 1
  y /= D1(2.0, 1.0);  // ((x + 3) x - 1) / x = x + 3 - 1/x
  ExpectClose(y.v, 2 + 3 - 0.5, "value");
  ExpectClose(y.d, 1 + 0.25, "derivative");

  // comparisons look at values only
  const D1 a(1.0, 100.0), b(2.0, -100.0), c(1.0, -5.0);
  EXPECT_TRUE(a < b);
  EXPECT_TRUE(b > a);
  EXPECT_TRUE(a <= c);
  EXPECT_TRUE(a >= c);
  EXPECT_TRUE(a == c);
  EXPECT_TRUE(a != b);
  EXPECT_FALSE(a < c);
  EXPECT_FALSE(a != c);
}

TEST(Dual, ElementaryFunctionsMatchAnalyticDerivatives) {
  const double x = 0.37, y = 2.3, p = 2.5;
  const double t = std::tan(x), one_minus = 1 - x * x;
  const std::vector<Case> cases = {
      TETHER_CASE("sqrt", y, sqrt(t), std::sqrt(y), 0.5 / std::sqrt(y), -0.25 / (y * std::sqrt(y))),
      TETHER_CASE("sin", x, sin(t), std::sin(x), std::cos(x), -std::sin(x)),
      TETHER_CASE("cos", x, cos(t), std::cos(x), -std::sin(x), -std::cos(x)),
      TETHER_CASE("tan", x, tan(t), t, 1 + t * t, 2 * t * (1 + t * t)),
      TETHER_CASE("asin", x, asin(t), std::asin(x), 1 / std::sqrt(one_minus), x / std::pow(one_minus, 1.5)),
      TETHER_CASE("acos", x, acos(t), std::acos(x), -1 / std::sqrt(one_minus), -x / std::pow(one_minus, 1.5)),
      TETHER_CASE("atan", x, atan(t), std::atan(x), 1 / (1 + x * x), -2 * x / ((1 + x * x) * (1 + x * x))),
      TETHER_CASE("exp", x, exp(t), std::exp(x), std::exp(x), std::exp(x)),
      TETHER_CASE("log", y, log(t), std::log(y), 1 / y, -1 / (y * y)),
      TETHER_CASE("pow", y, pow(t, 2.5), std::pow(y, p), p * std::pow(y, p - 1), p * (p - 1) * std::pow(y, p - 2)),
      TETHER_CASE("abs (negative)", -y, abs(t), y, -1.0, 0.0),
      TETHER_CASE("abs (positive)", y, abs(t), y, 1.0, 0.0),
  };
  for (const Case& c : cases) Check(c);
}

// atan2 and hypot: two arguments moving along a direction (dy, dx); the second derivative along it is the
// Hessian's quadratic form.
TEST(Dual, TwoArgumentFunctionsMatchAnalyticDerivatives) {
  const double dy = 0.6, dx = -1.3;
  // all four quadrants of atan2
  for (const auto& [y, x] :
       std::vector<std::pair<double, double>>{{0.8, 1.1}, {0.8, -1.1}, {-0.8, -1.1}, {-0.8, 1.1}}) {
    SCOPED_TRACE("(y, x) = (" + std::to_string(y) + ", " + std::to_string(x) + ")");
    const double r2 = x * x + y * y, r = std::sqrt(r2);
    const D2 Y(D1(y, dy), D1(dy, 0.0)), X(D1(x, dx), D1(dx, 0.0));

    // atan2: gradient (x, -y) / r^2 over (y, x); Hessian [-2xy, y^2 - x^2; y^2 - x^2, 2xy] / r^4
    const D2 angle = atan2(Y, X);
    ExpectClose(angle.v.v, std::atan2(y, x), "atan2 value");
    ExpectClose(angle.d.v, (x * dy - y * dx) / r2, "atan2 first derivative");
    ExpectClose(angle.d.d, (-2 * x * y * dy * dy + 2 * (y * y - x * x) * dy * dx + 2 * x * y * dx * dx) / (r2 * r2),
                "atan2 second derivative");
    const D1 angle1 = atan2(D1(y, dy), D1(x, dx));
    ExpectClose(angle1.d, (x * dy - y * dx) / r2, "atan2 first derivative (Dual<double>)");

    // hypot: gradient n = (y, x) / r; Hessian (I - n n^T) / r
    const D2 length = hypot(Y, X);
    const double along = (y * dy + x * dx) / r;
    ExpectClose(length.v.v, std::hypot(y, x), "hypot value");
    ExpectClose(length.d.v, along, "hypot first derivative");
    ExpectClose(length.d.d, (dy * dy + dx * dx - along * along) / r, "hypot second derivative");
  }
}

// Different directions at the two levels give the mixed second derivative: for f = x^2 y along (1, 0) inside and
// (0, 1) outside, d.d = d^2 f / dx dy = 2x.
TEST(Dual, MixedSecondDerivative) {
  const double x = 1.3, y = -0.4;
  const D2 X(D1(x, 1.0), D1(0.0, 0.0)), Y(D1(y, 0.0), D1(1.0, 0.0));
  const D2 f = X * X * Y;
  ExpectClose(f.v.v, x * x * y, "value");
  ExpectClose(f.v.d, 2 * x * y, "df/dx");
  ExpectClose(f.d.v, x * x, "df/dy");
  ExpectClose(f.d.d, 2 * x, "d2f/dxdy");
}

// dual.h lists + - * / "with Dual, S and double": a Dual<S> mixes with its own scalar S as well as with double.
template <typename D, typename S, typename = void>
struct MixesWith : std::false_type {};
template <typename D, typename S>
struct MixesWith<
    D, S,
    std::void_t<decltype(std::declval<D>() + std::declval<S>()), decltype(std::declval<S>() + std::declval<D>()),
                decltype(std::declval<D>() - std::declval<S>()), decltype(std::declval<S>() - std::declval<D>()),
                decltype(std::declval<D>() * std::declval<S>()), decltype(std::declval<S>() * std::declval<D>()),
                decltype(std::declval<D>() / std::declval<S>()), decltype(std::declval<S>() / std::declval<D>())>>
    : std::true_type {};

// x op s against x op Dual<S>(s) (s promoted explicitly, derivative zero).
template <typename S>
void CheckMixedWithScalar(const char* name, const Dual<S>& x, const S& s) {
  constexpr bool kMixes = MixesWith<Dual<S>, S>::value;
  EXPECT_TRUE(kMixes) << "Dual<S> op S (+ - * /, either order) does not compile for S = " << name;
  if constexpr (kMixes) {
    const Dual<S> promoted(s);
    const Dual<S> mixed = (x + s) * s - s / x + (s - x) / s;
    const Dual<S> reference = (x + promoted) * promoted - promoted / x + (promoted - x) / promoted;
    EXPECT_EQ(mixed.v, reference.v);
    EXPECT_EQ(mixed.d, reference.d);
  }
}

TEST(Dual, MixesWithItsScalar) {
  EXPECT_TRUE((MixesWith<D1, double>::value));
  CheckMixedWithScalar("double", D1(1.3, 1.0), 0.7);
  // S = Dual<double> (the nested dual of the Jdot q' derivation) and S = Jet
  CheckMixedWithScalar("Dual<double>", SeedTwice(1.3), D1(0.7, 0.2));
  CheckMixedWithScalar("Jet", Dual<Jet>(Jet(1.3, 0), Jet(1.0)), Jet(0.7, 1));
}

// Dual<Jet>: x is a Jet carrying its own derivative directions (dx/dp), and the dual part seeds d/dx. For each
// function, the value part must equal ceres' f(x) and the dual part ceres' f'(x), Jet parts included (the
// latter's Jet part is f''(x) dx/dp).
TEST(Dual, OverJetCarriesJetDerivatives) {
  Jet x(0.41);
  x.v << 1.0, -0.5, 0.25, 2.0;
  Jet y(1.9);
  y.v << 0.3, 1.0, -2.0, 0.0;
  const Dual<Jet> X(x, Jet(1.0)), Y(y, Jet(0.0));  // d/dx only
  const Jet one(1.0);
  struct JetCase {
    std::string name;
    Dual<Jet> result;
    Jet value, first;
  };
  const std::vector<JetCase> cases = {
      {"x * y + x / y - 3", X * Y + X / Y - 3.0, x * y + x / y - 3.0, y + one / y},
      {"sqrt", sqrt(X), sqrt(x), one / (2.0 * sqrt(x))},
      {"sin", sin(X), sin(x), cos(x)},
      {"cos", cos(X), cos(x), -sin(x)},
      {"tan", tan(X), tan(x), one + tan(x) * tan(x)},
      {"asin", asin(X), asin(x), one / sqrt(one - x * x)},
      {"acos", acos(X), acos(x), -one / sqrt(one - x * x)},
      {"atan", atan(X), atan(x), one / (one + x * x)},
      {"atan2", atan2(Y, X), atan2(y, x), -y / (x * x + y * y)},
      {"exp", exp(X), exp(x), exp(x)},
      {"log", log(X), log(x), one / x},
      {"pow", pow(X, 1.5), pow(x, 1.5), 1.5 * sqrt(x)},
      {"abs", abs(-X), x, one},
      {"hypot", hypot(X, Y), sqrt(x * x + y * y), x / sqrt(x * x + y * y)},
  };
  for (const JetCase& c : cases) {
    SCOPED_TRACE(c.name);
    ExpectClose(c.result.v.a, c.value.a, "value");
    ExpectClose(c.result.d.a, c.first.a, "derivative");
    for (int k = 0; k < kJetStride; ++k) {
      ExpectClose(c.result.v.v[k], c.value.v[k], "Jet part of the value, direction " + std::to_string(k));
      ExpectClose(c.result.d.v[k], c.first.v[k], "Jet part of the derivative, direction " + std::to_string(k));
    }
  }
  // one explicit analytic check of the Jet part of the derivative: d/dp (sin'(x)) = -sin(x) dx/dp
  const Dual<Jet> s = sin(X);
  for (int k = 0; k < kJetStride; ++k) ExpectClose(s.d.v[k], -std::sin(x.a) * x.v[k], "d cos(x) / dp");
}

}  // namespace
}  // namespace tether
