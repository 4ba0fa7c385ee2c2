/// \file
/// The three-stage Radau IIA method (Ehle 1969; Hairer & Wanner, "Solving
/// Ordinary Differential Equations II", 2nd ed. 1996, §IV.5 and §IV.8, the
/// code RADAU5) on a Lie group in Runge–Kutta–Munthe-Kaas form: order 5,
/// L-stable and stiffly accurate. It is the method for stiff scenes (light
/// links on strong dashpots, stiff springs) where an explicit method is held
/// to hλ ≲ 3 and the trapezoidal rule of generalized-α (ρ∞ = 1) keeps the fast
/// modes ringing: its stability function R(z) → 0 as z → −∞, so a mode far
/// beyond 1/h is damped out in one step, and as an implicit Runge–Kutta method
/// it keeps every linear invariant (a dashpotted joint's λq + q̇).
///
/// ## The method
/// Nodes c = ((4 − √6)/10, (4 + √6)/10, 1) and the coefficients a_ij of
/// Hairer & Wanner Table IV.5.6. In algebra coordinates the stage increments
/// Θ_i solve (Munthe-Kaas 1999, the implicit case)
///     Θ_i = h Σ_j a_ij K_j,   K_j = dexp⁻¹_{Θ_j} f(t + c_j h, y ⊕ Θ_j),
/// and, the method being stiffly accurate (b = the last row of A, c₃ = 1),
///     y_{n+1} = y ⊕ Θ₃.
/// dexp⁻¹ is taken to ad⁴ (order 5 needs its terms up to ad³; on a vector
/// space it is the identity and the method is Radau IIA itself).
///
/// ## Simplified Newton (Hairer & Wanner §IV.8)
/// With Z = (Θ₁, Θ₂, Θ₃) the equations read (h⁻¹A⁻¹ ⊗ I) Z − K(Z) = 0. The
/// iteration matrix keeps one Jacobian J = ∂f/∂δ at (t, y) (forward
/// differences along the state's tangent, one evaluation per column) and
/// drops dexp⁻¹'s derivative. A⁻¹ has one real eigenvalue γ and a complex
/// pair α ± iβ: with T = [v_γ, Re v, −Im v] (v the eigenvector of α + iβ),
/// T⁻¹A⁻¹T = [[γ, 0, 0], [0, α, −β], [0, β, α]], and in W = (T⁻¹ ⊗ I) Z the
/// Newton system splits into one real and one complex system of the
/// tangent's size n:
///     (γ/h − J) ΔW₁ = R₁,   ((α + iβ)/h − J)(ΔW₂ + iΔW₃) = R₂ + iR₃,
///     R = (T⁻¹ ⊗ I) K(Z) − (h⁻¹Λ ⊗ I) W.
/// Both are factored once per Jacobian and step size. J is kept from step to
/// step while the iteration contracts fast (rate θ below `jacobian_reuse`,
/// RADAU5's 0.001) and recomputed when it did not, or when an iteration
/// diverges (then the step is solved again from its start).
///
/// Start: at the first step, and after a change of h, Z = 0; otherwise the
/// collocation polynomial of the last step extrapolated (RADAU5's start):
/// w(τ) through (0, 0), (c_i, Θ_i), and Θ_i' = w(1 + c_i) − Θ₃, or Z = 0
/// again when that was nearer the last step's solution (RADAU5 leaves this
/// choice to its user, STARTN): on a stiff transient the polynomial carries
/// the fast decay far beyond the step. From Z = 0 the three stages are the
/// point y itself, evaluated once when the system says its f does not depend
/// on t (`bool autonomous() const`).
///
/// Stop: with the increment's size ‖ΔZ‖ = max |ΔZ| / (1 + max |Z|) (every
/// component of every stage; positions and velocities alike) and θ_k =
/// ‖ΔZ_k‖/‖ΔZ_{k−1}‖, when the remaining error θ_k/(1 − θ_k)·‖ΔZ_k‖ is below
/// `tolerance` (the first iteration uses the last step's rate, as RADAU5), or
/// ‖ΔZ‖ is at the rounding level. θ_k ≥ 1 is a diverging iteration.
///
/// Cost per step: 3 evaluations of f per iteration (1 for a first iteration
/// from Z = 0 on an autonomous system, 0 beside a new Jacobian); per new
/// Jacobian n + 1 evaluations and an n × n real and a complex LU. No heap
/// allocation after the first step (the workspace is sized then).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <limits>
#include <type_traits>
#include <utility>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include "integrators/lu_substitution.hpp"
#include "integrators/state_workspace.hpp"
#include "integrators/step_report.hpp"

