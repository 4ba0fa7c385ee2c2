/// \file
/// A constrained Lie group variational integrator of RATTLE type for systems
/// of rigid bodies in maximal coordinates: every body on its own group
/// (SO(3) × ℝ³, or SO(3) for a rotation-only body), the joints as position
/// constraints Φ(q, t) = 0 with Lagrange multipliers, and velocity-only
/// (gear-type) rows B(q) u = 0.
///
/// ## The scheme
/// Per body: the rotational discrete Lagrangian of Lee, Leok & McClamroch
/// ("Lie group variational integrators for the full body problem", CMAME 196
/// (2007) 2907–2924; integrators/lgvi.hpp, whose per-body step lgviKickDrift
/// and lgviEndKick — the free body's LGVI — this stepper runs for every body,
/// the joints' reactions entering as impulses) and the trapezoidal one for the
/// centre of mass; the constraints enter through the augmented discrete
/// Lagrangian (Marsden & West, Acta Numerica 2001, §3.5; Leyendecker, Marsden
/// & Ortiz, "Variational integrators for constrained dynamical systems", ZAMM
/// 88 (2008) 677–708), which gives RATTLE (Andersen 1983; Leimkuhler & Reich,
/// "Simulating Hamiltonian Dynamics", 2004, §7.2) on the bodies' groups. With
/// Π = J ω (body frame), m v (world), generalized forces F = (f world, τ body)
/// = system.forces(t, y, gyroscopic = false) — the gyroscopic term is carried
/// by the discrete rotation update — and G(q) the Jacobian of the position
/// rows, one step (t_k, q_k, u_k) → (t_{k+1}, q_{k+1}, u_{k+1}) is
///   kick    Π⁺ = Π_k + (h/2)(τ_k − G_θ(q_k)ᵀ λ),   m v⁺ = m v_k + (h/2)(f_k − G_p(q_k)ᵀ λ),
///   drift   h Π⁺^ = F J_d − J_d Fᵀ  (F ∈ SO(3), per body),  R_{k+1} = R_k F,  p_{k+1} = p_k + h v⁺,
///           Φ(q_{k+1}, t_{k+1}) = 0,
///   kick    Π_{k+1} = Fᵀ Π⁺ + (h/2)(τ_{k+1} − G_θ(q_{k+1})ᵀ μ),
///           m v_{k+1} = m v⁺ + (h/2)(f_{k+1} − G_p(q_{k+1})ᵀ μ),
///           J(q_{k+1}) u_{k+1} = b(t_{k+1})  (all rows, gears included).
/// A rotation-only body has only the rotational part. The mid-step velocity
/// is ξ = (v⁺, log(F)/h): q_{k+1} = q_k ⊕ h ξ exactly.
///
/// ## The multipliers
/// λ (with ν for the gear rows, below) solves r(λ) = 0 by a quasi-Newton
/// iteration with the matrix −(h²/2) S(q_k), S = J M⁻¹ Jᵀ factored once per
/// step at q_k (dq_{k+1}/dλ = −(h²/2) M⁻¹ Jᵀ to leading order):
///   λ ← λ + (2/h²) S⁻¹ r(λ),
/// until max |r| ≤ tolerance, from λ = 0. The matrix is exact to O(h ω)
/// (G(q_{k+1}) vs G(q_k), and the derivative of the rotation update), and
/// that mismatch, amplified by the conditioning of S, sets the contraction,
/// so the start matters little: measured on the 3-D double pendulum of the
/// tests, 3.00 corrections per step from 0, 2.88 from the previous step's λ
/// and 2.58 from its linear extrapolation at h = 1e-3 (5.70, 5.74, 5.29 at
/// h = 1e-2). The stepper therefore keeps no state between steps
/// (deterministic, and `step` is const in earnest). Along chains S becomes
/// ill-conditioned and the contraction slows: on random revolute chains
/// (chain_builder.hpp, joint rates up to 3 rad/s) at h = 1e-3, 3.0 / 5.0 /
/// 7.4 / 10.9 corrections per step for N = 2 / 10 / 30 / 50 bodies; N = 100
/// needs h ≤ 2e-4 (8.2 per step) and stops, reported, at h ≥ 5e-4. The end kick is linear in μ: it is the
/// mass-orthogonal velocity projection u_{k+1} = u* − M⁻¹ Jᵀ S(q_{k+1})⁻¹
/// (J u* − b), u* the unconstrained end kick, with S(q_{k+1}) factored once.
///
/// ## Gear rows (velocity-only)
/// Rows that exist only on velocities are nonholonomic-style constraints
/// (McLachlan & Perlmutter, "Integrators for nonholonomic mechanical systems",
/// J. Nonlinear Sci. 16 (2006) 283–328): they are imposed on the mid-step
/// velocity by the symmetric discrete constraint
///   ½ (B(q_k) + B(q_{k+1})) ξ = 0,
/// with the reaction −(h/2) B(q_k)ᵀ ν in the first kick, and at the end of
/// the step with μ like every row. The row of r is h·½(B(q_k) + B(q_{k+1}))ξ
/// (the position-like defect over the step, in metres or radians), so one
/// iteration matrix S over all rows serves λ and ν together. A one-sided
/// B(q_k) ξ = 0 would be first order when the carrier turns (B(q_k) ξ differs
/// from B(q(t_{k+½})) q̇(t_{k+½}) by O(h)); the average is second order and
/// time-symmetric. For a gear on the ground (or a carrier that does not turn)
/// B ξ does not depend on q (the spin about a body-fixed axis, ω·r, and
/// log(F)·r is the turn of the step about r), so the position-level relation
/// α φ₁ + φ₂ = const holds to the iteration tolerance per step, without
/// truncation error.
///
/// ## Velocity-dependent forces (dashpots)
/// Discrete Lagrange–d'Alembert principle with the trapezoidal forcing
/// (Marsden & West 2001, §3.2; Kane, Marsden, Ortiz & West, IJNME 49 (2000)):
/// (h/2) F(t_k, q_k, u_k) in the first kick and (h/2) F(t_{k+1}, q_{k+1},
/// u_{k+1}) in the second — the dashpots see the velocities at the ends of the
/// step, as in the generalized Störmer–Verlet method (Hairer, Lubich & Wanner,
/// "Geometric Numerical Integration", §VI.3; second order and symmetric). The
/// first kick is explicit, so the λ iteration is the same as without dampers.
/// The second kick is implicit and linear in u_{k+1}; it is solved by the
/// fixed point u ← P(u* + (h/2) M⁻¹ D(u)) (D the dashpot forces, P the
/// projection of the end kick, S(q_{k+1}) factored once), which contracts by
/// about h c/(2 I), I the effective inertia of the damped joint coordinate (P
/// removes the motions the joints forbid), and stops when ‖Δu‖∞ ≤
/// velocity_tolerance·(1 + ‖u‖∞). (Evaluating the dashpots at the mid-step
/// velocity instead couples them to the λ iteration, which then contracts only
/// by h c/(2 I_body), I_body the smallest inertia of a body about its own
/// centre of mass: measured 0.2–0.5 per pass on a pendulum at h c/(2 I_o) = 0.002.)
/// Springs, gravity and applied moments are position- or time-dependent: they
/// enter F at (t_k, q_k) and (t_{k+1}, q_{k+1}) (the trapezoidal discrete
/// Lagrangian of the potential).
///
/// ## Properties
/// Second order. Without dampers, gears and time-dependent rows or forces it
/// is a variational integrator: symplectic on the constraint manifold, energy
/// error bounded without drift (measured on the double pendulum of the tests,
/// h = 1e-3, 10⁶ steps: max |E − E₀|/|E₀| = 4.5e-6, the means of the first
/// and last tenths differ by 5e-9 of E₀), max |Φ| ≤ tolerance at every step,
/// and — when no external moment acts (system.conservesAngularMomentum()) —
/// the spatial angular momentum Σ (R Π + p × m v) is conserved up to the
/// constraint tolerance and rounding (measured max ‖L − L₀‖/‖L₀‖ over 10⁴
/// steps: 7e-13 at tolerance 1e-12, 3e-14 at 1e-13): the reactions
/// Gᵀλ of constraints invariant under a global rotation, the joint springs
/// and dashpots have zero net moment at every configuration, and the kick–
/// drift–kick of each body changes Σ (R Π + p × m v) by (h/2)(net moment at
/// q_k + net moment at q_{k+1}) exactly (R F Fᵀ Π⁺ = R Π⁺, p_{k+1} × v⁺ =
/// p_k × v⁺). A spherical joint's rows are covariant, not invariant: their
/// net moment is O(|Φ|), so the momentum error per step is at the level of
/// the constraint tolerance.
///
/// ## Report
/// StepReport::newton_iterations = the quasi-Newton corrections of λ (0 when
/// the start already meets the tolerance; each pass costs one per-body LGVI
/// solve, one Φ and one S⁻¹ solve), plus, with dampers, the passes of the end
/// kick's fixed point; StepReport::residual = the final max |r|, the
/// constraint drift of the step. On failure (a singular S, a per-body rotation
/// equation without solution — h‖ω‖ ≥ 1 for the exponential map —, no
/// convergence or no contraction within max_iterations, a non-finite iterate)
/// the report says which via fail() and `detail`, and the step is not taken:
/// y is returned unchanged.
///
/// ## Cost
/// Per step: forces at both ends, two factorizations of S (at q_k and
/// q_{k+1}), and per correction one LGVI solve per body (1–2 Newton
/// iterations), Φ(q_{k+1}) and one S⁻¹ solve. Measured 9 µs per step on the
/// double pendulum of the tests (Release, h = 1e-3, 3 corrections per step).
///
/// ## System concept (what the stepper uses; joints/multibody's
/// MultibodySystem models it — integrators/ includes nothing of joints/)
///   using State, Scalar (double), RowSet (enumerator kAll);
///   int dofs(), bodyCount(), dofBegin(i); bool rotationOnly(i);
///   double bodyMass(i); const Eigen::Matrix3d& bodyInertia(i);
///   bool hasConstraints(), hasGears(), hasDampers(); int positionRowCount();
///   void forces(t, y, bool gyroscopic, Eigen::VectorXd* F);         (f world, τ body per body)
///   void positionResidual(t, y, Eigen::VectorXd* phi);
///   void gearVelocityResidual(y, Eigen::VectorXd* Bu);               (gear rows, untouched factorizations)
///   bool factorConstraints(t, y, RowSet, std::string* why, Eigen::VectorXd* b, Eigen::VectorXd* c);
///   schur(RowSet) with rows(), solve(rhs, x), multiplyJ(u, out),
///     addJTranspose(λ, scale, y), applyInverseMass(x, y);
/// and the State: velocities(), setVelocities(u) (per body (v, ω) or ω, as
/// the dofs), zeroTangent() and rplus(d) with d = [position increments per
/// body ((δp world, δθ body) or δθ); velocity increments], and isFinite(y).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/LU>

