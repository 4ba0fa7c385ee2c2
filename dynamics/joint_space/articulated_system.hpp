/// \file
/// Forward dynamics of a tree in joint coordinates: the articulated-body
/// algorithm (Featherstone 1983; "Rigid Body Dynamics Algorithms", 2008,
/// §7.3) in world coordinates about the world origin (as Pinocchio's ABA:
/// no coordinate transform between a body and its parent, each body's
/// spatial inertia is moved to the world once per evaluation), O(n) in the
/// number of bodies.
///
/// Spatial vectors (Featherstone's notation, world axes, reference point the
/// world origin O): a motion V = (ω, v_O), v_O the velocity of the body point
/// passing through O; a force (n_O, f). A body of mass m, centre of mass c and
/// world inertia J_w = R J Rᵀ has I_O V = (J_w ω + c × m v_c, m v_c),
/// v_c = v_O + ω × c. A joint's motion subspace S (6 × dofs) in world
/// coordinates:
///   revolute   s = σ (A, x × A),         A = R_main a,  x the anchor;
///   universal  s₁ = σ (A₁, x × A₁), s₂ = σ (A₂, x × A₂), A₁ = R_main a₁, A₂ = R_sec a₂;
///   spherical  S = (R_c, [x]× R_c)       (u = ω_rel in the child's axes),
///   prismatic  s = σ (0, A),             A = R_main a (a translation along A),
/// σ = +1 when the parent is the joint's main body, −1 otherwise. Then
///   V_c = V_p + S u,    a_c = a_p + S u̇ + Ṡ u,
/// with Ṡ u = V_p ×ₘ (S u) for revolute, prismatic and spherical joints (their
/// columns are fixed in the child and turn with it: ṡ = V_c ×ₘ s, and
/// (Su) ×ₘ (Su) = 0; a prismatic column is fixed in the main body, which is
/// the parent or the child, and (0, A) ×ₘ (0, A) = 0 either way)
/// and Ṡ u = σ (V_main ×ₘ s₁ φ̇₁ + V_sec ×ₘ s₂ φ̇₂) for a universal joint
/// (s₁ is fixed in the main body, s₂ in the secondary). Gravity is a force
/// (c × m g, m g) on each body that translates.
///
/// A rotation-only body (centre of mass c held, as in the maximal
/// formulation) turns with its joint about c: its motion is P(V_p + S_x u)
/// with P (ω, v) = (ω, c × ω), a constant linear map (the support takes the
/// force: the parent receives Pᵀ f = (n − c × f, 0), the moment about c). The
/// recursion keeps its form with V_c = P V_p + S u, S = P S_x, the bias P Ṡ_x u,
/// and Pᵀ I_a P, Pᵀ p_a passed to the parent.
///
/// A prescribed coordinate is not integrated: its angle, rate and
/// acceleration are the time function's at the stage time, and its column
/// contributes S_p φ̇(t) to V and S_p φ̈(t) to the bias acceleration; the ABA
/// runs over the free columns only. The state keeps a slot for it that is
/// advanced with the function's rate (so the state stays near the truth),
/// but every evaluation and every output uses the function itself.
///
/// Model/data split: ArticulatedModel (articulated_model.hpp) is built once;
/// the workspace ArticulatedData (articulated_data.hpp) is allocated at
/// construction and reused by every evaluation, so a step allocates nothing.
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "dynamics/joint_space/articulated_data.hpp"
#include "dynamics/joint_space/articulated_model.hpp"
#include "dynamics/joint_space/articulated_state.hpp"
#include "dynamics/joint_space/spatial_algebra.hpp"
#include "dynamics/joint_space/tree_passes.hpp"

namespace lieflow {
namespace articulated {

/// One joint's outputs (CSV `J.phi, J.phidot, J.moment`): angles, rates and
/// the moment the joint exerts on its main body about each axis (the same
/// definition as the maximal formulation's JointOutput).
struct ArticulatedJointOutput {
  int coordinates = 0;
  std::array<double, 3> phi{{0.0, 0.0, 0.0}}, phidot{{0.0, 0.0, 0.0}}, moment{{0.0, 0.0, 0.0}};
  /// A weld's reaction on its secondary body (the maximal formulation's
  /// J.fx … J.mz): the force and its moment about the anchor, main body's axes.
  bool welded = false;
  std::array<double, 6> reaction{{0.0, 0.0, 0.0, 0.0, 0.0, 0.0}};
};

class ArticulatedSystem {
 public:
  using Scalar = double;
  using State = ArticulatedState;
  using Tangent = Eigen::VectorXd;
  /// A body torque from a program (UserLoads::BodyTorque): body axes, from t,
  /// the orientation, the centre of mass, ω (body axes) and v_c (world).
  using UserTorque = std::function<Eigen::Vector3d(double t, const Eigen::Quaterniond& q, const Eigen::Vector3d& p,
                                                   const Eigen::Vector3d& omega, const Eigen::Vector3d& v)>;

