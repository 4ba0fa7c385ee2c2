/// \file
/// The scalar kernels shared by SO(3) and SE(3): the half-angle quaternion
/// coefficients of exp and log, and the coefficients of V, Jr, Jr⁻¹ and Q,
/// each computed without cancellation and with Jet-safe series near θ = 0.
///
/// Notation: w ∈ ℝ³ a rotation vector, θ = ‖w‖, W = w^,
///   h = cos(θ/2),  k = sin(θ/2)/θ   (so exp(w) = (h, k w) as a quaternion).
/// Everything below is expressed through θ², h and k: sin θ/θ = 2hk and
/// (1 − cos θ)/θ² = 2k², so no `1 − cos θ` is ever formed.
#pragma once

#include <cmath>

#include <Eigen/Core>

#include "liegroup/detail/series.hpp"

namespace lieflow {
namespace detail {

/// h = cos(θ/2) and k = sin(θ/2)/θ from θ²: their polynomials in θ² below
/// kHalfAngleThetaSq (series.hpp), √ and sincos above.
template <typename T>
inline void halfAngle(const T& theta_sq, T* h, T* k) {
  using std::cos;
  using std::sin;
  if (theta_sq < T(kHalfAngleThetaSq)) {
    *h = horner(theta_sq, halfCosSeries());
    *k = horner(theta_sq, halfSincSeries());
  } else {
    // numext::sqrt: no errno branch (θ² ≥ 0 here); ADL still finds Jet's sqrt.
    const T theta = Eigen::numext::sqrt(theta_sq);
    const T half = T(0.5) * theta;
    *h = cos(half);
    *k = sin(half) / theta;
  }
}

/// (1 − cos θ)/θ² = 2 sin²(θ/2)/θ² = 2k². Exact, no cancellation.
template <typename T>
inline T oneMinusCosCoefficient(const T& k) {
  return T(2.0) * k * k;
}

/// (θ − sin θ)/θ³ = (1 − 2hk)/θ². The closed form is used only for θ ≥ 1,
/// where 1 − sin θ/θ ≥ 0.16 and nothing cancels.
template <typename T>
inline T thetaMinusSinCoefficient(const T& theta_sq, const T& h, const T& k) {
  if (theta_sq < T(kThetaMinusSinThetaSq)) return horner(theta_sq, thetaMinusSinSeries());
  return (T(1.0) - T(2.0) * h * k) / theta_sq;
}

/// (1 − (θ/2) cot(θ/2))/θ² = (1 − h/(2k))/θ², the W² coefficient of Jr⁻¹ and
/// V⁻¹. It is exact near π (h → 0, no `(1 + cos θ)/(θ sin θ)` form) and uses
/// its Bernoulli series for θ < 1.5. Precondition: θ < 2π (k ≠ 0).
template <typename T>
inline T halfCotCoefficient(const T& theta_sq, const T& h, const T& k) {
  if (theta_sq < T(kHalfCotThetaSq)) return horner(theta_sq, halfCotSeries());
  return (T(1.0) - h / (T(2.0) * k)) / theta_sq;
}

/// (θ²/2 + cos θ − 1)/θ⁴ = (θ²/2 − 2 sin²(θ/2))/θ⁴ = (1/2 − 2k²)/θ².
template <typename T>
inline T cosRemainderCoefficient(const T& theta_sq, const T& k) {
  if (theta_sq < T(kCosRemainderThetaSq)) return horner(theta_sq, cosRemainderSeries());
  return (T(0.5) - T(2.0) * k * k) / theta_sq;
}

/// (2θ − 3 sin θ + θ cos θ)/(2θ⁵) = (2 − 6hk + (h² − θ²k²))/(2θ⁴),
/// using sin θ/θ = 2hk and cos θ = h² − θ²k².
template <typename T>
inline T sinCosMixCoefficient(const T& theta_sq, const T& h, const T& k) {
  if (theta_sq < T(kSinCosMixThetaSq)) return horner(theta_sq, sinCosMixSeries());
  const T cos_theta = h * h - theta_sq * k * k;
  return (T(2.0) - T(6.0) * h * k + cos_theta) / (T(2.0) * theta_sq * theta_sq);
}

/// The logarithm of a unit quaternion (w, v), v = vec part, n² = ‖v‖².
/// Returns the scale s ≥ 0 with log = s · sign(w) v, θ = s·n ∈ [0, π], and
/// sets *h = |w| = cos(θ/2) of the representative with w ≥ 0.
///   s = θ/n = 2 atan2(n, |w|)/n,
/// and for n² < kSmallAngleSq its series s = (2/|w|)(1 − x²/3 + x⁴/5),
/// x² = n²/w², the series of atan(x)/x (error < x⁶/7 ≤ 3e-25).
/// Above it, atan(n/|w|) = atan2(n, |w|) for |w| > 0 keeps full relative
/// accuracy near π, where |w| → 0 and n/|w| → ∞ (atan of a large argument
/// is π/2 − atan(|w|/n) to the last bit); it is ~1.4× faster than atan2,
/// which is kept only for θ = π exactly (|w| = 0).
template <typename T>
inline T logScale(const T& abs_w, const T& n_sq) {
  using std::atan;
  using std::atan2;
  if (n_sq < T(kSmallAngleSq)) {
    const T inv_w = T(1.0) / abs_w;
    const T x_sq = n_sq * inv_w * inv_w;
    return T(2.0) * inv_w * (T(1.0) - x_sq * (T(1.0 / 3.0) - x_sq * T(1.0 / 5.0)));
  }
  const T n = Eigen::numext::sqrt(n_sq);
  const T half_angle = abs_w > T(0) ? atan(n / abs_w) : atan2(n, abs_w);
  return T(2.0) * half_angle / n;
}

}  // namespace detail
}  // namespace lieflow