#include "integrators/lgvi.hpp"
#include "integrators/step_report.hpp"
#include "liegroup/invalid_input.hpp"
#include "liegroup/so3.hpp"
#include "liegroup/number_text.hpp"

namespace lieflow {

struct ConstrainedLgviOptions {
  /// The multiplier iteration stops when max |r| ≤ tolerance, r = (Φ(q_{k+1},
  /// t_{k+1}), h·½(B(q_k) + B(q_{k+1}))ξ): metres and radians, absolute. Φ
  /// is evaluated to about ε·max|p|, so scenes far from the origin need a
  /// looser tolerance (the iteration stops as "not contracting" otherwise).
  double tolerance = 1e-12;
  /// Quasi-Newton corrections of λ allowed per step.
  int max_iterations = 50;
  /// With dampers: the end kick's fixed point stops when ‖Δu‖∞ ≤
  /// velocity_tolerance · (1 + ‖u‖∞) (at most max_iterations passes).
  double velocity_tolerance = 1e-13;
  /// The per-body rotation update (Newton on the LGVI equation; map exp or Cayley).
  LgviOptions rotation;
};

/// The RATTLE-type constrained LGVI (see the file comment) for a System of
/// the documented concept.
template <typename System>
class ConstrainedLgviStepper {
 public:
  using State = typename System::State;
  using Scalar = double;
  static constexpr int kOrder = 2;

