/// \file
/// The Lie group variational integrator (LGVI) of a rigid body: Lee, Leok &
/// McClamroch, "A Lie group variational integrator for the attitude dynamics
/// of a rigid body with applications to the 3D pendulum", IEEE CCA 2005, and
/// "Lie group variational integrators for the full body problem", CMAME 196
/// (2007) 2907–2924, §3. Second order, symplectic, and it preserves the
/// spatial angular momentum R Π exactly (up to rounding) when no torque acts.
///
/// Discrete Lagrangian L_d = (1/h) tr((I − F_k) J_d) − (h/2)(U(R_k) + U(R_{k+1})),
/// F_k = R_kᵀ R_{k+1}, J_d = ½ tr(J) I − J. Its discrete Euler–Poincaré
/// equations in the body frame, with Π = J ω and M_k = τ(t_k, R_k) (body):
///   h Π_k^ + (h²/2) M_k^ = F_k J_d − J_d F_kᵀ,                           (1)
///   R_{k+1} = R_k F_k,
///   Π_{k+1} = F_kᵀ Π_k + (h/2) F_kᵀ M_k + (h/2) M_{k+1}.
/// With F = exp(f^), θ = ‖f‖, (1) in vector form is G(f) = 0,
///   G(f) = a(θ) J f + b(θ) f × J f − (h Π_k + (h²/2) M_k),
///   a = sin θ/θ = 2 c s,  b = (1 − cos θ)/θ² = 2 s²,
/// in the half-angle variables c = cos(θ/2), s = sin(θ/2)/θ of
/// liegroup/detail/so3_kernels.hpp (no 1 − cos θ is ever formed). It is solved
/// by Newton's method with the analytic Jacobian
///   ∇G = (a'/θ) J f fᵀ + a J + (b'/θ)(f × J f) fᵀ + b (f^ J − (J f)^),
///   a'/θ = (θ cos θ − sin θ)/θ³,  b'/θ = (θ sin θ − 2(1 − cos θ))/θ⁴,
/// from a start f₀ with an O(θ⁴) error: f₁ = J⁻¹ r, r = h Π_k + (h²/2) M_k
/// (error O(θ²)); f₂ = f₁ − ½ J⁻¹(f₁ × r) (O(θ³)); f₀ = J⁻¹(r − ½ f₂ × J f₂)
/// + (θ₂²/6) f₂ (O(θ⁴)), from a = 1 − θ²/6 + O(θ⁴), b = ½ + O(θ²).
/// Measured at the default tolerance: 1 iteration per step for a free body at
/// θ ≈ 0.012, 2 for the Brüls–Cardona–Arnold heavy top at h = 1e-3 (θ ≈ 0.15),
/// 3 at θ ≈ 0.75.
///
/// Solvability: (1) has a solution only for moderate steps. For a spin about
/// a principal axis it reads sin θ = h‖ω‖, so h‖ω‖ < 1 is necessary; beyond,
/// Newton fails and reports it. The Cayley variant below is solvable for
/// every h (its equation there is θ(1 + θ²/4) = h‖ω‖).
///
/// Torque-free, the LGVI conserves the kinetic energy exactly as well:
/// h Π_k = a J f + b f × J f and h Π_{k+1} = F_kᵀ h Π_k = a J f − b f × J f
/// have the same J⁻¹-norm, since f · (f × J f) = 0.
///
/// Cayley variant (LgviMap::kCayley; Kobilarov & Marsden, "Discrete geometric
/// optimal control on Lie groups", IEEE T-RO 27 (2011) §3–4): F = cay(f) and
/// L_d = (1/h) ½ fᵀ J f − (h/2)(U_k + U_{k+1}), a different (also second order,
/// symplectic, momentum-preserving) integrator whose implicit equation is a
/// polynomial, with no trigonometric function at all:
///   G(f) = J f + ½ f × J f + ¼ (fᵀ J f) f − r,
///   ∇G = J + ½ (f^ J − (J f)^) + ¼ ((fᵀ J f) I + 2 f (J f)ᵀ).
/// (Derivation: with δR = R η^, cay(f + δf) ≈ cay(f) exp(dcayRight(f) δf), the
/// stationarity of the action gives F_k μ_k = Π_k + (h/2) M_k with
/// μ_k = (1/h) dcayRight(f)⁻ᵀ J f, and F dcayRight(f)⁻ᵀ = dcayRight(f)⁻¹
/// = I + f^/2 + f fᵀ/4; the momentum update is the same as above.)
///
/// Translation (FreeBodyState): velocity Verlet, the variational integrator of
/// the trapezoidal discrete Lagrangian,
///   v_{k+½} = v_k + (h/2) F(t_k)/m,  p_{k+1} = p_k + h v_{k+½},
///   v_{k+1} = v_{k+½} + (h/2) F(t_{k+1})/m,   F = system.force(t).
///
/// Scalars: double, or ceres::Jet (branches compare the scalar with `<`, the
/// series below keep Jet derivatives right at θ = 0). For Jets the Newton loop
/// iterates until the value converges and then takes one more step: with the
/// exact Jacobian that step puts the derivative parts on the implicit-function
/// derivative −∇G⁻¹ ∂G/∂p. Fixed-size Eigen only: no allocation per step.
#pragma once

