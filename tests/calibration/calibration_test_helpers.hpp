/// \file
/// Shared helpers of the calibration tests: angles between fitted and true
/// axes, and the sanitizer switch for the sample counts of the slow tests.
#pragma once

#include <Eigen/Core>

#include "calibration/unit_axis.hpp"

namespace lieflow {
namespace calibration {
namespace test {

/// Angle in degrees between a fitted axis and the true one, up to sign.
inline double lineErrorDeg(const Eigen::Vector3d& fitted, const Eigen::Vector3d& truth) {
  return angleBetweenLines(fitted, truth) * kRadToDeg;
}

/// Angle in degrees between a fitted axis and the true one, sign included.
inline double errorDeg(const Eigen::Vector3d& fitted, const Eigen::Vector3d& truth) {
  return angleBetween(fitted, truth) * kRadToDeg;
}

/// The Monte Carlo tests run fewer samples per trial under AddressSanitizer
/// (CI's Debug -O1 + ASan/UBSan build, ~20× slower); the trial counts, the
/// tolerances and what they check stay the same.
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kSanitized = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif
#else
constexpr bool kSanitized = false;
#endif

}  // namespace test
}  // namespace calibration
}  // namespace lieflow
