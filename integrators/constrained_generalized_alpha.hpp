/// \file
/// The Lie-group generalized-α method with holonomic constraints, in the
/// stabilized index-2 form (the default, option index = 2: Arnold, Brüls &
/// Cardona 2015, Numer. Math. 129, "Error analysis of generalized-α Lie group
/// time integration methods for constrained mechanical systems"; see
/// "Stabilized index 2" below) or at index 3 (index = 3: Brüls, Cardona &
/// Arnold 2012, "Lie group generalized-α time integration of constrained
/// flexible multibody systems", Mech. Mach. Theory 48, 121–137, Algorithm 1
/// with the constraint rows; parameters of Arnold & Brüls 2007, Multibody
/// Syst. Dyn. 18, 185–202), with a sparse Newton solve whose cost grows
/// linearly along chains. The unconstrained method is
/// integrators/generalized_alpha.hpp; its coefficients α_m, α_f, β, γ (from
/// ρ∞) and recurrences (G1)–(G3) (GeneralizedAlphaCoefficients) are this
/// stepper's too: only the Newton solve differs.
///
/// ## Equations (BCA 2012, Sec. 2; lieflow's right trivialization)
///   (E1)  M(q) u̇ + g(q, u, t) + Jᵀ(q) λ = 0,     q̇ = q · u,
///   (E2)  Φ(q, t) = 0                    (position rows, m_p of them),
///   (E3)  B(q) u − b(t) = 0              (velocity-only rows, m_v: gears),
/// J = [Φ_q; B] stacking both row kinds. The velocity-only rows have no
/// position form; they are imposed as (E3) at t_{n+1} inside the same Newton
/// iteration (a mixed index-3 / index-2 formulation), their multipliers are
/// the last m_v entries of λ.
///
/// ## The method (BCA 2012, Algorithm 1)
/// With α_m, α_f, γ, β from ρ∞ (GeneralizedAlphaCoefficients) one step
/// t_n → t_{n+1} = t_n + h solves for (u̇_{n+1}, λ_{n+1}):
///   (G1)  q_{n+1} = q_n exp(h Δq_n),   Δq_n = u_n + (½ − β) h a_n + β h a_{n+1},
///   (G2)  u_{n+1} = u_n + (1 − γ) h a_n + γ h a_{n+1},
///   (G3)  (1 − α_m) a_{n+1} + α_m a_n = (1 − α_f) u̇_{n+1} + α_f u̇_n,
///   (G4)  (E1) at (q_{n+1}, u_{n+1}, u̇_{n+1}, λ_{n+1}, t_{n+1}),
///   (G5)  Φ(q_{n+1}, t_{n+1}) = 0  and  B(q_{n+1}) u_{n+1} = b(t_{n+1}).
/// Index 3: the position rows hold at t_{n+1} to the Newton tolerance; the
/// hidden velocity constraints Φ_q u = ∂Φ/∂t are not imposed (their error is
/// O(h²): Arnold, Brüls & Cardona 2015, Numer. Math. 129, "Error analysis of
/// generalized-α Lie group time integration methods for constrained mechanical
/// systems").
///
/// Newton on x = hΔq (and λ): by (G1)–(G3) a correction ΔΔ of hΔq moves
///   u̇_{n+1} by β' ΔΔ,  u_{n+1} by γ' ΔΔ,  q_{n+1} to q_{n+1} exp(T(hΔq) ΔΔ),
///   β' = (1 − α_m)/(h² β (1 − α_f)),   γ' = γ/(h β),
/// T the tangent operator of exp (Jr on rotation blocks, I on vector blocks).
/// The iteration matrix (BCA 2012, the tangent of (G4)–(G5); the labels (E·),
/// (G·) are this file's):
///   [ M β' + C_t γ' + K_t T    Jᵀ ] [ ΔΔ ]     [ r ]
///   [ Φ_q T                    0  ] [ Δλ ] = − [ Φ ],       r = M u̇ + g + Jᵀλ,
///   [ γ' B                     0  ]            [ Bu − b ]
/// with C_t = ∂g/∂u and K_t = ∂(g + Jᵀλ)/∂δq; what the System puts into them
/// (and what it leaves out) is documented with its assembly
/// (dynamics/maximal/kkt_assembly.hpp: spring, dashpot, gyroscopic and
/// constraint-force terms). Conditioning (Bottasso, Bauchau & Cardona 2007,
/// SIAM J. Sci. Comput. 29, 397–414; BCA 2012): the first block row is divided
/// by β' and the unknown λ scaled by β', the velocity rows divided by γ':
///   [ M + (γ'/β') C_t + (1/β') K_t T    Jᵀ ] [ ΔΔ     ]     [ r/β'         ]
///   [ Φ_q T                             0  ] [ Δλ/β'  ] = − [ Φ            ]
///   [ B                                 0  ]                [ (Bu − b)/γ'  ]
/// whose condition number does not grow like h⁻⁴ as h → 0. This matrix is
/// sparse (per body blocks, couplings only between the bodies of a joint) and
/// its pattern is fixed: KLU (integrators/fixed_pattern_lu.hpp), the pattern
/// analysed once per system topology, the pivots chosen at the first
/// factorization and reused by every later one (full Newton: a factorization
/// per iteration) until they go bad, so the cost per iteration grows linearly
/// along chains and a refactorization allocates nothing. Nothing dense of the
/// whole system is formed.
///
/// Predictor: u̇_{n+1} = u̇_n, λ_{n+1} = λ_n (then a_{n+1}, u_{n+1}, q_{n+1} by
/// (G1)–(G3)). Damped Newton: a correction that does not decrease the scaled
/// residual ‖[r/β'; Φ; (Bu − b)/γ']‖₂ (Armijo) is halved, at most
/// kMaxBacktracks times; near the solution the full correction is taken and
/// the convergence is quadratic. After convergence a_{n+1} follows from (G3).
///
/// ## Stabilized index 2 (the default)
/// The GGL idea (Gear, Gupta & Leimkuhler 1985) in the Lie-group
/// generalized-α method (Arnold, Brüls & Cardona 2015): the velocity rows of
/// all constraints are imposed at t_{n+1} and the position rows through an
/// extra multiplier ν in the position update,
///   (G1')  q_{n+1} = q_n exp(h Δq_n + M⁻¹ J̄ᵀ ν_{n+1}),
///   (G5')  Φ(q_{n+1}, t_{n+1}) = 0   and   J(q_{n+1}) u_{n+1} = b(t_{n+1}),
/// with (G2)–(G4) unchanged. J̄ = ½ (J(q_n) + J(q̃_{n+1})) of the position rows,
/// q̃_{n+1} the step's first Newton iterate, held for the step: with J(q_n)
/// alone the step is not symmetric and the energy of the ρ∞ = 1 method
/// drifts (measured at h = 0.01 over 1000 s: +9·10⁻³ J on the pendulum,
/// +0.10 J on the double pendulum; with J̄ both stay within their first
/// oscillation, 6·10⁻⁴ and 1.4·10⁻² J). ν is O(h³) per step (it removes the
/// drift of the velocity-level integration), so the order is that of the
/// unconstrained method, and positions, velocities and multipliers all
/// converge at order 2 (tests/simulation/stabilized_genalpha_test.cpp measures
/// 2.00, 2.00, 2.00 on a three-link chain at ρ∞ = 1 and 0.8; index 3 at
/// ρ∞ = 1 gives λ errors that do not converge at all, 0.18 at every h).
/// No damping is needed for stability: ρ∞ = 1 runs the built-in jointed
/// scenes for 100 s with bounded energy, where index 3 stops within seconds.
/// Newton runs on (ΔQ, Δλ, Δν) with ΔQ = ΔΔ + M⁻¹ J̄ᵀ Δν the correction of
/// the whole position increment; the matrix and its sparsity are documented
/// with the assembly (dynamics/maximal/kkt_assembly.hpp).
///
/// ## Numerical damping at index 3
/// ρ∞ < 1 damps the modes with hω ≫ 1 (stiff springs, the spurious
/// oscillations of λ and of the hidden constraints) by about ρ∞ per step. The
/// undamped ρ∞ = 1 (the trapezoidal rule) conserves the energy of linear
/// systems but is unstable at index 3 on nonlinear constraints (Cardona &
/// Géradin 1989, Comput. Struct. 33, 801–820). Measured: the compound
/// pendulum of the tests (θ₀ = 1.2, h = 5 ms) runs away after 7 s (1456
/// steps) with ρ∞ = 1, where ρ∞ = 0.9 keeps |E − E₀| ≤ 8·10⁻⁴ J of 3.2 J
/// over 20 s; a rotor at 1000 rad/s with a flapping blade fails after ~200
/// steps at h Ω = 0.1 with ρ∞ = 1 and keeps its energy to 2·10⁻⁴ with
/// ρ∞ = 0.9 (tests/dynamics/constrained_genalpha_test.cpp). At index 3 use
/// ρ∞ ≤ 0.9 with constraints; the stabilized index-2 default needs no damping.
///
/// ## Stopping test
/// Converged when, at the current iterate,
///   ‖r‖∞ ≤ tolerance · max(‖M u̇‖∞, ‖g‖∞, ‖Jᵀλ‖∞) + absolute_tolerance,
///   ‖Φ‖∞ ≤ constraint_tolerance   and   h ‖Bu − b‖∞ ≤ constraint_tolerance,
/// or when a full correction is at the rounding level of the unknowns,
/// ‖ΔΔ‖∞ ≤ 8ε ‖hΔq‖∞ and ‖Δλ‖∞ ≤ 8ε ‖λ‖∞. Non-convergence within
/// max_iterations, a non-finite residual or a singular iteration matrix is
/// reported through StepReport::fail with a detail (which norms, how far off),
/// never silently; the failed step is not committed (a retry from the same y,
/// say with a smaller h, reuses the carried history).
///
/// ## State between steps
/// Like GeneralizedAlphaStepper the stepper carries (u̇_n, a_n, λ_n). `step`
/// calls `initialize(system, t, y)` — u̇₀, λ₀ from the index-1 equations,
/// a₀ = u̇₀ — when it has no history, when y is not exactly its last output or
/// when the system is another one; call it yourself after changing the system
/// between steps.
///
/// ## The System concept
/// The System itself supplies `double achievablePositionTolerance(const State&,
/// double tolerance) const` (the tolerance raised to the round-off floor of
/// the state's positions). A System plugs in through ConstrainedSystemTraits<System>::Assembly, a
/// default-constructible class specialized next to the system (for
/// multibody::MultibodySystem: dynamics/maximal/kkt_assembly.hpp) with
///   using State;                    // State::Scalar is double
///   bool bind(const System& s);    // keep a reference to s and (re)build
///                                  // the sparse pattern if s's topology
///                                  // differs from the bound one; true when
///                                  // the pattern is new
///   bool boundTo(const System& s) const;  // bound to s, same topology
///   int dofs() const;              // n: size of u, u̇, δq
///   int positionRows() const;      // m_p: rows of (E2), first in λ
///   int velocityRows() const;      // m_v: rows of (E3), after them
///   static void velocityInto(const State& y, Eigen::VectorXd* u);  // u
///   static void advanceInto(const State& y, const Eigen::VectorXd& dq,
///                           const Eigen::VectorXd& u, State* out);
///                                  // out = (q exp(dq), u), reusing out's storage
///   static bool identical(const State& a, const State& b);    // exact equality
///   bool accelerations(double t, const State& y, Eigen::VectorXd* udot,
///                      Eigen::VectorXd* lambda, std::string* why);
///                                  // index-1 solve of (E1) with the second
///                                  // derivative of (E2) and the first of (E3)
///   double residual(double t, const State& y, const Eigen::VectorXd& udot,
///                   const Eigen::VectorXd& lambda, Eigen::VectorXd* r,
///                   Eigen::VectorXd* c);
///                                  // r = M u̇ + g + Jᵀλ (size n), c = [Φ; Bu − b]
///                                  // (size m_p + m_v); returns the force scale
///                                  // max(‖M u̇‖∞, ‖g‖∞, ‖Jᵀλ‖∞)
///   void setStabilized(bool);      // index 2 (true) or 3; unbinds on change
///   void startStep(double t, const State& y);  // stabilized: J(q_n) kept
///   void addStartCorrection(const Eigen::VectorXd& nu, Eigen::VectorXd* dq) const;
///                                  // stabilized: dq += M⁻¹ J̄ᵀ ν
///                                  // (stabilized: c = [Φ; J u − b] of all
///                                  // rows, the matrix in the order force,
///                                  // velocity, position rows)
///   const Eigen::SparseMatrix<double>& matrix(const State& y, const Eigen::VectorXd& dq,
///                   double damping_factor, double stiffness_factor,
///                   const Eigen::VectorXd& lambda);
///                                  // the scaled matrix above at the y of the
///                                  // last residual() call, with dq = hΔq (for
///                                  // T), damping_factor = γ'/β',
///                                  // stiffness_factor = 1/β'; same pattern
///                                  // while bound to one topology
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <utility>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "integrators/fixed_pattern_lu.hpp"
#include "integrators/generalized_alpha.hpp"
#include "integrators/step_report.hpp"
#include "liegroup/invalid_input.hpp"
#include "liegroup/number_text.hpp"