#include <array>
#include <cmath>
#include <sstream>
#include <limits>
#include <type_traits>

#include <Eigen/LU>

#include "integrators/rigid_body_state.hpp"
#include "integrators/step_report.hpp"
#include "liegroup/detail/series.hpp"
#include "liegroup/detail/so3_kernels.hpp"
#include "liegroup/so3.hpp"
#include "liegroup/number_text.hpp"

namespace lieflow {

/// The map from the Newton unknown f to the relative rotation F_k.
enum class LgviMap {
  kExponential,  ///< F = exp(f^): the LGVI of Lee, Leok & McClamroch.
  kCayley,       ///< F = cay(f): the Cayley variational integrator (Kobilarov–Marsden).
};

struct LgviOptions {
  /// Newton stops when ‖G(f)‖ ≤ tolerance · ‖h Π_k + (h²/2) M_k‖ + absolute_tolerance.
  double tolerance = 1e-14;
  /// Absolute floor of the stopping test (units of h × angular momentum, N·m·s²).
  /// It matters only when h Π_k + (h²/2) M_k is (nearly) zero, e.g. a body at rest.
  double absolute_tolerance = 1e-300;
  int max_iterations = 20;
  LgviMap map = LgviMap::kExponential;
};

namespace detail {

/// (d/dθ (sin θ/θ))/θ = (θ cos θ − sin θ)/θ³ = Σ_{n≥0} (−1)^{n+1} 2(n+1) θ^{2n}/(2n+3)!.
/// Series (n ≤ 9) for θ² < kLgviSincSlopeThetaSq = 1: the first term left out,
/// 22/23! = 9e-22, is 3e-21 of the value (≈ −0.30 at θ = 1). Above, (cos θ −
/// 2cs)/θ² with cos θ = c² − θ² s², which loses ~1.5 bits at θ = 1 and, beyond,
/// cancels only near the zeros of the function itself.
constexpr double kLgviSincSlopeThetaSq = 1.0;
constexpr std::array<double, 10> lgviSincSlopeSeries() {
  std::array<double, 10> coeff{};
  for (int n = 0; n < 10; ++n)
    coeff[n] = (n % 2 ? 1.0 : -1.0) * 2.0 * (n + 1) / factorial(2 * n + 3);
  return coeff;
}
template <typename T>
inline T lgviSincSlope(const T& theta_sq, const T& c, const T& s) {
  if (theta_sq < T(kLgviSincSlopeThetaSq)) return horner(theta_sq, lgviSincSlopeSeries());
  const T cos_theta = c * c - theta_sq * s * s;
  return (cos_theta - T(2.0) * c * s) / theta_sq;
}

/// (d/dθ ((1 − cos θ)/θ²))/θ = (θ sin θ − 2(1 − cos θ))/θ⁴
///   = Σ_{n≥0} (−1)^{n+1} 2(n+1) θ^{2n}/(2n+4)!.
/// Series (n ≤ 12) for θ² < kLgviVersineSlopeThetaSq = 4: the first term left
/// out, 28·4¹³/30! = 7e-24, is 1e-22 of the value (≈ −0.063 at θ = 2). Above,
/// 2s(c − 2s)/θ², which loses ~1.5 bits at θ = 2 (c − 2s = cos 1 − sin 1
/// there) and, beyond, cancels only near the zeros of the function itself.
constexpr double kLgviVersineSlopeThetaSq = 4.0;
constexpr std::array<double, 13> lgviVersineSlopeSeries() {
  std::array<double, 13> coeff{};
  for (int n = 0; n < 13; ++n)
    coeff[n] = (n % 2 ? 1.0 : -1.0) * 2.0 * (n + 1) / factorial(2 * n + 4);
  return coeff;
}
template <typename T>
inline T lgviVersineSlope(const T& theta_sq, const T& c, const T& s) {
  if (theta_sq < T(kLgviVersineSlopeThetaSq)) return horner(theta_sq, lgviVersineSlopeSeries());
  return T(2.0) * s * (c - T(2.0) * s) / theta_sq;
}

/// Rotations near the identity are carried as increments 1 + (w − 1, v) with
/// w − 1 computed to full relative accuracy, and applied as q + q ⊗ (w − 1, v).
/// Why: a step multiplies R by a unit quaternion whose norm is 1 only to
/// rounding, and for a steady motion (θ, hence the rounding, the same at every
/// step) that error is the same at every step and drifts linearly (measured:
/// |R Π| off by 1e-10 after 10⁶ steps). In increment form the norm error of
/// the factor is O(ε θ²) instead of O(ε), and what remains is a random walk.
///
/// w − 1 of a unit quaternion (w, v), ‖v‖² = v_sq: −‖v‖²/(1 + w) for w ≥ 0
/// (1 − w = (1 − w²)/(1 + w), no cancellation), w − 1 itself for w < 0.
template <typename T>
inline T quaternionRealMinusOne(const T& w, const T& v_sq) {
  if (w < T(0)) return w - T(1);
  return -v_sq / (T(1) + w);
}

/// q ⊗ (1 + (dw, dv)) = q + q ⊗ (dw, dv), with the Hamilton product
/// q ⊗ (dw, dv) = (q_w dw − q_v·dv, q_w dv + dw q_v + q_v × dv).
template <typename T>
inline Eigen::Quaternion<T> composeNearIdentity(const Eigen::Quaternion<T>& q, const T& dw,
                                               const Vector3<T>& dv) {
  const Vector3<T> qv = q.vec();
  const Vector3<T> v = qv + (q.w() * dv + dw * qv + qv.cross(dv));
  return Eigen::Quaternion<T>(q.w() + (q.w() * dw - qv.dot(dv)), v.x(), v.y(), v.z());
}

/// The type in which solveInertia forms its residual: x87 extended precision
/// for double where long double is that (x86), double for float, and the
/// scalar itself otherwise (ceres::Jet, or where long double is no wider).
template <typename T>
struct ResidualScalar {
  using type = T;
};
template <>
struct ResidualScalar<double> {
  using type = std::conditional_t<std::numeric_limits<long double>::digits == 64, long double,
                                  double>;
};
template <>
struct ResidualScalar<float> {
  using type = double;
};

/// ω = J⁻¹ Π, to within a fraction of an ulp: ω₀ = J⁻¹ Π, then one step of
/// iterative refinement ω = ω₀ + J⁻¹(Π − J ω₀) with the residual in wider
/// precision. Why: every step does the round trip Π = J ω → ω = J⁻¹ Π, and
/// the stored J⁻¹ is J's inverse only to a fixed rounding error, which that
/// round trip would accumulate linearly (measured on a free body, 10⁶ steps:
/// ‖R Π‖ drifts by 1e-10 with ω₀ alone, 3e-12 with the refinement in double,
/// and only by rounding, a random walk of 1e-13, with the residual in long
/// double). Costs ~10 ns.
template <typename T>
inline Vector3<T> solveInertia(const Matrix3<T>& J, const Matrix3<T>& J_inv, const Vector3<T>& Pi) {
  using W = typename ResidualScalar<T>::type;
  const Vector3<T> omega = J_inv * Pi;
  if constexpr (std::is_same<W, T>::value) {
    return omega + J_inv * (Pi - J * omega);
  } else {
    const Eigen::Matrix<W, 3, 1> residual =
        Pi.template cast<W>() - J.template cast<W>() * omega.template cast<W>();
    return (omega.template cast<W>() + J_inv.template cast<W>() * residual).template cast<T>();
  }
}

/// G(f) = (sin θ/θ) J f + ((1 − cos θ)/θ²) f × J f − r and its Jacobian, for
/// F = exp(f^) (Lee, Leok & McClamroch 2005, eq. (16) in vector form).
template <typename T>
class LgviExpEquation {
 public:
  LgviExpEquation(const Matrix3<T>& J, const Vector3<T>& rhs) : J_(J), rhs_(rhs) {}