  explicit ArticulatedSystem(ArticulatedModel model);

  const ArticulatedModel& model() const { return model_; }
  /// Whether a body floats on a free joint (a root no joint holds).
  bool hasFreeRoot() const {
    for (const ArticulatedBody& b : model_.bodies)
      if (b.kind == JointKind::kFree) return true;
    return false;
  }
  int dofs() const { return model_.dofs(); }
  int bodyCount() const { return model_.bodyCount(); }

  /// A torque from a program on tree body i.
  void setUserTorque(int i, UserTorque torque);
  bool hasUserTorques() const { return has_user_torques_; }

  /// F = (u as position increments, u̇): the right-hand side ẏ = y · F.
  void velocity(double t, const State& y, Tangent* F) const;
  /// Whether F does not depend on t: no prescribed coordinate, applied
  /// moment M(t), program moment or program torque (an implicit stepper
  /// then evaluates its stages at one point once).
  bool autonomous() const;

  /// The accelerations u̇ at (t, y) into *udot (size dofs()).
  void accelerations(double t, const State& y, Eigen::VectorXd* udot) const;

  /// The velocities u whose body velocities are closest, in the kinetic-energy
  /// metric, to the given ones (ω in body axes, v_c world; by tree index),
  /// with prescribed coordinates at their function's rate at t: the
  /// mass-metric projection the maximal formulation applies to initial
  /// velocities. The angles of `y` are used; its u is replaced.
  void projectVelocities(double t, const std::vector<Eigen::Vector3d>& omega_body,
                         const std::vector<Eigen::Vector3d>& v_com, State* y) const;

  /// Poses and velocities of every body at (t, y), by tree index, valid until
  /// the next call of any function of this system.
  void kinematics(double t, const State& y) const;
  const Eigen::Matrix3d& rotation(int i) const { return data_.bodies[i].R; }
  const Eigen::Vector3d& centreOfMass(int i) const { return data_.bodies[i].c; }
  Eigen::Vector3d angularVelocityBody(int i) const { return data_.bodies[i].R.transpose() * data_.bodies[i].V.head<3>(); }
  Eigen::Vector3d velocityOfCentre(int i) const {
    return data_.bodies[i].V.tail<3>() + data_.bodies[i].V.head<3>().cross(data_.bodies[i].c);
  }

  /// The terms of M(q) v̇ + g(q, v, t) = 0 for the generalized-α method
  /// (integrators/generalized_alpha.hpp, articulated_second_order.hpp): the
  /// joint-space mass matrix by the composite-rigid-body algorithm
  /// (Featherstone 2008, §6.2, in world coordinates: a body's composite
  /// inertia is added to its parent's as it is, through Pᵀ · P for a
  /// rotation-only body; a free root's columns S_r = freeColumns as one 6 × 6
  /// block), g = −M u̇ with u̇ from the ABA (so the residual
  /// vanishes exactly at the ABA's accelerations), and C_t, K_t the joints'
  /// dashpots and springs (the velocity- and configuration-dependence of the
  /// other forces left out: Newton then converges linearly, at a rate of
  /// order h² for them). A prescribed coordinate's row is v̇ = φ̈(t).
  void secondOrderTerms(double t, const State& y, Eigen::MatrixXd* M, Eigen::VectorXd* g, Eigen::MatrixXd* Ct,
                        Eigen::MatrixXd* Kt) const;

  /// Body i's angular acceleration (body axes) and its centre of mass's
  /// acceleration (world), a_c = a_O + α × c + ω × v_c from the spatial
  /// acceleration (α, a_O) of the last accelerations() or jointOutputs().
  Eigen::Vector3d angularAccelerationBody(int i) const {
    return data_.bodies[i].R.transpose() * data_.bodies[i].a.head<3>();
  }
  Eigen::Vector3d accelerationOfCentre(int i) const {
    const BodyData& d = data_.bodies[i];
    return d.a.tail<3>() + d.a.head<3>().cross(d.c) + d.V.head<3>().cross(velocityOfCentre(i));
  }