namespace lieflow {

/// Maps a constrained System to its Newton assembly (see "The System
/// concept"); specialized next to the system.
template <class System>
struct ConstrainedSystemTraits;

struct ConstrainedGeneralizedAlphaOptions {
  /// Spectral radius at infinity, in [0, 1]: 1 non-dissipative (unstable at
  /// index 3 on nonlinear constraints: see "Numerical damping at index 3"),
  /// ρ∞ < 1 damps the modes with hω → ∞ by the factor ρ∞ per step.
  double rho_inf = 1.0;
  /// Relative residual of the equations of motion (see "Stopping test").
  double tolerance = 1e-10;
  /// Absolute floor of the force residual (N, N·m).
  double absolute_tolerance = 0.0;
  /// max |Φ| (m, rad) at convergence; velocity rows: h·|Bu − b| (m, rad).
  double constraint_tolerance = 1e-12;
  /// Newton corrections allowed per step (≥ 1).
  int max_iterations = 20;
  /// 2: the stabilized index-2 formulation (file comment, "Stabilized index
  /// 2"), stable at ρ∞ = 1; 3: index 3 (BCA 2012), which needs ρ∞ < 1 on
  /// nonlinear constraints.
  int index = 2;
};

/// The index-3 Lie-group generalized-α stepper for a System with
/// ConstrainedSystemTraits<System> (see the file comment). Stateful; movable,
/// not copyable.
template <class System>
class ConstrainedGeneralizedAlphaStepper {
 public:
  using Assembly = typename ConstrainedSystemTraits<System>::Assembly;
  using State = typename Assembly::State;
  using Scalar = double;
  using Vector = Eigen::VectorXd;
  static constexpr int kOrder = 2;
  /// A correction at kRoundingFloor · ε of its unknown has converged.
  static constexpr double kRoundingFloor = 8.0;
  /// Halvings of a Newton correction allowed by the line search.
  static constexpr int kMaxBacktracks = 6;

