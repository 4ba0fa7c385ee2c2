/// \file
/// Dense output of the adaptive RKMK driver (integrators/adaptive.hpp):
/// the continuous extension of Dormand–Prince inside one step has local
/// error O(h⁵) (order 4) on the group, measured against a fine reference; the
/// step size comes from the error estimate alone (a fine output grid costs no
/// steps); the step limit stops a run that would not end and says so.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "integrators/adaptive.hpp"
#include "dynamics/rigid_body/rigid_body_system.hpp"
#include "integrators/rkmk.hpp"
#include "tests/integrators/torqued_top.hpp"
#include "tests/order_slope.hpp"

namespace lieflow {
namespace {

/// The pivoted top of the convergence tests, without its applied torque.
RigidBodyParameters<double> heavyTop() { return testing_support::torquedTop<double>(false); }
RotorState<double> initial() { return testing_support::initialRotor(); }

/// The state at time t from RKMK-RK4 with a tiny step (error ~1e-15).
RotorState<double> reference(const RotorSystem<double>& sys, double t) {
  const RkmkStepper<RotorState<double>> rk4(ButcherTableau::rk4());
  const int n = 2000;
  RotorState<double> y = initial();
  for (int k = 0; k < n; ++k) y = rk4.step(sys, k * t / n, y, t / n);
  return y;
}

double distance(const RotorState<double>& a, const RotorState<double>& b) {
  return (a.R.inverse() * b.R).log().norm() + (a.omega - b.omega).norm();
}

TEST(DenseOutput, InsideOneStepIsFourthOrder) {
  const RotorSystem<double> sys(heavyTop());
  const RkmkStepper<RotorState<double>> dp(ButcherTableau::dormandPrince54());
  for (const double theta : {0.3, 0.7}) {
    std::vector<double> hs, errors;
    for (const double h : {0.2, 0.1, 0.05, 0.025}) {
      RkmkStepper<RotorState<double>>::Stages K;
      RotorState<double>::Tangent error, increment;
      const RotorState<double> y0 = initial();
      const RotorState<double> y1 = dp.stepWithError(sys, 0.0, y0, h, &error, &K, &increment);
      // The extension ends on the step's own end point.
      EXPECT_LT(distance(y0.rplus(dp.denseIncrement(K, increment, h, 1.0)), y1), 1e-14);
      const RotorState<double> y_theta = y0.rplus(dp.denseIncrement(K, increment, h, theta));
      hs.push_back(h);
      errors.push_back(distance(y_theta, reference(sys, theta * h)));
    }
    const double slope = testing_support::logLogSlope(hs, errors);
    // Local error O(h^5) of an order-4 continuous extension (a cubic Hermite
    // interpolant would give 4; the measured slope is 5.0 at θ = 0.3 and 5.45
    // at θ = 0.7, where the h^6 term still weighs at h = 0.2).
    EXPECT_GT(slope, 4.7) << "theta " << theta << ", errors " << errors[0] << " ... " << errors.back();
    EXPECT_LT(slope, 5.8) << "theta " << theta;
    EXPECT_LT(errors.back(), 2e-9) << "theta " << theta;  // measured 8e-10 and 3e-10 at h = 0.025
  }
}

TEST(DenseOutput, StepCountDoesNotDependOnTheOutputGrid) {
  const RotorSystem<double> sys(heavyTop());
  const RkmkStepper<RotorState<double>> dp(ButcherTableau::dormandPrince54());
  AdaptiveOptions options;
  options.rtol = 1e-9;
  options.atol = 1e-12;
  long outputs = 0;
  RotorState<double> last;
  auto observer = [&](long, double, const RotorState<double>& y) {
    ++outputs;
    last = y;
    return true;
  };
  const RunSummary coarse = integrateAdaptive(dp, sys, initial(), 0.0, 1.0, 1.0, options, observer);
  const RotorState<double> end_coarse = last;
  outputs = 0;
  const RunSummary fine = integrateAdaptive(dp, sys, initial(), 0.0, 1.0, 1e-5, options, observer);
  ASSERT_FALSE(fine.failed) << fine.failure;
  EXPECT_EQ(outputs, 100001);
  EXPECT_EQ(fine.steps, coarse.steps);
  EXPECT_LT(coarse.steps, 200);
  // The last output is the state at t_end itself, not an interpolation.
  EXPECT_EQ(distance(last, end_coarse), 0.0);
  EXPECT_LT(distance(last, reference(sys, 1.0)), 1e-7);
}

TEST(DenseOutput, StepLimitStopsAndSaysSo) {
  const RotorSystem<double> sys(heavyTop());
  const RkmkStepper<RotorState<double>> dp(ButcherTableau::dormandPrince54());
  AdaptiveOptions options;
  options.max_steps = 10;
  const RunSummary s = integrateAdaptive(dp, sys, initial(), 0.0, 100.0, 1.0, options,
                                         [](long, double, const RotorState<double>&) { return true; });
  EXPECT_TRUE(s.failed);
  EXPECT_TRUE(s.step_limit_reached);
  EXPECT_EQ(s.steps + s.rejected_steps, 10);
  EXPECT_NE(s.failure.find("step limit"), std::string::npos) << s.failure;
}

}  // namespace
}  // namespace lieflow
