/// \file
/// A variational integrator for a mechanical system in generalized
/// coordinates q (the joint coordinates of a tree of rigid bodies, `lgvi`
/// with --formulation joint: angles and slides on vector spaces, spherical
/// joints and free roots on SO(3), below), L(q, q̇) = ½ q̇ᵀ M(q) q̇ − V(q),
/// with the non-conservative forces by the discrete Lagrange–d'Alembert
/// principle.
///
/// ## The discrete Lagrangian
/// Kinetic energy at the midpoint, potential by the trapezoidal rule
/// (Marsden & West, "Discrete mechanics and variational integrators", Acta
/// Numerica 10 (2001), §2.2 and §3.2):
///   L_d(q₀, q₁) = h T(q_m, v) − (h/2)(V(q₀) + V(q₁)),   q_m = (q₀ + q₁)/2,  v = (q₁ − q₀)/h,
/// with the forces Q (all of them: springs and gravity, −∂V/∂q, and the
/// dashpots, the time-dependent moments, the program's torques) at the ends
/// of the step, f⁻ = (h/2) Q(t₀, q₀, q̇₀), f⁺ = (h/2) Q(t₁, q₁, q̇₁). The
/// discrete Legendre transforms p₀ = −D₁L_d − f⁻, p₁ = D₂L_d + f⁺ give,
/// with ∂T/∂q taken at fixed rates,
///   M(q_m) v − (h/2) ∂T/∂q(q_m, v) = p₀ + (h/2) Q₀,                 (1)
///   p₁ = M(q_m) v + (h/2) ∂T/∂q(q_m, v) + (h/2) Q₁,   q₁ = q₀ + h v,  (2)
/// and q̇₁ = M(q₁)⁻¹ p₁ (the continuous Legendre transform: the state keeps
/// the rates, p₀ = M(q₀) q̇₀). Second order and symmetric; without dashpots
/// and time-dependent forces symplectic, with an energy error that stays
/// bounded, and a coordinate whose shift leaves L invariant (the first angle
/// of a tree turning freely about a fixed axis, no gravity or gravity along
/// it) keeps its momentum p to round-off (discrete Noether theorem). Why not
/// the trapezoidal kinetic energy as well: its (1) holds M(q₁) too, and M at
/// the unknown midpoint costs one pass per iteration, M at q₁ another.
///
/// ## Rotations
/// A spherical joint's relative rotation and a free root's orientation live
/// on SO(3), not on a vector space. On each of them the discrete Lagrangian
/// takes the midpoint on the group, N_m = N₀ exp(ξ/2), ξ = log(N₀ᵀ N₁) = h v,
/// with the body rates v there (L_d is then a function on the group: a
/// variational integrator on SO(3) as Lee, Leok & McClamroch's, Comput.
/// Methods Appl. Mech. Engrg. 196 (2007), with the midpoint and the joints
/// of Johnson & Murphey 2009). Its derivatives in the body's terms
/// (System::rotationStartTerms, rotationEndMomenta: the Jacobians of exp) take the
/// places of M v and ∂T/∂q in (1) and of p₁ in (2); at ξ = 0 they are the
/// vector-space midpoint rule's. L_d is invariant under a turn of the whole
/// system (N₀, N₁ → G N₀, G N₁ leaves ξ), so a free system keeps its
/// angular momentum to round-off (discrete Noether).
///
/// ## Free roots and constraint rows (the System's step coordinates)
/// The System may write the step in coordinates of its own: ArticulatedSystem
/// takes a free root's translation as its tree's centre of mass (so the
/// centre moves exactly under gravity and the momentum about it is kept;
/// articulated_system.hpp), with momenta() and rates() mapping the state's
/// rates to and from them. Constraint rows are RATTLE's multipliers
/// (Hairer, Lubich & Wanner, "Geometric Numerical Integration", 2nd ed.,
/// §VII.1.4, on the discrete Lagrangian above):
///   M(q_m) v − (h/2) ∂T/∂q = p₀ + (h/2) Q₀ − G(q₀)ᵀλ,   Φ(q₁) = 0,
///   p₁ = … (2) … + G(q₁)ᵀμ,                              G(q₁) q̇₁ = 0,
/// G = ∂Φ̇/∂q̇ the rows' Jacobian. Each increment of the iteration takes the
/// multiplier that meets the rows to first order with G(q₀)
/// (projectIncrement): coupling rows G q = const, linear, as G v = 0; a
/// loop's rows as Φ(q₀ ⊕ h v) = 0; gear rows, imposed on velocities, as
/// B(q_m) v = 0 at the midpoint (symmetric, as the step). (1)'s right side
/// then loses G(q₀)ᵀλ (constraintImpulse), and p₁ takes G(q₁)ᵀμ so that
/// G(q₁) q̇₁ = 0 (rates()). The rows' G(q₀) stands in for G(q₁) in the
/// increments as M(q₀) does for M(q_m): the same O(h |q̇|) per pass.
///
/// ## The iteration
/// (1) is solved for v by the quasi-Newton iteration
///   v ← v + M(q₀)⁻¹ r(v),  r(v) = p₀ + (h/2)(Q₀ + ∂T/∂q(q_m, v)) − M(q_m) v,
/// with M(q₀) factored once per step (the factorization at q₁ of the step
/// before when the step starts where that one ended: the same numbers,
/// computed once). The exact Jacobian of r is −(M(q_m) + (h/2)(C − Cᵀ)) +
/// O(h²), C = ∂(M v)/∂q, so each pass gains a factor of order h |q̇| (the
/// joint rates times the step; the skew, gyroscopic part C − Cᵀ is what
/// M(q₀) leaves out): measured 0.002–0.01 per pass at h = 1e-3 on the
/// falling chains of bench/multibody. On a turning tree with light links
/// (Talos's wrists and grippers turning at 2 rad/s, h = 2 ms) M(q₀)⁻¹ scales
/// that part up beyond 1 in a few modes and the plain iteration diverges
/// there; the passes are therefore Anderson-accelerated (andersonStep:
/// depth 4, least squares in the kinetic-energy norm), which solves for
/// those modes. Measured per step at h = 2 ms, plain against accelerated:
/// Talos turning 21.3 passes, 91 µs (half its steps substepped) against
/// 2.9 passes, 13 µs; chain-30 4.92 against 4.44 passes; the UR5 3.07
/// against 2.77; Solo12 turning 2.30 against 2.29 (4 % dearer per step
/// for the bookkeeping). The start is the quartic extrapolation
/// of the mid-step rates of the last five steps when the step continues them
/// (same h; 5 v₋₁ − 10 v₋₂ + 10 v₋₃ − 5 v₋₄ + v₋₅, error O(h⁵)), lower orders
/// after fewer, else q̇₀ (error O(h)); on chain-10 at h = 1e-3 it brings the
/// passes per step from 4.27 (quadratic) and 4.7 (linear) to 3.18. The
/// start sets only how many passes the iteration takes.
///
/// The iteration stops when ‖Δv‖ ≤ tolerance ‖v‖ in the kinetic-energy norm
/// (‖x‖² = xᵀ M x; Δvᵀ M(q₀) Δv = Δvᵀ r costs nothing), also when the
/// changes to come, extrapolated at the rate of the last two, add up to
/// that; it accepts the rounding floor (no further decrease, below 1000 ×
/// the bound). It gives up after four passes without a new smallest change
/// or after max_iterations, and the step is then taken as 2, 4, …, 16 steps
/// of h/2^k (a composition of the same symmetric, symplectic step; counted
/// in StepReport::substeps and the run's `substepped_steps`), failing only
/// when those fail too. Measured: at h = 1e-3 chain-100 (3 s) and chains up
/// to N = 30 never substep; a chain-6 spun at 100 rad/s does at h = 0.1.
///
/// With (1) met, (2) is p₁ = p₀ + (h/2)(Q₀ + Q₁) + h ∂T/∂q(q_m, v). With
/// dashpots Q₁ depends on q̇₁ = M(q₁)⁻¹ p₁, linearly: Q(q̇) = Q(0) − D_c q̇
/// (D_c the dashpot constants on their coordinates), so q̇₁ solves
/// (M(q₁) + (h/2) D_c) q̇₁ = p₁* + (h/2) Q(t₁, q₁, 0), one solve with the
/// factorization at q₁ holding (h/2) D_c as an armature (System::frames) —
/// for any dashpot and step, where a fixed-point iteration contracts only by
/// about h c/(2 I) (8 passes per step on the Panda's light fingers).
///
/// ## Cost
/// One factorization (at q₁; O(n), an articulated-body pass), then per
/// iteration one kinematics pass at q_m, one momentum pass (out and back)
/// and one solve with the factorization (two O(n) passes without 6 × 6
/// products); nothing allocated after the first step.
///
/// ## System concept (joints/articulated's ArticulatedSystem models it)
///   using State (members q, u: Eigen::VectorXd), Frames;
///   int dofs();
///   void frames(t, y, bool factor, Frames*, w);     (at y.q; factored: M + w D_c)
///   void solveMass(const Frames&, rhs, x*);          (x = M(q)⁻¹ rhs)
///   void kinetic(const Frames&, v, Mv*, dTdq*);      (M(q) v, ∂T/∂q(q, v))
///   void kineticAt(t, y, v, near, Frames*, Mv*, dTdq*); (frames at y.q, then kinetic, in one pass;
///                                                     near: frames at a nearby configuration)
///   void generalizedForces(t, const Frames&, u, Q*);
///   bool hasVelocityDependentForces();
///   void momenta(const Frames&, u, p*);              (the momenta of the state's rates u, step's coordinates)
///   void rates(const Frames&, p*, u*);               (the state's rates of the momenta p, p onto the rows)
///   void projectIncrement(start, mid, y, v, h, dv*, r*); (the constraint rows' multipliers in the iteration)
///   void constraintImpulse(start, b*);               (b −= G(q₀)ᵀλ, λ of the last increment)
///   void placeFreeRoots(start, end, y0, v, h, y1*);  (what advance leaves to the end's frames)
///   void advance(y, v, s, State* out);              (out's configuration y ⊕ s v)
///   static bool sameConfiguration(a, b);
///   void rotationStartTerms(v, h, Mv*, dTdq*, terms*); (the rotations' −D₁L_d terms; RotationTerms keeps the body's)
///   void rotationEndMomenta(h, terms, b, p*);        (the rotations' D₂L_d in the body's terms)
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "integrators/step_report.hpp"
#include "liegroup/number_text.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {

struct JointSpaceVariationalOptions {
  /// The iteration over v stops when ‖Δv‖ ≤ tolerance · ‖v‖ in the
  /// kinetic-energy norm.
  double tolerance = 1e-14;
  /// Passes allowed per step (each iteration).
  int max_iterations = 20;
  /// When the iteration does not converge, the step is taken as 2, 4, …,
  /// 2^max_halvings steps of h/2^k (the composition of symmetric symplectic
  /// steps is one); 0: fail at once.
  int max_halvings = 4;
};

template <typename System>
class JointSpaceVariationalStepper {
 public:
  using State = typename System::State;
  using Frames = typename System::Frames;
  using Scalar = double;
  static constexpr int kOrder = 2;

  /// Throws InvalidInput for a tolerance that is not finite and > 0 or
  /// max_iterations < 1.
  explicit JointSpaceVariationalStepper(JointSpaceVariationalOptions options = {}) : options_(options) {
    if (!(options.tolerance > 0.0 && std::isfinite(options.tolerance)))
      throw InvalidInput("tolerance", "must be finite and > 0");
    if (options.max_iterations < 1) throw InvalidInput("max_iterations", "must be at least 1");
  }

  const JointSpaceVariationalOptions& options() const { return options_; }
  int order() const { return kOrder; }