  /// Throws InvalidInput for ρ∞ ∉ [0, 1], negative or non-finite tolerances,
  /// or max_iterations < 1.
  explicit ConstrainedGeneralizedAlphaStepper(ConstrainedGeneralizedAlphaOptions options = {})
      : options_(options), c_(GeneralizedAlphaCoefficients::fromRhoInf(options.rho_inf)) {
    if (!(options.rho_inf >= 0.0 && options.rho_inf <= 1.0)) throw InvalidInput("rho_inf", "must be in [0, 1]");
    checkTolerance(options.tolerance, "tolerance");
    checkTolerance(options.absolute_tolerance, "absolute_tolerance");
    checkTolerance(options.constraint_tolerance, "constraint_tolerance");
    if (options.max_iterations < 1) throw InvalidInput("max_iterations", "must be at least 1");
    if (options.index != 2 && options.index != 3) throw InvalidInput("index", "must be 2 or 3");
    assembly_.setStabilized(options.index == 2);
  }

  const ConstrainedGeneralizedAlphaOptions& options() const { return options_; }
  const GeneralizedAlphaCoefficients& coefficients() const { return c_; }
  int order() const { return kOrder; }

  /// Consistent start at (t0, y0): u̇₀, λ₀ from the index-1 equations,
  /// a₀ = u̇₀. Returns false with `why` when that solve fails (redundant
  /// constraints); the stepper then has no history.
  bool initialize(const System& system, double t0, const State& y0, std::string* why = nullptr) {
    bindTo(system);
    initialized_ = false;
    std::string reason;
    if (!assembly_.accelerations(t0, y0, &udot_, &lambda_, &reason)) {
      if (why) *why = reason;
      return false;
    }
    a_ = udot_;
    last_ = y0;
    initialized_ = true;
    ++resets_;
    return true;
  }