  /// Third-order predictor: G(f) = J f + ½ f × J f − (θ²/6) J f − r + O(θ⁴),
  /// so one fixed-point pass f = J⁻¹(r − ½ f₀ × J f₀) + (θ₀²/6) f₀ from the
  /// second-order f₀ leaves an O(θ⁴) error, and one Newton step usually suffices.
  Vector3<T> predictor(const Matrix3<T>& J_inv, const Vector3<T>& f0) const {
    return J_inv * (rhs_ - T(0.5) * f0.cross(J_ * f0)) + (f0.squaredNorm() * T(1.0 / 6.0)) * f0;
  }

  /// Evaluates G(f) and keeps what the Jacobian and the rotation need.
  Vector3<T> residual(const Vector3<T>& f) {
    theta_sq_ = f.squaredNorm();
    halfAngle(theta_sq_, &c_, &s_);
    a_ = T(2.0) * c_ * s_;
    b_ = T(2.0) * s_ * s_;
    Jf_ = J_ * f;
    f_x_Jf_ = f.cross(Jf_);
    return a_ * Jf_ + b_ * f_x_Jf_ - rhs_;
  }

  /// ∇G at the f of the last residual() call.
  Matrix3<T> jacobian(const Vector3<T>& f) const {
    const T da = lgviSincSlope(theta_sq_, c_, s_);
    const T db = lgviVersineSlope(theta_sq_, c_, s_);
    return (da * Jf_ + db * f_x_Jf_) * f.transpose() + a_ * J_ +
           b_ * (SO3<T>::hat(f) * J_ - SO3<T>::hat(Jf_));
  }

