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
/// traits (integrators/second_order_traits.hpp), specialized for
/// LinearSecondOrderSystem (integrators/vector_state.hpp) there and for
/// RotorSystem and FreeBodySystem beside them
/// (dynamics/rigid_body/rigid_body_system.hpp); a new system specializes
/// them next to its own definition:
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
///     optional, for a run-time-sized state:
///     static const std::vector<std::vector<int>>& independentBlocks(const System& s);
///         index sets of v that no term of M, C_t, K_t or T couples with
///         another (trees of a model that share no joint): the Newton
///         matrix is then factored block by block, Σ nᵢ³ instead of (Σ nᵢ)³
///         (MuJoCo's 22 humanoids: 22 blocks of 27, not one of 594).
///
/// Rigid bodies (dynamics/rigid_body/rigid_body_system.hpp):
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
#include <vector>

#include <Eigen/Core>
#include <Eigen/LU>

#include "integrators/second_order_traits.hpp"
#include "integrators/state_workspace.hpp"
#include "integrators/step_report.hpp"
#include "liegroup/invalid_input.hpp"
#include "liegroup/scalar.hpp"

namespace lieflow {

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

  /// The method's recurrences, written once for GeneralizedAlphaStepper and
  /// ConstrainedGeneralizedAlphaStepper (Brüls, Cardona & Arnold 2012,
  /// Algorithm 1; vectors of any size and scalar):
  ///   (G3)  a_{n+1} = (α_f v̇_n − α_m a_n + (1 − α_f) v̇_{n+1}) / (1 − α_m),
  ///   (G2)  v_{n+1} = v_n + h ((1 − γ) a_n + γ a_{n+1}),
  ///   (G1)  Δq_n = v_n + h ((½ − β) a_n + β a_{n+1}),  q_{n+1} = q_n exp(hΔq_n).
  /// (Coefficient-wise: *a_next may be a_n; nothing is allocated once it has
  /// its size. Without vdot_next: the part of a_{n+1} that does not depend on it.)
  template <class V>
  void auxiliary(const V& vdot_n, const V& a_n, const V& vdot_next, V* a_next) const {
    using S = typename V::Scalar;
    *a_next = S(alpha_f / (1.0 - alpha_m)) * vdot_n - S(alpha_m / (1.0 - alpha_m)) * a_n +
              S((1.0 - alpha_f) / (1.0 - alpha_m)) * vdot_next;
  }
  template <class V>
  void auxiliary(const V& vdot_n, const V& a_n, V* a_next) const {
    using S = typename V::Scalar;
    *a_next = S(alpha_f / (1.0 - alpha_m)) * vdot_n - S(alpha_m / (1.0 - alpha_m)) * a_n;
  }
  template <class V, class S>
  void advance(const V& v_n, const V& a_n, const V& a_next, const S& h, V* v_next, V* dq) const {
    *v_next = v_n + (h * S(1.0 - gamma)) * a_n + (h * S(gamma)) * a_next;
    *dq = v_n + (h * S(0.5 - beta)) * a_n + (h * S(beta)) * a_next;
  }
  /// How a Newton correction ΔΔ of hΔq moves the unknowns: u̇_{n+1} by
  /// β' ΔΔ and v_{n+1} by γ' ΔΔ, β' = (1 − α_m)/(h² β (1 − α_f)), γ' = γ/(h β).
  template <class S>
  S betaPrime(const S& h) const {
    return S((1.0 - alpha_m) / (beta * (1.0 - alpha_f))) / (h * h);
  }
  template <class S>
  S gammaPrime(const S& h) const {
    return S(gamma / beta) / h;
  }

  static GeneralizedAlphaCoefficients fromRhoInf(double rho_inf) {
    GeneralizedAlphaCoefficients c;
    c.alpha_m = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0);
    c.alpha_f = rho_inf / (rho_inf + 1.0);
    c.gamma = 0.5 + c.alpha_f - c.alpha_m;
    c.beta = 0.25 * (c.gamma + 0.5) * (c.gamma + 0.5);
    return c;
  }
};