  bool initialized() const { return initialized_; }
  /// u̇_n, a_n and λ_n of the last committed step (or of initialize()).
  const Vector& acceleration() const { return udot_; }
  const Vector& auxiliaryAcceleration() const { return a_; }
  const Vector& multipliers() const { return lambda_; }
  const StepReport& lastReport() const { return last_report_; }
  /// The System's assembly (its options, e.g. KktAssemblyOptions for a
  /// MultibodySystem, are set through it).
  Assembly& assembly() { return assembly_; }
  int resetCount() const { return resets_; }
  /// Symbolic analyses of the iteration matrix so far (one per topology).
  int analyzeCount() const { return analyze_count_; }
  /// Factorizations that chose pivots so far (the only ones that allocate:
  /// FixedPatternLu reuses pivots until they go bad).
  int pivotChoices() const { return lu_.pivotingFactorizations(); }
  /// Halvings of Newton corrections by the line search so far.
  long backtrackCount() const { return backtracks_; }
  /// Size of the iteration matrix and nonzeros of its last LU factors
  /// (L and U, supernodal storage): fill that grows linearly along chains.
  Eigen::Index matrixSize() const { return size_; }
  Eigen::Index factorNonzeros() const { return factored_ ? lu_.factorNonzeros() : 0; }

  /// One step of size h from (t, y) (see the file comment).
  /// The result lives in the stepper until its next step (y may be it).
  const State& step(const System& system, double t, const State& y_in, double h, StepReport* report = nullptr) {
    // y may be a result this stepper handed out and is about to overwrite.
    const State& y = &y_in == &y1_ || &y_in == &y_trial_ ? (start_copy_ = y_in) : y_in;
    last_report_ = StepReport{};
    if (!initialized_ || !assembly_.boundTo(system) || !Assembly::identical(y, last_)) {
      std::string why;
      if (!initialize(system, t, y, &why)) {
        last_report_.fail("generalized-alpha: inconsistent start (index-1 solve failed)",
                          std::numeric_limits<double>::quiet_NaN());
        last_report_.detail = why;
        if (report) *report = last_report_;
        return y;
      }
    }
    // The constraint tolerance that round-off allows at this state's extent.
    constraint_tolerance_ = system.achievablePositionTolerance(y, options_.constraint_tolerance);
    const int n = assembly_.dofs();
    const int mp = assembly_.positionRows();
    const int m = mp + assembly_.velocityRows();
    // Stabilized: ν, one per position row (none without constraints).
    const bool stabilized = options_.index == 2 && m > 0;
    const int mnu = stabilized ? mp : 0;
    const double beta_p = c_.betaPrime(h);
    const double gamma_p = c_.gammaPrime(h);
    const double t1 = t + h;
    if (stabilized) assembly_.startStep(t, y);
    const StepShape shape{n, mp, m, mnu, stabilized, beta_p, gamma_p, t1};

    // Predictor: u̇_{n+1} = u̇_n, λ_{n+1} = λ_n, ν = 0; (G3), (G2), (G1).
    // The iterate lives in members (no allocation once they have the
    // system's sizes).
    Vector& u0 = u0_;
    Vector& udot1 = udot1_;
    Vector& lambda1 = lambda1_;
    Vector& nu1 = nu1_;
    Vector& a1 = a1_;
    Vector& u1 = u1_;
    Vector& hdq = hdq_;
    Vector& dq_total = dq_total_;
    State& y1 = y1_;
    Assembly::velocityInto(y, &u0);
    udot1 = udot_;
    lambda1 = lambda_;
    nu1.setZero(mnu);
    c_.auxiliary(udot_, a_, udot1, &a1);
    // hdq: the increment h Δq_n of (G1) without the ν correction; dq_total
    // with it (the increment q_{n+1} = q_n exp(dq_total) is taken with).
    c_.advance(u0, a_, a1, h, &u1, &hdq);
    hdq *= h;
    dq_total = hdq;
    Assembly::advanceInto(y, dq_total, u1, &y1);

    const double eps = std::numeric_limits<double>::epsilon();
    int iterations = 0;
    bool converged = false;
    const char* failure = nullptr;
    bool singular = false;
    Norms now = evaluate(t1, y1, udot1, lambda1, mp, m, stabilized, h, beta_p, gamma_p);
    for (;;) {
      if (!now.finite) {
        failure = "generalized-alpha: non-finite residual";
        break;
      }
      if (now.small) {
        converged = true;
        break;
      }
      if (iterations >= options_.max_iterations) {
        failure = "generalized-alpha Newton did not converge";
        break;
      }
      if (!newtonCorrection(shape, y1, dq_total, lambda1)) {
        failure = "generalized-alpha: singular iteration matrix";
        singular = true;
        break;
      }
      Norms trial;
      const double alpha = lineSearch(shape, y, now, hdq, u1, udot1, lambda1, nu1, h, &trial);
      State& y_trial = y_trial_;
      hdq.swap(hdq_t_);
      dq_total.swap(dq_t_);
      u1.swap(u_t_);
      udot1.swap(udot_t_);
      lambda1.swap(lambda_t_);
      if (stabilized) nu1.swap(nu_t_);
      std::swap(y1, y_trial);
      now = trial;
      ++iterations;
      // A full correction at the rounding level of the unknowns: converged.
      if (alpha == 1.0 && now.finite &&
          detail::maxAbsValue(dd_) <= kRoundingFloor * eps * detail::maxAbsValue(hdq) &&
          (m == 0 || beta_p * detail::maxAbsValue(x_.segment(n, m)) <=
                         kRoundingFloor * eps * detail::maxAbsValue(lambda1)) &&
          (mnu == 0 || detail::maxAbsValue(dnu_) <= kRoundingFloor * eps * detail::maxAbsValue(nu1))) {
        converged = true;
        break;
      }
    }
    const double force = now.force, force_bound = now.bound, position = now.position, velocity = now.velocity;

    last_report_.newton_iterations = iterations;
    last_report_.residual = force;
    if (converged) {
      c_.auxiliary(udot_, a_, udot1, &a_);
      udot_ = udot1;
      lambda_ = lambda1;
      last_ = y1;
    } else {
      last_report_.fail(failure, force);
      std::ostringstream s;
      s << "after " << iterations << " Newton iterations (h = " << h << "): force residual " << formatNumber(force)
        << " (bound " << formatNumber(force_bound) << "), max |Phi| = " << formatNumber(position)
        << ", h max |B u - b| = " << formatNumber(velocity)
        << " (constraint tolerance " << constraint_tolerance_ << ")";
      if (singular) s << "; " << lu_.lastError();
      last_report_.detail = s.str();
    }
    if (report) *report = last_report_;
    return y1;
  }

