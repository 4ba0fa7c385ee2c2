#include "calibration/shooting_grid.hpp"

#include <algorithm>
#include <climits>
#include <cmath>

#include <Eigen/Core>

#include "liegroup/input_number.hpp"
#include "liegroup/invalid_input.hpp"
#include "liegroup/number_text.hpp"

namespace lieflow {
namespace calibration {

double largestInterval(const std::vector<double>& time) {
  double largest = 0.0;
  for (std::size_t j = 0; j + 1 < time.size(); ++j) largest = std::max(largest, time[j + 1] - time[j]);
  return largest;
}

void requireResolved(const std::string& source, double max_interval, double omega, const std::string& what) {
  if (!(max_interval * omega > kPi)) return;
  throw InvalidInput(source + ": t", "the largest sample interval " + formatNumber(max_interval) +
                                         " s is longer than half a period (" + formatNumber(kPi / omega) +
                                         " s) of the fastest oscillation " + what + " (" + formatNumber(omega) +
                                         " rad/s): the recording cannot resolve it; is t in seconds?");
}

int shootingSegments(int requested, double duration, double period, int n) {
  const int segments = requested > 0 ? requested : clampedInt(std::round(duration / (0.25 * period)), 0, INT_MAX / 4);
  return std::max(1, std::min(segments, (n - 1) / kMinSegmentSamples));
}

std::vector<int> segmentBounds(int n, int segments) {
  std::vector<int> bound(static_cast<std::size_t>(segments) + 1);
  for (int s = 0; s <= segments; ++s)
    bound[static_cast<std::size_t>(s)] = static_cast<int>(std::lround(static_cast<double>(s) * (n - 1) / segments));
  return bound;
}

int localFitHalfWidth(double period, double duration, int n) {
  return std::max(2, clampedInt(std::round(period / (16.0 * duration / (n - 1))), 2, INT_MAX / 4));
}

}  // namespace calibration
}  // namespace lieflow