  /// exp(f^) = (c, s f) = 1 + (c − 1, s f) at the f of the last residual() call.
  void increment(const Vector3<T>& f, T* w_minus_one, Vector3<T>* vec) const {
    *vec = s_ * f;
    *w_minus_one = quaternionRealMinusOne(c_, vec->squaredNorm());
  }

 private:
  const Matrix3<T>& J_;
  const Vector3<T>& rhs_;
  T theta_sq_, c_, s_, a_, b_;
  Vector3<T> Jf_, f_x_Jf_;
};

/// G(f) = J f + ½ f × J f + ¼ (fᵀ J f) f − r and its Jacobian, for F = cay(f^)
/// (the Cayley variational integrator; see the file comment).
template <typename T>
class LgviCayleyEquation {
 public:
  LgviCayleyEquation(const Matrix3<T>& J, const Vector3<T>& rhs) : J_(J), rhs_(rhs) {}

  /// Third-order predictor: one fixed-point pass of f = J⁻¹(r − ½ f × J f −
  /// ¼ (fᵀ J f) f) from the second-order f₀ (error O(θ⁴)).
  Vector3<T> predictor(const Matrix3<T>& J_inv, const Vector3<T>& f0) const {
    const Vector3<T> Jf0 = J_ * f0;
    return J_inv * (rhs_ - T(0.5) * f0.cross(Jf0) - (T(0.25) * f0.dot(Jf0)) * f0);
  }

