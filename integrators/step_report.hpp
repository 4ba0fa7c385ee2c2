/// \file
/// What a stepper reports about one step: implicit methods count Newton
/// iterations and say when they failed to converge (never silently).
#pragma once

#include <string>

namespace lieflow {

struct StepReport {
  /// Newton (or fixed-point) iterations used; 0 for explicit methods.
  int newton_iterations = 0;
  /// False when an implicit solve did not converge; `failure` says why.
  bool converged = true;
  /// Static text naming the failure (no allocation on the step path).
  const char* failure = "";
  /// Longer text for failures whose reason is only known at run time
  /// (which constraint, how far off); empty (no allocation) otherwise.
  std::string detail;
  /// Final residual norm of the implicit solve (0 for explicit methods).
  double residual = 0.0;
  /// Steps of h/substeps the stepper took in place of one whose implicit
  /// solve failed (0: the step was taken whole).
  int substeps = 0;

  void fail(const char* why, double final_residual) {
    converged = false;
    failure = why;
    residual = final_residual;
  }
};

}  // namespace lieflow