 private:
  /// The residual's norms at one iterate (see "Stopping test").
  struct Norms {
    double force = 0.0, bound = 0.0, position = 0.0, velocity = 0.0;
    double merit = 0.0;  ///< ‖[r/β'; Φ; (Bu − b)/γ']‖₂, the scaled residual
    bool finite = true;
    bool small = false;  ///< the stopping test holds
  };
  /// The sizes and coefficients of one step (step()'s constants).
  struct StepShape {
    int n = 0, mp = 0, m = 0, mnu = 0;  ///< dofs, position rows, all rows, ν (stabilized: mp)
    bool stabilized = false;
    double beta_p = 0.0, gamma_p = 0.0, t1 = 0.0;
  };

  /// The Newton correction at the iterate of the last evaluate(): the scaled
  /// iteration matrix (file comment) factored, its system solved into x_,
  /// a_{n+1}'s part of the increment in dd_ (stabilized: ν's in dnu_).
  /// False when the matrix is singular.
  bool newtonCorrection(const StepShape& z, const State& y1, const Vector& dq_total, const Vector& lambda1) {
    const int n = z.n, mp = z.mp, m = z.m, mnu = z.mnu;
    const bool stabilized = z.stabilized;
    const double beta_p = z.beta_p, gamma_p = z.gamma_p;
    // The scaled iteration matrix and right-hand side (file comment), at the
    // iterate of the last evaluate().
    const Eigen::SparseMatrix<double>& A =
        assembly_.matrix(y1, dq_total, gamma_p / beta_p, 1.0 / beta_p, lambda1);
    if (pattern_new_ || A.rows() != size_) {
      lu_.reset();
      ++analyze_count_;
      pattern_new_ = false;
      size_ = A.rows();
    }
    factored_ = lu_.factorize(A);
    if (!factored_) return false;
    rhs_.resize(n + m + mnu);
    rhs_.head(n) = -r_ / beta_p;
    if (stabilized) {
      // Rows: velocity (all m), then position (m_p); cr_ = [Φ; J u − b].
      rhs_.segment(n, m) = -cr_.tail(m) / gamma_p;
      rhs_.tail(mp) = -cr_.head(mp);
    } else {
      if (mp > 0) rhs_.segment(n, mp) = -cr_.head(mp);
      if (m > mp) rhs_.tail(m - mp) = -cr_.tail(m - mp) / gamma_p;
    }
    x_ = rhs_;
    lu_.solveInPlace(&x_);
    // The correction of a_{n+1}'s part of the increment: x's first block
    // (index 3: ΔΔ; stabilized: ΔQ, and ΔΔ = ΔQ − M⁻¹ J_nᵀ Δν).
    dd_ = x_.head(n);
    if (stabilized) {
      dnu_ = -x_.tail(mp);
      assembly_.addStartCorrection(dnu_, &dd_);
      dnu_ = x_.tail(mp);
    }
    return true;
  }