  /// Throws InvalidInput for a tolerance that is not finite and > 0, or
  /// max_iterations < 1, or a negative velocity_tolerance.
  explicit ConstrainedLgviStepper(ConstrainedLgviOptions options = {}) : options_(options) {
    if (!(options.tolerance > 0.0 && std::isfinite(options.tolerance)))
      throw InvalidInput("tolerance", "must be finite and > 0");
    if (options.max_iterations < 1) throw InvalidInput("max_iterations", "must be at least 1");
    if (!(options.velocity_tolerance >= 0.0 && std::isfinite(options.velocity_tolerance)))
      throw InvalidInput("velocity_tolerance", "must be finite and >= 0");
  }

  const ConstrainedLgviOptions& options() const { return options_; }
  int order() const { return kOrder; }

  /// One step of size h ≠ 0 from (t, y); see the file comment. The result
  /// lives in the stepper until its next step (y must not be that result);
  /// a failed step returns y. The step's vectors and states are kept between
  /// steps: nothing is allocated on the heap after the first step.
  const State& step(const System& system, double t, const State& y, double h,
                    StepReport* report = nullptr) const {
    StepReport local;
    StepReport& rep = report ? *report : local;
    rep = StepReport{};
    if (h == 0.0) return y;
    Step& s = step_;
    s.begin(system, t, y, h, options_);
    if (!s.factor(&rep)) return y;
    if (!s.solveMultipliers(&rep)) return y;
    const State& y1 = s.endKick(&rep);
    if (!rep.converged) return y;
    if (!isFinite(y1)) {
      rep.fail("constrained LGVI: the state became non-finite", std::numeric_limits<double>::infinity());
      return y;
    }
    return y1;
  }