namespace lieflow {

struct RadauOptions {
  /// Stop the Newton iteration when its estimated remaining error is below
  /// this (relative to 1 + the stage increments; file comment).
  double tolerance = 1e-10;
  int max_iterations = 20;
  /// Keep the Jacobian for the next step while the iteration's contraction
  /// rate stays below this (RADAU5's default).
  double jacobian_reuse = 1e-3;
};

/// The fixed constants of three-stage Radau IIA and of its transformed
/// Newton system.
struct RadauIIACoefficients {
  std::array<double, 3> c{};
  Eigen::Matrix3d A, T, T_inv;
  double gamma = 0.0, alpha = 0.0, beta = 0.0;  ///< eigenvalues of A⁻¹: γ, α ± iβ

  static const RadauIIACoefficients& get() {
    static const RadauIIACoefficients k = make();
    return k;
  }

 private:
  static RadauIIACoefficients make() {
    RadauIIACoefficients k;
    const double s6 = std::sqrt(6.0);
    k.c = {(4.0 - s6) / 10.0, (4.0 + s6) / 10.0, 1.0};
    k.A << (88.0 - 7.0 * s6) / 360.0, (296.0 - 169.0 * s6) / 1800.0, (-2.0 + 3.0 * s6) / 225.0,
        (296.0 + 169.0 * s6) / 1800.0, (88.0 + 7.0 * s6) / 360.0, (-2.0 - 3.0 * s6) / 225.0,
        (16.0 - s6) / 36.0, (16.0 + s6) / 36.0, 1.0 / 9.0;
    const Eigen::EigenSolver<Eigen::Matrix3d> eigen(k.A.inverse());
    int real = 0, upper = 0;
    for (int i = 0; i < 3; ++i) {
      if (std::abs(eigen.eigenvalues()[i].imag()) < 1e-12) real = i;
      if (eigen.eigenvalues()[i].imag() > 1e-12) upper = i;
    }
    k.gamma = eigen.eigenvalues()[real].real();
    k.alpha = eigen.eigenvalues()[upper].real();
    k.beta = eigen.eigenvalues()[upper].imag();
    k.T.col(0) = eigen.eigenvectors().col(real).real();
    k.T.col(1) = eigen.eigenvectors().col(upper).real();
    k.T.col(2) = -eigen.eigenvectors().col(upper).imag();
    k.T_inv = k.T.inverse();
    return k;
  }
};

template <typename State>
class RadauIIAStepper {
 public:
  using StateType = State;
  using Scalar = typename State::Scalar;
  using Tangent = typename State::Tangent;
  static_assert(std::is_same<Scalar, double>::value, "Radau IIA's Newton matrix is factored in double");

  explicit RadauIIAStepper(RadauOptions options = {}) : options_(options) {
    if constexpr (Tangent::SizeAtCompileTime != Eigen::Dynamic) {  // (defined before the first step sizes them)
      for (auto* a : {&work_.Z, &work_.K, &work_.W, &work_.dW, &work_.Z_extrapolated})
        for (Tangent& v : *a) v.setZero();
      for (Tangent* v : {&work_.f0, &work_.f, &work_.direction}) v->setZero();
    }
  }

  static constexpr int order() { return 5; }
  const RadauOptions& options() const { return options_; }
  /// Jacobians computed so far (each n evaluations of f).
  int jacobianCount() const { return work_.jacobians; }