  /// Damped Newton along the correction from the iterate (hdq, u1, udot1,
  /// lambda1, nu1): the trial in the *_t_ members and y_trial_, its norms in
  /// *trial; returns the step length α taken.
  double lineSearch(const StepShape& z, const State& y, const Norms& now, const Vector& hdq, const Vector& u1,
                    const Vector& udot1, const Vector& lambda1, const Vector& nu1, double h, Norms* trial_out) {
    const int n = z.n, mp = z.mp, m = z.m;
    const bool stabilized = z.stabilized;
    const double beta_p = z.beta_p, gamma_p = z.gamma_p, t1 = z.t1;
    Norms& trial = *trial_out;
    // Damped Newton: the full correction unless it fails to decrease the
    // scaled residual (Armijo, halving the step up to kMaxBacktracks times;
    // the last trial is taken in any case). Near the solution the full
    // step is always taken, so the convergence stays quadratic.
    double alpha = 1.0;
    State& y_trial = y_trial_;
    for (int k = 0;; ++k) {
      hdq_t_ = hdq + alpha * dd_;
      u_t_ = u1 + (alpha * gamma_p) * dd_;
      udot_t_ = udot1 + (alpha * beta_p) * dd_;
      lambda_t_ = lambda1;
      if (m > 0) lambda_t_ += (alpha * beta_p) * x_.segment(n, m);
      dq_t_ = hdq_t_;
      if (stabilized) {
        nu_t_ = nu1 + alpha * dnu_;
        assembly_.addStartCorrection(nu_t_, &dq_t_);
      }
      Assembly::advanceInto(y, dq_t_, u_t_, &y_trial);
      trial = evaluate(t1, y_trial, udot_t_, lambda_t_, mp, m, stabilized, h, beta_p, gamma_p);
      if (trial.small || (trial.finite && trial.merit <= (1.0 - 1e-4 * alpha) * now.merit) || k == kMaxBacktracks)
        break;
      alpha *= 0.5;
      ++backtracks_;
      // A correction that had to be shortened may come from pivots gone
      // bad: the next factorization chooses them again.
      lu_.choosePivotsNext();
    }
    return alpha;
  }