  /// One step of size h ≠ 0 from (t, y); see the file comment. The result
  /// lives in the stepper until its next step (y must not be that result); a
  /// failed step returns y with the report saying why.
  const State& step(const System& system, double t, const State& y, double h, StepReport* report = nullptr) const {
    StepReport local;
    StepReport& rep = report ? *report : local;
    rep = StepReport{};
    if (h == 0.0) return y;
    if (stepOnce(system, t, y, h, &rep)) return result_;
    // Substeps: 2^k steps of h/2^k, until they all converge.
    Work& w = work_;
    for (int k = 1; k <= options_.max_halvings; ++k) {
      const long m = 1L << k;
      const double hs = h / static_cast<double>(m);
      w.substep = y;
      StepReport sub;
      int passes = 0;
      bool ok = true;
      for (long i = 0; i < m && ok; ++i) {
        ok = stepOnce(system, t + static_cast<double>(i) * hs, w.substep, hs, &sub);
        passes += sub.newton_iterations;
        if (ok && i + 1 < m) w.substep = result_;
      }
      if (ok) {
        rep = sub;
        rep.newton_iterations = passes;
        rep.substeps = static_cast<int>(m);
        return result_;
      }
      rep = sub;
    }
    if (options_.max_halvings > 0) {
      std::ostringstream s;
      s << rep.detail << " (the step h = " << h << " failed whole and in 2 to " << (1L << options_.max_halvings)
        << " substeps)";
      rep.detail = s.str();
    }
    return y;
  }

