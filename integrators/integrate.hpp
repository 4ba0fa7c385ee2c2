/// \file
/// Drivers that advance a system with a stepper from t0 to t_end and hand
/// every step to an observer (Boost.odeint's integrate_n_steps pattern):
/// steppers know one step, systems know their vector field, observers decide
/// what to record. The drivers detect blow-up (a non-finite state) and
/// implicit-solver failure and stop there, saying so.
#pragma once

#include <cmath>
#include <sstream>
#include <string>
#include <utility>

#include "integrators/step_report.hpp"
#include "liegroup/scalar.hpp"
#include "liegroup/number_text.hpp"

namespace lieflow {

/// What a run did: steps taken, Newton work, and why it stopped early.
struct RunSummary {
  long steps = 0;
  long rejected_steps = 0;
  long newton_iterations = 0;
  /// Steps a stepper took as substeps (StepReport::substeps).
  long substepped_steps = 0;
  bool failed = false;
  /// The run stopped at its step limit (a failure, `failure` says where).
  bool step_limit_reached = false;
  std::string failure;
  double t_reached = 0.0;

  double newtonIterationsMean() const {
    return steps > 0 ? static_cast<double>(newton_iterations) / static_cast<double>(steps) : 0.0;
  }
};

/// Number of steps of size ≤ h covering [t0, t_end]: ⌈(t_end − t0)/h⌉, where
/// a ratio within 1e-9 of an integer counts as that integer (so t_end = 2,
/// h = 0.01 is 200 steps, not 201).
inline long stepCount(double t0, double t_end, double h) {
  const double ratio = (t_end - t0) / h;
  const double nearest = std::round(ratio);
  if (std::abs(ratio - nearest) <= 1e-9 * std::max(1.0, nearest)) return static_cast<long>(nearest);
  return static_cast<long>(std::ceil(ratio));
}

/// Advances *y from t0 to t_end with steps h (the last one shortened to land
/// on t_end exactly, when t_end − t0 is not a multiple of h), calling
/// observer(step_index, t, state) for step 0 (the initial state) and after
/// every step. The observer returns false to stop. Stops with `failed` set
/// when a step's implicit solve does not converge or the state becomes
/// non-finite. On return *y is the last state the observer accepted: a
/// refused or failed step does not overwrite it, so an observer needs no
/// copy of the last good state (one state copy per step, as a bare loop).
template <typename Stepper, typename System, typename Observer>
RunSummary integrateFixedStepInPlace(Stepper&& stepper, const System& system, typename System::State* y, double t0,
                                     double t_end, double h, Observer&& observer) {
  using Scalar = typename System::Scalar;
  RunSummary summary;
  summary.t_reached = t0;
  const long n = stepCount(t0, t_end, h);
  if (!observer(0L, t0, *y)) return summary;
  for (long k = 0; k < n; ++k) {
    const double t = t0 + static_cast<double>(k) * h;
    const double t_next = k + 1 == n ? t_end : t0 + static_cast<double>(k + 1) * h;
    StepReport report;
    // A value for fixed-size states, the stepper's own buffer for heap-backed ones.
    auto&& y1 = stepper.step(system, Scalar(t), *y, Scalar(t_next - t), &report);
    summary.steps = k + 1;
    summary.newton_iterations += report.newton_iterations;
    if (report.substeps > 0) ++summary.substepped_steps;
    if (!report.converged) {
      std::ostringstream why;
      why << report.failure << (report.detail.empty() ? "" : ": ") << report.detail << " at t = " << t << " (step " << k + 1 << ", residual "
          << formatNumber(report.residual) << ")";
      summary.failed = true;
      summary.failure = why.str();
      return summary;
    }
    if (!isFinite(y1)) {
      std::ostringstream why;
      why << "blow-up: the state became non-finite at t = " << t_next << " (step " << k + 1
          << "); the step h = " << h << " is beyond this integrator's stability limit";
      summary.failed = true;
      summary.failure = why.str();
      return summary;
    }
    summary.t_reached = t_next;
    if (!observer(k + 1, t_next, y1)) return summary;
    *y = std::forward<decltype(y1)>(y1);
  }
  return summary;
}

/// integrateFixedStepInPlace from a copy of y.
template <typename Stepper, typename System, typename Observer>
RunSummary integrateFixedStep(Stepper&& stepper, const System& system, typename System::State y,
                              double t0, double t_end, double h, Observer&& observer) {
  return integrateFixedStepInPlace(std::forward<Stepper>(stepper), system, &y, t0, t_end, h,
                                   std::forward<Observer>(observer));
}

}  // namespace lieflow