  Vector3<T> residual(const Vector3<T>& f) {
    Jf_ = J_ * f;
    fJf_ = f.dot(Jf_);
    return Jf_ + T(0.5) * f.cross(Jf_) + (T(0.25) * fJf_) * f - rhs_;
  }

  Matrix3<T> jacobian(const Vector3<T>& f) const {
    return J_ + T(0.5) * (SO3<T>::hat(f) * J_ - SO3<T>::hat(Jf_)) +
           (T(0.25) * fJf_) * Matrix3<T>::Identity() + (T(0.5) * f) * Jf_.transpose();
  }

  /// cay(f) = (1, f/2)/n, n = √(1 + θ²/4) (liegroup/cayley.hpp), as 1 + (1/n − 1, f/(2n)).
  void increment(const Vector3<T>& f, T* w_minus_one, Vector3<T>* vec) const {
    using std::sqrt;
    const T inv_n = T(1) / sqrt(T(1) + T(0.25) * f.squaredNorm());
    *vec = (T(0.5) * inv_n) * f;
    *w_minus_one = quaternionRealMinusOne(inv_n, vec->squaredNorm());
  }

 private:
  const Matrix3<T>& J_;
  const Vector3<T>& rhs_;
  T fJf_;
  Vector3<T> Jf_;
};

/// Translation of a rotation-only body: nothing to do.
template <typename System, typename T>
inline void velocityVerletTranslation(const System&, const T&, const RotorState<T>&, const T&,
                                      RotorState<T>*) {}

/// Velocity Verlet for the centre of mass (world frame), force F = system.force(t):
///   v_{k+½} = v_k + (h/2) F(t_k)/m,  p_{k+1} = p_k + h v_{k+½},
///   v_{k+1} = v_{k+½} + (h/2) F(t_{k+1})/m.
template <typename System, typename T>
inline void velocityVerletTranslation(const System& system, const T& t, const FreeBodyState<T>& y,
                                      const T& h, FreeBodyState<T>* out) {
  const T half_h_over_m = T(0.5) * h / system.mass();
  const Vector3<T> v_half = y.v + half_h_over_m * system.force(t);
  out->p = y.p + h * v_half;
  out->v = v_half + half_h_over_m * system.force(t + h);
}

}  // namespace detail

/// The solution of one LGVI implicit equation (1): the Newton unknown f and
/// the relative rotation F_k = 1 + (w_minus_one, vec) as a quaternion (exp(f^)
/// or cay(f), by LgviOptions::map), with the Newton statistics.
template <typename T>
struct LgviSolution {
  Vector3<T> f;     ///< the last Newton iterate
  T w_minus_one;    ///< F_k's quaternion is (1 + w_minus_one, vec)
  Vector3<T> vec;
  int iterations = 0;     ///< Newton corrections
  double residual = 0.0;  ///< ‖G(f)‖ at the last iterate
  double threshold = 0.0; ///< the stopping test ‖G‖ ≤ threshold that was applied
  bool converged = false;
};

namespace detail {

/// Newton's method on G(f) = 0 (see the file comment) from the third-order
/// predictor; the stopping test and the extra Jet step are those of
/// LgviStepper.
template <typename T, typename Equation>
LgviSolution<T> solveLgviNewton(Equation* equation, const Matrix3<T>& J_inv, const Vector3<T>& rhs,
                                const LgviOptions& options) {
  constexpr bool kPlainFloat = std::is_floating_point<T>::value;
  auto norm = [](const Vector3<T>& v) { return std::sqrt(scalarValue(v.squaredNorm())); };
  const double threshold = options.tolerance * norm(rhs) + options.absolute_tolerance;
  // Predictors: f₁ = J⁻¹ r (first order), f₀ = f₁ − ½ J⁻¹(f₁ × r) (second
  // order, since J f₁ = r), then the map's third-order predictor.
  const Vector3<T> f1 = J_inv * rhs;
  LgviSolution<T> out;
  Vector3<T>& f = out.f;
  f = equation->predictor(J_inv, f1 - T(0.5) * (J_inv * f1.cross(rhs)));
  Vector3<T> G = equation->residual(f);
  double residual = norm(G);
  int iterations = 0;
  while (!(residual <= threshold) && iterations < options.max_iterations) {
    f -= equation->jacobian(f).inverse() * G;
    ++iterations;
    G = equation->residual(f);
    residual = norm(G);
  }
  const bool converged = residual <= threshold;
  if (!kPlainFloat && converged) {
    // Derivative parts: one more Newton step on the converged value.
    f -= equation->jacobian(f).inverse() * G;
    ++iterations;
    G = equation->residual(f);
    residual = norm(G);
  }
  out.iterations = iterations;
  out.residual = residual;
  out.threshold = threshold;
  out.converged = converged;
  equation->increment(f, &out.w_minus_one, &out.vec);
  return out;
}

}  // namespace detail

/// Solves the LGVI equation (1), h Π^ + (h²/2) M^ = F J_d − J_d Fᵀ, for the
/// relative rotation F (exp or Cayley map by options.map), given J, J⁻¹ and
/// rhs = h Π + (h²/2) M (Lee, Leok & McClamroch 2005, eq. (16)). Shared by
/// LgviStepper and the constrained LGVI (integrators/constrained_lgvi.hpp).
template <typename T>
LgviSolution<T> solveLgviEquation(const Matrix3<T>& J, const Matrix3<T>& J_inv, const Vector3<T>& rhs,
                                  const LgviOptions& options) {
  if (options.map == LgviMap::kCayley) {
    detail::LgviCayleyEquation<T> equation(J, rhs);
    return detail::solveLgviNewton(&equation, J_inv, rhs, options);
  }
  detail::LgviExpEquation<T> equation(J, rhs);
  return detail::solveLgviNewton(&equation, J_inv, rhs, options);
}

/// One body's rotational step of the LGVI (Lee, Leok & McClamroch 2007,
/// eqs. (1)–(2)), the method's one implementation: LgviStepper steps a free
/// body with it, and the multibody RATTLE (integrators/constrained_lgvi.hpp)
/// every body of a mechanism, the joints' reactions entering as impulses.
///   kick    Π⁺ = J ω_k + I_k,            I_k = (h/2) τ_k  (− (h/2) G_θᵀλ),
///   drift   h Π⁺^ = F J_d − J_d Fᵀ       (F = F_k, the relative rotation),
///   kick    ω_{k+1} = J⁻¹ (F_kᵀ Π⁺ + I_{k+1}),  I_{k+1} = (h/2) τ_{k+1} (− (h/2) G_θᵀμ).
/// R_{k+1} = R_k F_k is the caller's (a quaternion product near the identity
/// for a free body, the state's ⊕ of log F_k in a mechanism).
template <typename T>
struct LgviBodyDrift {
  Vector3<T> Pi_plus;        ///< Π⁺, the body-frame momentum after the first kick
  LgviSolution<T> solution;  ///< F_k = (1 + w_minus_one, vec) and the Newton statistics

