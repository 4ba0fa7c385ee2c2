#include "calibration/wobble_check.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include "calibration/low_pass.hpp"
#include "liegroup/number_text.hpp"

namespace lieflow {
namespace calibration {

namespace {

double meanSquare(const std::vector<double>& x, std::size_t trim) {
  double s = 0.0;
  std::size_t n = 0;
  for (std::size_t k = trim; k + trim < x.size(); ++k, ++n) s += x[k] * x[k];
  return n ? s / static_cast<double>(n) : 0.0;
}

struct AxisPower {
  double high = 0.0;   ///< above the split
  double white = 0.0;  ///< white noise's share of it
  double total = 0.0;  ///< about the mean
};

}  // namespace

LowPassChoice chooseLowPass(const JointSamples& samples) {
  LowPassChoice none;
  if (!samples.hasAngularVelocities() || samples.size() < 3) {
    none.reason = "no filter: the recording has no gyroscopes on both bodies";
    return none;
  }
  const std::vector<double>& t = samples.time;
  const double h = (t.back() - t.front()) / static_cast<double>(t.size() - 1);
  if (firstUnevenInterval(t) >= 0) {
    none.reason = "no filter: the sampling is not uniform, so the wobble check cannot run";
    return none;
  }
  const double rate = 1.0 / h;
  const std::size_t trim = static_cast<std::size_t>(std::ceil(kLowPassTrimPeriods * rate / kWobbleCutoffHz));
  if (!(kWobbleSplitHz < kMaxLowPassNyquistFraction * rate / 2.0) || samples.size() < static_cast<int>(4 * trim + 20)) {
    none.reason = "no filter: the recording is too slow or too short for the wobble check (" +
                  formatNumber(rate) + " Hz, " + std::to_string(samples.size()) + " samples)";
    return none;
  }
  const LowPassFilter split(kWobbleSplitHz, rate);
  const double gain = split.noisePowerGain();
  double worst_ratio = 0.0;
  std::string worst;
  bool wobble = false;
  for (int b = 0; b < 2; ++b) {
    const BodySamples& body = b == 0 ? samples.main : samples.secondary;
    for (int i = 0; i < 3; ++i) {
      std::vector<double> x(body.angular_velocity.size());
      double mean = 0.0;
      for (std::size_t k = 0; k < x.size(); ++k) mean += (x[k] = body.angular_velocity[k][i]);
      mean /= static_cast<double>(x.size());
      // White noise's σ² from third differences (Δ³ of white noise: 20σ²).
      double d3 = 0.0;
      for (std::size_t k = 3; k < x.size(); ++k) d3 += std::pow(x[k] - 3.0 * x[k - 1] + 3.0 * x[k - 2] - x[k - 3], 2);
      const double sigma2 = d3 / (20.0 * static_cast<double>(x.size() - 3));
      AxisPower a;
      const std::vector<double> band = split.apply(x);
      std::vector<double> high(x.size()), centred(x.size());
      for (std::size_t k = 0; k < x.size(); ++k) {
        high[k] = x[k] - band[k];
        centred[k] = x[k] - mean;
      }
      a.high = meanSquare(high, trim);
      a.white = sigma2 * (1.0 - gain);
      a.total = meanSquare(centred, trim);
      const double ratio = a.white > 0.0 ? a.high / a.white : (a.high > 0.0 ? HUGE_VAL : 0.0);
      const bool wobbles = ratio > kWobbleExcess && a.high - a.white > kWobbleShare * kWobbleShare * a.total;
      if (ratio > worst_ratio || worst.empty()) {
        worst_ratio = ratio;
        std::ostringstream w;
        w << (b == 0 ? "the main" : "the secondary") << " body's gyroscope " << "xyz"[i] << " axis has "
          << formatNumber(a.high, 3) << " (rad/s)^2 above " << formatNumber(kWobbleSplitHz) << " Hz, "
          << formatNumber(ratio, 3) << " times what its white noise (" << formatNumber(std::sqrt(sigma2), 3)
          << " rad/s from third differences) puts there";
        worst = w.str();
      }
      wobble = wobble || wobbles;
    }
  }
  if (!wobble) {
    none.reason = "no filter: no gyroscope wobbles (the largest: " + worst + "; a wobble is above " +
                  formatNumber(kWobbleExcess) + " times)";
    return none;
  }
  LowPassChoice chosen;
  chosen.cutoff_hz = kWobbleCutoffHz;
  chosen.reason = "a sensor wobbles on soft tissue: " + worst + "; low-passed at " + formatNumber(kWobbleCutoffHz) +
                  " Hz (gait's 4-6 Hz; `low_pass` none: unfiltered, `low_pass` HZ: another cutoff)";
  return chosen;
}

}  // namespace calibration
}  // namespace lieflow