 private:
  /// Two times (or steps) closer than this fraction of the step are the
  /// same: a run's k-th step starts at t₀ + k h and lasts (t₀ + (k+1)h) −
  /// (t₀ + k h), which differ from the last step's end and length in their
  /// last bits. The continued quantities (p₁, Q₁) and the extrapolated start
  /// then carry over; without this a run through integrateFixedStep lost
  /// them at every step (5.3 passes per step instead of 3.4 on a chain of 10).
  static constexpr double kSameInstantFraction = 1e-9;
  static bool sameInstant(double a, double b, double h) {
    return std::abs(a - b) <= kSameInstantFraction * std::abs(h);
  }

  /// One step of size h (the file comment) into result_; false, with the
  /// report saying why, when an iteration does not converge.
  bool stepOnce(const System& system, double t, const State& y, double h, StepReport* report) const {
    StepReport& rep = *report;
    rep = StepReport{};
    Work& w = work_;
    // M(q₀) factored: reuse the end of the last step when this one starts there.
    const bool continues = w.end_valid && w.end_system == &system && System::sameConfiguration(w.end_config, y);
    // The factorizations hold the dashpots' (h/2) D_c (System::frames): the
    // end kick's matrix, and as good a start for (1)'s iteration.
    const bool implicit_forces = system.hasVelocityDependentForces();
    const double damping_weight = implicit_forces ? 0.5 * h : 0.0;
    if (!continues) system.frames(t, y, true, &w.end, damping_weight);
    std::swap(w.start, w.end);
    w.end_valid = false;
    // p₀ = M(q₀) q̇₀ and Q₀: the last step's p₁ and Q₁ when this one continues
    // it (the same quantities, p₁ exactly the momentum q̇₀ was solved from).
    if (!(continues && sameInstant(t, w.t_end, h))) {
      system.momenta(w.start, y.u, &w.p_end);
      system.generalizedForces(t, w.start, y.u, &w.Q_end);
    }
    w.b = w.p_end + (0.5 * h) * w.Q_end;  // p₀ + (h/2) Q₀

    // (1): v from the mid-step rates v₋₁ … v₋₅ of the steps this one
    // continues (same h), extrapolated by the polynomial through as many as
    // there are (quartic: error O(h⁵)); after one step 2 q̇₀ − v₋₁ (O(h²));
    // else q̇₀ (O(h)). The start only sets how many passes the iteration takes.
    if (!(continues && sameInstant(h, w.h_last, h))) w.history = 0;
    if (w.history < 3) system.solveMass(w.start, w.p_end, &w.u_step);  // q̇₀ in the step's coordinates
    if (w.history >= 5)
      w.v = 5.0 * (w.v1 - w.v4) + 10.0 * (w.v3 - w.v2) + w.v5;
    else if (w.history >= 4)
      w.v = 4.0 * (w.v1 + w.v3) - 6.0 * w.v2 - w.v4;
    else if (w.history >= 3)
      w.v = 3.0 * (w.v1 - w.v2) + w.v3;
    else if (w.history >= 1)
      w.v = 2.0 * w.u_step - w.v1;
    else
      w.v = w.u_step;
    w.mid = y;
    if (!quasiNewton(system, t, y, h, &rep)) {
      rep.fail("lgvi (joint coordinates): the iteration for the mid-step rates did not converge", rep.residual);
      std::ostringstream s;
      s << "last change of the rates " << formatNumber(rep.residual) << " (kinetic-energy norm) after " << rep.newton_iterations
        << " passes at h = " << h << ": "
        << (rep.newton_iterations >= options_.max_iterations ? "max_iterations reached"
                                                              : "the quasi-Newton iteration does not contract");
      rep.detail = s.str();
      return false;
    }

    // The constraint impulse of the first half: b = −D₁L_d (a loop's G(q₀)ᵀλ).
    system.constraintImpulse(w.start, &w.b);

    // (2): q₁, p₁* = p₀ + (h/2) Q₀ + h ∂T/∂q(q_m, v), q̇₁.
    State& y1 = result_;
    y1 = y;
    system.advance(y, w.v, h, &y1);
    system.frames(t + h, y1, true, &w.end, damping_weight);
    system.placeFreeRoots(w.start, w.end, y, w.v, h, &y1);
    w.p1 = w.b + h * w.dT;
    system.rotationEndMomenta(h, w.rotation_terms, w.b, &w.p1);  // the rotations' D₂L_d
    if (!implicit_forces) {
      system.generalizedForces(t + h, w.end, w.v, &w.Q);
      w.r = w.p1 + (0.5 * h) * w.Q;
      system.rates(w.end, &w.r, &w.dv);
      y1.u = w.dv;
    } else {
      // Q(q̇) = Q(0) − D_c q̇: (M₁ + (h/2) D_c) q̇₁ = p₁* + (h/2) Q(0) in one
      // solve, then p₁ = p₁* + (h/2) Q(q̇₁) (+ Gᵀμ, from rates()).
      w.dv.setZero(y.u.size());
      system.generalizedForces(t + h, w.end, w.dv, &w.Q0);
      w.r = w.p1 + (0.5 * h) * w.Q0;
      system.rates(w.end, &w.r, &w.dv);
      y1.u = w.dv;
      system.generalizedForces(t + h, w.end, y1.u, &w.Q);
      w.r += (0.5 * h) * (w.Q - w.Q0);
    }
    if (!isFinite(y1)) {
      rep.fail("lgvi (joint coordinates): the state became non-finite", std::numeric_limits<double>::infinity());
      return false;
    }
    w.end_config = y1;
    w.end_system = &system;
    w.end_valid = true;
    w.h_last = h;
    w.t_end = t + h;
    std::swap(w.v5, w.v4);
    std::swap(w.v4, w.v3);
    std::swap(w.v3, w.v2);
    std::swap(w.v2, w.v1);
    w.v1 = w.v;
    w.history = std::min(w.history + 1, 5);
    std::swap(w.p_end, w.r);  // p₁ = p₁* + (h/2) Q₁
    std::swap(w.Q_end, w.Q);
    return true;
  }

