/// \file
/// The Lie-group generalized-α method (Brüls, Cardona & Arnold 2012, "Lie group
/// generalized-α time integration of constrained flexible multibody systems",
/// Mech. Mach. Theory 48, 121–137, Algorithm 1 without constraints; the
/// vector-space method is Chung & Hulbert 1993, J. Appl. Mech. 60, 371–375, in
/// the form of Arnold & Brüls 2007, Multibody Syst. Dyn. 18, 185–202).
///
/// ## Second-order systems
/// The method integrates
///     M(q) v̇ + g(q, v, t) = 0,     q̇ = q · v   (right trivialization),
/// with q on a Lie group G of dimension n and the velocity v ∈ ℝⁿ, on a State
/// whose Tangent is lieflow's [δq (n); δv (n)]. A system plugs in through two
/// traits, specialized here for RotorSystem, FreeBodySystem and
/// LinearSecondOrderSystem (integrators/vector_state.hpp); a new system
/// specializes them next to its own definition:
///
///   SecondOrderStateTraits<State>: the geometry of the state.
///     using Scalar; using State; static constexpr int kDof = n;
///     using Vector = Eigen::Matrix<Scalar, n, 1>; using Matrix = …<Scalar, n, n>;
///     static Vector velocity(const State& y);                       // v
///     static State advance(const State& y, const Vector& dq, const Vector& v);
///                                  // (q exp(dq), v): the configuration moved
///                                  // on the right, the velocity replaced
///     static Matrix tangentOperator(const Vector& dq);                // T(dq)
///                                  // q exp(dq + δ) ≈ q exp(dq) exp(T(dq) δ):
///                                  // Jr on rotation blocks, I on vector blocks
///     static bool identical(const State& a, const State& b);
///                                  // exact equality (values and, for Jets,
///                                  // derivative parts)
///
///   SecondOrderSystemTraits<System>: the equations of motion.
///     using Scalar; using State; using Vector; using Matrix;   (as above)
///     static void evaluate(const System& s, const Scalar& t, const State& y,
///                          Matrix* M, Vector* g, Matrix* Ct, Matrix* Kt);
///         M and g always; when Ct (Kt) is non-null, the tangent damping
///         C_t = ∂g/∂v (tangent stiffness K_t = ∂g/∂δq for the right
///         perturbation q exp(δq)). If M depends on q, K_t should include
///         ∂(M v̇)/∂δq; leaving it out costs Newton iterations, not accuracy.
///
/// Rigid bodies (integrators/rigid_body_system.hpp):
///   RotorSystem (q = R, v = ω):  M = J,  g = ω × Jω − τ(t, R),
///     C_t = ω^ J − (Jω)^,  K_t = −∂τ/∂δθ = −torqueJacobian,  T = Jr.
///   FreeBodySystem (q = (p, R), v = (v_world, ω_body)): adds m v̇ − F(t) = 0,
///     M = diag(m I, J), g = (−F(t), ω × Jω − τ), T = diag(I, Jr).
///
/// ## The method (BCA 2012, Alg. 1)
/// Parameters from the spectral radius at infinity ρ∞ ∈ [0, 1] (Chung &
/// Hulbert 1993): α_m = (2ρ∞ − 1)/(ρ∞ + 1), α_f = ρ∞/(ρ∞ + 1),
/// γ = ½ + α_f − α_m, β = ¼(γ + ½)². ρ∞ = 1 has no numerical dissipation;
/// ρ∞ < 1 damps the modes with hω ≫ 1 by the factor ρ∞ per step.
/// The stepper carries, besides y_n = (q_n, v_n), the acceleration v̇_n and the
/// auxiliary acceleration a_n defined by
///     (1 − α_m) a_{n+1} + α_m a_n = (1 − α_f) v̇_{n+1} + α_f v̇_n.
/// One step from t_n to t_{n+1} = t_n + h:
///   predictor  v̇ = 0,  a = (α_f v̇_n − α_m a_n)/(1 − α_m),
///              v = v_n + h(1 − γ) a_n + hγ a,
///              Δq = v_n + h(½ − β) a_n + hβ a,   q = q_n exp(hΔq);
///   Newton     r = M v̇ + g(q, v, t_{n+1}),
///              S_t = β' M + γ' C_t + K_t T(hΔq),
///              β' = (1 − α_m)/(h²β(1 − α_f)),  γ' = γ/(hβ),
///              ΔΔ = −S_t⁻¹ r;  Δq += ΔΔ/h, v += γ'ΔΔ, v̇ += β'ΔΔ,
///              q = q_n exp(hΔq);  until ‖r‖ is small (below);
///   update     a_{n+1} = a + (1 − α_f)/(1 − α_m) v̇_{n+1}.
/// S_t is the exact derivative of r with respect to ΔΔ, so Newton converges
/// quadratically. The method is second order in q and v (Arnold, Brüls &
/// Cardona 2015, Numer. Math. 129, "Error analysis of generalized-α Lie group
/// time integration methods for constrained mechanical systems").
///
/// ## Stopping test
/// ‖r‖∞ ≤ tolerance · max(‖M v̇‖∞, ‖g‖∞) + absolute_tolerance (relative to the
/// inertia force and to the applied and gyroscopic force), or a correction at
/// the rounding level of the increment, ‖ΔΔ‖∞ ≤ 8ε‖hΔq‖∞. The second test ends
/// the iteration when rounding keeps the residual above the first: when M v̇
/// and g nearly cancel while their parts do not (steady precession, v̇ ≈ 0),
/// or when the Newton corrections were much larger than the converged
/// increment (hω ≫ 1, where the predictor v̇ = 0 is far off).
/// With a Jet scalar one more Newton correction follows the residual test:
/// the derivative parts of a Newton iterate lag the values by one iteration.
/// Failure (iteration limit, non-finite residual) is reported through
/// StepReport::fail and lastReport(), never silently; the failed step is not
/// committed, so a retry from the same y (say with a smaller h) reuses the
/// carried accelerations.
///
/// ## State between steps
/// `step` calls `reset(system, t, y)` (v̇ = −M⁻¹ g(q, v, t), a = v̇) when the
/// stepper has no history or when the incoming y is not exactly the last
/// output: a stepper continued from its own output keeps its history, any
/// other start is consistent. Call `reset` yourself after changing the system
/// between steps (parameters, forces) or to restart at the same y;
/// `setHistory` sets (y, v̇, a) explicitly (perturbed starting values, the
/// amplification matrix). a_n approximates v̇(t_n + (α_m − α_f)h) to O(h²)
/// (Arnold & Brüls 2007, §3), so changing h between steps perturbs a_n by
/// O(Δh), as an inconsistent start would; the stepper keeps a_n as it is.
///
/// Fixed-size Eigen throughout: no heap allocation per step for the rigid-body
/// states. Templated on the scalar (double, ceres::Jet).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>
#include <utility>

