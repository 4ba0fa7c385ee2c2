/// \file
/// Angles continuous across ±π: the principal value in [−π, π] and the
/// unwrapped value nearest a previous one (joint angles of revolute and
/// universal joints are coordinates, so they must not jump by 2π).
///
/// The shift by 2πk is chosen from the plain values (k an integer), so the
/// ceres::Jet derivative of the result is that of the input angle.
#pragma once

#include <cmath>

#include "liegroup/scalar.hpp"

namespace lieflow {
namespace constraints {

constexpr double kTwoPi = 2.0 * kPi;

/// angle − 2πk in [−π, π], k = round(angle/2π).
template <typename T>
T wrapToPi(const T& angle) {
  const double k = std::round(scalarValue(angle) / kTwoPi);
  return angle - T(kTwoPi * k);
}

/// principal + 2πk, the representative of `principal` (mod 2π) nearest to
/// `previous` (so |result − previous| ≤ π). Unwrapping is correct as long as
/// the true angle moves by less than π between two calls.
template <typename T>
T unwrapAngle(const T& principal, const T& previous) {
  const double k = std::round((scalarValue(previous) - scalarValue(principal)) / kTwoPi);
  return principal + T(kTwoPi * k);
}

}  // namespace constraints
}  // namespace lieflow
