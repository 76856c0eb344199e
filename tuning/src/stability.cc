#include "tether/tuning/stability.h"

#include <Eigen/LU>  // 2x2 determinant
#include <cmath>
#include <complex>

#include "tether/dynamics/integration/integrator_descriptor.h"

namespace tether {
namespace {

using Matrix2 = Eigen::Matrix2d;

Matrix2 Amplification(Integrator integrator, double x, double zeta) {
  Matrix2 k;
  k << 0.0, 1.0, -1.0, -2.0 * zeta;
  const Matrix2 z = x * k;
  const Matrix2 identity = Matrix2::Identity();
  const IntegratorDescriptor& method = Describe(integrator);
  if (method.stability_terms == 0) {  // symplectic Euler, a partitioned method (integrator_descriptor.h)
    Matrix2 m;
    m << 1.0 - x * x, x * (1.0 - 2.0 * zeta * x), -x, 1.0 - 2.0 * zeta * x;
    return m;
  }
  Matrix2 sum = identity, power = identity;  // R(Z) = I + Z/d_1 + Z^2/(d_1 d_2) + ...
  for (int k = 0; k < method.stability_terms; ++k) {
    power = power * z / method.stability_divisors[k];
    sum += power;
  }
  return sum;
}

}  // namespace

double AmplificationRadius(Integrator integrator, double x, double zeta) {
  const Matrix2 m = Amplification(integrator, x, zeta);
  const double trace = m.trace(), det = m.determinant();
  const std::complex<double> root = std::sqrt(std::complex<double>(trace * trace - 4.0 * det));
  return std::max(std::abs((trace + root) / 2.0), std::abs((trace - root) / 2.0));
}

double StabilityBound(Integrator integrator, double zeta) {
  constexpr double kScan = 1e-3, kTolerance = 1e-12;
  auto stable = [&](double x) { return AmplificationRadius(integrator, x, zeta) <= 1.0 + kTolerance; };
  double low = 0.0;
  while (low < 100.0 && stable(low + kScan)) low += kScan;
  double high = low + kScan;
  while (high - low > 1e-10 * high) {
    const double middle = 0.5 * (low + high);
    (stable(middle) ? low : high) = middle;
  }
  return low;
}

}  // namespace tether