  /// Kinetic + gravitational + spring energy (the maximal formulation's).
  double energy(double t, const State& y) const;
  /// The sum of the magnitudes of the energy's terms (kinetic, m ‖g‖ ‖c‖ per
  /// body, springs): the scale of the energy's round-off, against which an
  /// energy near zero is zero (DriftTracker).
  double energyTermScale(double t, const State& y) const;
  /// Spatial angular momentum about the world origin.
  Eigen::Vector3d angularMomentum(double t, const State& y) const;
  /// Whether the scene conserves its spatial angular momentum: the same
  /// physics as in maximal coordinates, so the scene's assembly sets the
  /// maximal system's answer (joints to the ground, gravity, supports of
  /// rotation-only bodies and loads from a program are external).
  bool conservesAngularMomentum() const { return conserves_momentum_; }
  /// The angular momentum about the bodies' centre of mass (the maximal
  /// formulation's MultibodySystem::centreOfMassMomentum).
  Eigen::Vector3d centreOfMassMomentum(double t, const State& y) const;
  /// Σ c φ̇², the power the joints' dashpots dissipate.
  double dissipatedPower(double t, const State& y) const;
  void setConservesAngularMomentum(bool conserved) { conserves_momentum_ = conserved; }

  /// Loops (ArticulatedClosure; articulated_closures.cpp). The closing joints'
  /// rows Φ(q) = 0 are imposed with multipliers λ on top of the ABA:
  ///   M u̇ = Q + Gᵀ λ,   G u̇ + γ = 0  (Φ̈ = 0),
  /// G = ∂Φ̇/∂u the rows on the free velocities. With u̇₀ the ABA's answer
  /// without λ and Y = M⁻¹ Gᵀ (m solves with the ABA's factorization, O(n)
  /// each), G Y λ = −Φ̈(u̇₀) and u̇ = u̇₀ + Y λ (the Schur complement of the
  /// saddle-point system; Featherstone 2008, §8.2). G Y is factored by
  /// Cholesky with diagonal pivoting and a rank threshold: rows a loop repeats (the point
  /// rows of a universal joint between two bodies turning about their held
  /// centres, the rows of a planar loop out of its plane) get no pivot and
  /// no multiplier instead of making the system singular. accelerations(), velocity() and jointOutputs() include λ; the
  /// explicit steppers run in index-1 form with ProjectedStepper
  /// (integrators/projected_stepper.hpp) keeping Φ = 0 and Φ̇ = 0.
  bool hasClosures() const { return !model_.closures.empty(); }
  /// The coupling rows G (m × dofs; constant in joint coordinates) when
  /// every closure is a coupling row, else empty: lgvi imposes them with
  /// multipliers, genalpha in the coordinates of their kernel
  /// (articulated_coupled_alpha.hpp).
  const Eigen::MatrixXd& couplingRows() const { return coupling_G_; }
  /// The index sets of u of the trees that share no joint (each body whose
  /// parent is the ground starts one), when there are two or more and no
  /// closure joins them; else empty. M, the drives' tangent matrices and the
  /// rotations' tangent operators have no entry between two of them, so
  /// genalpha factors its Newton matrix tree by tree (22 humanoids: 22
  /// blocks of 27 rates instead of one of 594).
  const std::vector<std::vector<int>>& independentBlocks() const { return independent_blocks_; }
  /// max |Φ| over the closing joints' rows at (t, y) (metres, radians).
  double constraintError(double t, const State& y) const;
  /// The closures' rows G (m × dofs) and Φ (gear rows: 0) at (t, y), for
  /// genalpha's assembly (articulated_kkt_assembly.hpp).
  void closureRowsAt(double t, const State& y, Eigen::MatrixXd* G, Eigen::VectorXd* phi) const;
  /// The closure rows with a pivot in G M⁻¹ Gᵀ at (t, y), in pivot order
  /// (the rows a loop repeats left out; pivoted_cholesky.hpp).
  std::vector<int> independentClosureRows(double t, const State& y) const;
  /// Whether the closures' rows were independent (G M⁻¹ Gᵀ of full rank) at
  /// the scene's start (set by the assembly, articulated_scene.cpp): genalpha's
  /// iteration matrix in joint coordinates needs them so.
  bool closureRowsIndependent() const { return closure_rows_independent_; }
  void setClosureRowsIndependent(bool independent) { closure_rows_independent_ = independent; }
  /// The multipliers of the last accelerations() (+Gᵀλ on the rates' side).
  const Eigen::VectorXd& lastClosureMultipliers() const { return data_.closure_lambda; }
  /// Whether closure row k is a loop's position row (else a gear row, on velocities).
  bool isPositionRow(int k) const { return position_rows_[k] != 0.0; }
  /// `tolerance` raised to the rounding of the bodies' positions at y
  /// (kPositionRoundoffUlps ε times the farthest centre, at least 1 m), as
  /// MultibodySystem's: what genalpha can ask of the loops' rows.
  double achievablePositionTolerance(const State& y, double tolerance) const;
  static constexpr double kPositionRoundoffUlps = 16.0;
  /// Moves y's coordinates onto Φ = 0 by Gauss–Newton steps in the mass
  /// metric, δ = Y λ with G Y λ = −Φ, until max |Φ| ≤ tolerance (false with `why`
  /// after max_iterations, or if a step does not reduce Φ). Coupling rows
  /// alone are linear in joint coordinates, Φ = G q + Φ(0), and are checked
  /// so, without the bodies' poses: an explicit Runge–Kutta step keeps a
  /// linear invariant exactly, so most steps end at that check.
  bool projectPositions(double t, State* y, double tolerance, int max_iterations, int* iterations,
                        std::string* why) const;
  /// Removes from y.u its part that violates Φ̇ = 0, in the mass metric:
  /// u ← u + Y λ with G Y λ = −Φ̇ (prescribed rates stay). Coupling rows
  /// alone: Φ̇ = G u, and a u whose G u lies within kCouplingRateUlps of
  /// rounding (of max |G| max |u|) is left as it is: projecting it would
  /// cost a dynamics evaluation (a fifth of an rkmk4 step) to move u by
  /// rounding. Rounding accumulates across steps until it passes that floor,
  /// then it is projected.
  bool projectVelocities(double t, State* y, std::string* why) const;
  static constexpr double kCouplingRateUlps = 64.0;

