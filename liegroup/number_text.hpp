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
#include <string>

namespace lieflow {

/// v to `digits` significant digits ("%g"); "nan", "inf" and "-inf" as such.
inline std::string formatNumber(double v, int digits = 6) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.*g", digits, v);
  return buffer;
}

}  // namespace lieflow