  /// One step of size h from (t, y). The result lives in the stepper until
  /// its next step (y may be that result). A Newton iteration that does not
  /// converge (with a fresh Jacobian) is reported in *report.
  template <typename System>
  state_ops::StepResult<State> step(const System& system, double t, const State& y, double h,
                                    StepReport* report = nullptr) const {
    Workspace& w = work_;
    const RadauIIACoefficients& k = RadauIIACoefficients::get();
    const int n = state_ops::tangentSize(y);
    if (w.J.rows() != n) resize(y, n);
    const bool same_step = w.have_previous && h == w.h_previous;
    if (same_step) extrapolateStart(k);
    bool zero_start = !(same_step && w.extrapolate);
    if (zero_start)
      for (Tangent& z : w.Z) z.setZero();
    else
      w.Z = w.Z_extrapolated;
    int iterations = 0;
    bool converged = false;
    double residual = 0.0;
    for (int attempt = 0; attempt < 2 && !converged; ++attempt) {
      if (attempt == 1) {  // again from Z = 0, with a Jacobian of this point
        if (w.jacobian_fresh && !same_step) break;  // that was the first attempt
        for (Tangent& z : w.Z) z.setZero();
        zero_start = true;
        if (!w.jacobian_fresh) w.have_jacobian = false;
      }
      if (!w.have_jacobian) jacobian(system, t, y, h, n);
      if (w.h_factored != h) factor(k, h);
      converged = newton(system, t, y, h, k, zero_start, &iterations, &residual);
    }
    state_ops::rplusInto(y, w.Z[2], &w.result);
    if (converged && same_step) chooseStart();
    w.have_previous = converged;
    w.h_previous = h;
    // Keep J while the iteration contracted fast; a fresh one next step otherwise.
    if (!converged || w.theta_max > options_.jacobian_reuse) w.have_jacobian = false;
    w.jacobian_fresh = false;
    if (report) {
      report->newton_iterations = iterations;
      report->residual = residual;
      if (!converged)
        report->fail("Radau IIA: the simplified Newton iteration did not converge, with a Jacobian of the step's "
                     "start too (a shorter step would)",
                     residual);
    }
    if constexpr (state_ops::kHeapBacked<State>)
      return w.result;
    else
      return State(w.result);
  }

 private:
  struct Workspace {
    Eigen::MatrixXd J, E_real;
    Eigen::MatrixXcd E_complex;
    LuSubstitution<double> lu_real;
    LuSubstitution<std::complex<double>> lu_complex;
    Eigen::VectorXcd rhs_complex, x_complex;
    std::array<Tangent, 3> Z, K, W, dW, Z_extrapolated;
    Tangent f0, f, direction;
    State stage, result;
    bool have_jacobian = false, jacobian_fresh = false, have_previous = false;
    bool extrapolate = true;  ///< start from the extrapolation (else from Z = 0)
    double h_factored = std::numeric_limits<double>::quiet_NaN();
    double h_previous = std::numeric_limits<double>::quiet_NaN();
    double eta = 1.0;  ///< the last iteration's θ/(1 − θ), the first estimate of the next
    double theta_max = 0.0;
    int jacobians = 0;
  };

  void resize(const State& y, int n) const {
    Workspace& w = work_;
    w.J.resize(n, n);
    w.E_real.resize(n, n);
    w.E_complex.resize(n, n);
    w.rhs_complex.resize(n);
    w.x_complex.resize(n);
    for (auto* a : {&w.Z, &w.K, &w.W, &w.dW, &w.Z_extrapolated})
      for (Tangent& v : *a) state_ops::setZeroTangent(y, &v);
    state_ops::setZeroTangent(y, &w.f0);
    state_ops::setZeroTangent(y, &w.f);
    state_ops::setZeroTangent(y, &w.direction);
    w.stage = y;
    w.result = y;
    w.have_jacobian = w.have_previous = false;
    w.extrapolate = true;
    w.h_factored = std::numeric_limits<double>::quiet_NaN();
  }

  /// J = ∂f/∂δ at (t, y) by forward differences: column j from
  /// f(t, y ⊕ d e_j), d = √ε max(1, h |f_j|) (a component's change over the
  /// step sets its scale).
  template <typename System>
  void jacobian(const System& system, double t, const State& y, double h, int n) const {
    Workspace& w = work_;
    system.velocity(t, y, &w.f0);
    const double root_eps = std::sqrt(std::numeric_limits<double>::epsilon());
    w.direction.setZero();
    for (int j = 0; j < n; ++j) {
      const double d = root_eps * std::max(1.0, h * std::abs(w.f0[j]));
      w.direction[j] = d;
      state_ops::rplusInto(y, w.direction, &w.stage);
      system.velocity(t, w.stage, &w.f);
      w.J.col(j) = (w.f - w.f0) / d;
      w.direction[j] = 0.0;
    }
    w.have_jacobian = w.jacobian_fresh = true;
    w.h_factored = std::numeric_limits<double>::quiet_NaN();
    ++w.jacobians;
  }