  /// Evaluates r_, cr_ at an iterate and measures them.
  /// cr_ = [Φ; B u − b] (index 3) or [Φ; J u − b] over all m rows (stabilized).
  Norms evaluate(double t1, const State& y1, const Vector& udot1, const Vector& lambda1, int mp, int m,
                 bool stabilized, double h, double beta_p, double gamma_p) {
    Norms out;
    const double scale = assembly_.residual(t1, y1, udot1, lambda1, &r_, &cr_);
    const int mv = stabilized ? m : m - mp;  // velocity rows
    out.force = detail::maxAbsValue(r_);
    out.bound = options_.tolerance * scale + options_.absolute_tolerance;
    out.position = mp > 0 ? detail::maxAbsValue(cr_.head(mp)) : 0.0;
    out.velocity = mv > 0 ? h * detail::maxAbsValue(cr_.tail(mv)) : 0.0;
    double merit2 = r_.squaredNorm() / (beta_p * beta_p);
    if (mp > 0) merit2 += cr_.head(mp).squaredNorm();
    if (mv > 0) merit2 += cr_.tail(mv).squaredNorm() / (gamma_p * gamma_p);
    out.merit = std::sqrt(merit2);
    out.finite = std::isfinite(out.force) && std::isfinite(out.position) && std::isfinite(out.velocity) &&
                 std::isfinite(out.merit) && std::isfinite(scale);
    out.small = out.finite && out.force <= out.bound && out.position <= constraint_tolerance_ &&
                out.velocity <= constraint_tolerance_;
    return out;
  }

