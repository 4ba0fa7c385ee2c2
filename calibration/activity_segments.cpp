#include "calibration/activity_segments.hpp"

#include <algorithm>
#include <cmath>

namespace lieflow {
namespace calibration {

namespace {

/// ‖ω₁‖² + ‖ω₂‖² per sample, from the gyroscopes or, without them, from
/// successive orientations (the last sample repeats the one before it).
std::vector<double> squaredRates(const JointSamples& s) {
  const int n = s.size();
  std::vector<double> r(static_cast<std::size_t>(n), 0.0);
  if (s.hasAngularVelocities()) {
    for (int k = 0; k < n; ++k)
      r[k] = s.main.angular_velocity[k].squaredNorm() + s.secondary.angular_velocity[k].squaredNorm();
    return r;
  }
  for (int k = 0; k + 1 < n; ++k) {
    const double dt = s.time[k + 1] - s.time[k];
    if (!(dt > 0.0)) continue;  // (a repeated time: no rate there)
    for (const BodySamples* b : {&s.main, &s.secondary})
      r[k] += (b->orientation[k].inverse() * b->orientation[k + 1]).log().squaredNorm() / (dt * dt);
  }
  r[n - 1] = r[n - 2];
  return r;
}

}  // namespace

std::vector<SampleSpan> activityParts(const JointSamples& s) {
  const int n = s.size();
  if (n < 2 || !(s.hasAngularVelocities() || s.hasOrientations())) return {};
  const double step = s.meanStep();
  if (!(step > 0.0)) return {};  // (times that do not advance: nothing to cut by)
  const std::vector<double> r = squaredRates(s);
  // The level: the RMS over a centred window (prefix sums).
  const int half = static_cast<int>(std::min<double>(n, std::round(0.5 * kActivityWindowSeconds / step)));
  std::vector<double> prefix(static_cast<std::size_t>(n) + 1, 0.0);
  for (int k = 0; k < n; ++k) prefix[k + 1] = prefix[k] + r[k];
  std::vector<double> level(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) {
    const int a = std::max(0, k - half), b = std::min(n, k + half + 1);
    level[k] = std::sqrt((prefix[b] - prefix[a]) / (b - a));
  }
  std::vector<double> sorted = level;
  const std::size_t p90 = static_cast<std::size_t>(0.9 * (n - 1));
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(p90), sorted.end());
  const double threshold = kRestFraction * sorted[p90];
  // Rests long enough to cut, each cut in its middle.
  std::vector<SampleSpan> parts;
  int start = 0;  // where the current activity began
  int k = 0;
  while (k < n) {
    if (!(level[k] < threshold)) {
      ++k;
      continue;
    }
    int e = k;
    while (e < n && level[e] < threshold) ++e;
    const bool inside = k > 0 && e < n;  // a rest at either end divides nothing
    if (inside && s.time[e - 1] - s.time[k] >= kMinRestSeconds) {
      const int middle = (k + e) / 2;
      parts.push_back(SampleSpan{start, middle});
      start = middle;
    }
    k = e;
  }
  parts.push_back(SampleSpan{start, n});
  return parts;
}

}  // namespace calibration
}  // namespace lieflow
