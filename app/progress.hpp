/// \file
/// Progress of long runs on stderr: silent for the first kProgressDelay
/// seconds (short runs print nothing), then one line at most every
/// kProgressInterval seconds, so that a run that takes minutes shows that it
/// advances, and how far it is.
#pragma once

#include <chrono>
#include <iostream>
#include <string>

namespace lieflow {
namespace app {

/// When a progress line is due: none in the first `delay` seconds since the
/// start (or restart()), then one at most every `interval` seconds.
class LineThrottle {
 public:
  LineThrottle(double delay, double interval) : delay_(delay), interval_(interval) { restart(); }
  void restart() {
    start_ = Clock::now();
    last_ = -1e300;
  }
  double elapsed() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }
  /// Whether a line is due now (then the next one is `interval` away).
  bool due() {
    const double t = elapsed();
    if (t < delay_ || t - last_ < interval_) return false;
    last_ = t;
    return true;
  }

 private:
  using Clock = std::chrono::steady_clock;
  double delay_, interval_;
  Clock::time_point start_;
  double last_;
};

class ProgressReporter {
 public:
  static constexpr double kProgressDelay = 2.0;
  static constexpr double kProgressInterval = 5.0;

  /// `what` names the work ("simulate pendulum with rkmk4"); `t_end` its end time.
  ProgressReporter(std::string what, double t_end, std::ostream& out = std::cerr)
      : what_(std::move(what)), t_end_(t_end), out_(out), lines_(kProgressDelay, kProgressInterval) {}

  /// Reports (t, steps) if it is time to.
  void operator()(double t, long steps) {
    if (!lines_.due()) return;
    const double elapsed = lines_.elapsed();
    const double fraction = t_end_ > 0.0 ? t / t_end_ : 0.0;
    out_ << "lieflow: " << what_ << ": t = " << t << " of " << t_end_ << " (" << static_cast<int>(100.0 * fraction)
         << " %), " << steps << " steps, " << static_cast<long>(elapsed) << " s";
    if (fraction > 0.0) out_ << ", about " << static_cast<long>(elapsed * (1.0 - fraction) / fraction) << " s left";
    out_ << std::endl;
  }

 private:
  std::string what_;
  double t_end_;
  std::ostream& out_;
  LineThrottle lines_;
};

}  // namespace app
}  // namespace lieflow
