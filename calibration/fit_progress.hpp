/// \file
/// Progress of a fit: a ceres::IterationCallback that hands each
/// Levenberg–Marquardt iteration (its number and cost) to a caller's function,
/// so that the command can report long fits on stderr. An empty function
/// makes it do nothing; it never stops the solve.
#pragma once

#include <functional>

#include <ceres/iteration_callback.h>

namespace lieflow {
namespace calibration {

/// (iteration, cost) of each solver iteration of a fit.
using FitProgress = std::function<void(int, double)>;

class FitProgressCallback : public ceres::IterationCallback {
 public:
  explicit FitProgressCallback(FitProgress progress) : progress_(std::move(progress)) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& summary) override {
    if (progress_) progress_(summary.iteration, summary.cost);
    return ceres::SOLVER_CONTINUE;
  }

 private:
  FitProgress progress_;
};

}  // namespace calibration
}  // namespace lieflow