#include <Eigen/Core>
#include <Eigen/LU>

#include "integrators/rigid_body_state.hpp"
#include "integrators/rigid_body_system.hpp"
#include "integrators/step_report.hpp"
#include "integrators/vector_state.hpp"
#include "liegroup/invalid_input.hpp"
#include "liegroup/scalar.hpp"
#include "liegroup/so3.hpp"

namespace lieflow {

/// The geometry of a state for second-order steppers (see the file comment).
template <class State>
struct SecondOrderStateTraits;

/// The equations of motion M v̇ + g = 0 of a system (see the file comment).
template <class System>
struct SecondOrderSystemTraits;

namespace detail {

/// True for scalars with a value part `.a` and a derivative part `.v`
/// (ceres::Jet), detected without including Ceres.
template <typename T, typename = void>
struct HasDerivativePart : std::false_type {};
template <typename T>
struct HasDerivativePart<T, std::void_t<decltype(std::declval<const T&>().a),
                                        decltype(std::declval<const T&>().v)>>
    : std::true_type {};

/// Exact equality of two scalars, derivative parts included.
template <typename T>
bool identicalScalar(const T& a, const T& b) {
  if constexpr (HasDerivativePart<T>::value) {
    return a.a == b.a && (a.v.array() == b.v.array()).all();
  } else {
    return a == b;
  }
}

/// Exact equality of two coefficient arrays of the same size.
template <typename A, typename B>
bool identicalCoefficients(const Eigen::DenseBase<A>& a, const Eigen::DenseBase<B>& b) {
  if (a.size() != b.size()) return false;
  for (Eigen::Index i = 0; i < a.size(); ++i)
    if (!identicalScalar(a.derived().coeff(i), b.derived().coeff(i))) return false;
  return true;
}

/// max |xᵢ| of the value parts; NaN if any entry is NaN (so that a stopping
/// test `residual <= bound` fails on it).
template <typename Derived>
double maxAbsValue(const Eigen::MatrixBase<Derived>& x) {
  double m = 0.0;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    const double v = std::abs(scalarValue(x.derived().coeff(i)));
    if (std::isnan(v)) return std::numeric_limits<double>::quiet_NaN();
    m = std::max(m, v);
  }
  return m;
}

}  // namespace detail