  /// The joints' outputs by scene joint index (from a full dynamics solve at
  /// (t, y): the moment includes what prescribed motion needs and, in a
  /// loop, the closing joints' forces).
  void jointOutputs(double t, const State& y, std::vector<ArticulatedJointOutput>* out) const;

  /// What the joint-space variational integrator (integrators/
  /// joint_space_variational.hpp) reads at one configuration q: per body its
  /// pose and motion subspace S (world, free columns), and — when factored —
  /// the articulated-body factorization of the mass matrix M(q) (U = I_A S,
  /// D⁻¹ = (Sᵀ I_A S)⁻¹; Featherstone 2008, §7.3), with which M(q)⁻¹ τ costs
  /// two O(n) passes and no 6 × 6 product.
  /// Sized once; reused step after step (nothing allocated per step).
  struct Frame {
    Eigen::Matrix3d R, Dinv;
    Eigen::Vector3d c;
    Eigen::Matrix<double, 6, 3> S, U;
    std::array<double, 3> phi{{0.0, 0.0, 0.0}}, cos_phi{{1.0, 1.0, 1.0}}, sin_phi{{0.0, 0.0, 0.0}};
    int free = 0;
    std::array<int, 3> free_u{{0, 0, 0}};
  };
  struct Frames {
    std::vector<Frame> bodies;
    /// A free root's six rates are one block, not columns: the inverse of its
    /// articulated inertia (about the origin), by the root's rotation index.
    std::vector<Matrix6> root_inverse;
    /// Each free tree's centre of mass from its root, by the root's rotation index.
    std::vector<Eigen::Vector3d> root_offset;
    /// With closures (when factored): Y = M⁻¹ Gᵀ and (G Y)⁻¹ (m × m, m the
    /// rows; with loops the inverse on the rows with a pivot, 0 on those a
    /// loop repeats) at this configuration, and with loops G itself (coupling
    /// rows: constant, couplingRows()).
    Eigen::MatrixXd rows_G, rows_Y, rows_Ainv;
    bool factored = false;
  };

