#include "calibration/low_pass.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <string>
#include <type_traits>
#include <utility>

#include "liegroup/invalid_input.hpp"
#include "liegroup/number_text.hpp"
#include "liegroup/input_number.hpp"

namespace lieflow {
namespace calibration {
namespace {

/// Reflections longer than this many time constants 1/(2π f_c) add nothing
/// (the section's impulse response has decayed below 1e-6 after about 3 f_s/f_c samples).
constexpr double kPaddingPerCutoff = 3.0;

/// One causal pass of a biquad over x, starting in the steady state of x[0]
/// (DC gain 1: y = x for a constant input).
template <class T>
void pass(const LowPassFilter::Section& f, std::vector<T>* x) {
  if (x->empty()) return;
  T x1 = (*x)[0], x2 = (*x)[0], y1 = (*x)[0], y2 = (*x)[0];
  for (T& v : *x) {
    const T y = f.b0 * v + f.b1 * x1 + f.b2 * x2 - f.a1 * y1 - f.a2 * y2;
    x2 = x1;
    x1 = v;
    y2 = y1;
    y1 = y;
    v = y;
  }
}

/// One causal pass of the cascade.
template <class T>
void pass(const LowPassFilter& f, std::vector<T>* x) {
  for (const LowPassFilter::Section& s : f.sections) pass(s, x);
}

template <class T>
std::vector<T> filtfilt(const LowPassFilter& f, const std::vector<T>& x) {
  const int n = static_cast<int>(x.size());
  if (n < 2) return x;
  const int pad = clampedInt(std::ceil(kPaddingPerCutoff * f.sample_rate_hz / f.cutoff_hz), 0, n - 1);
  // Odd reflection about each end sample: 2x₀ − x_i, which continues the
  // signal's value and slope through the end.
  std::vector<T> y;
  y.reserve(n + 2 * pad);
  for (int i = pad; i >= 1; --i) y.push_back(2.0 * x[0] - x[i]);
  y.insert(y.end(), x.begin(), x.end());
  for (int i = 1; i <= pad; ++i) y.push_back(2.0 * x[n - 1] - x[n - 1 - i]);
  pass(f, &y);
  std::reverse(y.begin(), y.end());
  pass(f, &y);
  std::reverse(y.begin(), y.end());
  return std::vector<T>(y.begin() + pad, y.begin() + pad + n);
}

}  // namespace

LowPassFilter::LowPassFilter(double cutoff, double sample_rate) : cutoff_hz(cutoff), sample_rate_hz(sample_rate) {
  // The analogue Butterworth-4 is 1/((s² + s/Q₁ + 1)(s² + s/Q₂ + 1)) with
  // 1/Q = 2 cos(π/8), 2 cos(3π/8) (its poles at angles π/8, 3π/8 from the
  // negative real axis); each factor's bilinear transform, prewarped so that
  // the digital cutoff is exactly f_c.
  const double w0 = 2.0 * kPi * cutoff / sample_rate;
  const double c = std::cos(w0);
  const double inverse_q[2] = {2.0 * std::cos(kPi / 8.0), 2.0 * std::cos(3.0 * kPi / 8.0)};
  for (int i = 0; i < 2; ++i) {
    const double alpha = 0.5 * std::sin(w0) * inverse_q[i];  // sin(w₀)/(2Q)
    const double a0 = 1.0 + alpha;
    Section& s = sections[i];
    s.b0 = 0.5 * (1.0 - c) / a0;
    s.b1 = (1.0 - c) / a0;
    s.b2 = s.b0;
    s.a1 = -2.0 * c / a0;
    s.a2 = (1.0 - alpha) / a0;
  }
}

std::vector<Eigen::Vector3d> LowPassFilter::apply(const std::vector<Eigen::Vector3d>& x) const {
  return filtfilt(*this, x);
}

std::vector<double> LowPassFilter::apply(const std::vector<double>& x) const { return filtfilt(*this, x); }

double LowPassFilter::noisePowerGain() const {
  // The zero-phase response to a unit impulse in the middle of a long zero
  // signal (the reflections are then zero as well).
  const int half = clampedInt(std::ceil(40.0 * sample_rate_hz / cutoff_hz), 0, INT_MAX / 4) + 8;
  std::vector<double> impulse(2 * half + 1, 0.0);
  impulse[half] = 1.0;
  const std::vector<double> h = apply(impulse);
  double sum = 0.0;
  for (double v : h) sum += v * v;
  return sum;
}

int firstUnevenInterval(const std::vector<double>& t) {
  if (t.size() < 2) return -1;
  const double h = (t.back() - t.front()) / static_cast<double>(t.size() - 1);
  for (std::size_t k = 0; k + 1 < t.size(); ++k)
    if (!(std::abs(t[k + 1] - t[k] - h) <= kLowPassUniformSampling * h)) return static_cast<int>(k);
  return -1;
}

JointSamples lowPassed(const JointSamples& samples, double cutoff_hz, const char* field, LowPassFilter* filter_out,
                       JointSamples* unfiltered) {
  const std::vector<double>& t = samples.time;
  if (!(cutoff_hz > 0.0) || !std::isfinite(cutoff_hz))
    throw InvalidInput(samples.source, std::string(field) + ": the cutoff must be a positive frequency in Hz");
  if (t.size() < 4) throw InvalidInput(samples.source, std::string(field) + " needs at least 4 samples");
  const double h = (t.back() - t.front()) / static_cast<double>(t.size() - 1);
  if (const int k = firstUnevenInterval(t); k >= 0)
    throw InvalidInput(samples.source, std::string(field) + " needs uniformly sampled times: t[" +
                                           std::to_string(k + 1) + "] - t[" + std::to_string(k) +
                                           "] differs from the mean interval by more than " +
                                           formatNumber(kLowPassUniformSampling) + " of it");
  const double rate = 1.0 / h;
  if (cutoff_hz >= kMaxLowPassNyquistFraction * 0.5 * rate)
    throw InvalidInput(samples.source, std::string(field) + " " + formatNumber(cutoff_hz) +
                                           " Hz: the cutoff must lie below " +
                                           formatNumber(kMaxLowPassNyquistFraction * 0.5 * rate) + " Hz (" +
                                           formatNumber(kMaxLowPassNyquistFraction) +
                                           " of the Nyquist frequency of the " + formatNumber(rate) +
                                           " Hz sampling)");
  // The samples dropped at each end, counted in double precision first: a
  // cutoff far below the sampling rate asks for more than an int holds.
  const std::size_t n = t.size();
  const double trim_wanted = std::ceil(kLowPassTrimPeriods * rate / cutoff_hz);
  const double needed = 4.0 * trim_wanted + 20.0;
  if (!(needed <= static_cast<double>(n)))
    throw InvalidInput(samples.source, std::string(field) + " " + formatNumber(cutoff_hz) + " Hz drops " +
                                           formatNumber(trim_wanted) + " samples at each end (the filter's memory, " +
                                           formatNumber(kLowPassTrimPeriods) + "/cutoff): the recording's " +
                                           std::to_string(n) + " samples are too few (at least " +
                                           formatNumber(needed) + "); record longer or raise the cutoff");
  const int trim = static_cast<int>(trim_wanted);
  const LowPassFilter filter(cutoff_hz, rate);
  JointSamples out = samples;
  for (BodySamples* b : {&out.main, &out.secondary}) {
    if (b->hasAngularVelocity()) b->angular_velocity = filter.apply(b->angular_velocity);
    if (b->hasSpecificForce()) b->specific_force = filter.apply(b->specific_force);
  }
  if (filter_out) *filter_out = filter;
  const int end = static_cast<int>(n) - trim;
  if (unfiltered) *unfiltered = samplesBetween(samples, trim, end);
  return samplesBetween(out, trim, end);
}

}  // namespace calibration
}  // namespace lieflow
