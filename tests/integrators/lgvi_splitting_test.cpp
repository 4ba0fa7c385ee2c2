/// Tests of the Lie group variational integrator (integrators/lgvi.hpp) and the
/// explicit splitting (integrators/splitting.hpp) against independent
/// references: conservation laws over long runs, measured convergence orders
/// against RK4-RKMK at a tiny step, the Brüls–Cardona–Arnold heavy top, the
/// exact parabola of the centre of mass under gravity, ceres::Jet derivatives
/// against central finite differences, and reported Newton failure.
#include "integrators/lgvi.hpp"
#include "integrators/splitting.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "integrators/butcher_tableau.hpp"
#include "dynamics/rigid_body/rigid_body_system.hpp"
#include "integrators/rkmk.hpp"
#include "integrators/step_report.hpp"
#include "liegroup/invalid_input.hpp"

#ifdef LIEFLOW_HAVE_CERES
#include <ceres/jet.h>
#endif

namespace lieflow {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using Rotor = RotorState<double>;

// ---- bodies ------------------------------------------------------------------

/// Asymmetric body, principal moments (1, 2, 3) kg·m², with principal axes
/// rotated away from the body axes (a non-diagonal inertia), torque-free.
RigidBodyParameters<double> asymmetricBody() {
  const Matrix3d Q =
      Eigen::AngleAxisd(0.7, Vector3d(1.0, -2.0, 0.5).normalized()).toRotationMatrix();
  RigidBodyParameters<double> p;
  p.inertia = Q * Vector3d(1.0, 2.0, 3.0).asDiagonal() * Q.transpose();
  return p;
}

/// Symmetric top: moments (1.5, 1.5, 0.8) kg·m², torque-free.
RigidBodyParameters<double> symmetricTop() {
  RigidBodyParameters<double> p;
  p.inertia = Vector3d(1.5, 1.5, 0.8).asDiagonal();
  return p;
}

/// The heavy top of Brüls, Cardona & Arnold, "Lie group generalized-α time
/// integration of constrained flexible multibody systems", Mech. Mach. Theory
/// 48 (2012), §5.1: m = 15 kg, J_c = diag(0.234375, 0.46875, 0.234375) kg·m²,
/// centre of mass at (0, 1, 0) m from the pivot (body axes), g = (0, 0, −9.81).
RigidBodyParameters<double> heavyTop() {
  RigidBodyParameters<double> p;
  p.mass = 15.0;
  p.inertia = Vector3d(0.234375, 0.46875, 0.234375).asDiagonal();
  p.gravity = Vector3d(0.0, 0.0, -9.81);
  p.has_pivot = true;
  p.com_from_pivot = Vector3d(0.0, 1.0, 0.0);
  return p;
}

Rotor initialState(const Vector3d& omega, double angle = 0.4,
                   const Vector3d& axis = Vector3d(1.0, 2.0, 3.0)) {
  Rotor y;
  y.R = SO3d::exp(angle * axis.normalized());
  y.omega = omega;
  return y;
}

// ---- methods -----------------------------------------------------------------

/// Calls f(name, stepper, is_default) for every integrator of the two headers:
/// the defaults (exponential LGVI, symmetric + residual splitting) and the
/// variants (Cayley LGVI, three-axis splitting).
template <typename State, typename F>
void forEachMethod(const Matrix3d& inertia, F&& f) {
  f("lgvi", LgviStepper<State>(), true);
  f("splitting", SplittingStepper<State>(inertia), true);
  LgviOptions cayley;
  cayley.map = LgviMap::kCayley;
  f("lgvi-cayley", LgviStepper<State>(cayley), false);
  SplittingOptions axes;
  axes.scheme = SplittingScheme::kAxisRotations;
  f("splitting-axes", SplittingStepper<State>(inertia, axes), false);
}

/// y after `steps` steps of size h from t = 0.
template <typename Stepper, typename System, typename State>
State integrate(const Stepper& stepper, const System& system, State y, double h, int steps) {
  using T = typename State::Scalar;
  for (int n = 0; n < steps; ++n) y = stepper.step(system, T(n * h), y, T(h));
  return y;
}

/// Least-squares slope of log(err) against log(h).
double logLogSlope(const std::vector<double>& h, const std::vector<double>& err) {
  double mx = 0, my = 0;
  const int n = static_cast<int>(h.size());
  for (int i = 0; i < n; ++i) {
    mx += std::log(h[i]) / n;
    my += std::log(err[i]) / n;
  }
  double sxy = 0, sxx = 0;
  for (int i = 0; i < n; ++i) {
    sxy += (std::log(h[i]) - mx) * (std::log(err[i]) - my);
    sxx += (std::log(h[i]) - mx) * (std::log(h[i]) - mx);
  }
  return sxy / sxx;
}

// ---- long runs: bounded energy error, exact spatial angular momentum ----------

/// 10⁶ steps of h = 0.01 (t = 10⁴ s, ~2000 periods of the motion) for each
/// method. The energy error of a symplectic method oscillates without drift:
/// its maximum over the last tenth of the run must not exceed twice that over
/// the first tenth. Some cases conserve energy exactly and show only rounding,
/// which random-walks like √n (a factor √10 between the windows): the LGVI of
/// a free body (hΠ_k = a Jf + b f×Jf and hΠ_{k+1} = a Jf − b f×Jf have the same
/// J⁻¹-norm, since f·(f×Jf) = 0), the Cayley LGVI of a symmetric top, and the
/// splitting of a symmetric top (exact flow). kRoundingFloor (~5·10³ ulp, far
/// below any truncation error seen here) absorbs them. The spatial angular momentum R J ω is preserved exactly by
/// every method, so only rounding (a random walk, ~1e-13 after 10⁶ steps) is
/// allowed. The two variants run 2·10⁵ steps (t = 2000 s, ~400 periods), to
/// keep the file's run time at ~2 s (Release) and ~15 s (ASan + UBSan).
constexpr int kLongRunSteps = 1000000;
constexpr int kLongRunStepsVariants = 200000;
constexpr double kLongRunStep = 0.01;
constexpr double kRoundingFloor = 1e-12;

struct LongRunResult {
  double energy_first_tenth = 0.0;  ///< max |E − E₀|/E₀ over the first tenth
  double energy_last_tenth = 0.0;   ///< ... over the last tenth
  double energy_max = 0.0;
  double momentum_max = 0.0;  ///< max ‖L − L₀‖/‖L₀‖
};

template <typename Stepper>
LongRunResult longRun(const Stepper& stepper, const RotorSystem<double>& system, Rotor y,
                      int steps) {
  const double E0 = system.energy(0.0, y);
  const Vector3d L0 = system.spatialAngularMomentum(y);
  const int tenth = steps / 10;
  LongRunResult r;
  for (int n = 0; n < steps; ++n) {
    y = stepper.step(system, n * kLongRunStep, y, kLongRunStep);
    const double dE = std::abs(system.energy(0.0, y) - E0) / E0;
    r.energy_max = std::max(r.energy_max, dE);
    if (n < tenth) r.energy_first_tenth = std::max(r.energy_first_tenth, dE);
    if (n >= steps - tenth) r.energy_last_tenth = std::max(r.energy_last_tenth, dE);
    r.momentum_max =
        std::max(r.momentum_max, (system.spatialAngularMomentum(y) - L0).norm() / L0.norm());
  }
  return r;
}

void checkLongRun(const char* body, const RigidBodyParameters<double>& params,
                  const Vector3d& omega0) {
  const RotorSystem<double> system(params);
  const Rotor y0 = initialState(omega0);
  forEachMethod<Rotor>(system.inertia(), [&](const char* name, const auto& stepper,
                                              bool is_default) {
    SCOPED_TRACE(name);
    const int steps = is_default ? kLongRunSteps : kLongRunStepsVariants;
    const LongRunResult r = longRun(stepper, system, y0, steps);
    std::printf("[ measured ] %s %-15s %7d steps: |dE|/E first tenth %.2e last tenth %.2e "
                "max %.2e, |dL|/|L| %.2e\n",
                body, name, steps, r.energy_first_tenth, r.energy_last_tenth, r.energy_max,
                r.momentum_max);
    EXPECT_LT(r.energy_last_tenth, 2.0 * r.energy_first_tenth + kRoundingFloor);
    EXPECT_LT(r.energy_max, 1e-4);
    EXPECT_LE(r.momentum_max, 1e-12);
  });
}

TEST(LgviSplitting, AsymmetricFreeBodyLongRun) {
  checkLongRun("asymmetric", asymmetricBody(), Vector3d(0.3, 1.0, -0.6));
}

TEST(LgviSplitting, SymmetricTopLongRun) {
  checkLongRun("symmetric ", symmetricTop(), Vector3d(0.8, -0.4, 2.0));
}

// ---- convergence orders ----------------------------------------------------------

/// Measured order in orientation (‖log(R_refᵀ R)‖) and ω at t_end against
/// RK4-RKMK with kReferenceSubsteps steps per step of the finest h. The
/// reference's own error, estimated by halving its step once more, must be
/// below 1e-3 of the smallest error measured.
constexpr int kReferenceSubsteps = 16;

void checkOrder(const char* problem, const RigidBodyParameters<double>& params, const Rotor& y0,
                double t_end, const std::vector<int>& step_counts) {
  const RotorSystem<double> system(params);
  const RkmkStepper<Rotor> rk4(ButcherTableau::rk4());
  const int ref_steps = step_counts.back() * kReferenceSubsteps;
  const Rotor ref = integrate(rk4, system, y0, t_end / ref_steps, ref_steps);
  const Rotor ref_fine = integrate(rk4, system, y0, t_end / (2 * ref_steps), 2 * ref_steps);
  const double ref_err_R = (ref_fine.R.inverse() * ref.R).log().norm();
  const double ref_err_w = (ref_fine.omega - ref.omega).norm();
  forEachMethod<Rotor>(system.inertia(), [&](const char* name, const auto& stepper, bool) {
    SCOPED_TRACE(name);
    std::vector<double> hs, err_R, err_w;
    for (int n : step_counts) {
      const double h = t_end / n;
      const Rotor y = integrate(stepper, system, y0, h, n);
      hs.push_back(h);
      err_R.push_back((ref.R.inverse() * y.R).log().norm());
      err_w.push_back((y.omega - ref.omega).norm());
    }
    const double slope_R = logLogSlope(hs, err_R), slope_w = logLogSlope(hs, err_w);
    std::printf("[ measured ] %s %-15s order R %.3f, omega %.3f (errors at h = %.4g: %.2e, "
                "%.2e)\n",
                problem, name, slope_R, slope_w, hs.back(), err_R.back(), err_w.back());
    EXPECT_NEAR(slope_R, 2.0, 0.15);
    EXPECT_NEAR(slope_w, 2.0, 0.15);
    EXPECT_LT(ref_err_R, 1e-3 * err_R.back());
    EXPECT_LT(ref_err_w, 1e-3 * err_w.back());
  });
  std::printf("[ measured ] %s reference RK4 error estimate: R %.1e, omega %.1e\n", problem,
              ref_err_R, ref_err_w);
}

TEST(LgviSplitting, SecondOrderOnHeavyTopWithModestSpin) {
  checkOrder("heavy top ", heavyTop(), initialState(Vector3d(0.5, 8.0, -0.4), 0.3), 1.0,
             {40, 80, 160, 320});
}

TEST(LgviSplitting, SecondOrderOnAsymmetricFreeBody) {
  checkOrder("free body ", asymmetricBody(), initialState(Vector3d(0.3, 1.0, -0.6)), 5.0,
             {40, 80, 160, 320});
}

// ---- Brüls–Cardona–Arnold heavy top ------------------------------------------

/// ω0 = (0, 150, −4.61538) rad/s, R0 = I, h = 1e-3: the 2 s of the paper,
/// then on to 20 s to see that the energy error stays bounded (its maximum
/// over the last 2 s equals that over the first 2 s; measured 4.95e-6 for the
/// LGVI, 1.5e-7 for the splitting, unchanged over 200 s). The gravity torque
/// about the pivot is horizontal, so the vertical spatial angular momentum is
/// conserved; both methods conserve it exactly (each half kick changes R Π by
/// (h/2) R(c × Rᵀ m g) = (h/2)(R c) × m g ⟂ g).
TEST(LgviSplitting, BrulsCardonaArnoldHeavyTop) {
  const RotorSystem<double> system(heavyTop());
  Rotor y0;
  y0.omega = Vector3d(0.0, 150.0, -4.61538);
  const double h = 1e-3;
  const int steps = 20000, paper_steps = 2000;
  const double E0 = system.energy(0.0, y0);
  const double Lz0 = system.spatialAngularMomentum(y0).z();

  struct Stats {
    double energy_max = 0, energy_last = 0, Lz_max = 0, iterations_mean = 0;
    int iterations_max = 0;
    bool all_converged = true;
  };
  auto run = [&](const auto& stepper) {
    Stats s;
    Rotor y = y0;
    StepReport report;
    for (int n = 0; n < steps; ++n) {
      y = stepper.step(system, n * h, y, h, &report);
      s.all_converged = s.all_converged && report.converged;
      s.iterations_max = std::max(s.iterations_max, report.newton_iterations);
      s.iterations_mean += report.newton_iterations / double(steps);
      const double dE = std::abs(system.energy(0.0, y) - E0) / std::abs(E0);
      if (n < paper_steps) s.energy_max = std::max(s.energy_max, dE);
      if (n >= steps - paper_steps) s.energy_last = std::max(s.energy_last, dE);
      s.Lz_max = std::max(s.Lz_max,
                          std::abs(system.spatialAngularMomentum(y).z() - Lz0) / std::abs(Lz0));
    }
    return s;
  };

  const Stats lgvi = run(LgviStepper<Rotor>());
  std::printf("[ measured ] BCA top lgvi: |dE|/E max %.2e (0-2 s), %.2e (18-20 s), |dLz|/|Lz| "
              "%.2e, Newton mean %.3f max %d\n",
              lgvi.energy_max, lgvi.energy_last, lgvi.Lz_max, lgvi.iterations_mean,
              lgvi.iterations_max);
  EXPECT_TRUE(lgvi.all_converged);
  EXPECT_LE(lgvi.iterations_max, 5);
  EXPECT_LT(lgvi.energy_max, 1e-5);
  EXPECT_LT(lgvi.energy_last, 2.0 * lgvi.energy_max);
  EXPECT_LE(lgvi.Lz_max, 1e-10);

  const Stats split = run(SplittingStepper<Rotor>(system.inertia()));
  std::printf("[ measured ] BCA top splitting: |dE|/E max %.2e (0-2 s), %.2e (18-20 s), "
              "|dLz|/|Lz| %.2e\n",
              split.energy_max, split.energy_last, split.Lz_max);
  EXPECT_LT(split.energy_max, 1e-6);
  EXPECT_LT(split.energy_last, 2.0 * split.energy_max);
  EXPECT_LE(split.Lz_max, 1e-10);
}

// ---- translation ----------------------------------------------------------------

/// Velocity Verlet is exact for a constant force: p(t) = p0 + v0 t + ½ g t².
/// The rotation of a FreeBodyState is the RotorState's, bit for bit.
TEST(LgviSplitting, FreeBodyTranslationIsTheExactParabola) {
  RigidBodyParameters<double> params = asymmetricBody();
  params.mass = 2.5;
  params.gravity = Vector3d(0.3, -0.2, -9.81);
  const FreeBodySystem<double> system(params);
  const RotorSystem<double> rotor_system(asymmetricBody());
  FreeBodyState<double> y0;
  const Rotor r0 = initialState(Vector3d(0.3, 1.0, -0.6));
  y0.R = r0.R;
  y0.omega = r0.omega;
  y0.p = Vector3d(1.0, -2.0, 3.0);
  y0.v = Vector3d(0.5, 4.0, 6.0);
  const double h = 0.01, t = 2.0;
  const int steps = 200;
  const Vector3d p_exact = y0.p + t * y0.v + 0.5 * t * t * params.gravity;
  const Vector3d v_exact = y0.v + t * params.gravity;
  forEachMethod<FreeBodyState<double>>(system.inertia(), [&](const char* name, const auto& s,
                                                              bool) {
    SCOPED_TRACE(name);
    const FreeBodyState<double> y = integrate(s, system, y0, h, steps);
    EXPECT_LT((y.p - p_exact).norm(), 1e-12 * p_exact.norm());
    EXPECT_LT((y.v - v_exact).norm(), 1e-12 * v_exact.norm());
  });
  const LgviStepper<FreeBodyState<double>> lgvi;
  const LgviStepper<Rotor> lgvi_rotor;
  const FreeBodyState<double> y = integrate(lgvi, system, y0, h, steps);
  const Rotor r = integrate(lgvi_rotor, rotor_system, r0, h, steps);
  EXPECT_EQ(y.R.quaternion().coeffs(), r.R.quaternion().coeffs());
  EXPECT_EQ(y.omega, r.omega);
}

// ---- the Newton equations ----------------------------------------------------------

/// The analytic Jacobians of G against central differences, and the two slope
/// coefficients of the exponential map against their closed forms in long
/// double, on both sides of the series thresholds (θ² = 1 and θ² = 4).
TEST(LgviSplitting, NewtonJacobianMatchesFiniteDifferences) {
  Matrix3d J;
  J << 2.0, 0.3, -0.1, 0.3, 1.5, 0.2, -0.1, 0.2, 1.0;
  const Vector3d rhs(0.1, 0.2, 0.3);
  for (double theta : {1e-5, 0.02, 0.5, 0.99, 1.01, 1.99, 2.01, 3.0, 5.0}) {
    SCOPED_TRACE(theta);
    const Vector3d f = theta * Vector3d(0.3, -0.5, 0.8).normalized();
    detail::LgviExpEquation<double> exp_eq(J, rhs);
    detail::LgviCayleyEquation<double> cay_eq(J, rhs);
    exp_eq.residual(f);
    cay_eq.residual(f);
    const Matrix3d exp_jac = exp_eq.jacobian(f), cay_jac = cay_eq.jacobian(f);
    Matrix3d exp_fd, cay_fd;
    const double d = 1e-6 * std::max(theta, 1e-2);
    for (int j = 0; j < 3; ++j) {
      const Vector3d e = d * Vector3d::Unit(j);
      exp_fd.col(j) = (exp_eq.residual(f + e) - exp_eq.residual(f - e)) / (2 * d);
      cay_fd.col(j) = (cay_eq.residual(f + e) - cay_eq.residual(f - e)) / (2 * d);
    }
    EXPECT_LT((exp_jac - exp_fd).norm(), 1e-8 * exp_fd.norm());
    EXPECT_LT((cay_jac - cay_fd).norm(), 1e-8 * cay_fd.norm());

    const long double t = theta;
    const long double sinc_slope = (t * std::cos(t) - std::sin(t)) / (t * t * t);
    const long double versine_slope = (t * std::sin(t) - 2 * (1 - std::cos(t))) / (t * t * t * t);
    double c, s;
    detail::halfAngle(theta * theta, &c, &s);
    if (theta > 1e-3) {  // below, the closed forms themselves cancel
      EXPECT_NEAR(detail::lgviSincSlope(theta * theta, c, s), static_cast<double>(sinc_slope),
                  1e-15 * std::abs(static_cast<double>(sinc_slope)));
    }
    if (theta > 0.1) {
      EXPECT_NEAR(detail::lgviVersineSlope(theta * theta, c, s),
                  static_cast<double>(versine_slope),
                  2e-15 * std::abs(static_cast<double>(versine_slope)));
    }
  }
  double c, s;
  detail::halfAngle(0.0, &c, &s);
  EXPECT_DOUBLE_EQ(detail::lgviSincSlope(0.0, c, s), -1.0 / 3.0);
  EXPECT_DOUBLE_EQ(detail::lgviVersineSlope(0.0, c, s), -1.0 / 12.0);
}

// ---- Newton failure and bad input ------------------------------------------------

/// The BCA top spins at 150 rad/s about its axis of least inertia.
/// (a) h = 5e-3 (hω = 0.75): one Newton iteration cannot reach 1e-16, and the
///     failure is reported; the default options converge (in 3 iterations).
/// (b) h = 1e-2: the exponential LGVI has no solution at all (for a spin about
///     a principal axis, (1) reads sin θ = hω = 1.5), so Newton fails with the
///     default options too, while the Cayley variant (J_y θ(1 + θ²/4) = J_y hω,
///     always solvable) converges.
TEST(LgviSplitting, NewtonFailureIsReported) {
  const RotorSystem<double> system(heavyTop());
  Rotor y;
  y.omega = Vector3d(0.0, 150.0, -4.61538);
  for (LgviMap map : {LgviMap::kExponential, LgviMap::kCayley}) {
    SCOPED_TRACE(map == LgviMap::kCayley ? "cayley" : "exp");
    LgviOptions options;
    options.map = map;
    options.max_iterations = 1;
    options.tolerance = 1e-16;
    StepReport report;
    const Rotor y1 = LgviStepper<Rotor>(options).step(system, 0.0, y, 5e-3, &report);
    EXPECT_FALSE(report.converged);
    EXPECT_STRNE(report.failure, "");
    EXPECT_EQ(report.newton_iterations, 1);
    EXPECT_GT(report.residual, 0.0);
    EXPECT_TRUE(y1.omega.allFinite());  // the last iterate is still returned
    LgviOptions defaults;
    defaults.map = map;
    StepReport ok;
    LgviStepper<Rotor>(defaults).step(system, 0.0, y, 5e-3, &ok);
    EXPECT_TRUE(ok.converged);
    EXPECT_STREQ(ok.failure, "");
    EXPECT_LE(ok.newton_iterations, 4);
  }
  LgviOptions cayley;
  cayley.map = LgviMap::kCayley;
  StepReport no_solution, cayley_report;
  LgviStepper<Rotor>().step(system, 0.0, y, 1e-2, &no_solution);
  EXPECT_FALSE(no_solution.converged);
  EXPECT_STRNE(no_solution.failure, "");
  EXPECT_EQ(no_solution.newton_iterations, LgviOptions().max_iterations);
  LgviStepper<Rotor>(cayley).step(system, 0.0, y, 1e-2, &cayley_report);
  EXPECT_TRUE(cayley_report.converged);
}

TEST(LgviSplitting, SplittingRejectsANonPositiveInertia) {
  Matrix3d J = Vector3d(1.0, -2.0, 3.0).asDiagonal();
  EXPECT_THROW(SplittingStepper<Rotor>{J}, InvalidInput);
  J = Vector3d(1.0, 2.0, 3.0).asDiagonal();
  J(0, 1) = J(1, 0) = 5.0;  // indefinite
  EXPECT_THROW(SplittingStepper<Rotor>{J}, InvalidInput);
}

// ---- ceres::Jet: derivatives through the Newton solve ------------------------------

#ifdef LIEFLOW_HAVE_CERES
using Jet = ceres::Jet<double, 1>;

/// ω after `steps` LGVI steps of the heavy top with J_c(0, 0) = I1, in scalar T.
template <typename T>
Vector3<T> finalOmega(const T& I1, LgviMap map, int steps, double h) {
  const RigidBodyParameters<double> d = heavyTop();
  RigidBodyParameters<T> p;
  p.mass = T(d.mass);
  p.inertia = d.inertia.cast<T>();
  p.inertia(0, 0) = I1;
  p.gravity = d.gravity.cast<T>();
  p.has_pivot = true;
  p.com_from_pivot = d.com_from_pivot.cast<T>();
  const RotorSystem<T> system(p);
  RotorState<T> y;
  y.R = SO3<T>::exp(Vector3<T>(T(0.2), T(-0.1), T(0.3)));
  y.omega = Vector3<T>(T(0.5), T(8.0), T(-0.4));
  LgviOptions options;
  options.map = map;
  const LgviStepper<RotorState<T>> stepper(options);
  StepReport report;
  for (int n = 0; n < steps; ++n) {
    y = stepper.step(system, T(n * h), y, T(h), &report);
    EXPECT_TRUE(report.converged);
  }
  return y.omega;
}

/// d ω(t = 1 s)/d J_c(0, 0) through 100 LGVI steps against a central finite
/// difference of step 1e-5 · J_c(0, 0) (truncation ~1e-10, rounding ~1e-10).
TEST(LgviSplitting, JetDerivativeThroughNewtonMatchesFiniteDifference) {
  const double I1 = heavyTop().inertia(0, 0), delta = 1e-5 * I1, h = 0.01;
  const int steps = 100;
  for (LgviMap map : {LgviMap::kExponential, LgviMap::kCayley}) {
    const Vector3<Jet> w = finalOmega(Jet(I1, 0), map, steps, h);
    const Vector3d dw_fd = (finalOmega(I1 + delta, map, steps, h) -
                            finalOmega(I1 - delta, map, steps, h)) /
                           (2 * delta);
    const Vector3d dw_jet(w.x().v[0], w.y().v[0], w.z().v[0]);
    const double rel = (dw_jet - dw_fd).norm() / dw_fd.norm();
    std::printf("[ measured ] Jet dω/dI1 (%s) |dw| %.4e, relative difference to FD %.2e\n",
                map == LgviMap::kCayley ? "cayley" : "exp", dw_fd.norm(), rel);
    EXPECT_LT(rel, 1e-6);
    // The values agree with the double run.
    const Vector3d w_double = finalOmega(I1, map, steps, h);
    EXPECT_LT((Vector3d(w.x().a, w.y().a, w.z().a) - w_double).norm(), 1e-12 * w_double.norm());
  }
}

/// The splitting compiles and runs with Jets for a diagonal inertia; its
/// derivative w.r.t. a principal moment matches a finite difference too.
TEST(LgviSplitting, SplittingWithJets) {
  const double I3 = 0.8, delta = 1e-5, h = 0.01;
  auto final_omega = [&](auto moment) {
    using T = decltype(moment);
    RigidBodyParameters<T> p;
    p.inertia = Vector3<T>(T(1.0), T(2.0), moment).asDiagonal();
    const RotorSystem<T> system(p);
    RotorState<T> y;
    y.omega = Vector3<T>(T(0.3), T(1.0), T(-0.6));
    return integrate(SplittingStepper<RotorState<T>>(system.inertia()), system, y, h, 100).omega;
  };
  const Vector3<Jet> w = final_omega(Jet(I3, 0));
  const Vector3d dw_fd = (final_omega(I3 + delta) - final_omega(I3 - delta)) / (2 * delta);
  const Vector3d dw_jet(w.x().v[0], w.y().v[0], w.z().v[0]);
  EXPECT_LT((dw_jet - dw_fd).norm(), 1e-6 * dw_fd.norm());
}
/// FreeBodyState with Jets: the rotation's derivative equals the RotorState's,
/// and the centre of mass under a constant force F, p(t) = p0 + v0 t +
/// F t²/(2m) (Verlet is exact), has dp/dm = −F t²/(2m²).
TEST(LgviSplitting, FreeBodyStateWithJets) {
  const double m = 2.0, h = 0.01;
  const int steps = 100;
  const Vector3d force(1.0, -2.0, 0.5);
  RigidBodyParameters<Jet> p;
  p.mass = Jet(m, 0);
  p.inertia = Vector3<Jet>(Jet(1.0), Jet(2.0), Jet(3.0)).asDiagonal();
  p.force_world = [force](const Jet&) -> Vector3<Jet> { return force.cast<Jet>(); };
  const FreeBodySystem<Jet> system(p);
  FreeBodyState<Jet> y;
  y.omega = Vector3<Jet>(Jet(0.3), Jet(1.0), Jet(-0.6));
  y.v = Vector3<Jet>(Jet(1.0), Jet(0.0), Jet(0.0));
  const FreeBodyState<Jet> y1 = integrate(LgviStepper<FreeBodyState<Jet>>(), system, y, h, steps);
  const double t = steps * h;
  const Vector3d dp_exact = -force * t * t / (2 * m * m);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(y1.p[i].v[0], dp_exact[i], 1e-12);
  // The rotation matches the RotorState run in double (to rounding: the Jet
  // run takes one more Newton step) and does not depend on the mass.
  RigidBodyParameters<double> rp;
  rp.inertia = Vector3d(1.0, 2.0, 3.0).asDiagonal();
  Rotor r;
  r.omega = Vector3d(0.3, 1.0, -0.6);
  r = integrate(LgviStepper<Rotor>(), RotorSystem<double>(rp), r, h, steps);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(y1.omega[i].a, r.omega[i], 1e-13);
    EXPECT_EQ(y1.omega[i].v[0], 0.0);
  }
}

TEST(LgviSplitting, SplittingWithJetsNeedsADiagonalInertia) {
  Matrix3<Jet> J = Vector3<Jet>(Jet(1.0), Jet(2.0), Jet(3.0)).asDiagonal();
  J(0, 1) = J(1, 0) = Jet(0.1);
  EXPECT_THROW(SplittingStepper<RotorState<Jet>>{J}, InvalidInput);
}
#endif  // LIEFLOW_HAVE_CERES

}  // namespace
}  // namespace lieflow