// ---- state geometry ----------------------------------------------------------

/// RotorState: q = R ∈ SO(3), v = ω (body frame).
template <typename T>
struct SecondOrderStateTraits<RotorState<T>> {
  using Scalar = T;
  using State = RotorState<T>;
  static constexpr int kDof = 3;
  using Vector = Vector3<T>;
  using Matrix = Matrix3<T>;

  static Vector velocity(const State& y) { return y.omega; }
  static State advance(const State& y, const Vector& dq, const Vector& v) {
    return {y.R * SO3<T>::exp(dq), v};
  }
  static Matrix tangentOperator(const Vector& dq) { return SO3<T>::Jr(dq); }
  static bool identical(const State& a, const State& b) {
    return detail::identicalCoefficients(a.R.quaternion().coeffs(), b.R.quaternion().coeffs()) &&
           detail::identicalCoefficients(a.omega, b.omega);
  }
};

/// FreeBodyState: q = (p, R) ∈ ℝ³ × SO(3), v = (v_world, ω_body); δq = (δp, δθ).
template <typename T>
struct SecondOrderStateTraits<FreeBodyState<T>> {
  using Scalar = T;
  using State = FreeBodyState<T>;
  static constexpr int kDof = 6;
  using Vector = Vector6<T>;
  using Matrix = Matrix6<T>;

  static Vector velocity(const State& y) {
    Vector v;
    v << y.v, y.omega;
    return v;
  }
  static State advance(const State& y, const Vector& dq, const Vector& v) {
    return {y.R * SO3<T>::exp(dq.template tail<3>()), y.p + dq.template head<3>(),
            v.template tail<3>(), v.template head<3>()};
  }
  static Matrix tangentOperator(const Vector& dq) {
    Matrix Tm = Matrix::Identity();
    Tm.template bottomRightCorner<3, 3>() = SO3<T>::Jr(dq.template tail<3>());
    return Tm;
  }
  static bool identical(const State& a, const State& b) {
    return detail::identicalCoefficients(a.R.quaternion().coeffs(), b.R.quaternion().coeffs()) &&
           detail::identicalCoefficients(a.p, b.p) &&
           detail::identicalCoefficients(a.omega, b.omega) &&
           detail::identicalCoefficients(a.v, b.v);
  }
};

/// VectorState: q = x ∈ ℝᴺ (exp = identity, T = I), v = ẋ.
template <typename T, int N>
struct SecondOrderStateTraits<VectorState<T, N>> {
  using Scalar = T;
  using State = VectorState<T, N>;
  static constexpr int kDof = N;
  using Vector = Eigen::Matrix<T, N, 1>;
  using Matrix = Eigen::Matrix<T, N, N>;

