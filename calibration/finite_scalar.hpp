/// \file
/// Whether a number a residual functor computes — a double, or a ceres::Jet
/// with its value and every derivative — is finite and small enough that the
/// cost ½ Σ r² over a whole recording stays finite. A functor returns false
/// on anything else, so that Ceres rejects the trial step (or refuses the
/// start) instead of carrying NaN or inf into the solution and its covariance.
#pragma once

#include <cmath>

#include <ceres/jet.h>

namespace lieflow {
namespace calibration {

/// Largest |value| a residual functor passes on: squared and summed over
/// 10⁷ samples (kMaxRecordingRows) it stays far below the overflow at 1e308.
/// A residual this large means the model has left the data altogether.
constexpr double kMaxResidualMagnitude = 1e100;

inline bool isUsable(double x) { return std::abs(x) <= kMaxResidualMagnitude; }  // false for NaN

template <typename T, int N>
bool isUsable(const ceres::Jet<T, N>& x) {
  return isUsable(x.a) && (x.v.array().abs() <= kMaxResidualMagnitude).all();
}

}  // namespace calibration
}  // namespace lieflow
