/// \file
/// Time functions for joint moments and prescribed joint motion (scene
/// field values such as {"type": "sine", ...}; README "Scene file"):
///   constant   f(t) = value
///   ramp       f(t) = initial + rate · t
///   sine       f(t) = offset + amplitude · sin(2π frequency · t + phase)
///   table      piecewise-linear through points (tᵢ, fᵢ), t₀ < t₁ < …,
///              constant before the first and after the last point.
/// Each gives f, ḟ and f̈. A table's ḟ jumps at the points and its f̈ is zero
/// between them (the impulses at the points are not represented): a motion
/// prescribed by a table is C⁰ in angle and the integrator sees a jump in
/// the prescribed rate at each point.
#pragma once

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace lieflow {

struct TimeFunction {
  enum class Kind { kConstant, kRamp, kSine, kTable };
  Kind kind = Kind::kConstant;
  double value = 0.0;      ///< constant
  double initial = 0.0;    ///< ramp
  double rate = 0.0;       ///< ramp
  double amplitude = 0.0;  ///< sine
  double frequency = 0.0;  ///< sine, Hz
  double phase = 0.0;      ///< sine, rad
  double offset = 0.0;     ///< sine
  std::vector<std::pair<double, double>> points;  ///< table (t, f), t increasing

  static TimeFunction constant(double v) {
    TimeFunction f;
    f.value = v;
    return f;
  }
  static TimeFunction ramp(double initial, double rate) {
    TimeFunction f;
    f.kind = Kind::kRamp;
    f.initial = initial;
    f.rate = rate;
    return f;
  }
  static TimeFunction sine(double amplitude, double frequency, double phase = 0.0, double offset = 0.0) {
    TimeFunction f;
    f.kind = Kind::kSine;
    f.amplitude = amplitude;
    f.frequency = frequency;
    f.phase = phase;
    f.offset = offset;
    return f;
  }

  double operator()(double t) const { return evaluate(t, 0); }
  double derivative(double t) const { return evaluate(t, 1); }
  double secondDerivative(double t) const { return evaluate(t, 2); }

  /// The d-th derivative (d = 0, 1, 2) at t.
  double evaluate(double t, int d) const {
    switch (kind) {
      case Kind::kConstant:
        return d == 0 ? value : 0.0;
      case Kind::kRamp:
        return d == 0 ? initial + rate * t : (d == 1 ? rate : 0.0);
      case Kind::kSine: {
        const double w = 2.0 * 3.141592653589793 * frequency;
        const double a = w * t + phase;
        if (d == 0) return offset + amplitude * std::sin(a);
        if (d == 1) return amplitude * w * std::cos(a);
        return -amplitude * w * w * std::sin(a);
      }
      case Kind::kTable: {
        if (points.empty()) return 0.0;
        if (t <= points.front().first) return d == 0 ? points.front().second : 0.0;
        if (t >= points.back().first) return d == 0 ? points.back().second : 0.0;
        const auto it = std::upper_bound(points.begin(), points.end(), t,
                                         [](double x, const std::pair<double, double>& p) { return x < p.first; });
        const auto& p1 = *it;
        const auto& p0 = *(it - 1);
        const double slope = (p1.second - p0.second) / (p1.first - p0.first);
        if (d == 0) return p0.second + slope * (t - p0.first);
        return d == 1 ? slope : 0.0;
      }
    }
    return 0.0;
  }
};

}  // namespace lieflow