 private:
  /// Per-body data of one step.
  struct Body {
    double mass = 0.0;
    Eigen::Matrix3d J, J_inv;
    LgviBodyDrift<double> drift;  ///< Π⁺ and the relative rotation F = R_k⁻¹ R_{k+1}
  };

  /// One step's work: the iteration over λ and the end kick. Its vectors,
  /// states and per-body data persist from step to step (the workspace).
  class Step {
   public:
    /// Starts a step from (t, y).
    void begin(const System& system, double t, const State& y, double h, const ConstrainedLgviOptions& options) {
      bodies_.resize(system.bodyCount());
      for (int i = 0; i < system.bodyCount(); ++i) {
        Body& b = bodies_[i];
        b.mass = system.rotationOnly(i) ? 0.0 : system.bodyMass(i);
        b.J = system.bodyInertia(i);
        b.J_inv = b.J.inverse();
      }
      sys_ = &system;
      t_ = t;
      y_ = &y;
      h_ = h;
      opt_ = &options;
      n_ = system.dofs();
      rows_ = position_rows_ = 0;
      y.velocitiesInto(&u_);
      d_.setZero(y.tangentSize());
      xi_.setZero(n_);
      gears_ = system.hasGears();
      system.forces(t, y, false, &F0_);  // F(t_k, q_k, u_k)
    }

    /// Factors S(q_k) over all rows (and keeps the gear targets b).
    bool factor(StepReport* rep) {
      if (!sys().hasConstraints()) return true;
      if (!factorAt(t_, *y_, &b_, rep)) return false;
      rows_ = sys().schur(System::RowSet::kAll).rows();
      position_rows_ = sys().positionRowCount();
      lambda_.setZero(rows_);  // the start (see "The multipliers")
      return true;
    }

    /// The quasi-Newton iteration λ ← λ + (2/h²) S(q_k)⁻¹ r(λ). Leaves y1_, ξ
    /// and the bodies' Π⁺ and F at the converged λ.
    bool solveMultipliers(StepReport* rep) {
      double previous = std::numeric_limits<double>::infinity();
      Eigen::VectorXd& correction = correction_;
      for (int it = 0;; ++it) {
        if (!evaluate(rep)) return false;
        const double err = rows_ > 0 ? residual_.lpNorm<Eigen::Infinity>() : 0.0;
        rep->residual = err;
        rep->newton_iterations = it;
        if (err <= sys().achievablePositionTolerance(y1_, opt_->tolerance)) return true;
        const bool stalled = it >= 2 && !(err < previous);
        if (!std::isfinite(err) || stalled || it == opt_->max_iterations) {
          rep->fail("constrained LGVI: the constraint iteration did not converge", err);
          std::ostringstream s;
          s << "max |Phi| = " << err << " (tolerance " << sys().achievablePositionTolerance(y1_, opt_->tolerance) << ") after " << it
            << " quasi-Newton corrections; ";
          if (it == opt_->max_iterations && !stalled)
            s << "max_iterations reached";
          else
            s << "not contracting: the step h = " << h_ << " is too large for the constraint iteration";
          rep->detail = s.str();
          return false;
        }
        sys().schur(System::RowSet::kAll).solve(residual_, correction);
        lambda_ += (2.0 / (h_ * h_)) * correction;
        previous = err;
      }
    }

