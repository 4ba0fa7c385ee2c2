/// \file
/// Numbers in messages. Every error and report that shows a number to a user
/// writes it with formatNumber: six significant digits in the shortest of
/// fixed and exponent form ("0.0004", "4.6e-08", "1e+300"), so that a cutoff
/// of 4.6e-8 Hz is not "0.000000 Hz" and 1e300 is not 301 digits (what
/// std::to_string(double) writes, "%f"). Files that must round-trip (CSV, the
/// JSON of --stats) use their own 17-digit writers, not this.
#pragma once

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace lieflow {

/// v to `digits` significant digits ("%g"); a computed value that is not
/// finite (a diverged Newton residual) as "not finite": a message says so in
/// words, and output that holds it still holds no NaN or inf token.
inline std::string formatNumber(double v, int digits = 6) {
  if (!std::isfinite(v)) return "not finite";
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.*g", digits, v);
  return buffer;
}

/// v in the fewest significant digits that read back as v (at most 17):
/// where a message compares a value with a bound, 1.0000000001 must not
/// show as 1 ("must be <= 1, got 1").
inline std::string formatExact(double v) {
  if (!std::isfinite(v)) return formatNumber(v);
  char buffer[40];
  for (int digits = 1; digits <= 17; ++digits) {
    std::snprintf(buffer, sizeof buffer, "%.*g", digits, v);
    if (std::strtod(buffer, nullptr) == v) break;
  }
  return buffer;
}

/// The entries of a vector (anything with size() and operator[], an Eigen
/// vector included), each by formatNumber, separated by spaces: "0.1 2 3e-05"
/// (Eigen's own stream pads them into columns).
template <typename Vector>
std::string formatNumbers(const Vector& v, int digits = 6) {
  std::string out;
  for (decltype(v.size()) i = 0; i < v.size(); ++i) out += (i ? " " : "") + formatNumber(static_cast<double>(v[i]), digits);
  return out;
}

}  // namespace lieflow
