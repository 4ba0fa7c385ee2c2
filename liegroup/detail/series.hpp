/// \file
/// Power series in θ² of the coefficient functions of the SO(3)/SE(3)
/// exponential map and its Jacobians, with the thresholds below which lieflow
/// evaluates them instead of the closed forms.
///
/// Why: the closed forms cancel catastrophically near θ = 0 (θ − sin θ loses
/// all digits below θ ≈ 1e-5) and need θ = √(θ²), whose derivative is infinite
/// at 0 for `ceres::Jet`. Each series below is a polynomial in θ² only, so its
/// value *and* its Jet derivatives are right at θ = 0 exactly; its truncation
/// error at the threshold is below 1e-17 relative to its leading term (stated
/// for each one), and the closed form above the threshold loses at most
/// ~30 ulp relative (checked against long double in tests/liegroup).
#pragma once

#include <array>
#include <cstddef>

namespace lieflow {
namespace detail {

/// n! as a double (exact up to 22!, correctly rounded beyond for our use).
constexpr double factorial(int n) {
  double r = 1.0;
  for (int i = 2; i <= n; ++i) r *= static_cast<double>(i);
  return r;
}

/// Σ_k c[k] x^k by Horner's rule; x is θ² in every use here.
template <typename T, std::size_t N>
inline T horner(const T& x, const std::array<double, N>& c) {
  T r = T(c[N - 1]);
  for (std::size_t k = N - 1; k-- > 0;) r = r * x + T(c[k]);
  return r;
}

/// (θ − sin θ)/θ³ = Σ_k (−1)^k θ^{2k} / (2k+3)!.
/// Used for θ² < kThetaMinusSinThetaSq = 1: the k = 9 term is 1/21! = 2e-20.
constexpr double kThetaMinusSinThetaSq = 1.0;
constexpr std::array<double, 9> thetaMinusSinSeries() {
  std::array<double, 9> c{};
  for (int k = 0; k < 9; ++k) c[k] = (k % 2 ? -1.0 : 1.0) / factorial(2 * k + 3);
  return c;
}

/// (θ²/2 + cos θ − 1)/θ⁴ = Σ_k (−1)^k θ^{2k} / (2k+4)!.
/// Used for θ² < kCosRemainderThetaSq = 4: the k = 11 term is 4¹¹/26! = 1e-20.
constexpr double kCosRemainderThetaSq = 4.0;
constexpr std::array<double, 11> cosRemainderSeries() {
  std::array<double, 11> c{};
  for (int k = 0; k < 11; ++k) c[k] = (k % 2 ? -1.0 : 1.0) / factorial(2 * k + 4);
  return c;
}

/// (2θ − 3 sin θ + θ cos θ)/(2θ⁵) = Σ_k (−1)^k (k+1) θ^{2k} / (2k+5)!.
/// Used for θ² < kSinCosMixThetaSq = 4: the k = 11 term is 12·4¹¹/27! = 5e-21.
constexpr double kSinCosMixThetaSq = 4.0;
constexpr std::array<double, 11> sinCosMixSeries() {
  std::array<double, 11> c{};
  for (int k = 0; k < 11; ++k) c[k] = (k % 2 ? -1.0 : 1.0) * (k + 1) / factorial(2 * k + 5);
  return c;
}

/// (1 − (θ/2) cot(θ/2))/θ² = 1/θ² − (1 + cos θ)/(2 θ sin θ)
///                          = Σ_{k≥1} |B_{2k}| θ^{2k−2} / (2k)!,
/// from 1 − x cot x = Σ_{k≥1} 2^{2k} |B_{2k}| x^{2k}/(2k)! (Abramowitz–Stegun
/// 4.3.70) with x = θ/2. Radius of convergence θ = 2π; the terms fall like
/// 2 (θ/2π)^{2k}. Used for θ² < kHalfCotThetaSq = 2.25 (θ < 1.5), where the
/// k = 16 term is 6e-18 of the leading 1/12; above it the closed form
/// 1 − (θ/2)cot(θ/2) ≥ 0.19 loses at most a factor 5 to cancellation.
constexpr double kHalfCotThetaSq = 2.25;
constexpr std::array<double, 15> halfCotSeries() {
  // |B_2|, |B_4|, ..., |B_30| (Abramowitz–Stegun Table 23.2).
  constexpr double abs_bernoulli[15] = {
      1.0 / 6.0,        1.0 / 30.0,          1.0 / 42.0,       1.0 / 30.0,
      5.0 / 66.0,       691.0 / 2730.0,      7.0 / 6.0,        3617.0 / 510.0,
      43867.0 / 798.0,  174611.0 / 330.0,    854513.0 / 138.0, 236364091.0 / 2730.0,
      8553103.0 / 6.0,  23749461029.0 / 870.0, 8615841276005.0 / 14322.0};
  std::array<double, 15> c{};
  for (int k = 1; k <= 15; ++k) c[k - 1] = abs_bernoulli[k - 1] / factorial(2 * k);
  return c;
}

/// The half-angle coefficients of exp as polynomials in θ², used for
/// θ² < kHalfAngleThetaSq = 1 instead of √, sincos and a division (faster,
/// and a polynomial in θ² keeps Jet derivatives right at θ = 0):
///   cos(θ/2)   = Σ_k (−1)^k θ^{2k} / (4^k (2k)!)        (k = 8 term: 7e-19)
///   sin(θ/2)/θ = Σ_k (−1)^k θ^{2k} / (2·4^k (2k+1)!)    (k = 8 term: 2e-20)
constexpr double kHalfAngleThetaSq = 1.0;
constexpr std::array<double, 8> halfCosSeries() {
  std::array<double, 8> c{};
  double four_k = 1.0;
  for (int k = 0; k < 8; ++k, four_k *= 4.0) c[k] = (k % 2 ? -1.0 : 1.0) / (four_k * factorial(2 * k));
  return c;
}
constexpr std::array<double, 8> halfSincSeries() {
  std::array<double, 8> c{};
  double four_k = 1.0;
  for (int k = 0; k < 8; ++k, four_k *= 4.0)
    c[k] = (k % 2 ? -1.0 : 1.0) / (2.0 * four_k * factorial(2 * k + 1));
  return c;
}

/// Below kSmallAngleSq = 1e-8 the logarithm uses the series of atan(x)/x
/// (see logScale), where √(n²) would break Jet derivatives at 0.
constexpr double kSmallAngleSq = 1e-8;

}  // namespace detail
}  // namespace lieflow
