/// \file
/// Measured convergence orders of the explicit Lie-group methods (RKMK for
/// every tableau, CG3, CF4), orientation included, on a smooth torqued rotor
/// (a pivoted body under gravity plus a time-dependent torque) and on a free
/// body with translation. Reference: the same problem solved by RKMK with the
/// Dormand–Prince tableau at a step 16× below the finest tested one.
#include <cmath>
#include <functional>
#include <vector>

#include <gtest/gtest.h>

#include "integrators/commutator_free.hpp"
#include "integrators/integrate.hpp"
#include "dynamics/rigid_body/rigid_body_system.hpp"
#include "integrators/rkmk.hpp"
#include "tests/integrators/torqued_top.hpp"
#include "tests/order_slope.hpp"

#ifdef LIEFLOW_HAVE_CERES
#include <ceres/jet.h>
#endif

namespace lieflow {
namespace {

using testing_support::logLogSlope;

using testing_support::initialRotor;
using testing_support::torquedTop;

template <typename Stepper, typename System>
typename System::State solve(Stepper stepper, const System& system, typename System::State y0,
                             double t_end, double h) {
  typename System::State last = y0;
  const RunSummary s = integrateFixedStep(stepper, system, y0, 0.0, t_end, h,
                                          [&](long, double, const typename System::State& y) {
                                            last = y;
                                            return true;
                                          });
  EXPECT_FALSE(s.failed) << s.failure;
  return last;
}

/// Error in orientation (geodesic angle) plus error in ω.
double error(const RotorState<double>& a, const RotorState<double>& b) {
  return (a.R.inverse() * b.R).log().norm() + (a.omega - b.omega).norm();
}
double orientationError(const RotorState<double>& a, const RotorState<double>& b) {
  return (a.R.inverse() * b.R).log().norm();
}

struct OrderCase {
  const char* name;
  int order;
  std::function<RotorState<double>(const RotorSystem<double>&, double)> run;
  std::vector<double> steps;
};

class ConvergenceOrder : public ::testing::TestWithParam<int> {};

std::vector<OrderCase> orderCases() {
  const double T = 1.0;
  auto rkmk = [T](ButcherTableau tab) {
    return [T, tab](const RotorSystem<double>& sys, double h) {
      return solve(RkmkStepper<RotorState<double>>(tab), sys, initialRotor(), T, h);
    };
  };
  return {
      {"rkmk-euler", 1, rkmk(ButcherTableau::euler()), {0.02, 0.01, 0.005, 0.0025}},
      {"rkmk-heun", 2, rkmk(ButcherTableau::heun()), {0.04, 0.02, 0.01, 0.005}},
      {"rkmk3", 3, rkmk(ButcherTableau::kutta3()), {0.04, 0.02, 0.01, 0.005}},
      {"rkmk4", 4, rkmk(ButcherTableau::rk4()), {0.04, 0.02, 0.01, 0.005}},
      {"bogacki-shampine", 3, rkmk(ButcherTableau::bogackiShampine32()), {0.04, 0.02, 0.01, 0.005}},
      {"dormand-prince", 5, rkmk(ButcherTableau::dormandPrince54()), {0.08, 0.04, 0.02, 0.01}},
      {"rkmk6", 6, rkmk(ButcherTableau::butcher6()), {0.16, 0.08, 0.04, 0.02}},
      {"cg3", 3,
       [T](const RotorSystem<double>& sys, double h) {
         return solve(CrouchGrossman3Stepper<RotorState<double>>(), sys, initialRotor(), T, h);
       },
       {0.04, 0.02, 0.01, 0.005}},
      {"cf4", 4,
       [T](const RotorSystem<double>& sys, double h) {
         return solve(CommutatorFree4Stepper<RotorState<double>>(), sys, initialRotor(), T, h);
       },
       {0.04, 0.02, 0.01, 0.005}},
  };
}

TEST_P(ConvergenceOrder, MeasuredSlopeMatchesTheory) {
  const OrderCase c = orderCases()[GetParam()];
  const RotorSystem<double> sys(torquedTop<double>());
  const RotorState<double> ref =
      solve(RkmkStepper<RotorState<double>>(ButcherTableau::dormandPrince54()), sys, initialRotor(), 1.0,
            c.steps.back() / 16);
  std::vector<double> total, orientation;
  for (double h : c.steps) {
    const RotorState<double> y = c.run(sys, h);
    total.push_back(error(y, ref));
    orientation.push_back(orientationError(y, ref));
  }
  const double s_total = logLogSlope(c.steps, total);
  const double s_orientation = logLogSlope(c.steps, orientation);
  RecordProperty("slope", std::to_string(s_total));
  EXPECT_NEAR(s_total, c.order, 0.15) << c.name << " errors " << total.front() << " .. " << total.back();
  // Orientation alone converges at the full order too (MuJoCo 2.2's RK4 was
  // measured at order 2 in orientation).
  EXPECT_NEAR(s_orientation, c.order, 0.15) << c.name;
}

INSTANTIATE_TEST_SUITE_P(AllMethods, ConvergenceOrder, ::testing::Range(0, 9),
                         [](const ::testing::TestParamInfo<int>& info) {
                           std::string n = orderCases()[info.param].name;
                           for (char& ch : n)
                             if (ch == '-') ch = '_';
                           return n;
                         });

TEST(ConvergenceOrder, FreeBodyWithTranslationIsFourthOrderWithCf4AndRkmk4) {
  RigidBodyParameters<double> p;
  p.mass = 3.0;
  p.inertia << 2.0, 0.1, 0.0, 0.1, 3.0, 0.2, 0.0, 0.2, 4.0;
  p.gravity << 0.0, 0.0, -9.81;
  p.force_world = [](const double& t) { return Eigen::Vector3d(std::cos(t), 0.0, 0.5 * t); };
  p.torque_body = [](const double& t) { return Eigen::Vector3d(0.3, std::sin(3 * t), 0.0); };
  const FreeBodySystem<double> sys(p);
  FreeBodyState<double> y0;
  y0.R = SO3d::exp(Eigen::Vector3d(-0.4, 0.1, 0.9));
  y0.omega << 3.0, -1.0, 2.0;
  y0.v << 1.0, 2.0, 3.0;
  auto err = [](const FreeBodyState<double>& a, const FreeBodyState<double>& b) {
    return (a.R.inverse() * b.R).log().norm() + (a.omega - b.omega).norm() + (a.p - b.p).norm() +
           (a.v - b.v).norm();
  };
  const auto ref = solve(RkmkStepper<FreeBodyState<double>>(ButcherTableau::dormandPrince54()), sys, y0,
                         1.0, 0.005 / 16);
  const std::vector<double> hs = {0.04, 0.02, 0.01, 0.005};
  std::vector<double> e_rk4, e_cf4;
  for (double h : hs) {
    e_rk4.push_back(err(solve(RkmkStepper<FreeBodyState<double>>(ButcherTableau::rk4()), sys, y0, 1.0, h), ref));
    e_cf4.push_back(err(solve(CommutatorFree4Stepper<FreeBodyState<double>>(), sys, y0, 1.0, h), ref));
  }
  EXPECT_NEAR(logLogSlope(hs, e_rk4), 4.0, 0.15);
  EXPECT_NEAR(logLogSlope(hs, e_cf4), 4.0, 0.15);
}

TEST(Integrate, LastStepLandsOnTEndAndCountsSteps) {
  EXPECT_EQ(stepCount(0.0, 2.0, 0.01), 200);
  EXPECT_EQ(stepCount(0.0, 1.0, 0.3), 4);
  const RotorSystem<double> sys(torquedTop<double>());
  double t_last = -1;
  long k_last = -1;
  integrateFixedStep(RkmkStepper<RotorState<double>>(ButcherTableau::rk4()), sys, initialRotor(), 0.0, 1.0,
                     0.3, [&](long k, double t, const RotorState<double>&) {
                       k_last = k;
                       t_last = t;
                       return true;
                     });
  EXPECT_EQ(k_last, 4);
  EXPECT_EQ(t_last, 1.0);
}

TEST(Integrate, BlowUpIsReportedNotReturnedAsNaN) {
  // Lie–Euler on a fast, strongly torqued top with a huge step diverges.
  RigidBodyParameters<double> p = torquedTop<double>();
  p.gravity *= 1e6;
  const RotorSystem<double> sys(p);
  bool saw_nan = false;
  const RunSummary s = integrateFixedStep(
      RkmkStepper<RotorState<double>>(ButcherTableau::euler()), sys, initialRotor(), 0.0, 1000.0, 0.5,
      [&](long, double, const RotorState<double>& y) {
        saw_nan = saw_nan || !isFinite(y);
        return true;
      });
  EXPECT_TRUE(s.failed);
  EXPECT_NE(s.failure.find("blow-up"), std::string::npos) << s.failure;
  EXPECT_FALSE(saw_nan);
}

/// The in-place driver leaves in *y the last state the observer accepted: the
/// state of the step before a refused one, the last finite state before a
/// blow-up, the final state after a whole run (what the command writes as the
/// last good row without copying every state).
TEST(Integrate, InPlaceDriverLeavesTheLastAcceptedState) {
  const RotorSystem<double> sys(torquedTop<double>());
  const RkmkStepper<RotorState<double>> rk4(ButcherTableau::rk4());
  std::vector<RotorState<double>> seen;
  RotorState<double> y = initialRotor();
  integrateFixedStepInPlace(rk4, sys, &y, 0.0, 1.0, 0.1, [&](long k, double, const RotorState<double>& s) {
    seen.push_back(s);
    return k < 5;
  });
  ASSERT_EQ(seen.size(), 6u);
  EXPECT_EQ(y.R.quaternion().coeffs(), seen[4].R.quaternion().coeffs());
  EXPECT_EQ(y.omega, seen[4].omega);

  RotorState<double> whole = initialRotor();
  RotorState<double> last_seen;
  integrateFixedStepInPlace(rk4, sys, &whole, 0.0, 1.0, 0.1, [&](long, double, const RotorState<double>& s) {
    last_seen = s;
    return true;
  });
  EXPECT_EQ(whole.omega, last_seen.omega);

  RigidBodyParameters<double> p = torquedTop<double>();
  p.gravity *= 1e6;
  const RotorSystem<double> wild(p);
  RotorState<double> blown = initialRotor();
  const RunSummary s = integrateFixedStepInPlace(RkmkStepper<RotorState<double>>(ButcherTableau::euler()), wild,
                                                 &blown, 0.0, 1000.0, 0.5,
                                                 [&](long, double, const RotorState<double>& z) {
                                                   last_seen = z;
                                                   return true;
                                                 });
  ASSERT_TRUE(s.failed);
  EXPECT_TRUE(isFinite(blown));
  EXPECT_EQ(blown.omega, last_seen.omega);
}

#ifdef LIEFLOW_HAVE_CERES
/// A ceres::Jet flows through a whole RKMK4 simulation: the derivative of
/// the final orientation and ω with respect to the mass (which enters the
/// pivot inertia and the gravity torque) matches a central difference.
TEST(JetThroughSimulation, Rkmk4DerivativeMatchesFiniteDifference) {
  using J = ceres::Jet<double, 1>;
  auto final_state = [](auto mass) {
    using T = decltype(mass);
    RigidBodyParameters<T> p = torquedTop<T>();
    p.mass = mass;
    const RotorSystem<T> sys(p);
    RotorState<T> y;
    y.R = initialRotor().R.cast<T>();
    y.omega = initialRotor().omega.cast<T>();
    const RkmkStepper<RotorState<T>> stepper(ButcherTableau::rk4());
    for (int k = 0; k < 100; ++k) y = stepper.step(sys, T(0.01 * k), y, T(0.01));
    Eigen::Matrix<T, 6, 1> out;
    out << y.R.log(), y.omega;
    return out;
  };
  const double m = 2.0, dm = 1e-6;
  const auto jet = final_state(J(m, 0));
  const Eigen::Matrix<double, 6, 1> fd = (final_state(m + dm) - final_state(m - dm)) / (2 * dm);
  for (int i = 0; i < 6; ++i) {
    EXPECT_TRUE(std::isfinite(jet[i].v[0]));
    EXPECT_NEAR(jet[i].v[0], fd[i], 1e-6 * std::max(1.0, std::abs(fd[i]))) << "component " << i;
  }
}
#endif

}  // namespace
}  // namespace lieflow