namespace detail {

template <class G, class S, class V, typename = void>
struct HasAdvanceInto : std::false_type {};
template <class G, class S, class V>
struct HasAdvanceInto<G, S, V,
                      std::void_t<decltype(G::advanceInto(std::declval<const S&>(), std::declval<const V&>(),
                                                          std::declval<const V&>(), std::declval<S*>()))>>
    : std::true_type {};

}  // namespace detail

/// The Lie-group generalized-α stepper for a State with
/// SecondOrderStateTraits<State>. Stateful: see "State between steps".
///
/// A state sized at run time (SecondOrderStateTraits::kDof = Eigen::Dynamic,
/// e.g. a tree in joint coordinates) is stepped through a workspace kept by
/// the stepper, and its traits add
///   static int dofs(const State& y);
///   static void advanceInto(const State& y, const Vector& dq, const Vector& v, State* out);
///   static void tangentOperatorInto(const State& y, const Vector& dq, Matrix* T);
/// so that a step allocates nothing once the workspace has its size; step()
/// then returns a reference to the workspace's state, valid until the next
/// step. Fixed-size states keep the workspace on the stack (faster than
/// through `this`, state_workspace.hpp) and step() returns by value.
template <typename State>
class GeneralizedAlphaStepper {
 public:
  using Scalar = typename State::Scalar;
  using Geometry = SecondOrderStateTraits<State>;
  static constexpr int kDof = Geometry::kDof;
  static constexpr bool kDynamic = kDof == Eigen::Dynamic;
  using Vector = Eigen::Matrix<Scalar, kDof, 1>;
  using Matrix = Eigen::Matrix<Scalar, kDof, kDof>;
  using Result = std::conditional_t<kDynamic, const State&, State>;
  static constexpr int kOrder = 2;
  /// A Newton correction with ‖ΔΔ‖∞ ≤ kRoundingFloor · ε · ‖hΔq‖∞ is at the
  /// rounding level of the increment: the iteration has converged.
  static constexpr double kRoundingFloor = 8.0;