  /// Whether the variational integrator covers this tree: every joint kind
  /// (the rotations on SO(3), joint_space_variational.hpp), coupling rows,
  /// gear rows on angular rates, loop-closing joints and rack-and-pinion rows
  /// within one tree (the ground's or a floating one), but no prescribed
  /// coordinate (a time-dependent constraint) and no loop or rack between a
  /// floating tree and the ground or another tree (whose step coordinates,
  /// its centre of mass, the row would move). If not, `why` names the joint
  /// or body and the reason.
  bool variationalCovers(std::string* why) const;
  /// The floating tree of `body` (its index), or −1 for the ground and the
  /// trees hung from it.
  int stepTreeOf(int body) const;
  /// Whether a coordinate's motion is prescribed (`why` names the body and
  /// says that `integrator` does not take it in joint coordinates).
  bool hasPrescribedCoordinate(const std::string& integrator, std::string* why) const;
  /// The frames at the configuration of y (factored when `factor`: M, or
  /// M + damping_weight · D_c with D_c the joints' dashpot constants on
  /// their coordinates, an armature in the articulated-body factorization —
  /// the dashpots' forces −D_c q̇ are linear, so lgvi's end kick
  /// (M + (h/2) D_c) q̇₁ = p₁* + (h/2) Q(q̇ = 0) is one solve).
  void frames(double t, const State& y, bool factor, Frames* f, double damping_weight = 0.0) const;
  /// out's configuration = y's ⊕ s v: the scalar coordinates plus s v, each
  /// rotation N exp(s v_k) (out->u is left as it is).
  void advance(const State& y, const Eigen::VectorXd& v, double s, State* out) const;
  /// Whether a and b are the same configuration, bit for bit.
  static bool sameConfiguration(const State& a, const State& b);
  /// The rotations' terms of the discrete Lagrangian on the group
  /// (joint_space_variational.hpp): with ξ = h v_k = log(N₀ᵀ N₁), the
  /// midpoint N_m = N₀ exp(ξ/2) and the body rates v_k there, from the body's
  /// π = ∂T/∂ω and δ = ∂T/∂(N_m exp(·)) at the midpoint,
  ///   −D₁L_d = Jl⁻¹(ξ)ᵀ π − h Bᵀ δ,   D₂L_d = Jr⁻¹(ξ)ᵀ π + h Aᵀ δ,
  /// where N₀ exp(η) moves N_m by B η, B = exp(−ξ/2) − ½ Jr(ξ/2) Jl⁻¹(ξ), and
  /// N₁ exp(η) by A η, A = ½ Jr(ξ/2) Jr⁻¹(ξ) (both ½ I at ξ = 0: the
  /// vector-space midpoint rule).
  struct RotationTerms {
    std::vector<Eigen::Vector3d> xi, pi, delta;  ///< ξ, π, δ per rotation, for rotationEndMomenta
  };
  /// Mv ← Jl⁻¹(ξ)ᵀ π and dT ← 2 Bᵀ δ on each rotation, so that (1) keeps its
  /// form Mv − (h/2) dT = p₀ + (h/2) Q₀; π, δ kept in *terms. Nothing to do
  /// without rotations.
  void rotationStartTerms(const Eigen::VectorXd& v, double h, Eigen::VectorXd* Mv, Eigen::VectorXd* dT,
                   RotationTerms* terms) const;
  /// p ← D₂L_d on each rotation as b + (D₂L_d + D₁L_d), b = −D₁L_d the
  /// right side of (1), the sum from ξ, π, δ of the last rotationStartTerms: as the
  /// vector-space p₁ = b + h ∂T/∂q, whose error from the iteration's last
  /// change is O(h) times that change, not the change itself.
  void rotationEndMomenta(double h, const RotationTerms& terms, const Eigen::VectorXd& b, Eigen::VectorXd* p) const;
  /// The step's coordinates: the state's, except that a free root's
  /// translation rate is its tree's centre-of-mass velocity v_z (and its
  /// translation that centre z): by König's theorem T = ½ M_tree |v_z|² +
  /// T_rel(q_rel, rates_rel), so the discrete Lagrangian moves each centre
  /// exactly as a point mass under uniform gravity and keeps the momentum
  /// about it as a rotation-invariant T_rel does (the maximal formulation
  /// keeps both that way too). Uniform gravity has no generalized force on
  /// the other coordinates there, and M is block-diagonal, (M_tree I, M_rel),
  /// M_rel⁻¹ being the rest's block of the state's M⁻¹. Without free roots
  /// the step's coordinates are the state's.
  /// x = M(q)⁻¹ rhs in the step's coordinates with the factorization in f
  /// (f.factored).
  void solveMass(const Frames& f, const Eigen::VectorXd& rhs, Eigen::VectorXd* x) const;
  /// The state's rates u whose momenta in the step's coordinates are p;
  /// with coupling rows p is first moved to p + Gᵀμ, the momenta whose rates
  /// keep G u = 0 (the end of a RATTLE step).
  void rates(const Frames& f, Eigen::VectorXd* p, Eigen::VectorXd* u) const;
  /// The rows' multipliers in the iteration for the mid-step rates v
  /// (joint_space_variational.hpp): the increment dv = M(q₀)⁻¹ r becomes
  /// M(q₀)⁻¹ (r − G₀ᵀλ), r becomes r − G₀ᵀλ, with λ such that, to first
  /// order in dv (G₀ = G(q₀) in start),
  ///   coupling rows (α q̇₁ + q̇₂ = 0: constant G, G q stays constant when
  ///   G v = 0):                      G (v + dv) = 0;
  ///   a loop's position rows:        Φ(q₀ ⊕ h v) + h G₀ dv = 0  (Φ(q₁) = 0);
  ///   gear rows (on velocities):     B(q_m) v + G₀ dv = 0  (B at the
  ///                                  midpoint q_m of `mid`: symmetric).
  /// y is the step's start, mid the frames at q_m = q₀ ⊕ (h/2) v. Nothing
  /// without closures.
  void projectIncrement(const Frames& start, const Frames& mid, const State& y, const Eigen::VectorXd& v, double h,
                        Eigen::VectorXd* dv, Eigen::VectorXd* r) const;
  /// With loops or gear rows, b ← b − G₀ᵀλ, λ of the last projectIncrement:
  /// the constraint impulse of the step's first half, −D₁L_d = p₀ + (h/2)Q₀
  /// − G₀ᵀλ (RATTLE; Hairer, Lubich & Wanner, "Geometric Numerical
  /// Integration", §VII.1.4), which p₁ = −D₁L_d + (D₁ + D₂)L_d carries. With
  /// coupling rows only, G is constant and rates() absorbs G ᵀλ into its
  /// own multiplier: nothing to do.
  void constraintImpulse(const Frames& start, Eigen::VectorXd* b) const;
  /// The momenta, in the step's coordinates, of the state's rates u.
  void momenta(const Frames& f, const Eigen::VectorXd& u, Eigen::VectorXd* p) const;
  /// Each free root's translation at the end of a step from start to end
  /// with rates v (step's coordinates): z₁ = z₀ + h v_z, the root at z₁ less
  /// its tree's centre's offset at the end.
  void placeFreeRoots(const Frames& start, const Frames& end, const State& y0, const Eigen::VectorXd& v, double h,
                      State* y1) const;
  /// For the rates v at the configuration of f: the momenta M(q) v, and
  /// ∂T/∂q (q, v) of the kinetic energy T = ½ vᵀ M(q) v at fixed v. Each
  /// coordinate's column S_k turns everything beyond it, so ∂V_b/∂φ_k =
  /// S_k ×ₘ (V_b − V_k⁻) for every body b beyond it (V_k⁻ the twist before
  /// the column), and with the turn of b's inertia the terms in V_b cancel:
  ///   ∂T/∂φ_k = (V_k⁻ ×ₘ S_k)ᵀ H_k,   M(q) v|_k = S_kᵀ H_k,
  /// H_k the spatial momentum of the subtree (through Pᵀ past a rotation-only
  /// body): one pass out and one back, O(n). A spherical joint's N exp(δ)
  /// turns the subtree about its anchor by the columns S e_k at once:
  /// ∂T/∂δ_k = (V_p ×ₘ S e_k)ᵀ H, its relative twist turning with it. A
  /// free root's R exp(δ) turns the tree about c too, but its v_c (world)
  /// does not turn: T(G·q, v_c) = T(q, Gᵀ v_c), so ∂T/∂δ = Rᵀ(P × v_c), P the
  /// tree's linear momentum, and ∂T/∂c = 0 (a translation changes nothing).
  void kinetic(const Frames& f, const Eigen::VectorXd& v, Eigen::VectorXd* Mv, Eigen::VectorXd* dTdq) const;
  /// The frames at y.q (not factored) into *f and kinetic() there, in one
  /// pass; `near`, frames at angles close to y.q, lends the sines and cosines
  /// of its angles (sinCosNear).
  void kineticAt(double t, const State& y, const Eigen::VectorXd& v, const Frames& near, Frames* f,
                 Eigen::VectorXd* Mv, Eigen::VectorXd* dTdq) const;
  /// The generalized forces Q(t, q, u) at the configuration of f: the joints'
  /// springs, dashpots and moments, gravity and the program's body torques.
  void generalizedForces(double t, const Frames& f, const Eigen::VectorXd& u, Eigen::VectorXd* Q) const;
  /// Whether Q depends on the rates (dashpots, or torques from a program).
  bool hasVelocityDependentForces() const;