  static Vector velocity(const State& y) { return y.v; }
  static State advance(const State& y, const Vector& dq, const Vector& v) {
    return {y.x + dq, v};
  }
  static Matrix tangentOperator(const Vector& /*dq*/) { return Matrix::Identity(); }
  static bool identical(const State& a, const State& b) {
    return detail::identicalCoefficients(a.x, b.x) && detail::identicalCoefficients(a.v, b.v);
  }
};

// ---- equations of motion -------------------------------------------------------

/// J ω̇ + ω × Jω − τ(t, R) = 0.
template <typename T>
struct SecondOrderSystemTraits<RotorSystem<T>> {
  using Scalar = T;
  using State = RotorState<T>;
  using Vector = Vector3<T>;
  using Matrix = Matrix3<T>;

  static void evaluate(const RotorSystem<T>& s, const T& t, const State& y, Matrix* M, Vector* g,
                       Matrix* Ct, Matrix* Kt) {
    const Matrix3<T>& J = s.inertia();
    const Vector3<T> Jw = J * y.omega;
    *M = J;
    *g = y.omega.cross(Jw) - s.externalTorque(t, y.R);
    // ∂(ω × Jω)/∂ω = ω^ J − (Jω)^.
    if (Ct) *Ct = SO3<T>::hat(y.omega) * J - SO3<T>::hat(Jw);
    if (Kt) *Kt = -s.torqueJacobian(t, y.R);
  }
};

/// m v̇ − F(t) = 0 (world frame) and J ω̇ + ω × Jω − τ(t, R) = 0 (body frame).
template <typename T>
struct SecondOrderSystemTraits<FreeBodySystem<T>> {
  using Scalar = T;
  using State = FreeBodyState<T>;
  using Vector = Vector6<T>;
  using Matrix = Matrix6<T>;

  static void evaluate(const FreeBodySystem<T>& s, const T& t, const State& y, Matrix* M,
                       Vector* g, Matrix* Ct, Matrix* Kt) {
    const Matrix3<T>& J = s.inertia();
    const Vector3<T> Jw = J * y.omega;
    M->setZero();
    M->template topLeftCorner<3, 3>() = s.mass() * Matrix3<T>::Identity();
    M->template bottomRightCorner<3, 3>() = J;
    g->template head<3>() = -s.force(t);
    g->template tail<3>() = y.omega.cross(Jw) - s.externalTorque(t, y.R);
    if (Ct) {
      Ct->setZero();
      Ct->template bottomRightCorner<3, 3>() = SO3<T>::hat(y.omega) * J - SO3<T>::hat(Jw);
    }
    if (Kt) {
      Kt->setZero();
      Kt->template bottomRightCorner<3, 3>() = -s.torqueJacobian(t, y.R);
    }
  }
};

/// M ẍ + C ẋ + K x − f(t) = 0.
template <typename T, int N>
struct SecondOrderSystemTraits<LinearSecondOrderSystem<T, N>> {
  using Scalar = T;
  using State = VectorState<T, N>;
  using Vector = Eigen::Matrix<T, N, 1>;
  using Matrix = Eigen::Matrix<T, N, N>;

  static void evaluate(const LinearSecondOrderSystem<T, N>& s, const T& t, const State& y,
                       Matrix* M, Vector* g, Matrix* Ct, Matrix* Kt) {
    *M = s.mass();
    *g = s.damping() * y.v + s.stiffness() * y.x - s.load(t);
    if (Ct) *Ct = s.damping();
    if (Kt) *Kt = s.stiffness();
  }
};

// ---- the stepper ---------------------------------------------------------------

struct GeneralizedAlphaOptions {
  /// Spectral radius at infinity, in [0, 1]: 1 non-dissipative, 0 annihilates
  /// the modes with hω → ∞ in one step.
  double rho_inf = 1.0;
  /// Relative residual of the Newton iteration (see "Stopping test").
  double tolerance = 1e-12;
  /// Absolute residual floor, in the units of the residual (N, N·m). The
  /// rounding-level test on the correction (see "Stopping test") makes a
  /// positive floor unnecessary for a problem with a well-scaled residual.
  double absolute_tolerance = 0.0;
  /// Newton corrections allowed per step (≥ 1).
  int max_iterations = 20;
};