    /// The end kick (see the file comment): u* = the kick by the forces at
    /// (t_{k+1}, q_{k+1}) without dashpots, then u_{k+1} = P(u* + (h/2) M⁻¹
    /// D(u_{k+1})), P the mass-orthogonal projection onto J(q_{k+1}) u = b
    /// (the μ of the file comment) and D the dashpot forces — a fixed point
    /// when there are dampers, one projection otherwise.
    const State& endKick(StepReport* rep) {
      State& y1 = result_;
      y1 = y1_;
      u_star_.setZero(n_);
      y1.setVelocities(u_star_);
      Eigen::VectorXd& F1 = F1_;
      sys().forces(t_ + h_, y1, false, &F1);  // no dashpot at u = 0
      Eigen::VectorXd& u_star = u_star_;
      for (int i = 0; i < sys().bodyCount(); ++i) {
        const Body& b = bodies_[i];
        const int o = sys().dofBegin(i), r = sys().rotationOnly(i) ? 0 : 3;
        if (r) u_star.segment<3>(o) = xi_.segment<3>(o) + (0.5 * h_ / b.mass) * F1.segment<3>(o);
        // ω* = J⁻¹ (Fᵀ Π⁺ + (h/2) τ_{k+1}) (the projection adds the reactions).
        const Eigen::Vector3d impulse = (0.5 * h_) * F1.segment<3>(o + r);
        u_star.segment<3>(o + r) = lgviEndKick(b.J, b.J_inv, b.drift, &impulse);
      }
      if (!sys().hasConstraints()) {
        y1.setVelocities(u_star);
        return y1;
      }
      Eigen::VectorXd& b1 = b1_;
      if (!factorAt(t_ + h_, y1, &b1, rep)) return y1;
      Eigen::VectorXd& u = u1_;
      u = u_star;
      project(b1, &u);
      if (sys().hasDampers() && !dampedEndKick(F1, u_star, b1, &u, rep)) return y1;
      y1.setVelocities(u);
      return y1;
    }

   private:
    const System& sys() const { return *sys_; }

    bool factorAt(double t, const State& y, Eigen::VectorXd* b, StepReport* rep) {
      std::string& why = why_;
      if (sys().factorConstraints(t, y, System::RowSet::kAll, &why, b, nullptr)) return true;
      rep->fail("constrained LGVI: singular constraint system", std::numeric_limits<double>::infinity());
      rep->detail = why;
      return false;
    }

    /// u ← u − M⁻¹ Jᵀ S⁻¹ (J u − b) with the factorization in schur(kAll).
    void project(const Eigen::VectorXd& b, Eigen::VectorXd* u) {
      auto& S = sys().schur(System::RowSet::kAll);
      S.multiplyJ(*u, Ju_);
      Ju_ -= b;
      S.solve(Ju_, nu_);
      JTnu_.setZero(n_);
      S.addJTranspose(nu_, 1.0, JTnu_);
      S.applyInverseMass(JTnu_, du_);
      *u -= du_;
    }

    /// The dashpot fixed point u ← P(u* + (h/2) M⁻¹ D(q_{k+1}, u)), D =
    /// F(t_{k+1}, q_{k+1}, u) − F(t_{k+1}, q_{k+1}, 0). Its contraction factor
    /// is about h c / (2 I), I the effective inertia of the damped coordinate.
    /// (Works on the state damped_ at q_{k+1}; result_ keeps u*.)
    bool dampedEndKick(const Eigen::VectorXd& F_undamped, const Eigen::VectorXd& u_star, const Eigen::VectorXd& b,
                       Eigen::VectorXd* u, StepReport* rep) {
      auto& S = sys().schur(System::RowSet::kAll);
      State& y1 = damped_;
      y1 = result_;
      Eigen::VectorXd &F = F_, &MinvD = MinvD_, &next = next_;
      double change = std::numeric_limits<double>::infinity();
      for (int pass = 1; pass <= opt_->max_iterations; ++pass) {
        y1.setVelocities(*u);
        sys().forces(t_ + h_, y1, false, &F);
        F -= F_undamped;
        S.applyInverseMass(F, MinvD);
        next = u_star + (0.5 * h_) * MinvD;
        project(b, &next);
        change = (next - *u).lpNorm<Eigen::Infinity>();
        *u = next;
        rep->newton_iterations += 1;
        if (change <= opt_->velocity_tolerance * (1.0 + u->lpNorm<Eigen::Infinity>())) return true;
        if (!std::isfinite(change)) break;
      }
      rep->fail("constrained LGVI: the implicit dashpot end kick did not converge", change);
      std::ostringstream s;
      s << "last velocity change " << change << " after " << opt_->max_iterations
        << " passes; h c / (2 I) of a damped joint coordinate is too large at h = " << h_;
      rep->detail = s.str();
      return false;
    }

