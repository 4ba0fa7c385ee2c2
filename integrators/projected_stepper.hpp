/// \file
/// Index reduction plus projection for constrained systems (Hairer, Lubich &
/// Roche 1989; Hairer & Wanner, "Solving ODEs II", §VII.2; on Lie groups:
/// Munthe-Kaas & Owren's projection remarks, and Arnold, Brüls & Cardona):
/// the constrained equations are stepped in their index-1 form by any
/// explicit Lie-group stepper (the system's velocity field solves for the
/// accelerations and multipliers), and after each step the state is
/// projected back onto the position constraints Φ(q, t) = 0 and then onto
/// the velocity constraints J u = b(t). Both projections are orthogonal in
/// the mass metric, so they remove only the constraint-violating part. The
/// order of the inner method is kept: its step error is O(h^{p+1}) and the
/// projection moves the state by no more than that.
///
/// A System supplies, besides velocity(t, y, f):
///   bool projectPositions(t, State*, tol, max_iterations, int* iterations, std::string* why);
///   bool projectVelocities(t, State*, std::string* why);
///   double constraintError(t, const State&)   (max |Φ|, for the report).
///
/// step() returns a reference to the projected state held by the stepper,
/// valid until its next step (copying into it reuses its storage: no heap
/// allocation per step when the inner stepper and the system allocate none).
#pragma once

#include <string>
#include <type_traits>
#include <utility>

#include "integrators/state_workspace.hpp"
#include "integrators/step_report.hpp"

namespace lieflow {

struct ProjectionOptions {
  /// Stop the position projection when max |Φ| ≤ tolerance (in the units of
  /// the constraint rows: metres and radians).
  double tolerance = 1e-12;
  int max_iterations = 20;
};

template <typename Inner>
class ProjectedStepper {
 public:
  explicit ProjectedStepper(Inner inner, ProjectionOptions options = {})
      : inner_(std::move(inner)), options_(options) {}

  const Inner& inner() const { return inner_; }

  template <typename System, typename State, typename Scalar>
  state_ops::StepResult<State> step(const System& system, const Scalar& t, const State& y, const Scalar& h,
                                    StepReport* report = nullptr) const {
    if constexpr (state_ops::kHeapBacked<State>) {
      static_assert(std::is_same<State, typename Inner::StateType>::value,
                    "ProjectedStepper: the state type is the inner stepper's");
      State& y1 = result_;
      y1 = inner_.step(system, t, y, h, report);
      project(system, t + h, &y1, report);
      return y1;
    } else {
      State y1 = inner_.step(system, t, y, h, report);
      project(system, t + h, &y1, report);
      return y1;
    }
  }

 private:
  template <typename System, typename State>
  void project(const System& system, double t1, State* y1, StepReport* report) const {
    if (!isFinite(*y1)) return;  // the driver reports the blow-up
    int iterations = 0;
    bool ok = system.projectPositions(t1, y1, options_.tolerance, options_.max_iterations, &iterations, &why_);
    if (ok) ok = system.projectVelocities(t1, y1, &why_);
    if (report) {
      report->newton_iterations += iterations;
      if (!ok) {
        report->fail("constraint projection failed", system.constraintError(t1, *y1));
        report->detail = why_;
      }
    }
  }

  Inner inner_;
  ProjectionOptions options_;
  struct NoState {};
  using Result = typename Inner::StateType;
  mutable std::conditional_t<state_ops::kHeapBacked<Result>, Result, NoState> result_;
  mutable std::string why_;  // the projection's failure, reused
};

}  // namespace lieflow