  Eigen::Quaternion<T> F() const {
    return Eigen::Quaternion<T>(T(1) + solution.w_minus_one, solution.vec.x(), solution.vec.y(), solution.vec.z());
  }
};

/// The first kick and the drift (see LgviBodyDrift) from the body rate ω_k
/// and the half-step impulse I_k (body frame; null: none).
template <typename T>
void lgviKickDrift(const Matrix3<T>& J, const Matrix3<T>& J_inv, const Vector3<T>& omega, const Vector3<T>* impulse,
                   const T& h, const LgviOptions& options, LgviBodyDrift<T>* out) {
  out->Pi_plus.noalias() = J * omega;
  if (impulse) out->Pi_plus += *impulse;
  out->solution = solveLgviEquation(J, J_inv, Vector3<T>(h * out->Pi_plus), options);
}

/// The second kick: ω_{k+1} = J⁻¹ (F_kᵀ Π⁺ + I_{k+1}) (see LgviBodyDrift;
/// impulse null: none).
template <typename T>
Vector3<T> lgviEndKick(const Matrix3<T>& J, const Matrix3<T>& J_inv, const LgviBodyDrift<T>& drift,
                       const Vector3<T>* impulse) {
  Vector3<T> Pi = drift.F().conjugate() * drift.Pi_plus;
  if (impulse) Pi += *impulse;
  return detail::solveInertia(J, J_inv, Pi);
}

/// The LGVI stepper for RotorState and FreeBodyState, on any System with
/// `inertia()`, `inertiaInverse()`, `hasExternalTorque()`,
/// `externalTorque(t, R)` (body frame) and, for FreeBodyState, `mass()` and
/// `force(t)` (world frame): RotorSystem and FreeBodySystem.
template <typename State>
class LgviStepper {
 public:
  using Scalar = typename State::Scalar;
  static constexpr int kOrder = 2;