  static_assert(kDynamic ? State::kTangentDim == Eigen::Dynamic : 2 * kDof == State::kTangentDim,
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
    if constexpr (kDynamic) {
      resetWith(system, t0, y0, work_);
    } else {
      Scratch w;
      resetWith(system, t0, y0, w);
    }
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
  Result step(const System& system, const Scalar& t, const State& y, const Scalar& h,
              StepReport* report = nullptr) {
    if constexpr (kDynamic) {
      stepWith(system, t, y, h, report, work_);
      return work_.y1;
    } else {
      Scratch w;
      stepWith(system, t, y, h, report, w);
      return w.y1;
    }
  }

 private:
  /// The iteration's vectors and matrices (file comment's names).
  struct Scratch {
    Vector v0, vdot1, a_pred, v1, dq, hdq, g, inertia, r, dd;
    Matrix M, Ct, Kt, T, S;
    Eigen::PartialPivLU<Matrix> lu;
    State y1{};
    /// With independent blocks (SecondOrderSystemTraits::independentBlocks):
    /// per block its Newton matrix, K_t's and T's blocks, its factorization
    /// and right side, sized at the first step.
    std::vector<Matrix> block_S, block_K, block_T;
    std::vector<Eigen::PartialPivLU<Matrix>> block_lu;
    std::vector<Vector> block_r, block_x;

    void resize(int n) {
      if constexpr (kDynamic) {
        for (Vector* v : {&v0, &vdot1, &a_pred, &v1, &dq, &hdq, &g, &inertia, &r, &dd}) v->resize(n);
        for (Matrix* m : {&M, &Ct, &Kt, &T, &S}) m->resize(n, n);
      } else {
        (void)n;
      }
    }
  };

  static void advance(const State& y, const Vector& dq, const Vector& v, State* out) {
    if constexpr (detail::HasAdvanceInto<Geometry, State, Vector>::value)
      Geometry::advanceInto(y, dq, v, out);
    else
      *out = Geometry::advance(y, dq, v);
  }

  using Blocks = std::vector<std::vector<int>>;
  /// The system's independent blocks when it names more than one, else null.
  template <class Dynamics, class System>
  static const Blocks* blocksOf(const System& system) {
    if constexpr (kDynamic && detail::HasIndependentBlocks<Dynamics, System>::value) {
      const Blocks& b = Dynamics::independentBlocks(system);
      return b.size() > 1 ? &b : nullptr;
    } else {
      (void)system;
      return nullptr;
    }
  }

  /// w.dd = −S⁻¹ rhs with S = β' M + γ' C_t + K_t T (w's matrices), or S = M
  /// when `mass_only` (the reset's v̇₀ = −M⁻¹ g); block by block when the
  /// system names independent blocks (the same solution: S has no entry
  /// between them).
  void solveNewton(const Blocks* blocks, const Vector& rhs, const Scalar& beta_p, const Scalar& gamma_p,
                   bool mass_only, Scratch& w) {
    if constexpr (kDynamic) {
      if (blocks) {
        const std::size_t nb = blocks->size();
        if (w.block_S.size() != nb) {
          w.block_S.resize(nb);
          w.block_K.resize(nb);
          w.block_T.resize(nb);
          w.block_lu.resize(nb);
          w.block_r.resize(nb);
          w.block_x.resize(nb);
        }
        for (std::size_t k = 0; k < nb; ++k) {
          const std::vector<int>& idx = (*blocks)[k];
          const Eigen::Index m = static_cast<Eigen::Index>(idx.size());
          // Gathered by loops: Eigen's indexed views copy an index vector
          // (a heap allocation each).
          Matrix& S = w.block_S[k];
          S.resize(m, m);
          if (mass_only) {
            for (Eigen::Index j = 0; j < m; ++j)
              for (Eigen::Index i = 0; i < m; ++i) S(i, j) = w.M(idx[i], idx[j]);
          } else {
            Matrix& K = w.block_K[k];
            Matrix& T = w.block_T[k];
            K.resize(m, m);
            T.resize(m, m);
            for (Eigen::Index j = 0; j < m; ++j)
              for (Eigen::Index i = 0; i < m; ++i) {
                K(i, j) = w.Kt(idx[i], idx[j]);
                T(i, j) = w.T(idx[i], idx[j]);
              }
            S.noalias() = K * T;
            for (Eigen::Index j = 0; j < m; ++j)
              for (Eigen::Index i = 0; i < m; ++i)
                S(i, j) += beta_p * w.M(idx[i], idx[j]) + gamma_p * w.Ct(idx[i], idx[j]);
          }
          w.block_lu[k].compute(S);
          Vector& r = w.block_r[k];
          Vector& x = w.block_x[k];
          r.resize(m);
          x.resize(m);
          for (Eigen::Index i = 0; i < m; ++i) r[i] = rhs[idx[i]];
          x.noalias() = w.block_lu[k].solve(r);
          for (Eigen::Index i = 0; i < m; ++i) w.dd[idx[i]] = -x[i];
        }
        return;
      }
    }
    (void)blocks;
    if (mass_only) {
      w.lu.compute(w.M);
    } else {
      w.S.noalias() = w.Kt * w.T;
      w.S += beta_p * w.M + gamma_p * w.Ct;
      w.lu.compute(w.S);
    }
    w.dd.noalias() = w.lu.solve(rhs);
    w.dd = -w.dd;
  }

  template <class System>
  void resetWith(const System& system, const Scalar& t0, const State& y0, Scratch& w) {
    using Dynamics = SecondOrderSystemTraits<System>;
    static_assert(std::is_same<typename Dynamics::State, State>::value,
                  "SecondOrderSystemTraits<System>::State differs from the stepper's State");
    if constexpr (kDynamic) w.resize(Geometry::dofs(y0));
    Dynamics::evaluate(system, t0, y0, &w.M, &w.g, nullptr, nullptr);
    solveNewton(blocksOf<Dynamics>(system), w.g, Scalar(0), Scalar(0), true, w);
    setHistory(y0, w.dd, w.dd);
    ++resets_;
  }

  template <class System>
  void stepWith(const System& system, const Scalar& t, const State& y, const Scalar& h, StepReport* report,
                Scratch& w) {
    using Dynamics = SecondOrderSystemTraits<System>;
    static_assert(std::is_same<typename Dynamics::State, State>::value,
                  "SecondOrderSystemTraits<System>::State differs from the stepper's State");
    if (!initialized_ || !Geometry::identical(y, last_)) resetWith(system, t, y, w);
    if constexpr (kDynamic) w.resize(Geometry::dofs(y));

    const Scalar beta_p = c_.betaPrime(h);
    const Scalar gamma_p = c_.gammaPrime(h);
    const Scalar t1 = t + h;
    w.v0 = Geometry::velocity(y);

    // Predictor: v̇_{n+1} = 0 (the Newton corrections build it up), then
    // (G3), (G2), (G1); a_pred is a_{n+1}'s part without v̇_{n+1}.
    w.vdot1.setZero();
    c_.auxiliary(vdot_, a_, &w.a_pred);
    c_.advance(w.v0, a_, w.a_pred, h, &w.v1, &w.dq);
    w.hdq = h * w.dq;
    advance(y, w.hdq, w.v1, &w.y1);

    // Newton iteration on ΔΔ.
    const double eps = scalarValue(Eigen::NumTraits<Scalar>::epsilon());
    bool polish = !std::is_floating_point<Scalar>::value;  // one more correction for Jets
    int iterations = 0;
    bool converged = false;
    double residual = 0.0;
    for (;;) {
      Dynamics::evaluate(system, t1, w.y1, &w.M, &w.g, &w.Ct, &w.Kt);
      w.inertia.noalias() = w.M * w.vdot1;
      w.r = w.inertia + w.g;
      residual = detail::maxAbsValue(w.r);
      const double scale = std::max(detail::maxAbsValue(w.inertia), detail::maxAbsValue(w.g));
      const bool small = residual <= options_.tolerance * scale + options_.absolute_tolerance;
      if (small && !polish) {
        converged = true;
        break;
      }
      if (!small && iterations >= options_.max_iterations) break;
      if constexpr (kDynamic) {
        Geometry::tangentOperatorInto(y, w.hdq, &w.T);
      } else {
        w.T = Geometry::tangentOperator(w.hdq);
      }
      solveNewton(blocksOf<Dynamics>(system), w.r, beta_p, gamma_p, false, w);
      w.dq += w.dd / h;
      w.v1 += gamma_p * w.dd;
      w.vdot1 += beta_p * w.dd;
      w.hdq = h * w.dq;
      advance(y, w.hdq, w.v1, &w.y1);
      ++iterations;
      // The Jet polish is done, or the correction no longer moves the
      // increment hΔq beyond rounding: the iterate is at working precision.
      if (small || detail::maxAbsValue(w.dd) <= kRoundingFloor * eps * detail::maxAbsValue(w.hdq)) {
        converged = true;
        break;
      }
    }

    last_report_ = StepReport{};
    last_report_.newton_iterations = iterations;
    last_report_.residual = residual;
    if (converged) {
      a_ = w.a_pred + Scalar((1.0 - c_.alpha_f) / (1.0 - c_.alpha_m)) * w.vdot1;
      vdot_ = w.vdot1;
      last_ = w.y1;
    } else {
      last_report_.fail("generalized-alpha Newton did not converge", residual);
    }
    if (report) *report = last_report_;
  }

  GeneralizedAlphaOptions options_;
  GeneralizedAlphaCoefficients c_;
  bool initialized_ = false;
  int resets_ = 0;
  State last_{};
  static Vector zero() {
    if constexpr (kDynamic)
      return Vector();
    else
      return Vector::Zero();
  }
  Vector vdot_ = zero();
  Vector a_ = zero();
  StepReport last_report_{};
  /// The workspace of a run-time-sized state (unused otherwise).
  std::conditional_t<kDynamic, Scratch, char> work_{};
};

}  // namespace lieflow