  /// (γ/h − J) and ((α + iβ)/h − J), factored.
  void factor(const RadauIIACoefficients& k, double h) const {
    Workspace& w = work_;
    w.E_real = -w.J;
    w.E_real.diagonal().array() += k.gamma / h;
    w.E_complex = (-w.J).template cast<std::complex<double>>();
    w.E_complex.diagonal().array() += std::complex<double>(k.alpha / h, k.beta / h);
    w.lu_real.compute(w.E_real);
    w.lu_complex.compute(w.E_complex);
    w.h_factored = h;
  }

  /// The collocation polynomial of the last step, w(τ) = τ(d₁ + (τ − c₁)(d₂ +
  /// (τ − c₂) d₃)) in Newton's form through (0, 0) and (c_i, Θ_i), read at
  /// 1 + c_i and taken relative to its value Θ₃ at 1 (the new step's base),
  /// into Z_extrapolated.
  void extrapolateStart(const RadauIIACoefficients& k) const {
    Workspace& w = work_;
    const double c1 = k.c[0], c2 = k.c[1];
    Tangent& d1 = w.W[0];
    Tangent& d2 = w.W[1];
    Tangent& d3 = w.W[2];
    d1 = w.Z[0] / c1;                                        // [0, c₁]
    w.dW[0] = (w.Z[1] - w.Z[0]) / (c2 - c1);                 // [c₁, c₂]
    d2 = (w.dW[0] - d1) / c2;                                // [0, c₁, c₂]
    w.dW[1] = (w.Z[2] - w.Z[1]) / (1.0 - c2);                // [c₂, 1]
    w.dW[2] = (w.dW[1] - w.dW[0]) / (1.0 - c1);              // [c₁, c₂, 1]
    d3 = w.dW[2] - d2;                                       // [0, c₁, c₂, 1]
    for (int i = 0; i < 3; ++i) {
      const double tau = 1.0 + k.c[static_cast<std::size_t>(i)];
      w.Z_extrapolated[i] = tau * (d1 + (tau - c1) * (d2 + (tau - c2) * d3)) - w.Z[2];
    }
  }

  /// Which start the next step takes: the one nearer this step's solution.
  /// Extrapolation is RADAU5's start and wins on smooth motion; on a stiff
  /// transient (modes decaying within a step) the polynomial extrapolates the
  /// fast decay far beyond the step and Z = 0 is nearer (on slider_crank at
  /// h = 62.5 ms the extrapolated start was 60–100× the step's Θ).
  void chooseStart() const {
    Workspace& w = work_;
    double from_extrapolation = 0.0, from_zero = 0.0;
    for (int i = 0; i < 3; ++i) {
      from_extrapolation = std::max(from_extrapolation, (w.Z[i] - w.Z_extrapolated[i]).cwiseAbs().maxCoeff());
      from_zero = std::max(from_zero, w.Z[i].cwiseAbs().maxCoeff());
    }
    w.extrapolate = from_extrapolation <= from_zero;
  }

  /// K_i = dexp⁻¹_{Θ_i} f(t + c_i h, y ⊕ Θ_i). From Z = 0 on a system whose
  /// f does not depend on t, the three stages are the one point y (dexp⁻¹_0 =
  /// I): one evaluation, or none when the Jacobian has just evaluated f(t, y).
  template <typename System>
  void stageRates(const System& system, double t, const State& y, double h, const RadauIIACoefficients& k,
                  bool at_start) const {
    Workspace& w = work_;
    if (at_start && isAutonomous(system)) {
      if (w.jacobian_fresh)
        w.K[0] = w.f0;
      else
        system.velocity(t, y, &w.K[0]);
      w.K[1] = w.K[0];
      w.K[2] = w.K[0];
      return;
    }
    for (int i = 0; i < 3; ++i) {
      state_ops::rplusInto(y, w.Z[i], &w.stage);
      system.velocity(t + k.c[static_cast<std::size_t>(i)] * h, w.stage, &w.f);
      state_ops::dexpInvRightInto(y, w.Z[i], w.f, kDexpOrder, &w.K[i]);
    }
  }