  explicit LgviStepper(LgviOptions options = {}) : options_(options) {}

  const LgviOptions& options() const { return options_; }

  /// One step of size h from (t, y). The report (reset at entry) receives the
  /// Newton iterations and the final residual norm ‖G(f)‖; on non-convergence
  /// report->fail("LGVI Newton did not converge", ‖G‖) is called and the step
  /// is still completed with the last iterate.
  template <typename System>
  State step(const System& system, const Scalar& t, const State& y, const Scalar& h,
             StepReport* report = nullptr) const {
    using T = Scalar;
    if (report) *report = StepReport{};
    const Matrix3<T>& J = system.inertia();
    const Matrix3<T>& J_inv = system.inertiaInverse();
    const bool torqued = system.hasExternalTorque();

    // Π⁺ = Π_k + (h/2) M_k; F_k from (1), whose right-hand side is h Π⁺.
    LgviBodyDrift<T> drift;
    if (torqued) {
      const Vector3<T> half_torque = (T(0.5) * h) * system.externalTorque(t, y.R);
      lgviKickDrift(J, J_inv, y.omega, &half_torque, h, options_, &drift);
    } else {
      lgviKickDrift<T>(J, J_inv, y.omega, nullptr, h, options_, &drift);
    }
    const LgviSolution<T>& solution = drift.solution;
    if (report) {
      report->newton_iterations = solution.iterations;
      report->residual = solution.residual;
      if (!solution.converged) {
        report->fail("LGVI Newton did not converge", solution.residual);
        // The residual against the test that was applied (relative to
        // ‖hΠ‖), and the step's rotation angle, which says why.
        std::ostringstream why;
        why << "|G| = " << formatNumber(scalarValue(solution.residual)) << " above the tolerance " << options_.tolerance
            << " x |h Pi| = " << formatNumber(scalarValue(solution.threshold)) << " after " << solution.iterations
            << " Newton iterations; h|omega| = " << formatNumber(scalarValue((J_inv * (h * drift.Pi_plus)).norm()))
            << (options_.map == LgviMap::kExponential
                    ? " (the exponential-map equation has no solution for h|omega| >= 1 about a principal axis: "
                      "use a smaller step or `options` cayley=1)"
                    : "");
        report->detail = why.str();
      }
    }

    State out = y;
    out.R = SO3<T>(detail::composeNearIdentity(y.R.quaternion(), solution.w_minus_one, solution.vec));
    // Π_{k+1} = F_kᵀ Π⁺ + (h/2) M_{k+1}.
    if (torqued) {
      const Vector3<T> half_torque_end = (T(0.5) * h) * system.externalTorque(t + h, out.R);
      out.omega = lgviEndKick(J, J_inv, drift, &half_torque_end);
    } else {
      out.omega = lgviEndKick<T>(J, J_inv, drift, nullptr);
    }
    detail::velocityVerletTranslation(system, t, y, h, &out);
    return out;
  }

 private:
  LgviOptions options_;
};

}  // namespace lieflow