 private:
  /// energy() and energyTermScale() in one pass over the bodies.
  std::pair<double, double> energyAndTermScale(double t, const State& y) const;
  using BodyData = ArticulatedData::Body;

  /// Pass 1 of the ABA: kinematics, velocities, bias accelerations and
  /// forces (`dynamics`: the rigid-body inertias and bias forces too), by
  /// the tree passes on any scalar (tree_passes.hpp) with the scene's loads.
  void forwardPass(double t, const State& y, bool dynamics, bool velocity_terms) const;
  /// Passes 2 and 3 with the generalized forces in data_.bodies[i].tau; ground
  /// acceleration a0; writes u̇ of the free columns.
  void solve(const Vector6& a0, Eigen::VectorXd* udot) const;
  /// The tree passes on this system's model, frames and workspace.
  TreePasses<double> passes() const {
    return TreePasses<double>(model_, frames_, data_.bodies, data_.root_momentum, data_.projecting);
  }

  /// The loops' terms at the kinematics in data_ (articulated_closures.cpp):
  /// G into data_.closure_G and, by `level`, Φ, Φ̇ or Φ̈ (at the accelerations in
  /// data_.bodies[i].a) into data_.closure_r.
  enum class ClosureLevel { kJacobian, kPosition, kVelocity, kAcceleration };
  /// Calls f(closure, bodies, blocks, value) for every closing joint or gear
  /// at the kinematics in data_: its bodies (tree indices, kGround), its
  /// rows' blocks on each body's (v_c, ω body) and, by level, Φ (gears: 0),
  /// 0, or the convective term c (Φ̈ = J q̈ + c).
  template <typename F>
  void forEachClosure(ClosureLevel level, F&& f) const;
  /// Tree body i's pose and velocity (v_c world, ω body) at the kinematics in
  /// data_, as the constraint library takes them (kGround: at rest at O).
  constraints::BodyPose<double> closurePose(int i) const;
  constraints::BodyVelocity<double> closureVelocity(int i) const;
  void closureTerms(ClosureLevel level) const;
  /// data_.closure_Y = M⁻¹ Gᵀ with the factorization of the last solve(), and the
  /// rank-revealing factorization of G Y; then data_.closure_lambda solves
  /// G Y λ = −data_.closure_r on the rows that have a pivot.
  void closureMultipliers() const;
  /// data_.closure_Y = M⁻¹ Gᵀ with the factorization of the last solve() (all
  /// m columns in one pass down and one up the tree).
  void closureInverseMass() const;
  /// Its passes on a workspace of C = m columns (Eigen::Dynamic, or 1).
  template <int C>
  void closureInverseMassWith(ArticulatedData::ClosureColumns<C>& w) const;
  /// closureInverseMass(), then G Y factored by pivoted Cholesky into
  /// data_.closure_A and closure_perm; returns its rank.
  int factorClosureRows() const;
  /// The closing joints' constraint forces W_aᵀ λ, W_bᵀ λ taken off the bias
  /// forces p_A of their bodies (as external forces), before solve().
  void applyClosureForces() const;