    /// Kick and drift for the current λ: Π⁺, v⁺, F per body, ξ, q_{k+1}
    /// (y1_) and the residual r. False (with the report) when a body's
    /// rotation equation has no solution.
    bool evaluate(StepReport* rep) {
      impulse_ = F0_;  // F_k − Jᵀλ
      if (rows_ > 0) sys().schur(System::RowSet::kAll).addJTranspose(lambda_, -1.0, impulse_);
      for (int i = 0; i < sys().bodyCount(); ++i)
        if (!driftBody(i, rep)) return false;
      y1_ = *y_;
      y1_.rplusInPlace(d_);
      if (rows_ == 0) return true;
      residual_.resize(rows_);
      sys().positionResidual(t_ + h_, y1_, &phi_);
      residual_.head(position_rows_) = phi_;
      if (gears_) gearDefect(residual_.tail(rows_ - position_rows_));
      return true;
    }

    /// Kick Π⁺ = Π_k + (h/2)(τ − G_θᵀλ), v⁺ = v_k + (h/2m)(f − G_pᵀλ); drift
    /// h Π⁺^ = F J_d − J_d Fᵀ; the increments (h v⁺, log F) into d_ and ξ.
    bool driftBody(int i, StepReport* rep) {
      Body& b = bodies_[i];
      const int o = sys().dofBegin(i), r = sys().rotationOnly(i) ? 0 : 3;
      if (r) {
        const Eigen::Vector3d v_plus = u_.segment<3>(o) + (0.5 * h_ / b.mass) * impulse_.segment<3>(o);
        xi_.segment<3>(o) = v_plus;
        d_.template segment<3>(o) = h_ * v_plus;
      }
      const Eigen::Vector3d omega = u_.segment<3>(o + r), impulse = (0.5 * h_) * impulse_.segment<3>(o + r);
      lgviKickDrift(b.J, b.J_inv, omega, &impulse, h_, opt_->rotation, &b.drift);
      const LgviSolution<double>& sol = b.drift.solution;
      if (!sol.converged || !sol.f.allFinite()) {
        rep->fail("constrained LGVI: a body's rotation update did not converge", sol.residual);
        std::ostringstream s;
        s << "body " << i << ": |G(f)| = " << formatNumber(sol.residual) << " after " << sol.iterations
          << " Newton iterations, h|J^-1 Pi+| = " << formatNumber((b.J_inv * (h_ * b.drift.Pi_plus)).norm())
          << (opt_->rotation.map == LgviMap::kExponential
                  ? " (the exponential-map LGVI equation has no solution for h|omega| >= 1 about a principal axis)"
                  : "");
        rep->detail = s.str();
        return false;
      }
      const Eigen::Vector3d dtheta = opt_->rotation.map == LgviMap::kExponential
                                         ? sol.f
                                         : Eigen::Vector3d(SO3d(b.drift.F().normalized()).log());
      d_.template segment<3>(o + r) = dtheta;
      xi_.segment<3>(o + r) = dtheta / h_;
      return true;
    }

    /// out = h·½(B(q_k) + B(q_{k+1})) ξ − h b of the gear rows.
    template <typename Out>
    void gearDefect(Out out) {
      gear_a_ = *y_;
      gear_c_ = y1_;
      gear_a_.setVelocities(xi_);
      gear_c_.setVelocities(xi_);
      sys().gearVelocityResidual(gear_a_, &Ba_);
      sys().gearVelocityResidual(gear_c_, &Bc_);
      out = h_ * (0.5 * (Ba_ + Bc_) - b_.tail(rows_ - position_rows_));
    }

    const System* sys_ = nullptr;
    double t_ = 0.0;
    const State* y_ = nullptr;
    double h_ = 0.0;
    const ConstrainedLgviOptions* opt_ = nullptr;
    int n_ = 0;
    Eigen::VectorXd u_;
    std::vector<Body> bodies_;
    bool gears_ = false;
    int rows_ = 0, position_rows_ = 0;
    Eigen::VectorXd F0_, impulse_, xi_, lambda_, residual_, b_, phi_, correction_;
    Eigen::VectorXd F1_, u_star_, b1_, u1_, Ju_, nu_, JTnu_, du_, F_, MinvD_, next_, Ba_, Bc_;
    std::string why_;
    typename State::Tangent d_;
    State y1_, result_, damped_, gear_a_, gear_c_;
  };

  mutable Step step_;
  ConstrainedLgviOptions options_;
};

}  // namespace lieflow
