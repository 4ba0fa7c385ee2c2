/// \file
/// The exact torque-free motion of a rigid body (Euler–Poinsot problem), for any
/// inertia and any initial condition: the reference solution for tests and studies.
///
/// Conventions (shared/DESIGN.md): Hamilton quaternions (w, x, y, z); R maps body to
/// world; ω is in the body frame, Ṙ = R ω^; Euler's equations I ω̇ = (I ω) × ω; the
/// spatial angular momentum L = R I ω and the energy E = ½ ωᵀ I ω are constant.
///
/// Method (Landau & Lifshitz, Mechanics, §37; Celledoni, Fassò, Säfström & Zanna,
/// "The exact computation of the free rigid body motion and its use in splitting
/// methods", SIAM J. Sci. Comput. 30 (2008) 2084–2112):
///  * ω(t) in a principal frame through the Jacobi elliptic functions sn, cn, dn, whose
///    modulus k depends on the regime L² ≷ 2E·I_mid; sech/tanh on the separatrix. sn,
///    cn, dn come from the AGM/Landen recursion written in terms of k'² = 1 − k², which
///    is computed without cancellation from the data (boost::math::jacobi_elliptic
///    rebuilds k' from k and loses up to 1e-11 near the separatrix);
///  * the attitude as R(t) = R(0) B Swing(u₀)ᵀ Rz(Φ(t)) Swing(u(t)) Bᵀ, where u = I ω/|L|
///    is the unit angular momentum in the principal ("working") frame B, Swing(u) the
///    smallest rotation taking u to e_z and Φ(t) the precession angle about L, obtained in
///    closed form through the complete and incomplete elliptic integrals of the third
///    kind (Carlson's R_F, R_J from Boost.Math, in forms free of cancellation; periods
///    are precomputed, so evaluate() costs O(1) for any t);
///  * closed forms with trigonometric functions for the spherical and axisymmetric
///    bodies, the steady rotation about a principal axis and the body at rest.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>

namespace lieflow {

/// Exact torque-free motion of a rigid body, any inertia, any initial condition.
///
/// The returned quaternion is a continuous function of t (no sign flips), equal to q0
/// (same sign) at t = 0. Accuracy, measured against an independent long-double Taylor
/// integrator: ≲ 1e-15 per radian turned (≤ 7e-14 at |ω| t ≈ 100); E and L are
/// conserved to ~1e-15. The evaluation is backward stable: near the separatrix, where
/// the problem itself amplifies changes of the data by up to ~1e6 over t = 100, the
/// result is the exact motion for data within a few ulps. A non-diagonal inertia with
/// nearly equal moments has ill-conditioned principal axes (~ulp/gap) whatever the
/// method. Any units: the computation is scaled internally (only energy() and
/// spatialAngularMomentum() must fit in a double).
class ExactFreeRigidBody {
 public:
  /// inertia_body: symmetric positive-definite 3x3 inertia about the centre of mass in
  /// body axes (not necessarily diagonal: diagonalized internally, handedness kept).
  /// q0: unit quaternion (within 1e-9; renormalized), orientation at t = 0.
  /// omega0_body: body angular velocity at t = 0.
  /// Throws lieflow::InvalidInput (a std::invalid_argument whose message names the
  /// argument and the reason) for non-finite input, non-symmetric (beyond a relative
  /// 1e-12) or non-positive-definite inertia, principal moments violating the triangle
  /// inequality I_i + I_j ≥ I_k beyond a relative 1e-12, or a non-unit quaternion.
  ExactFreeRigidBody(const Eigen::Matrix3d& inertia_body, const Eigen::Quaterniond& q0,
                     const Eigen::Vector3d& omega0_body);

  /// Orientation and body angular velocity at time t (any real t, also negative).
  /// Either output pointer may be null.
  void evaluate(double t, Eigen::Quaterniond* q, Eigen::Vector3d* omega_body) const;

  /// Kinetic energy E = ½ ω₀ᵀ I ω₀ (constant along the motion).
  double energy() const { return energy_; }
  /// Spatial angular momentum L = R₀ I ω₀ (constant along the motion).
  Eigen::Vector3d spatialAngularMomentum() const { return momentum_world_; }

  /// Which closed form is used (for tests and diagnostics).
  enum class Regime {
    kSteady,        ///< at rest, spherical body, or rotation about a principal axis
    kAxisymmetric,  ///< two equal principal moments: trigonometric closed form
    kElliptic,      ///< generic: Jacobi elliptic functions with modulus 0 ≤ k < 1
    kSeparatrix     ///< L² = 2E·I_mid: hyperbolic functions (k = 1)
  };
  Regime regime() const { return regime_; }
  /// Elliptic modulus k (0 for the trigonometric cases, 1 on the separatrix).
  double modulus() const { return k_; }

