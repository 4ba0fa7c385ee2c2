/// \file
/// Progress of a fit: a ceres::IterationCallback that hands each
/// Levenberg–Marquardt iteration (its number and cost) to a caller's function,
/// so that the command can report long fits on stderr, and asks a caller's
/// FitInterrupt whether to stop (the Python module's Ctrl-C): then the solve
/// ends at once (ceres::SOLVER_ABORT) and the fit reports it unconverged or
/// failed. Empty functions do nothing.
#pragma once

#include <functional>

#include <ceres/iteration_callback.h>

namespace lieflow {
namespace calibration {

/// (iteration, cost) of each solver iteration of a fit.
using FitProgress = std::function<void(int, double)>;
/// Asked at every solver iteration: true stops the solve.
using FitInterrupt = std::function<bool()>;

class FitProgressCallback : public ceres::IterationCallback {
 public:
  explicit FitProgressCallback(FitProgress progress, FitInterrupt interrupt = {})
      : progress_(std::move(progress)), interrupt_(std::move(interrupt)) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& summary) override {
    if (progress_) progress_(summary.iteration, summary.cost);
    return interrupt_ && interrupt_() ? ceres::SOLVER_ABORT : ceres::SOLVER_CONTINUE;
  }

 private:
  FitProgress progress_;
  FitInterrupt interrupt_;
};

}  // namespace calibration
}  // namespace lieflow
