/// \file
/// Zero-phase low-pass filtering of recorded rates and specific forces
/// (`lieflow calibrate hinge --low-pass HZ`), and what the filter does to the
/// noise the fits' statistics rest on.
///
/// Body-worn sensors move on soft tissue: on the real knee recording of
/// tests/data/qmt the thigh's gyroscope reads ±5–10 rad/s at 7–50 Hz about the
/// segment's long axis (85 % of that axis' power), a wobble of the sensor on
/// the leg that no joint model describes, while the knee's own motion lies
/// below 5 Hz. Biomechanics low-passes such signals before any joint model
/// (Winter, *Biomechanics and Motor Control of Human Movement*, ch. 2: 6 Hz
/// for gait), and so does this.
///
/// The filter: a fourth-order Butterworth low-pass from the bilinear transform
/// with the cutoff prewarped (Oppenheim & Schafer §7.1), as two second-order
/// sections with Q = 1/(2 cos(π/8)) and 1/(2 cos(3π/8)) (each the biquad of
/// R. Bristow-Johnson's "Audio EQ cookbook"), run forward and then backward
/// over the signal (filtfilt: zero phase, response 1/(1 + (f_w/f_c)⁸) with
/// f_w = (f_s/π) tan(πf/f_s) the warped frequency: −6 dB at f_c, 0.4 % down at
/// f_c/2, 1/257 at 2f_c). Each pass starts in the steady state of its first
/// input, and the signal is extended at both ends by its odd reflection about
/// the end sample (3 f_s/f_c samples, at most the signal's length − 1), so the
/// ends carry no start-up transient; lowPassed then drops the ends, where the
/// reflection still shows (kLowPassTrimPeriods). (A second-order section
/// alone, 1/(1 + (f/f_c)⁴), lets 6 % of a 10 Hz wobble through a 5 Hz cutoff.)
#pragma once

#include <vector>

#include <Eigen/Core>

#include "calibration/joint_samples.hpp"

namespace lieflow {
namespace calibration {

/// The cutoff must lie below this fraction of the Nyquist frequency (the
/// bilinear transform's warping grows without bound at Nyquist).
constexpr double kMaxLowPassNyquistFraction = 0.8;
/// Largest relative spread of the sampling interval a filtered recording may have.
constexpr double kLowPassUniformSampling = 1e-3;

/// The first k whose interval t[k+1] − t[k] differs from the mean interval by
/// more than kLowPassUniformSampling of it, or −1 (uniformly sampled).
int firstUnevenInterval(const std::vector<double>& t);

/// The cascade of two biquads y_k = b₀x_k + b₁x_{k−1} + b₂x_{k−2} − a₁y_{k−1} − a₂y_{k−2}.
struct LowPassFilter {
  struct Section {
    double b0 = 1.0, b1 = 0.0, b2 = 0.0, a1 = 0.0, a2 = 0.0;
  };
  double cutoff_hz = 0.0;
  double sample_rate_hz = 0.0;
  Section sections[2];

  LowPassFilter() = default;
  /// The fourth-order Butterworth for `cutoff_hz` at `sample_rate_hz`.
  /// Preconditions: 0 < cutoff_hz < kMaxLowPassNyquistFraction · sample_rate_hz / 2.
  LowPassFilter(double cutoff_hz, double sample_rate_hz);

  /// The zero-phase (forward-backward) filtered signal, same length.
  std::vector<Eigen::Vector3d> apply(const std::vector<Eigen::Vector3d>& x) const;
  std::vector<double> apply(const std::vector<double>& x) const;

  /// Σ h_k² of the zero-phase impulse response: the variance of white noise
  /// after the filter over its variance before, ∫|H|² over the band / Nyquist
  /// ≈ (7/8)(π/8)/sin(π/8) · 2f_c/f_s = 0.898 · 2f_c/f_s for f_c ≪ f_s. The fits
  /// use it to turn the filtered residuals' variance back into the noise
  /// level that sets the axes' uncertainty (two_axis_solver.hpp, LowPassNoise).
  double noisePowerGain() const;
};

/// Samples dropped at each end of a filtered recording, in periods of the
/// cutoff: there the filter's memory reaches into the reflected extension, and
/// the end sample's own wobble and noise, doubled by the reflection, shift the
/// output (a 1 rad/s wobble at 10–20 Hz left errors of its size within ~0.2 s
/// of the ends, and σ twice too large).
constexpr double kLowPassTrimPeriods = 1.0;

/// Samples over which low-passed noise stays correlated, for a sandwich's lag
/// window (the zero-phase response's autocorrelation has decayed to a few %
/// after two periods of the cutoff).
inline int lowPassCorrelationSamples(const LowPassFilter& f) {
  return static_cast<int>(2.0 * f.sample_rate_hz / f.cutoff_hz + 1.0);
}

/// `samples` with every body's angular velocities and specific forces
/// filtered (orientations are left as recorded), and kLowPassTrimPeriods/f_c
/// of samples dropped at each end (every column, times included; `unfiltered`,
/// when given, receives `samples` trimmed the same way). Throws
/// lieflow::InvalidInput naming `samples.source` and `field` for a cutoff that
/// is not positive or not below kMaxLowPassNyquistFraction of the Nyquist
/// frequency, for non-uniform times, or for a recording shorter than 4 trims
/// plus 20 samples.
JointSamples lowPassed(const JointSamples& samples, double cutoff_hz, const char* field = "`low_pass`",
                       LowPassFilter* filter = nullptr, JointSamples* unfiltered = nullptr);

}  // namespace calibration
}  // namespace lieflow