  /// r(v) = p₀ + (h/2)(Q₀ + ∂T/∂q(q_m, v)) − M(q_m) v, q_m = q₀ + (h/2) v, into
  /// *r (with M(q_m) v and ∂T/∂q into *Mv, *dT).
  void residual(const System& system, double t, const State& y, double h, const Eigen::VectorXd& v,
                Eigen::VectorXd* Mv, Eigen::VectorXd* dT, Eigen::VectorXd* r) const {
    Work& w = work_;
    system.advance(y, v, 0.5 * h, &w.mid);
    system.kineticAt(t + 0.5 * h, w.mid, v, w.start, &w.midframes, Mv, dT);
    system.rotationStartTerms(v, h, Mv, dT, &w.rotation_terms);
    *r = w.b + (0.5 * h) * *dT - *Mv;
  }

  /// Whether a change meets the bound: itself, or with the changes to come
  /// at the rate of the last two (ρ/(1 − ρ) · change); or, no longer
  /// decreasing, within 1000 × the bound (the rounding floor).
  static bool converged(double change, double previous, double bound) {
    const double rate = change / previous;  // 0 on the first pass (previous = ∞)
    return change <= bound || (previous < std::numeric_limits<double>::infinity() && rate < 0.5 &&
                               change * rate / (1.0 - rate) <= bound) ||
           (!(change < previous) && change <= 1e3 * bound);
  }

