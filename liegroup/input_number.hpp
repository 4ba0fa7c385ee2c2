/// \file
/// What a number read from a scene or model file must be, in one place: the
/// scene reader (scene_json.cpp) and the model readers (import/) check every
/// number where they read it and name the field, or the element and
/// attribute, that held a bad one.
#pragma once

#include <climits>
#include <cmath>
#include <string>

#include "liegroup/number_text.hpp"

namespace lieflow {

/// The largest magnitude of a number in a scene or model file (SI units).
/// No quantity of a mechanism comes near it (the Earth's mass is 6e24 kg),
/// and with every input below it the products the simulation forms at the
/// start — energies ½kφ², inertias m r², momenta, up to six inputs in one
/// product — stay far inside double precision (1e180 against 1.8e308), so a
/// value such as a rest angle of 1e200 rad, whose spring energy overflows, is
/// refused where it is read instead of ending the run in infinities.
constexpr double kMaxInputMagnitude = 1e30;

/// Why `x` is not a usable input number ("is not a finite number", "1e+200
/// is beyond ±1e+30 ..."), or an empty string when it is.
inline std::string inputNumberProblem(double x) {
  if (std::isnan(x)) return "is not a finite number (nan)";
  if (std::isinf(x)) return std::string("is not a finite number (") + (x > 0 ? "inf" : "-inf") + ")";
  if (std::abs(x) > kMaxInputMagnitude)
    return formatNumber(x) + " is beyond ±" + formatNumber(kMaxInputMagnitude) +
           ", the largest magnitude lieflow reads (products of such numbers, an energy ½kφ² or an inertia m r², "
           "would overflow double precision)";
  return std::string();
}

/// The smallest value a quantity that must be positive may have: the
/// reciprocal of kMaxInputMagnitude, so that its inverse (a body's inverse
/// mass and inertia, a frequency) stays within it. A mass of 5e-324 kg once
/// passed as positive and made the constraint solve divide by zero.
constexpr double kMinPositiveInput = 1.0 / kMaxInputMagnitude;

/// Why `x` is not a usable positive input number, or an empty string.
inline std::string positiveInputProblem(double x) {
  if (std::string problem = inputNumberProblem(x); !problem.empty()) return problem;
  if (!(x > 0.0)) return "must be positive, got " + formatNumber(x);
  if (x < kMinPositiveInput)
    return formatNumber(x) + " is below " + formatNumber(kMinPositiveInput) +
           ", the smallest positive value lieflow reads (its reciprocal would exceed ±" +
           formatNumber(kMaxInputMagnitude) + ")";
  return std::string();
}

/// A count or index computed in double (a
/// period over a sampling interval, a time offset in samples) as an int:
/// clamped to [lo, hi] before the cast (a double beyond int's range, or NaN,
/// would make the cast undefined); NaN gives lo.
inline int clampedInt(double x, int lo, int hi) {
  if (!(x >= static_cast<double>(lo))) return lo;
  if (x >= static_cast<double>(hi)) return hi;
  return static_cast<int>(x);
}

}  // namespace lieflow
