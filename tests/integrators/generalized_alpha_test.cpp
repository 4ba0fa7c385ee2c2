/// Tests of the Lie-group generalized-α stepper (integrators/generalized_alpha.hpp)
/// against independent references: the closed-form linear oscillator and the
/// spectral radius of its amplification matrix (Chung & Hulbert 1993), a
/// converged RKMK-RK4 solution of the free rotor and of the heavy top of Brüls,
/// Cardona & Arnold 2012, the exact parabola of a body in uniform gravity, and
/// central finite differences for the ceres::Jet derivatives.
#include "dynamics/rigid_body/rigid_body_system.hpp"
#include "integrators/generalized_alpha.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <string>
#include <vector>

#include "integrators/butcher_tableau.hpp"
#include "integrators/rkmk.hpp"

#ifdef LIEFLOW_HAVE_CERES
#include <ceres/jet.h>
#endif

namespace lieflow {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
constexpr double kPi = 3.141592653589793;

using Oscillator = LinearSecondOrderSystem<double, 1>;
using OscillatorState = VectorState<double, 1>;

/// Least-squares slope of log(err) against log(h).
double logLogSlope(const std::vector<double>& h, const std::vector<double>& err) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = static_cast<double>(h.size());
  for (size_t i = 0; i < h.size(); ++i) {
    const double x = std::log(h[i]), y = std::log(err[i]);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

OscillatorState oscillatorState(double x, double v) {
  OscillatorState y;
  y.x(0) = x;
  y.v(0) = v;
  return y;
}

// ---- parameters and options -------------------------------------------------------

TEST(GeneralizedAlpha, ChungHulbertCoefficients) {
  // ρ∞ = 1: the trapezoidal rule (α_m = α_f = ½, γ = ½, β = ¼).
  const auto c1 = GeneralizedAlphaCoefficients::fromRhoInf(1.0);
  EXPECT_DOUBLE_EQ(c1.alpha_m, 0.5);
  EXPECT_DOUBLE_EQ(c1.alpha_f, 0.5);
  EXPECT_DOUBLE_EQ(c1.gamma, 0.5);
  EXPECT_DOUBLE_EQ(c1.beta, 0.25);
  // ρ∞ = 0: α_m = −1, α_f = 0, γ = 3/2, β = 1.
  const auto c0 = GeneralizedAlphaCoefficients::fromRhoInf(0.0);
  EXPECT_DOUBLE_EQ(c0.alpha_m, -1.0);
  EXPECT_DOUBLE_EQ(c0.alpha_f, 0.0);
  EXPECT_DOUBLE_EQ(c0.gamma, 1.5);
  EXPECT_DOUBLE_EQ(c0.beta, 1.0);
}

TEST(GeneralizedAlpha, RejectsBadOptions) {
  using Stepper = GeneralizedAlphaStepper<RotorState<double>>;
  GeneralizedAlphaOptions o;
  o.rho_inf = 1.5;
  EXPECT_THROW(Stepper{o}, InvalidInput);
  o.rho_inf = std::nan("");
  EXPECT_THROW(Stepper{o}, InvalidInput);
  o = {};
  o.tolerance = -1.0;
  EXPECT_THROW(Stepper{o}, InvalidInput);
  o = {};
  o.max_iterations = 0;
  try {
    Stepper s(o);
    FAIL() << "max_iterations = 0 accepted";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.field(), "max_iterations");
  }
}

// ---- linear oscillator ẍ + ω₀² x = 0 --------------------------------------------

/// Error max(|x − cos ω₀t|, |v + ω₀ sin ω₀t|/ω₀) at t = T from x = 1, v = 0.
double oscillatorError(double rho, double omega0, double h, double T) {
  GeneralizedAlphaOptions o;
  o.rho_inf = rho;
  GeneralizedAlphaStepper<OscillatorState> stepper(o);
  const Oscillator sys = Oscillator::oscillator(omega0);
  OscillatorState y = oscillatorState(1.0, 0.0);
  const int n = static_cast<int>(std::lround(T / h));
  StepReport rep;
  for (int i = 0; i < n; ++i) {
    y = stepper.step(sys, i * h, y, h, &rep);
    EXPECT_TRUE(rep.converged);
  }
  return std::max(std::abs(y.x(0) - std::cos(omega0 * T)),
                  std::abs(y.v(0) + omega0 * std::sin(omega0 * T)) / omega0);
}

TEST(GeneralizedAlphaOscillator, SecondOrderForEveryRho) {
  const double omega0 = 2.0, T = 5.0;
  for (double rho : {1.0, 0.8, 0.5, 0.0}) {
    std::vector<double> hs, errs;
    for (double h : {0.02, 0.01, 0.005, 0.0025}) {
      hs.push_back(h);
      errs.push_back(oscillatorError(rho, omega0, h, T));
    }
    const double slope = logLogSlope(hs, errs);
    std::printf("oscillator rho_inf=%.1f: errors %.3e %.3e %.3e %.3e slope %.4f\n", rho, errs[0],
                errs[1], errs[2], errs[3], slope);
    EXPECT_NEAR(slope, 2.0, 0.15) << "rho_inf = " << rho;
  }
}

/// Max relative energy deviation over `periods` periods at ρ∞ = 1.
double energyDrift(double h_omega0, double periods, double* amplitude_drift) {
  const double omega0 = 1.0, h = h_omega0 / omega0;
  GeneralizedAlphaStepper<OscillatorState> stepper;  // ρ∞ = 1
  const Oscillator sys = Oscillator::oscillator(omega0);
  OscillatorState y = oscillatorState(1.0, 0.3);
  const double e0 = sys.energy(0.0, y);
  const long n = std::lround(periods * 2.0 * kPi / h);
  double drift = 0.0;
  StepReport rep;
  for (long i = 0; i < n; ++i) {
    y = stepper.step(sys, static_cast<double>(i) * h, y, h, &rep);
    if (!rep.converged) ADD_FAILURE() << "step " << i << " did not converge";
    drift = std::max(drift, std::abs(sys.energy(0.0, y) / e0 - 1.0));
  }
  EXPECT_EQ(stepper.resetCount(), 1);
  // Amplitude A = sqrt(2E)/ω₀: its relative deviation is half the energy's.
  *amplitude_drift = std::abs(std::sqrt(sys.energy(0.0, y) / e0) - 1.0);
  return drift;
}

TEST(GeneralizedAlphaOscillator, NonDissipativeAtRhoOne) {
  for (double hw : {0.1, 10.0}) {
    double amplitude = 0.0;
    const double drift = energyDrift(hw, 1e4, &amplitude);
    std::printf("rho_inf=1, h*omega0=%g, 1e4 periods: max |E/E0-1| = %.3e, final amplitude "
                "deviation %.3e\n",
                hw, drift, amplitude);
    EXPECT_LT(drift, 1e-9) << "h omega0 = " << hw;
  }
}

TEST(GeneralizedAlphaOscillator, AuxiliaryAccelerationIsShifted) {
  // Arnold & Brüls 2007, §3: a_n = v̇(t_n + (α_m − α_f)h) + O(h²), while
  // a_n − v̇(t_n) is O(h). x = cos t, so v̇ = −cos t.
  for (double rho : {0.8, 0.5, 0.0}) {
    GeneralizedAlphaOptions o;
    o.rho_inf = rho;
    const auto c = GeneralizedAlphaCoefficients::fromRhoInf(rho);
    std::vector<double> hs, shifted, plain;
    for (double h : {0.02, 0.01, 0.005}) {
      GeneralizedAlphaStepper<OscillatorState> stepper(o);
      const Oscillator sys = Oscillator::oscillator(1.0);
      OscillatorState y = oscillatorState(1.0, 0.0);
      const int n = static_cast<int>(std::lround(3.0 / h));
      for (int i = 0; i < n; ++i) y = stepper.step(sys, i * h, y, h);
      const double t = n * h, a = stepper.auxiliaryAcceleration()(0);
      hs.push_back(h);
      shifted.push_back(std::abs(a + std::cos(t + (c.alpha_m - c.alpha_f) * h)));
      plain.push_back(std::abs(a + std::cos(t)));
    }
    EXPECT_NEAR(logLogSlope(hs, shifted), 2.0, 0.15) << "rho_inf = " << rho;
    EXPECT_NEAR(logLogSlope(hs, plain), 1.0, 0.15) << "rho_inf = " << rho;
  }
}

/// The amplification matrix of one step on (x, h v, h² a) for ω₀ = 1 (v̇ = −x
/// is implied by x), measured column by column through setHistory.
Matrix3d amplificationMatrix(double rho, double h) {
  GeneralizedAlphaOptions o;
  o.rho_inf = rho;
  GeneralizedAlphaStepper<OscillatorState> stepper(o);
  const Oscillator sys = Oscillator::oscillator(1.0);
  Matrix3d A;
  for (int j = 0; j < 3; ++j) {
    Vector3d e = Vector3d::Zero();
    e(j) = 1.0;
    const OscillatorState y = oscillatorState(e(0), e(1) / h);
    Eigen::Matrix<double, 1, 1> vdot, a;
    vdot(0) = -y.x(0);
    a(0) = e(2) / (h * h);
    stepper.setHistory(y, vdot, a);
    StepReport rep;
    const OscillatorState y1 = stepper.step(sys, 0.0, y, h, &rep);
    EXPECT_TRUE(rep.converged) << "rho " << rho << " h " << h << " column " << j;
    A.col(j) << y1.x(0), h * y1.v(0), h * h * stepper.auxiliaryAcceleration()(0);
  }
  EXPECT_EQ(stepper.resetCount(), 0);
  return A;
}

/// The same matrix from the textbook recurrence of the vector-space method
/// (Chung & Hulbert 1993; Arnold & Brüls 2007, eqs. (6)–(7)), with v̇ = −x,
/// in the scaled variables X = x, V = h v, A = h² a, Ω = hω₀ = h:
///   X₁ = X₀ + V₀ + (½ − β) A₀ + β A₁,   V₁ = V₀ + (1 − γ) A₀ + γ A₁,
///   (1 − α_m) A₁ + α_m A₀ = −Ω² ((1 − α_f) X₁ + α_f X₀).
Matrix3d textbookAmplificationMatrix(double rho, double h) {
  const auto c = GeneralizedAlphaCoefficients::fromRhoInf(rho);
  const double w2 = h * h;
  // Unknowns (X₁, V₁, A₁): L · new = R · old.
  Matrix3d L, R;
  L << 1, 0, -c.beta,  //
      0, 1, -c.gamma,  //
      w2 * (1 - c.alpha_f), 0, 1 - c.alpha_m;
  R << 1, 1, 0.5 - c.beta,  //
      0, 1, 1 - c.gamma,    //
      -w2 * c.alpha_f, 0, -c.alpha_m;
  return L.partialPivLu().solve(R);
}

/// max |λ| over the roots of the characteristic polynomial of A, by the
/// Durand–Kerner iteration in long double (a multiple root, as at hω₀ → ∞, is
/// found to about ε^(1/3)).
double spectralRadiusOf(const Matrix3d& A) {
  using C = std::complex<long double>;
  const long double tr = A.trace();
  const long double minors = A(0, 0) * A(1, 1) - A(0, 1) * A(1, 0) + A(0, 0) * A(2, 2) -
                             A(0, 2) * A(2, 0) + A(1, 1) * A(2, 2) - A(1, 2) * A(2, 1);
  const long double det = A.determinant();
  auto p = [&](C z) { return ((z - tr) * z + minors) * z - det; };
  C z[3] = {C(0.4L, 0.9L), C(0.4L, 0.9L) * C(0.4L, 0.9L), C(0.4L, 0.9L) * C(0.4L, 0.9L) * C(0.4L, 0.9L)};
  for (int it = 0; it < 2000; ++it)
    for (int i = 0; i < 3; ++i) {
      C den = 1.0L;
      for (int j = 0; j < 3; ++j)
        if (j != i) den *= z[i] - z[j];
      z[i] -= p(z[i]) / den;
    }
  return static_cast<double>(std::max({std::abs(z[0]), std::abs(z[1]), std::abs(z[2])}));
}

TEST(GeneralizedAlphaOscillator, AmplificationMatrixIsTheTextbookOne) {
  // The stepper works in unscaled variables: q_{n+1} = q_n + hΔq where hΔq
  // holds terms of size (hω₀)² |x|, so its matrix carries a rounding error of
  // about ε (hω₀)² (measured: 0.1–0.6 ε (hω₀)²).
  for (double rho : {1.0, 0.8, 0.5, 0.0})
    for (double hw = 1e-2; hw <= 1e6; hw *= 3.0) {
      const Matrix3d A = amplificationMatrix(rho, hw);
      const Matrix3d B = textbookAmplificationMatrix(rho, hw);
      const double tol = (1e-12 + 2e-15 * hw * hw) * std::max(1.0, B.cwiseAbs().maxCoeff());
      EXPECT_LT((A - B).cwiseAbs().maxCoeff(), tol)
          << "rho " << rho << " h omega0 " << hw << "\n" << A << "\n" << B;
    }
}

TEST(GeneralizedAlphaOscillator, SpectralRadius) {
  // Unconditional stability: ρ(A) ≤ 1 for every hω₀ (the stepper's matrix).
  for (double rho : {1.0, 0.8, 0.5, 0.0})
    for (double hw = 1e-2; hw <= 1e4; hw *= 3.0)
      EXPECT_LE(spectralRadiusOf(amplificationMatrix(rho, hw)), 1.0 + 1e-6)
          << "rho " << rho << " h omega0 " << hw;

  // ρ(A) → ρ∞ as hω₀ → ∞. At infinity −ρ∞ is a triple eigenvalue, so at
  // finite hω₀ the eigenvalues split by about (hω₀)^(−2/3): 2e-3 at 1e4 (the
  // stepper's matrix), 1e-4 at 1e6 (the textbook matrix, free of the
  // ε (hω₀)² rounding above).
  for (double rho : {1.0, 0.5, 0.0}) {
    const double r4 = spectralRadiusOf(amplificationMatrix(rho, 1e4));
    const double r6 = spectralRadiusOf(textbookAmplificationMatrix(rho, 1e6));
    std::printf("spectral radius, rho_inf = %.1f: %.6f at h*omega0 = 1e4 (stepper), %.6f at "
                "1e6 (textbook recurrence)\n",
                rho, r4, r6);
    EXPECT_NEAR(r4, rho, 5e-3) << "rho_inf = " << rho;
    EXPECT_NEAR(r6, rho, 2e-4) << "rho_inf = " << rho;
  }
}

TEST(GeneralizedAlphaOscillator, StiffModeDampedAtRhoZero) {
  const double h = 100.0;  // ω₀ = 1: hω₀ = 100
  const double r = spectralRadiusOf(amplificationMatrix(0.0, h));
  std::printf("rho_inf = 0, h*omega0 = 100: spectral radius %.4e\n", r);
  EXPECT_LT(r, 0.05);

  GeneralizedAlphaOptions o;
  o.rho_inf = 0.0;
  GeneralizedAlphaStepper<OscillatorState> stepper(o);
  const Oscillator sys = Oscillator::oscillator(1.0);
  OscillatorState y = oscillatorState(1.0, 0.0);
  const double e0 = sys.energy(0.0, y);
  for (int i = 0; i < 5; ++i) y = stepper.step(sys, i * h, y, h);
  const double ratio = std::sqrt(sys.energy(0.0, y) / e0);
  std::printf("rho_inf = 0, h*omega0 = 100: amplitude after 5 steps %.3e\n", ratio);
  EXPECT_LT(ratio, 1e-4);

  // ρ∞ = 1 at the same hω₀ keeps the amplitude.
  GeneralizedAlphaStepper<OscillatorState> trapezoid;
  y = oscillatorState(1.0, 0.0);
  for (int i = 0; i < 5; ++i) y = trapezoid.step(sys, i * h, y, h);
  EXPECT_NEAR(sys.energy(0.0, y) / e0, 1.0, 1e-12);
}

// ---- rigid bodies ---------------------------------------------------------------

/// ‖log(R_ref⁻¹ R)‖ + ‖ω − ω_ref‖/‖ω_ref‖ split into the two parts.
struct RotorError {
  double rotation;
  double omega;
};

RotorError rotorError(const RotorState<double>& y, const RotorState<double>& ref) {
  return {(ref.R.inverse() * y.R).log().norm(), (y.omega - ref.omega).norm() / ref.omega.norm()};
}

template <class System>
RotorState<double> rk4Reference(const System& sys, const RotorState<double>& y0, double T,
                                double h) {
  const RkmkStepper<RotorState<double>> rk4(ButcherTableau::rk4());
  RotorState<double> y = y0;
  const long n = std::lround(T / h);
  for (long i = 0; i < n; ++i) y = rk4.step(sys, static_cast<double>(i) * h, y, h);
  return y;
}

struct NewtonStats {
  double mean = 0.0;
  int max = 0;
};

template <class System>
RotorState<double> runGeneralizedAlpha(const System& sys, const RotorState<double>& y0, double T,
                                       double h, double rho, NewtonStats* stats = nullptr) {
  GeneralizedAlphaOptions o;
  o.rho_inf = rho;
  GeneralizedAlphaStepper<RotorState<double>> stepper(o);
  RotorState<double> y = y0;
  const long n = std::lround(T / h);
  StepReport rep;
  long total = 0;
  int most = 0;
  for (long i = 0; i < n; ++i) {
    y = stepper.step(sys, static_cast<double>(i) * h, y, h, &rep);
    if (!rep.converged) ADD_FAILURE() << "step " << i << ": " << rep.failure;
    total += rep.newton_iterations;
    most = std::max(most, rep.newton_iterations);
  }
  EXPECT_EQ(stepper.resetCount(), 1);
  if (stats) *stats = {static_cast<double>(total) / static_cast<double>(n), most};
  return y;
}

RotorSystem<double> freeRotor() {
  RigidBodyParameters<double> p;
  p.inertia = Vector3d(2.0, 3.0, 4.5).asDiagonal();
  return RotorSystem<double>(p);
}

RotorState<double> freeRotorStart() {
  RotorState<double> y;
  y.R = SO3d::exp(Vector3d(0.3, -0.2, 0.5));
  y.omega = Vector3d(1.2, -0.7, 0.9);
  return y;
}

TEST(GeneralizedAlphaRigidBody, FreeRotorSecondOrder) {
  const RotorSystem<double> sys = freeRotor();
  const RotorState<double> y0 = freeRotorStart();
  const double T = 5.0;
  const RotorState<double> ref = rk4Reference(sys, y0, T, 1e-4);
  for (double rho : {1.0, 0.5, 0.0}) {
    std::vector<double> hs, er, ew;
    for (double h : {0.02, 0.01, 0.005, 0.0025}) {
      const RotorError e = rotorError(runGeneralizedAlpha(sys, y0, T, h, rho), ref);
      hs.push_back(h);
      er.push_back(e.rotation);
      ew.push_back(e.omega);
    }
    const double sr = logLogSlope(hs, er), sw = logLogSlope(hs, ew);
    std::printf("free rotor rho_inf=%.1f: rotation errors %.3e .. %.3e slope %.4f; omega errors "
                "%.3e .. %.3e slope %.4f\n",
                rho, er.front(), er.back(), sr, ew.front(), ew.back(), sw);
    EXPECT_NEAR(sr, 2.0, 0.15) << "rho_inf = " << rho;
    EXPECT_NEAR(sw, 2.0, 0.15) << "rho_inf = " << rho;
  }
}

/// The heavy top of Brüls, Cardona & Arnold 2012, §5.1 (also Brüls & Cardona
/// 2010): m = 15 kg, J_c = diag(0.234375, 0.46875, 0.234375) kg m², centre of
/// mass (0, 1, 0) m from the fixed pivot in body axes, gravity (0, 0, −9.81).
template <typename T>
RotorSystem<T> heavyTop(const T& mass = T(15.0)) {
  RigidBodyParameters<T> p;
  p.mass = mass;
  p.inertia = Vector3<T>(T(0.234375), T(0.46875), T(0.234375)).asDiagonal();
  p.gravity = Vector3<T>(T(0), T(0), T(-9.81));
  p.has_pivot = true;
  p.com_from_pivot = Vector3<T>(T(0), T(1), T(0));
  return RotorSystem<T>(p);
}

template <typename T>
RotorState<T> heavyTopStart() {
  RotorState<T> y;
  y.omega = Vector3<T>(T(0), T(150), T(-4.61538));
  return y;
}

const RotorState<double>& heavyTopReference() {
  static const RotorState<double> ref =
      rk4Reference(heavyTop<double>(), heavyTopStart<double>(), 2.0, 2e-5);
  return ref;
}

TEST(GeneralizedAlphaRigidBody, HeavyTopSecondOrder) {
  const RotorSystem<double> sys = heavyTop<double>();
  const RotorState<double> y0 = heavyTopStart<double>();
  const RotorState<double>& ref = heavyTopReference();
  // The asymptotic range starts at smaller h with more numerical damping:
  // h = 2e-3 … 2.5e-4 for ρ∞ ≥ 0.9, halved for 0.5, quartered for 0.
  struct Range {
    double rho, h_max;
  };
  for (const Range& range : {Range{1.0, 2e-3}, Range{0.9, 2e-3}, Range{0.5, 1e-3},
                             Range{0.0, 5e-4}}) {
    const double rho = range.rho;
    std::vector<double> hs, er, ew;
    for (double h = range.h_max; h > range.h_max / 10.0; h /= 2.0) {
      const RotorError e = rotorError(runGeneralizedAlpha(sys, y0, 2.0, h, rho), ref);
      hs.push_back(h);
      er.push_back(e.rotation);
      ew.push_back(e.omega);
    }
    const double sr = logLogSlope(hs, er), sw = logLogSlope(hs, ew);
    std::printf("heavy top rho_inf=%.1f, h=%.3g..%.3g: rotation errors %.3e %.3e %.3e %.3e slope "
                "%.4f; omega errors %.3e %.3e %.3e %.3e slope %.4f\n",
                rho, hs.front(), hs.back(), er[0], er[1], er[2], er[3], sr, ew[0], ew[1], ew[2],
                ew[3], sw);
    EXPECT_NEAR(sr, 2.0, 0.15) << "rho_inf = " << rho;
    EXPECT_NEAR(sw, 2.0, 0.15) << "rho_inf = " << rho;
  }
}

TEST(GeneralizedAlphaRigidBody, HeavyTopNewtonIterations) {
  for (double rho : {1.0, 0.9, 0.0}) {
    NewtonStats stats;
    runGeneralizedAlpha(heavyTop<double>(), heavyTopStart<double>(), 2.0, 1e-3, rho, &stats);
    std::printf("heavy top h=1e-3 rho_inf=%.1f: Newton iterations per step mean %.3f max %d\n",
                rho, stats.mean, stats.max);
    EXPECT_LE(stats.max, 4) << "rho_inf = " << rho;
  }
}

TEST(GeneralizedAlphaRigidBody, FreeBodyFollowsTheParabolaExactly) {
  // Translation under uniform gravity: v̇ = g exactly, so a_n = v̇_n = g for
  // every n and the step is p + h v + ½h² g, v + h g — exact up to rounding
  // for every ρ∞; the rotation runs alongside (torque-free, asymmetric).
  RigidBodyParameters<double> p;
  p.mass = 2.5;
  p.inertia = Vector3d(1.0, 2.0, 2.5).asDiagonal();
  p.gravity = Vector3d(0.3, -0.1, -9.81);
  const FreeBodySystem<double> sys(p);
  FreeBodyState<double> y0;
  y0.R = SO3d::exp(Vector3d(0.1, 0.2, -0.3));
  y0.p = Vector3d(1.0, -2.0, 3.0);
  y0.v = Vector3d(4.0, 0.5, 12.0);
  y0.omega = Vector3d(0.4, 2.0, -0.6);
  const double h = 0.01, T = 3.0;
  const int n = static_cast<int>(std::lround(T / h));
  for (double rho : {1.0, 0.5, 0.0}) {
    GeneralizedAlphaOptions o;
    o.rho_inf = rho;
    GeneralizedAlphaStepper<FreeBodyState<double>> stepper(o);
    FreeBodyState<double> y = y0;
    double ep = 0.0, ev = 0.0;
    StepReport rep;
    for (int i = 0; i < n; ++i) {
      y = stepper.step(sys, i * h, y, h, &rep);
      ASSERT_TRUE(rep.converged) << rep.failure;
      const double t = (i + 1) * h;
      const Vector3d p_exact = y0.p + t * y0.v + 0.5 * t * t * p.gravity;
      const Vector3d v_exact = y0.v + t * p.gravity;
      ep = std::max(ep, (y.p - p_exact).norm() / p_exact.norm());
      ev = std::max(ev, (y.v - v_exact).norm() / v_exact.norm());
    }
    std::printf("free body in gravity rho_inf=%.1f: max relative error position %.2e, velocity "
                "%.2e over %d steps\n",
                rho, ep, ev, n);
    EXPECT_LT(ep, 1e-13);
    EXPECT_LT(ev, 1e-13);
    // The rotation: torque-free, so ½ωᵀJω is nearly kept (second order).
    EXPECT_NEAR(0.5 * y.omega.dot(sys.inertia() * y.omega),
                0.5 * y0.omega.dot(sys.inertia() * y0.omega), 1e-3);
  }
}

// ---- reporting and history ------------------------------------------------------

TEST(GeneralizedAlphaRigidBody, NonConvergenceIsReported) {
  GeneralizedAlphaOptions o;
  o.max_iterations = 1;
  o.tolerance = 1e-15;
  GeneralizedAlphaStepper<RotorState<double>> stepper(o);
  const RotorSystem<double> sys = heavyTop<double>();
  const RotorState<double> y0 = heavyTopStart<double>();
  StepReport rep;
  stepper.step(sys, 0.0, y0, 1e-3, &rep);
  EXPECT_FALSE(rep.converged);
  EXPECT_STREQ(rep.failure, "generalized-alpha Newton did not converge");
  EXPECT_GT(rep.residual, 0.0);
  EXPECT_EQ(rep.newton_iterations, 1);
  EXPECT_FALSE(stepper.lastReport().converged);
  EXPECT_STREQ(stepper.lastReport().failure, rep.failure);

  // Without a report pointer the failure is still in lastReport(). A failed
  // step is not committed: the retry from y0 (here with a smaller h) keeps the
  // history instead of resetting.
  stepper.step(sys, 0.0, y0, 5e-4);
  EXPECT_FALSE(stepper.lastReport().converged);
  EXPECT_EQ(stepper.resetCount(), 1);

  // The default options converge on the same step.
  GeneralizedAlphaStepper<RotorState<double>> fresh;
  StepReport ok;
  fresh.step(sys, 0.0, y0, 1e-3, &ok);
  EXPECT_TRUE(ok.converged);
  EXPECT_GE(ok.newton_iterations, 1);
}

TEST(GeneralizedAlphaRigidBody, HistoryIsKeptOnlyAlongItsOwnOutput) {
  GeneralizedAlphaOptions o;
  o.rho_inf = 0.5;  // a_n ≠ v̇_n after the first step
  GeneralizedAlphaStepper<RotorState<double>> stepper(o);
  const RotorSystem<double> sys = heavyTop<double>();
  RotorState<double> y = heavyTopStart<double>();
  EXPECT_FALSE(stepper.initialized());
  for (int i = 0; i < 10; ++i) y = stepper.step(sys, i * 1e-3, y, 1e-3);
  EXPECT_EQ(stepper.resetCount(), 1);
  EXPECT_GT((stepper.auxiliaryAcceleration() - stepper.acceleration()).norm(), 1e-3);

  // A different incoming state restarts with consistent accelerations.
  RotorState<double> other = y;
  other.omega.x() += 1e-9;
  stepper.step(sys, 0.01, other, 1e-3);
  EXPECT_EQ(stepper.resetCount(), 2);

  // reset() gives v̇₀ = −J⁻¹ g, a₀ = v̇₀.
  stepper.reset(sys, 0.0, y);
  const Vector3d expected = sys.angularAcceleration(0.0, y.R, y.omega);
  EXPECT_LT((stepper.acceleration() - expected).norm(), 1e-12 * expected.norm());
  EXPECT_EQ(stepper.acceleration(), stepper.auxiliaryAcceleration());
}

// ---- ceres::Jet -------------------------------------------------------------------

#ifdef LIEFLOW_HAVE_CERES
/// Ten heavy-top steps from the BCA start; returns (q_w, q_x, q_y, q_z, ω).
template <typename T>
Eigen::Matrix<T, 7, 1> heavyTopSteps(const T& h, const T& mass) {
  GeneralizedAlphaOptions o;
  o.rho_inf = 0.8;
  GeneralizedAlphaStepper<RotorState<T>> stepper(o);
  const RotorSystem<T> sys = heavyTop<T>(mass);
  RotorState<T> y = heavyTopStart<T>();
  StepReport rep;
  for (int i = 0; i < 10; ++i) {
    y = stepper.step(sys, T(double(i)) * h, y, h, &rep);
    EXPECT_TRUE(rep.converged);
  }
  Eigen::Matrix<T, 7, 1> out;
  const auto& q = y.R.quaternion();
  out << q.w(), q.x(), q.y(), q.z(), y.omega;
  return out;
}

TEST(GeneralizedAlphaJet, DerivativesMatchCentralDifferences) {
  using Jet = ceres::Jet<double, 1>;
  const double h = 2e-3, mass = 15.0;
  struct Case {
    const char* name;
    bool wrt_h;
    double delta;
  };
  for (const Case& c : {Case{"h", true, 1e-8}, Case{"mass", false, 1e-5}}) {
    const Jet hj = c.wrt_h ? Jet(h, 0) : Jet(h);
    const Jet mj = c.wrt_h ? Jet(mass) : Jet(mass, 0);
    const Eigen::Matrix<Jet, 7, 1> out = heavyTopSteps<Jet>(hj, mj);
    const double dh = c.wrt_h ? c.delta : 0.0, dm = c.wrt_h ? 0.0 : c.delta;
    const Eigen::Matrix<double, 7, 1> plus = heavyTopSteps<double>(h + dh, mass + dm);
    const Eigen::Matrix<double, 7, 1> minus = heavyTopSteps<double>(h - dh, mass - dm);
    const Eigen::Matrix<double, 7, 1> fd = (plus - minus) / (2.0 * c.delta);
    const Eigen::Matrix<double, 7, 1> base = heavyTopSteps<double>(h, mass);
    Eigen::Matrix<double, 7, 1> ad;
    for (int i = 0; i < 7; ++i) {
      ad(i) = out(i).v(0);
      // The Jet path polishes once more: values agree to the Newton tolerance.
      EXPECT_NEAR(out(i).a, base(i), 1e-12 * std::max(1.0, base.cwiseAbs().maxCoeff()));
    }
    const double err = (ad - fd).cwiseAbs().maxCoeff() / fd.cwiseAbs().maxCoeff();
    std::printf("Jet derivative w.r.t. %s: max |AD - FD| / max |FD| = %.2e\n", c.name, err);
    EXPECT_LT(err, 1e-6) << c.name;
  }
}
#endif

}  // namespace
}  // namespace lieflow