  /// Whether System says its f does not depend on t (`bool autonomous()`).
  template <typename System, typename = void>
  struct HasAutonomous : std::false_type {};
  template <typename System>
  struct HasAutonomous<System, std::void_t<decltype(std::declval<const System&>().autonomous())>>
      : std::true_type {};
  template <typename System>
  static bool isAutonomous(const System& system) {
    if constexpr (HasAutonomous<System>::value)
      return system.autonomous();
    else
      return false;
  }

  template <typename System>
  bool newton(const System& system, double t, const State& y, double h, const RadauIIACoefficients& k,
              bool zero_start, int* iterations, double* residual) const {
    Workspace& w = work_;
    const double eps = std::numeric_limits<double>::epsilon();
    double eta = std::pow(std::max(w.eta, eps), 0.8);
    double previous = 0.0;
    w.theta_max = 0.0;
    for (int it = 1; it <= options_.max_iterations; ++it) {
      ++*iterations;
      stageRates(system, t, y, h, k, zero_start && it == 1);
      for (int i = 0; i < 3; ++i) {
        w.W[i] = k.T_inv(i, 0) * w.Z[0] + k.T_inv(i, 1) * w.Z[1] + k.T_inv(i, 2) * w.Z[2];
        w.dW[i] = k.T_inv(i, 0) * w.K[0] + k.T_inv(i, 1) * w.K[1] + k.T_inv(i, 2) * w.K[2];
      }
      // R = T⁻¹K − (Λ/h) W, into dW.
      w.dW[0] -= (k.gamma / h) * w.W[0];
      w.dW[1] -= (k.alpha / h) * w.W[1] - (k.beta / h) * w.W[2];
      w.dW[2] -= (k.beta / h) * w.W[1] + (k.alpha / h) * w.W[2];
      if (!w.dW[0].allFinite() || !w.dW[1].allFinite() || !w.dW[2].allFinite()) {
        *residual = std::numeric_limits<double>::infinity();
        return false;
      }
      // ΔW into W.
      w.lu_real.solve(w.dW[0], &w.W[0]);
      w.rhs_complex.real() = w.dW[1];
      w.rhs_complex.imag() = w.dW[2];
      w.lu_complex.solve(w.rhs_complex, &w.x_complex);
      w.W[1] = w.x_complex.real();
      w.W[2] = w.x_complex.imag();
      double size = 0.0, change = 0.0;
      for (int i = 0; i < 3; ++i) {
        // ΔZ_i = Σ_j T_ij ΔW_j, added to Z_i (K_i is free as scratch).
        w.K[i] = k.T(i, 0) * w.W[0] + k.T(i, 1) * w.W[1] + k.T(i, 2) * w.W[2];
        w.Z[i] += w.K[i];
        change = std::max(change, w.K[i].cwiseAbs().maxCoeff());
        size = std::max(size, w.Z[i].cwiseAbs().maxCoeff());
      }
      const double norm = change / (1.0 + size);
      *residual = norm;
      if (!std::isfinite(norm)) return false;
      if (it > 1) {
        const double theta = norm / previous;
        // (An increment at the rounding level says nothing of the rate.)
        if (norm > kRateNoise * eps) w.theta_max = std::max(w.theta_max, theta);
        if (theta >= 1.0 && norm > kRoundingNorm * eps) return false;
        eta = theta / (1.0 - theta);
      }
      previous = norm;
      if (eta * norm <= options_.tolerance || norm <= kRoundingNorm * eps) {
        w.eta = eta;
        return true;
      }
    }
    return false;
  }

  static constexpr int kDexpOrder = 4;
  /// An increment this many roundings of 1 + |Z| is converged.
  static constexpr double kRoundingNorm = 8.0;
  /// Below this many roundings, an increment's ratio to the last one is
  /// rounding noise, not the iteration's contraction rate.
  static constexpr double kRateNoise = 1e3;

  RadauOptions options_;
  mutable Workspace work_;
};

}  // namespace lieflow