 private:
  /// Jacobi elliptic functions and the derived angles at the argument τ.
  struct Phase {
    double sn, cn, dn;
    double q;      ///< Q(τ) = ∫₀^τ dv / (1 − n sn² v) − τ/(1 − n) (continuous, odd)
    double gamma;  ///< continuous azimuth of (J1 ω1, J2 ω2) in the working frame
  };
  Phase phase(double tau) const;
  /// Q(r) = Π(n; am r, k) − r/(1 − n) for |r| ≤ K from (s, c, Δ) = (sn r, cn r, dn r).
  double ellipticPiRemainder(double s, double c, double delta) const;
  /// sn, cn, dn of u with the precomputed AGM of the modulus.
  void jacobi(double u, double* sn, double* cn, double* dn) const;
  /// The constructor's steps (P the principal axes, moments I1 ≤ I2 ≤ I3):
  /// a motion in closed trigonometric form (rest, a spherical or
  /// axisymmetric body, a steady turn about a principal axis), if it is one;
  /// else the working frame (basis_: the circulation axis third, rescaled
  /// inertias J and rates om, 2^omega_exp the rate unit; true on the
  /// separatrix) and, off the separatrix, the modulus, the AGM, the constants
  /// of Π and the phase τ0 (G, H: the cancellation-free energy differences).
  bool setTrigonometricCase(const Eigen::Matrix3d& P, const Eigen::Vector3d& moments);
  bool setWorkingFrame(const Eigen::Matrix3d& P, const Eigen::Vector3d& moments, Eigen::Vector3d* J,
                       Eigen::Vector3d* om, int* omega_exp);
  void setEllipticCase(const Eigen::Vector3d& J, const Eigen::Vector3d& om, double G, double H);
  /// Swing(u) as a quaternion: the smallest rotation taking the unit vector u (u_z > 0)
  /// to e_z.
  static Eigen::Quaterniond swing(const Eigen::Vector3d& u);

  Regime regime_ = Regime::kSteady;
  double energy_ = 0.0;
  Eigen::Vector3d momentum_world_ = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q0_ = Eigen::Quaterniond::Identity();
  Eigen::Vector3d omega0_ = Eigen::Vector3d::Zero();

  // kSteady / kAxisymmetric: q(t) = q0 ⊗ exp(t (ω0 − ν e_s)) ⊗ exp(t ν e_s).
  Eigen::Vector3d axis_body_ = Eigen::Vector3d::UnitZ();  ///< symmetry axis e_s (body)
  double nu_ = 0.0;  ///< ν = (I_t − I_s) ω_s / I_t; ω turns about e_s at the rate −ν

  // kElliptic / kSeparatrix, in the working frame (principal axes, circulation axis 3).
  Eigen::Matrix3d basis_ = Eigen::Matrix3d::Identity();  ///< B: working → body
  Eigen::Quaterniond basis_q_ = Eigen::Quaterniond::Identity();
  Eigen::Quaterniond left_ = Eigen::Quaterniond::Identity();  ///< q0 ⊗ B ⊗ Swing(u0)⁻¹
  Eigen::Vector3d moments_ = Eigen::Vector3d::Ones();         ///< J1, J2, J3
  Eigen::Vector3d amplitude_ = Eigen::Vector3d::Zero();       ///< A1, A2, A3 / omega_unit_
  double omega_unit_ = 1.0;  ///< power of two near |ω0| (internal scaling)
  double lambda_ = 0.0;      ///< τ = λ t + τ0
  double tau0_ = 0.0;
  double k_ = 0.0;    ///< modulus
  double kp2_ = 1.0;  ///< complementary parameter k'² = 1 − k² (computed directly)
  double n_ = 0.0;    ///< characteristic of Π (≤ 0)
  // Π(n) = pi_a Π(N) + b F + pi_e atan(pi_A s c/Δ) with N = (k² − n)/(1 − n) ∈ (k², 1).
  double pi_N_ = 0.0, pi_Nm1_ = 1.0, pi_a_ = 0.0, pi_e_ = 0.0, pi_A_ = 0.0;
  double K_ = 0.0;           ///< complete integral of the first kind K(k)
  double q_complete_ = 0.0;  ///< Q(K) = Π(n, k) − K/(1 − n)
  /// Precession ψ(t) = rate_linear t + rate_pi (Q(τ) − Q(τ0)); Φ = ψ − (γ − γ0).
  double rate_linear_ = 0.0, rate_pi_ = 0.0;
  double q0_phase_ = 0.0, gamma0_ = 0.0;  ///< phase(τ0).q, phase(τ0).gamma
  // Arithmetic–geometric mean for sn, cn (Abramowitz & Stegun 16.4), precomputed.
  static constexpr int kMaxAgmSteps = 32;
  int agm_steps_ = 0;
  double agm_scale_ = 1.0;  ///< 2^N a_N
  std::array<double, kMaxAgmSteps + 1> agm_c_over_a_{};
  std::array<double, kMaxAgmSteps + 1> agm_b_over_a_{};
};

}  // namespace lieflow