  /// After the ABA's u̇₀ in *udot: the multipliers and u̇ = u̇₀ + Y λ, and the
  /// bodies' accelerations in data_ moved by the same increment.
  void closureAccelerations(Eigen::VectorXd* udot) const;
  /// The closing joints' outputs (angles from the poses, moments from λ).
  void closureOutputs(double t, std::vector<ArticulatedJointOutput>* out) const;


  ArticulatedModel model_;
  std::vector<UserTorque> user_torques_;
  bool has_user_torques_ = false;
  bool conserves_momentum_ = false;
  /// The workspace every evaluation writes (articulated_data.hpp).
  mutable ArticulatedData data_;
  /// Each joint's first axis and Rodrigues basis (tree_passes.hpp).
  std::vector<JointFrame<double>> frames_;
  /// The relative rotation M (main → secondary) of body i's revolute or
  /// universal joint from the cosines and sines of its angles.
  EIGEN_ALWAYS_INLINE Eigen::Matrix3d jointRotation(int i, const std::array<double, 3>& c,
                                                     const std::array<double, 3>& s) const {
    return articulated::jointRotation(model_.bodies[i], frames_[i], c, s);
  }
  /// The variational passes' steps: body i's pose at q from its parent's in
  /// *f; its twist, momentum and the twist before its columns at rates v
  /// (data_.twist, data_.accumulated, data_.before); the backward pass over all bodies.
  void poseInto(int i, const State& y, const Frames* near, Frames* f) const;
  void momentumOut(int i, const Frame& fr, const Eigen::VectorXd& v) const;
  /// After momentumOut over all bodies: each free tree's v_z (from v's root
  /// slot, which holds v_z, or the state's v_c when `state_rates`), and the
  /// tree moved to its centre's rest frame (its momentum zero).
  void centreFreeTrees(const Frames& f, const Eigen::VectorXd& v, bool state_rates) const;
  /// frames()' factorization: the articulated inertias, U, D⁻¹, the free
  /// roots' blocks; with coupling rows, Y = M⁻¹ Gᵀ and G Y.
  void factorMassAndCouplings(Frames* f, double damping_weight) const;
  /// kinetic() (v in the step's coordinates) or, `state_rates`, momenta().
  void kineticPasses(const Frames& f, const Eigen::VectorXd& v, bool state_rates, Eigen::VectorXd* Mv,
                     Eigen::VectorXd* dTdq) const;
  /// solveMass (step's coordinates) or, `state_rates`, the state's rates.
  void solveStepMass(const Frames& f, const Eigen::VectorXd& rhs, bool state_rates, Eigen::VectorXd* x) const;
  /// By body: the rotation index of the free root whose tree holds it, or
  /// −1; by rotation index: a free tree's mass; the free roots' bodies.
  std::vector<int> free_tree_;
  std::vector<double> free_tree_mass_;
  std::vector<int> free_root_body_;
  /// The coupling rows G (m × dofs) when every closure is a coupling (lgvi
  /// takes them), computed at construction; empty otherwise.
  Eigen::MatrixXd coupling_G_;
  /// With coupling_G_: Φ at q = 0 (Φ(q) = G q + Φ(0) on the scalar
  /// coordinates, which are all a coupling row touches) and max |G|.
  Eigen::VectorXd coupling_phi0_;
  double coupling_G_max_ = 0.0;
  /// Whether every closure is a coupling row.
  bool onlyCouplings() const;
  bool closure_rows_independent_ = true;
  /// independentBlocks(), computed at construction.
  std::vector<std::vector<int>> independent_blocks_;
  void findIndependentBlocks();
  /// Whether the closures include loops or gear rows (not only couplings).
  bool loopRows() const { return hasClosures() && coupling_G_.size() == 0; }
  /// Per closure row: 1 on a loop's position rows, 0 on gear rows (imposed
  /// on velocities); computed at construction.
  Eigen::VectorXd position_rows_;
  bool has_position_rows_ = false, has_velocity_rows_ = false;
  /// data_'s bodies' poses and free columns from frames f (the closures'
  /// terms read data_).
  void loadFramePoses(const Frames& f) const;
  /// With loops: G, Y = M⁻¹ Gᵀ and the inverse of G Y at f's configuration.
  void factorLoopRows(Frames* f) const;
  /// Y = M⁻¹ Gᵀ (step's coordinates), column by column with f's factorization.
  void inverseMassColumns(const Frames& f, const Eigen::MatrixXd& G, Eigen::MatrixXd* Y) const;
  /// projectIncrement's configuration q₀ ⊕ h v and its frames.
  mutable State loop_end_;
  mutable Frames loop_frames_;
  void momentumBack(const Frames& f, const Eigen::VectorXd& v, Eigen::VectorXd* Mv, Eigen::VectorXd* dTdq) const;
};

}  // namespace articulated
}  // namespace lieflow