  /// options_.constraint_tolerance, raised to the round-off floor of the
  /// current step's positions (MultibodySystem::achievablePositionTolerance).
  double constraint_tolerance_ = 0.0;

  static void checkTolerance(double v, const char* name) {
    if (!(v >= 0.0 && std::isfinite(v))) throw InvalidInput(name, "must be finite and non-negative");
  }
  void bindTo(const System& system) {
    if (assembly_.bind(system)) pattern_new_ = true;
  }

  ConstrainedGeneralizedAlphaOptions options_;
  GeneralizedAlphaCoefficients c_;
  Assembly assembly_;
  FixedPatternLu lu_;
  bool pattern_new_ = true;
  bool factored_ = false;
  Eigen::Index size_ = -1;
  int analyze_count_ = 0;
  bool initialized_ = false;
  int resets_ = 0;
  State last_{};
  Vector udot_, a_, lambda_;
  Vector r_, cr_, rhs_, x_;
  Vector hdq_t_, u_t_, udot_t_, lambda_t_, nu_t_, dq_t_;  ///< trial iterate of the line search
  Vector u0_, udot1_, lambda1_, nu1_, a1_, u1_, hdq_, dq_total_;  ///< the step's iterate
  State y1_{}, y_trial_{}, start_copy_{};
  Vector dd_;   ///< the iteration's ΔΔ
  Vector dnu_;  ///< stabilized: its Δν
  long backtracks_ = 0;
  StepReport last_report_{};
};

}  // namespace lieflow