  /// The quasi-Newton iteration over v (file comment) from w.v; false when
  /// it does not contract (no new smallest change in four passes) or
  /// reaches max_iterations — w.v is then its best iterate.
  bool quasiNewton(const System& system, double t, const State& y, double h, StepReport* rep) const {
    Work& w = work_;
    double previous = std::numeric_limits<double>::infinity(), best = previous;
    int stalls = 0;
    for (int it = 1;; ++it) {
      residual(system, t, y, h, w.v, &w.Mv, &w.dT, &w.r);
      system.solveMass(w.start, w.r, &w.dv);
      system.projectIncrement(w.start, w.midframes, y, w.v, h, &w.dv, &w.r);
      // Sizes in the kinetic-energy norm: ‖Δv‖ = √(Δvᵀ M(q₀) Δv) = √(Δvᵀ r),
      // ‖v‖ = √(vᵀ M(q_m) v). (In the max norm the rounding of r, relative to
      // the heavy coordinates' momenta, shows through M⁻¹ in the light ones
      // amplified by the condition number of M: 1e5 on chain-100.)
      const double change = std::sqrt(std::max(0.0, w.dv.dot(w.r)));
      const double bound = options_.tolerance * std::sqrt(std::max(0.0, w.v.dot(w.Mv)));
      rep->newton_iterations = it;
      rep->residual = change;
      if (change < best) {
        best = change;
        stalls = 0;
        w.v_best = w.v;
      } else {
        ++stalls;
      }
      if (converged(change, previous, bound)) {
        w.v += w.dv;
        return true;
      }
      if (!std::isfinite(change) || stalls >= 4 || it == options_.max_iterations) {
        w.v = w.v_best;
        return false;
      }
      andersonStep(it == 1);
      previous = change;
    }
  }