/// α_m, α_f, γ, β of Chung & Hulbert 1993, eqs. (25), (17), (20).
struct GeneralizedAlphaCoefficients {
  double alpha_m = 0.5;
  double alpha_f = 0.5;
  double gamma = 0.5;
  double beta = 0.25;

  static GeneralizedAlphaCoefficients fromRhoInf(double rho_inf) {
    GeneralizedAlphaCoefficients c;
    c.alpha_m = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0);
    c.alpha_f = rho_inf / (rho_inf + 1.0);
    c.gamma = 0.5 + c.alpha_f - c.alpha_m;
    c.beta = 0.25 * (c.gamma + 0.5) * (c.gamma + 0.5);
    return c;
  }
};

/// The Lie-group generalized-α stepper for a State with
/// SecondOrderStateTraits<State>. Stateful: see "State between steps".
template <typename State>
class GeneralizedAlphaStepper {
 public:
  using Scalar = typename State::Scalar;
  using Geometry = SecondOrderStateTraits<State>;
  static constexpr int kDof = Geometry::kDof;
  using Vector = Eigen::Matrix<Scalar, kDof, 1>;
  using Matrix = Eigen::Matrix<Scalar, kDof, kDof>;
  static constexpr int kOrder = 2;
  /// A Newton correction with ‖ΔΔ‖∞ ≤ kRoundingFloor · ε · ‖hΔq‖∞ is at the
  /// rounding level of the increment: the iteration has converged.
  static constexpr double kRoundingFloor = 8.0;

  static_assert(2 * kDof == State::kTangentDim,
                "SecondOrderStateTraits: the tangent must be [δq (n); δv (n)]");

  /// Throws InvalidInput for ρ∞ ∉ [0, 1], a negative or non-finite tolerance,
  /// or max_iterations < 1.
  explicit GeneralizedAlphaStepper(GeneralizedAlphaOptions options = {})
      : options_(options), c_(GeneralizedAlphaCoefficients::fromRhoInf(options.rho_inf)) {
    if (!(options.rho_inf >= 0.0 && options.rho_inf <= 1.0))
      throw InvalidInput("rho_inf", "must be in [0, 1]");
    if (!(options.tolerance >= 0.0 && std::isfinite(options.tolerance)))
      throw InvalidInput("tolerance", "must be finite and non-negative");
    if (!(options.absolute_tolerance >= 0.0 && std::isfinite(options.absolute_tolerance)))
      throw InvalidInput("absolute_tolerance", "must be finite and non-negative");
    if (options.max_iterations < 1) throw InvalidInput("max_iterations", "must be at least 1");
  }

  const GeneralizedAlphaOptions& options() const { return options_; }
  const GeneralizedAlphaCoefficients& coefficients() const { return c_; }
  int order() const { return kOrder; }

  /// Start at (t0, y0) with consistent accelerations: v̇₀ = −M⁻¹ g, a₀ = v̇₀.
  template <class System>
  void reset(const System& system, const Scalar& t0, const State& y0) {
    using Dynamics = SecondOrderSystemTraits<System>;
    static_assert(std::is_same<typename Dynamics::State, State>::value,
                  "SecondOrderSystemTraits<System>::State differs from the stepper's State");
    Matrix M;
    Vector g;
    Dynamics::evaluate(system, t0, y0, &M, &g, nullptr, nullptr);
    const Vector vdot0 = -M.partialPivLu().solve(g);
    setHistory(y0, vdot0, vdot0);
    ++resets_;
  }

  /// Set the history explicitly: the next step from exactly y uses v̇_n = vdot
  /// and a_n = a.
  void setHistory(const State& y, const Vector& vdot, const Vector& a) {
    last_ = y;
    vdot_ = vdot;
    a_ = a;
    initialized_ = true;
  }

  bool initialized() const { return initialized_; }
  /// v̇_n and a_n of the last committed step (or of the last reset).
  const Vector& acceleration() const { return vdot_; }
  const Vector& auxiliaryAcceleration() const { return a_; }
  /// The report of the last step (also written to `report` when given).
  const StepReport& lastReport() const { return last_report_; }
  /// How many times the history was (re)initialized by reset().
  int resetCount() const { return resets_; }

  /// One step of size h from (t, y); see the file comment for the algorithm.
  template <class System>
  State step(const System& system, const Scalar& t, const State& y, const Scalar& h,
             StepReport* report = nullptr) {
    using Dynamics = SecondOrderSystemTraits<System>;
    static_assert(std::is_same<typename Dynamics::State, State>::value,
                  "SecondOrderSystemTraits<System>::State differs from the stepper's State");
    if (!initialized_ || !Geometry::identical(y, last_)) reset(system, t, y);

    const double am = c_.alpha_m, af = c_.alpha_f;
    const Scalar beta_p = Scalar((1.0 - am) / (c_.beta * (1.0 - af))) / (h * h);
    const Scalar gamma_p = Scalar(c_.gamma / c_.beta) / h;
    const Scalar t1 = t + h;
    const Vector v0 = Geometry::velocity(y);

    // Predictor.
    Vector vdot1 = Vector::Zero();
    const Vector a_pred = Scalar(af / (1.0 - am)) * vdot_ - Scalar(am / (1.0 - am)) * a_;
    Vector v1 = v0 + (h * Scalar(1.0 - c_.gamma)) * a_ + (h * Scalar(c_.gamma)) * a_pred;
    Vector dq = v0 + (h * Scalar(0.5 - c_.beta)) * a_ + (h * Scalar(c_.beta)) * a_pred;
    State y1 = Geometry::advance(y, Vector(h * dq), v1);

    // Newton iteration on ΔΔ.
    const double eps = scalarValue(Eigen::NumTraits<Scalar>::epsilon());
    bool polish = !std::is_floating_point<Scalar>::value;  // one more correction for Jets
    int iterations = 0;
    bool converged = false;
    double residual = 0.0;
    Matrix M, Ct, Kt;
    Vector g;
    for (;;) {
      Dynamics::evaluate(system, t1, y1, &M, &g, &Ct, &Kt);
      const Vector inertia = M * vdot1;
      const Vector r = inertia + g;
      residual = detail::maxAbsValue(r);
      const double scale = std::max(detail::maxAbsValue(inertia), detail::maxAbsValue(g));
      const bool small = residual <= options_.tolerance * scale + options_.absolute_tolerance;
      if (small && !polish) {
        converged = true;
        break;
      }
      if (!small && iterations >= options_.max_iterations) break;
      const Matrix S = beta_p * M + gamma_p * Ct + Kt * Geometry::tangentOperator(Vector(h * dq));
      const Vector dd = -S.partialPivLu().solve(r);
      dq += dd / h;
      v1 += gamma_p * dd;
      vdot1 += beta_p * dd;
      y1 = Geometry::advance(y, Vector(h * dq), v1);
      ++iterations;
      // The Jet polish is done, or the correction no longer moves the
      // increment hΔq beyond rounding: the iterate is at working precision.
      if (small || detail::maxAbsValue(dd) <=
                       kRoundingFloor * eps * detail::maxAbsValue(Vector(h * dq))) {
        converged = true;
        break;
      }
    }

    last_report_ = StepReport{};
    last_report_.newton_iterations = iterations;
    last_report_.residual = residual;
    if (converged) {
      a_ = a_pred + Scalar((1.0 - af) / (1.0 - am)) * vdot1;
      vdot_ = vdot1;
      last_ = y1;
    } else {
      last_report_.fail("generalized-alpha Newton did not converge", residual);
    }
    if (report) *report = last_report_;
    return y1;
  }

 private:
  GeneralizedAlphaOptions options_;
  GeneralizedAlphaCoefficients c_;
  bool initialized_ = false;
  int resets_ = 0;
  State last_{};
  Vector vdot_ = Vector::Zero();
  Vector a_ = Vector::Zero();
  StepReport last_report_{};
};

}  // namespace lieflow