  /// The next iterate by Anderson acceleration (Walker & Ni, SIAM J. Numer.
  /// Anal. 49 (2011), type II) of the fixed-point map g(v) = v + f(v), f the
  /// quasi-Newton increment M(q₀)⁻¹ r(v): with the last m differences ΔF of f
  /// and ΔG of g, γ = argmin ‖f − ΔF γ‖ in the kinetic-energy norm (Gram
  /// matrix ΔFᵀ M(q₀) ΔF = ΔFᵀ ΔR, the differences of r: no extra solve) and
  /// v ← v + f − ΔG γ. On a linear map it is GMRES over the last m
  /// increments, so the few modes the quasi-Newton matrix M(q₀) gets wrong by
  /// a factor beyond 1 (the gyroscopic part it leaves out, large on light
  /// links of a turning tree) are solved for instead of amplified. The
  /// converged v is the same; only the path there changes. `first`: a new
  /// step, no history yet (the plain step v + f).
  void andersonStep(bool first) const {
    Work& w = work_;
    const Eigen::Index n = w.v.size();
    if (w.anderson_F.rows() != n) {
      w.anderson_F.resize(n, kAndersonDepth);
      w.anderson_G.resize(n, kAndersonDepth);
      w.anderson_R.resize(n, kAndersonDepth);
    }
    if (first) {
      w.anderson_count = 0;
      w.anderson_next = 0;
    } else {
      const int c = w.anderson_next;
      w.anderson_F.col(c) = w.dv - w.f_last;
      w.anderson_R.col(c) = w.r - w.r_last;
      w.anderson_G.col(c) = (w.v + w.dv) - w.g_last;
      w.anderson_next = (c + 1) % kAndersonDepth;
      w.anderson_count = std::min(w.anderson_count + 1, kAndersonDepth);
    }
    w.f_last = w.dv;
    w.r_last = w.r;
    w.g_last = w.v + w.dv;
    w.v += w.dv;
    const int m = w.anderson_count;
    if (m == 0) return;
    // The m × m normal equations in a fixed 4 × 4 block (identity beyond m:
    // those γ are 0), symmetrized, regularized at kAndersonRegularization of
    // its trace against columns that repeat one another.
    Eigen::Matrix<double, kAndersonDepth, kAndersonDepth> A =
        Eigen::Matrix<double, kAndersonDepth, kAndersonDepth>::Identity();
    Eigen::Matrix<double, kAndersonDepth, 1> rhs = Eigen::Matrix<double, kAndersonDepth, 1>::Zero();
    double trace = 0.0;
    for (int i = 0; i < m; ++i) {
      for (int j = 0; j <= i; ++j) {
        A(i, j) = A(j, i) =
            0.5 * (w.anderson_F.col(i).dot(w.anderson_R.col(j)) + w.anderson_F.col(j).dot(w.anderson_R.col(i)));
      }
      rhs(i) = w.anderson_F.col(i).dot(w.r);
      trace += A(i, i);
    }
    if (!(trace > 0.0) || !std::isfinite(trace)) return;
    for (int i = 0; i < m; ++i) A(i, i) += kAndersonRegularization * trace;
    const Eigen::LDLT<Eigen::Matrix<double, kAndersonDepth, kAndersonDepth>> ldlt(A);
    const Eigen::Matrix<double, kAndersonDepth, 1> gamma = ldlt.solve(rhs);
    if (ldlt.info() != Eigen::Success || !gamma.allFinite()) return;
    // The valid columns only: the ring fills from column 0, and the others
    // are not yet written (0 × an unset value is not 0 when it is NaN).
    w.v.noalias() -= w.anderson_G.leftCols(m) * gamma.head(m);
  }

  /// The step's vectors and frames, kept from step to step.
  struct Work {
    Frames start, end, midframes;
    Eigen::VectorXd p_end, Q_end, Q, b, v, Mv, dT, r, dv, p1;
    Eigen::VectorXd u_step;  ///< q̇ at the step's start in its coordinates (the iteration's start)
    Eigen::VectorXd Q0;      ///< the end's forces at rest (the dashpots' part left out)
    State end_config;  ///< where the last step ended (its configuration is compared)
    typename System::RotationTerms rotation_terms;  ///< the rotations' body terms at the last midpoint
    Eigen::VectorXd v_best;
    State substep;  ///< the start of the next substep (see step())
    State mid;
    const System* end_system = nullptr;
    bool end_valid = false;
    double h_last = 0.0, t_end = 0.0;
    Eigen::VectorXd v1, v2, v3, v4, v5;  ///< the last steps' mid-step rates, newest first
    int history = 0;             ///< how many of them continue into this step
    /// Anderson acceleration's last kAndersonDepth differences of f, g and r
    /// (columns of a ring, anderson_next the next to overwrite) and the last f, r, g.
    Eigen::MatrixXd anderson_F, anderson_G, anderson_R;
    Eigen::VectorXd f_last, r_last, g_last;
    int anderson_count = 0, anderson_next = 0;
  };

  /// Anderson acceleration's memory: the last 4 increments (a handful of
  /// badly approximated modes: a turning tree's light links).
  static constexpr int kAndersonDepth = 4;
  /// Added to the normal equations' diagonal, relative to their trace: keeps
  /// γ bounded when two differences are nearly parallel (near convergence).
  static constexpr double kAndersonRegularization = 1e-10;

  mutable Work work_;
  mutable State result_;
  JointSpaceVariationalOptions options_;
};

}  // namespace lieflow
