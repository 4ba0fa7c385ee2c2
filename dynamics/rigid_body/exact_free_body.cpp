/// \file
/// The exact free rigid-body flow; see exact_free_body.hpp for the method and sources.
#include "dynamics/rigid_body/exact_free_body.hpp"

#include <Eigen/Eigenvalues>
#include <boost/math/special_functions/ellint_rf.hpp>
#include <boost/math/special_functions/ellint_rj.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include "liegroup/invalid_input.hpp"
#include "liegroup/scalar.hpp"

namespace lieflow {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();
/// Boost.Math evaluates double functions in long double by default; the arguments here
/// are accurate and Carlson's algorithms are stable, so double is enough (~3x faster).
using DoublePolicy = boost::math::policies::policy<boost::math::policies::promote_double<false>>;
/// Largest relative asymmetry |I − Iᵀ|_max / |I|_max accepted (then symmetrized).
constexpr double kSymmetryTol = 1e-12;
/// Largest relative violation (I3 − I1 − I2) / I3 of the triangle inequality accepted.
constexpr double kTriangleTol = 1e-12;
/// Largest |‖q0‖ − 1| accepted (then normalized).
constexpr double kUnitQuaternionTol = 1e-9;
/// Principal moments closer than this (relative to I3) are taken as equal: such a
/// difference is at the rounding level of the diagonalization, and the change of the
/// solution it causes, O(tol |ω|² t), stays below the accuracy target for |ω| t ≲ 10³.
constexpr double kEqualMomentsTol = 8 * kEps;
/// ω is taken along a principal axis when both other principal components are below
/// this fraction of |ω| (rounding level of the change to principal axes).
constexpr double kPrincipalAxisTol = 8 * kEps;

std::string str(double x) {
  std::ostringstream os;
  os.precision(17);
  os << x;
  return os.str();
}

/// exp of the pure quaternion (0, v/2): the rotation by the angle |v| about v.
Eigen::Quaterniond expq(const Eigen::Vector3d& v) {
  const double angle = v.norm();
  if (angle == 0.0) return Eigen::Quaterniond::Identity();
  const Eigen::Vector3d xyz = (std::sin(0.5 * angle) / angle) * v;
  return Eigen::Quaterniond(std::cos(0.5 * angle), xyz.x(), xyz.y(), xyz.z());
}

/// Rotation by the angle a about e_z.
Eigen::Quaterniond rotz(double a) {
  return Eigen::Quaterniond(std::cos(0.5 * a), 0.0, 0.0, std::sin(0.5 * a));
}

/// Refines an eigendecomposition inertia ≈ P diag(moments) Pᵀ by one step of the
/// first-order (Jacobi) correction in long double: with A = Pᵀ inertia P,
/// P ← orth(P (1 + X)), X_ij = A_ij / (A_jj − A_ii), then moments_i = (Pᵀ inertia P)_ii.
/// This brings the residual from the solver's few ulps to the rounding of P itself.
/// Pairs with a relative gap below `gap_tol` are left alone (any basis of a degenerate
/// eigenspace is principal).
void refineEigen(const Eigen::Matrix3d& inertia, double gap_tol, Eigen::Matrix3d* P,
                 Eigen::Vector3d* moments) {
  using Mat = Eigen::Matrix<long double, 3, 3>;
  const Mat I = inertia.cast<long double>();
  Mat Q = P->cast<long double>();
  const Mat A = Q.transpose() * I * Q;
  const long double scale = std::abs(A(2, 2)) + std::abs(A(0, 0));
  Mat X = Mat::Identity();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const long double gap = A(j, j) - A(i, i);
      if (i != j && std::abs(gap) > gap_tol * scale) X(i, j) = A(i, j) / gap;
    }
  Q = Q * X;
  for (int j = 0; j < 3; ++j) {  // modified Gram–Schmidt
    for (int i = 0; i < j; ++i) Q.col(j) -= Q.col(i).dot(Q.col(j)) * Q.col(i);
    Q.col(j).normalize();
  }
  const Mat B = Q.transpose() * I * Q;
  *P = Q.cast<double>();
  *moments = B.diagonal().cast<double>();
}

}  // namespace

Eigen::Quaterniond ExactFreeRigidBody::swing(const Eigen::Vector3d& u) {
  // Rotation about u × e_z = (u2, −u1, 0) by the angle θ, cos θ = u3, sin θ = ρ:
  // (cos θ/2, sin(θ/2)/ρ (u2, −u1, 0)) with sin(θ/2)/ρ = 1/(2 cos θ/2), cos θ/2 ≥ 1/√2.
  const double c = std::sqrt(0.5 * (1.0 + u.z()));
  const double s = 0.5 / c;
  return Eigen::Quaterniond(c, s * u.y(), -s * u.x(), 0.0);
}

namespace {

/// The inertia made exactly symmetric, after the checks of the constructor's
/// arguments (finite, symmetric to kSymmetryTol, a unit quaternion).
Eigen::Matrix3d validatedInertia(const Eigen::Matrix3d& inertia_body, const Eigen::Quaterniond& q0,
                                 const Eigen::Vector3d& omega0_body) {
  if (!inertia_body.allFinite()) throw InvalidInput("inertia_body", "has a non-finite entry");
  if (!q0.coeffs().allFinite()) throw InvalidInput("q0", "has a non-finite component");
  if (!omega0_body.allFinite()) throw InvalidInput("omega0_body", "has a non-finite component");
  const double inertia_scale = inertia_body.cwiseAbs().maxCoeff();
  const double asymmetry = (inertia_body - inertia_body.transpose()).cwiseAbs().maxCoeff();
  if (asymmetry > kSymmetryTol * inertia_scale)
    throw InvalidInput("inertia_body",
                       "is not symmetric: max |I(i,j) - I(j,i)| = " + str(asymmetry) + " exceeds " +
                           str(kSymmetryTol) + " relative");
  const Eigen::Matrix3d inertia = 0.5 * (inertia_body + inertia_body.transpose());
  const double qnorm = q0.norm();
  if (std::abs(qnorm - 1.0) > kUnitQuaternionTol)
    throw InvalidInput("q0", "quaternion norm " + str(qnorm) + " is not within " +
                                 str(kUnitQuaternionTol) + " of 1");
  return inertia;
}

/// Principal axes: inertia = P diag(I1 ≤ I2 ≤ I3) Pᵀ with det P = +1 (a
/// permutation, exactly, for a diagonal inertia); InvalidInput unless
/// positive definite and within the triangle inequality.
void principalAxes(const Eigen::Matrix3d& inertia, Eigen::Matrix3d* P_out, Eigen::Vector3d* moments_out) {
  Eigen::Matrix3d& P = *P_out;
  Eigen::Vector3d& moments = *moments_out;
  const bool diagonal = inertia(0, 1) == 0.0 && inertia(0, 2) == 0.0 && inertia(1, 2) == 0.0;
  if (diagonal) {  // exact: a permutation of the axes
    std::array<int, 3> order{0, 1, 2};
    std::sort(order.begin(), order.end(),
              [&](int a, int b) { return inertia(a, a) < inertia(b, b); });
    P.setZero();
    for (int i = 0; i < 3; ++i) {
      moments(i) = inertia(order[i], order[i]);
      P(order[i], i) = 1.0;
    }
  } else {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(inertia);
    moments = eig.eigenvalues();
    P = eig.eigenvectors();
    if (moments(0) > 0.0) refineEigen(inertia, kEqualMomentsTol, &P, &moments);
  }
  if (P.determinant() < 0.0) P.col(0) = -P.col(0);
  if (!(moments(0) > 0.0))
    throw InvalidInput("inertia_body",
                       "is not positive definite: smallest principal moment " + str(moments(0)));
  if (moments(2) - (moments(0) + moments(1)) > kTriangleTol * moments(2))
    throw InvalidInput("inertia_body", "principal moments (" + str(moments(0)) + ", " +
                                           str(moments(1)) + ", " + str(moments(2)) +
                                           ") violate the triangle inequality I1 + I2 >= I3");
}

}  // namespace

bool ExactFreeRigidBody::setTrigonometricCase(const Eigen::Matrix3d& P, const Eigen::Vector3d& moments) {
  const Eigen::Vector3d w = P.transpose() * omega0_;  // principal components
  const double I1 = moments(0), I2 = moments(1), I3 = moments(2);
  const double d21 = I2 - I1, d32 = I3 - I2;
  const double wnorm = omega0_.stableNorm();
  regime_ = Regime::kSteady;  // q(t) = q0 ⊗ exp(t ω0), ω constant (ν = 0)
  if (wnorm == 0.0 || I3 - I1 <= kEqualMomentsTol * I3) return true;  // rest or spherical
  if (d21 <= kEqualMomentsTol * I3 || d32 <= kEqualMomentsTol * I3) {
    // Axisymmetric body (Landau–Lifshitz §33): symmetry axis e_s with moment I_s, the
    // other two equal to I_t. With L/I_t = R (ω − ν e_s), ν = (I_t − I_s) ω_s / I_t,
    //   R(t) = exp(t (L/I_t)^) R0 exp(t ν e_s^) = R0 exp(t (ω0 − ν e_s)^) exp(t ν e_s^),
    //   ω(t) = exp(−t ν e_s^) ω0,
    // the limit k → 0 of the elliptic solution below (hence continuous with it).
    const bool axis3 = d21 <= kEqualMomentsTol * I3;
    const double Is = axis3 ? I3 : I1;
    const double It = axis3 ? 0.5 * (I1 + I2) : 0.5 * (I2 + I3);
    axis_body_ = P.col(axis3 ? 2 : 0);
    nu_ = (It - Is) * axis_body_.dot(omega0_) / It;
    regime_ = Regime::kAxisymmetric;
    return true;
  }
  for (int i = 0; i < 3; ++i) {  // steady rotation about principal axis i
    if (std::abs(w((i + 1) % 3)) <= kPrincipalAxisTol * wnorm &&
        std::abs(w((i + 2) % 3)) <= kPrincipalAxisTol * wnorm)
      return true;
  }
  return false;
}

bool ExactFreeRigidBody::setWorkingFrame(const Eigen::Matrix3d& P, const Eigen::Vector3d& moments,
                                         Eigen::Vector3d* J_out, Eigen::Vector3d* om_out, int* omega_exp_out) {
  const Eigen::Vector3d w = P.transpose() * omega0_;  // principal components
  const double I1 = moments(0), I2 = moments(1), I3 = moments(2);
  const double d21 = I2 - I1, d32 = I3 - I2;
  const double wnorm = omega0_.stableNorm();
  Eigen::Vector3d& J = *J_out;
  Eigen::Vector3d& om = *om_out;
  // ---- Working frame: principal axes with the circulation axis third ----------------
  // L² − 2E I2 = I3 (I3 − I2) ω3² − I1 (I2 − I1) ω1²: > 0, the body circulates about
  // axis 3 (ω3 keeps its sign); < 0, about axis 1. For the latter, relabel the axes
  // (e3, −e2, e1) so that the same formulas hold with J = (I3, I2, I1).
  // Near the separatrix L² − 2E I2 carries the conditioning of the whole problem (k'²
  // and the period depend on it): evaluate it in extended precision, so that the data
  // are taken as given. The separatrix is the case where it vanishes exactly; just off
  // it (k'² down to ~1e-19), the elliptic solution, with the AGM and Π in terms of k'²,
  // is accurate and tends to the hyperbolic one.
  using Long = long double;
  const Long spin3 = Long(I3) * d32 * w(2) * w(2), spin1 = Long(I1) * d21 * w(0) * w(0);
  const bool separatrix = spin3 == spin1;
  if (separatrix || spin3 > spin1) {
    basis_ = P;
    J = moments;
    om = w;
  } else {
    basis_ << P.col(2), -P.col(1), P.col(0);
    J << I3, I2, I1;
    om << w(2), -w(1), w(0);
  }
  if (om(2) < 0.0) {  // rotate the frame by π about e1: ω3 > 0, hence u3 > 0 throughout
    basis_.col(1) = -basis_.col(1);
    basis_.col(2) = -basis_.col(2);
    om(1) = -om(1);
    om(2) = -om(2);
  }
  if (separatrix && om(0) < 0.0) {  // rotate by π about e3: ω1 > 0 (sech > 0)
    basis_.col(0) = -basis_.col(0);
    basis_.col(1) = -basis_.col(1);
    om(0) = -om(0);
    om(1) = -om(1);
  }
  basis_q_ = Eigen::Quaterniond(basis_).normalized();
  // Exact rescaling by powers of two to J3, |ω| ~ 1: the formulas below are homogeneous
  // (A_i, λ, |L|/J3 scale with |ω|; k, n, τ0 and |L| d31/(J1 J3 |λ|) are invariant), so
  // no intermediate square can overflow or underflow whatever the units.
  const int inertia_exp = std::ilogb(J.maxCoeff()), omega_exp = std::ilogb(wnorm);
  *omega_exp_out = omega_exp;
  for (int i = 0; i < 3; ++i) {
    J(i) = std::ldexp(J(i), -inertia_exp);
    om(i) = std::ldexp(om(i), -omega_exp);
  }
  moments_ = J;
  return separatrix;
}

void ExactFreeRigidBody::setEllipticCase(const Eigen::Vector3d& J, const Eigen::Vector3d& om, double G, double H) {
  using Long = long double;
  const double J1 = J(0), J2 = J(1), J3 = J(2);
  const double e31 = std::abs(J3 - J1), e32 = std::abs(J3 - J2), e21 = std::abs(J2 - J1);
  regime_ = Regime::kElliptic;
  regime_ = Regime::kElliptic;
  const double D = double(Long(J3) * e32 * om(2) * om(2) - Long(J1) * e21 * om(0) * om(0));
  // k² and k'² from cancellation-free products; the smaller one is the accurate one,
  // the other is taken as its complement so that the pair is consistent (the AGM and
  // dn = √(k'² + k² cn²) rely on k² + k'² = 1).
  const double k2_direct = e21 * G / (e32 * H);
  kp2_ = e31 * D / (e32 * H);
  k_ = std::sqrt(kp2_ < 0.5 ? 1.0 - kp2_ : k2_direct);
  if (kp2_ >= 0.5) kp2_ = 1.0 - k2_direct;
  // AGM (A&S 16.4.1–2) with c_{n+1} = c_n²/(4 a_{n+1}) (no cancellation), from k'
  // itself so that the modulus stays accurate near the separatrix; K = π/(2 a_N).
  double a = 1.0, b = std::sqrt(kp2_), c = k_;
  agm_steps_ = 0;
  while (c > kEps * a && agm_steps_ < kMaxAgmSteps) {
    const double a_next = 0.5 * (a + b);
    b = std::sqrt(a * b);
    c = c * c / (4.0 * a_next);
    a = a_next;
    ++agm_steps_;
    agm_c_over_a_[agm_steps_] = c / a;
    agm_b_over_a_[agm_steps_] = b / a;
  }
  agm_scale_ = std::ldexp(a, agm_steps_);
  K_ = kPi / (2.0 * a);
  // Π for n < 0 through the characteristic N = (k² − n)/(1 − n) ∈ (k², 1)
  // (A&S 17.7.15, as rearranged in Boost.Math's ellint_3), with F(am r) = r and
  // Π(N; φ) = F + (N/3) s³ R_J(c², Δ², 1, c² + (1 − N) s²) (DLMF 19.25.14):
  //   Π(n; am r) = r/(1 − n) + Q(r),                       (s, c, Δ) = (sn, cn, dn) r,
  //   Q(r) = a (N/3) s³ R_J(c², Δ², 1, c² + (1 − N) s²) + e atan(A s c / Δ),
  //   a = −n k'²/((1 − n)(k² − n)), e = √(−n/((k² − n)(1 − n))), A = √(−n N),
  //   1 − N = k'²/(1 − n).
  // All terms have the sign of s: no cancellation even for n ≪ −1 (nearly
  // axisymmetric bodies), unlike Carlson's form for Π(n; φ) itself; and the modulus
  // enters only through the accurate k'². Q(K) = a (N/3) R_J(0, k'², 1, 1 − N).
  // The steep part r/(1 − n) is exact in r; Q is flat where F is steep:
  // dQ/dφ = −n c²/((1 − n s²)(1 − n) Δ) ≤ 1/k, so the AGM's absolute error in am r
  // stays an absolute error in Q even near the saddle (Δ ≪ 1, k' ≪ 1).
  const double k2 = k_ * k_;
  pi_N_ = (k2 - n_) / (1.0 - n_);
  pi_Nm1_ = kp2_ / (1.0 - n_);
  pi_a_ = -n_ * kp2_ / ((1.0 - n_) * (k2 - n_));
  pi_e_ = std::sqrt(-n_ / ((k2 - n_) * (1.0 - n_)));
  pi_A_ = std::sqrt(-n_ * pi_N_);
  q_complete_ =
      pi_a_ * pi_N_ / 3.0 * boost::math::ellint_rj(0.0, kp2_, 1.0, pi_Nm1_, DoublePolicy());
  // Phase: τ0 = F(φ0, k), (sin φ0, cos φ0, Δ(φ0)) = (ω2/A2, ω1/A1, ω3/A3). Carlson's
  // form F(φ) = sin φ R_F(cos² φ, Δ², 1) for |φ| ≤ π/2 (DLMF 19.25.5) uses the three
  // ratios directly (relative condition ≤ ½), and F(±π ∓ φ) = ±2K − F(φ) beyond.
  const double s0 = std::clamp(om(1) / amplitude_(1), -1.0, 1.0);
  const double c0 = std::clamp(om(0) / amplitude_(0), -1.0, 1.0);
  const double dn0 = om(2) / amplitude_(2);
  const double f = s0 * boost::math::ellint_rf(c0 * c0, dn0 * dn0, 1.0, DoublePolicy());
  tau0_ = c0 >= 0.0 ? f : std::copysign(2.0 * K_, s0) - f;
}

ExactFreeRigidBody::ExactFreeRigidBody(const Eigen::Matrix3d& inertia_body,
                                       const Eigen::Quaterniond& q0,
                                       const Eigen::Vector3d& omega0_body) {
  const Eigen::Matrix3d inertia = validatedInertia(inertia_body, q0, omega0_body);
  q0_ = q0.normalized();
  omega0_ = omega0_body;
  Eigen::Vector3d moments;
  Eigen::Matrix3d P;
  principalAxes(inertia, &P, &moments);
  const Eigen::Vector3d momentum_body = inertia * omega0_;
  energy_ = 0.5 * omega0_.dot(momentum_body);
  momentum_world_ = q0_ * momentum_body;
  if (setTrigonometricCase(P, moments)) return;

  Eigen::Vector3d J, om;
  int omega_exp = 0;
  const bool separatrix = setWorkingFrame(P, moments, &J, &om, &omega_exp);
  // ---- Body angular velocity (Landau–Lifshitz §37, eq. 37.10) ------------------------
  // With d_ij = |J_i − J_j|, σ = sign(J3 − J1) and the positive, cancellation-free
  //   G = |2E J3 − L²| = J1 d31 ω1² + J2 d32 ω2²,  H = |L² − 2E J1| = J2 d21 ω2² + J3 d31 ω3²,
  //   D = |L² − 2E J2| = J3 d32 ω3² − J1 d21 ω1²,
  // the solution of J ω̇ = (J ω) × ω is
  //   ω = (A1 cn τ, A2 sn τ, A3 dn τ),  τ = λ t + τ0,
  //   A1² = G/(J1 d31),  A2² = G/(J2 d32),  A3² = H/(J3 d31),
  //   λ = σ √(d32 H/(J1 J2 J3)),  k² = d21 G/(d32 H),  k'² = 1 − k² = d31 D/(d32 H);
  // on the separatrix (k = 1) sn = tanh, cn = dn = sech. Substituting in Euler's
  // equations fixes the signs: with ω3 > 0 (and ω1 > 0 on the separatrix) all A_i > 0.
  const double J1 = J(0), J2 = J(1), J3 = J(2);
  const double e31 = std::abs(J3 - J1), e32 = std::abs(J3 - J2), e21 = std::abs(J2 - J1);
  const double sigma = J3 > J1 ? 1.0 : -1.0;
  const double G = J1 * e31 * om(0) * om(0) + J2 * e32 * om(1) * om(1);
  const double H = J2 * e21 * om(1) * om(1) + J3 * e31 * om(2) * om(2);
  amplitude_ << std::sqrt(G / (J1 * e31)), std::sqrt(G / (J2 * e32)), std::sqrt(H / (J3 * e31));
  const double abs_lambda = std::sqrt(e32 * H / (J1 * J2 * J3));
  lambda_ = separatrix ? abs_lambda : sigma * abs_lambda;
  const double M = J.cwiseProduct(om).norm();  // |L| (in the rescaled units)

  // ---- Precession (Landau–Lifshitz §37, eq. 37.15; Celledoni et al. 2008 §2) --------
  // R = R0 B Swing(u0)ᵀ Rz(Φ) Swing(u) Bᵀ, u = J ω / |L|. Writing the frame
  // Rz(−β) Swing(u), whose rows are (e3 × u)/ρ, u × (e3 × u)/ρ, u, as S, the kinematics
  // Ṙ = R ω^ give for the angle ψ about L the rate ψ̇ = |L| (J1 ω1² + J2 ω2²) /
  // (J1² ω1² + J2² ω2²) (denominator |L|² ρ² > 0 since u3 > 0 keeps its sign), i.e.
  //   ψ̇ = |L|/J3 + σ |L| d31 / (J1 J3 (1 − n sn² τ)),   n = −J3 d21 / (J1 d32) ≤ 0,
  //   ψ(t) = |L| t/J3 + |L| d31/(J1 J3 |λ|) [Π(τ) − Π(τ0)],  Π(τ) = ∫₀^τ dv/(1 − n sn² v),
  // Π being the incomplete integral of the third kind Π(n; am τ, k). The azimuth of
  // (u1, u2) is γ = β − π/2, so Φ = ψ − (γ − γ0).
  // When λ ≪ |ω| (nearly axisymmetric bodies) the factor 1/|λ| would turn the rounding
  // of Π(τ0) ~ ulp·τ0 into a large angle, so Π(τ) = τ/(1 − n) + Q(τ) is split into its
  // secular part, integrated exactly in t, and a bounded remainder Q (see phase()):
  //   ψ(t) = [|L|/J3 + rate_pi λ/(1 − n)] t + rate_pi [Q(τ) − Q(τ0)].
  n_ = -J3 * e21 / (J1 * e32);
  rate_pi_ = M * e31 / (J1 * J3 * abs_lambda);
  rate_linear_ = M / J3 + rate_pi_ * lambda_ / (1.0 - n_);

  if (separatrix) {
    regime_ = Regime::kSeparatrix;
    k_ = 1.0;
    kp2_ = 0.0;
    // sech τ0 = ω1/A1, tanh τ0 = ω2/A2, so sinh τ0 = (ω2/A2)/(ω1/A1): well conditioned.
    tau0_ = std::asinh((om(1) / amplitude_(1)) / (om(0) / amplitude_(0)));
  } else {
    setEllipticCase(J, om, G, H);
  }
  omega_unit_ = std::ldexp(1.0, omega_exp);
  lambda_ = std::ldexp(lambda_, omega_exp);
  rate_linear_ = std::ldexp(rate_linear_, omega_exp);
  const Phase p0 = phase(tau0_);
  q0_phase_ = p0.q;
  gamma0_ = p0.gamma;
  const Eigen::Vector3d omega_w(amplitude_(0) * p0.cn, amplitude_(1) * p0.sn,
                                amplitude_(2) * p0.dn);
  left_ = q0_ * basis_q_ * swing(J.cwiseProduct(omega_w).normalized()).conjugate();
}

ExactFreeRigidBody::Phase ExactFreeRigidBody::phase(double tau) const {
  Phase p;
  const double J1A1 = moments_(0) * amplitude_(0), J2A2 = moments_(1) * amplitude_(1);
  if (regime_ == Regime::kSeparatrix) {
    // k = 1: sn = tanh, cn = dn = sech; with m = −n ≥ 0,
    //   Π(τ) = ∫₀^τ dv/(1 + m tanh² v) = [τ + √m atan(√m tanh τ)] / (1 + m).
    const double sech = 1.0 / std::cosh(tau), th = std::tanh(tau), root_m = std::sqrt(-n_);
    p.sn = th;
    p.cn = p.dn = sech;
    p.q = root_m * std::atan(root_m * th) / (1.0 - n_);
    p.gamma = std::atan2(J2A2 * th, J1A1 * sech);
    return p;
  }
  // Reduce τ = 2K j + r, |r| ≤ K: sn, cn change sign with j, dn and am(τ) − jπ do not,
  // and Q grows by 2 Q(K) per half period.
  const double j = std::nearbyint(tau / (2.0 * K_));
  const double r = std::fma(-2.0 * K_, j, tau);
  double sn_r, cn_r, dn_r;
  jacobi(r, &sn_r, &cn_r, &dn_r);
  const double sign = std::fmod(j, 2.0) == 0.0 ? 1.0 : -1.0;
  p.sn = sign * sn_r;
  p.cn = sign * cn_r;
  p.dn = dn_r;
  p.q = 2.0 * j * q_complete_ + ellipticPiRemainder(sn_r, cn_r, dn_r);
  p.gamma = j * kPi + std::atan2(J2A2 * sn_r, J1A1 * cn_r);  // cn_r ≥ 0: no jump
  return p;
}

void ExactFreeRigidBody::jacobi(double u, double* sn, double* cn, double* dn) const {
  // Descending Landen/AGM recursion (A&S 16.4.3) in the stable form
  //   φ_{n−1} = ½ [φ_n + atan2(c_n sin φ_n, √(a_n² cos² φ_n + b_n² sin² φ_n))],
  // equal to A&S's ½ [φ_n + arcsin((c_n/a_n) sin φ_n)] (as a_n² − b_n² = c_n²) but
  // without its loss of accuracy near k → 1; sn = sin φ_0, cn = cos φ_0.
  double phi = agm_scale_ * u;
  for (int i = agm_steps_; i >= 1; --i) {
    const double s = std::sin(phi), c = std::cos(phi), ba = agm_b_over_a_[i];
    phi = 0.5 * (phi + std::atan2(agm_c_over_a_[i] * s, std::sqrt(c * c + ba * ba * s * s)));
  }
  *sn = std::sin(phi);
  *cn = std::cos(phi);
  *dn = std::sqrt(kp2_ + k_ * k_ * *cn * *cn);  // dn² = k'² + k² cn², no cancellation
}

double ExactFreeRigidBody::ellipticPiRemainder(double s, double c, double delta) const {
  if (s == 0.0) return 0.0;
  const double c2 = c * c;
  return pi_a_ * pi_N_ / 3.0 * s * s * s *
             boost::math::ellint_rj(c2, delta * delta, 1.0, c2 + pi_Nm1_ * s * s, DoublePolicy()) +
         pi_e_ * std::atan(pi_A_ * s * c / delta);
}

void ExactFreeRigidBody::evaluate(double t, Eigen::Quaterniond* q,
                                  Eigen::Vector3d* omega_body) const {
  if (regime_ == Regime::kSteady || regime_ == Regime::kAxisymmetric) {
    if (q) *q = q0_ * expq(t * (omega0_ - nu_ * axis_body_)) * expq(t * nu_ * axis_body_);
    if (omega_body) *omega_body = Eigen::AngleAxisd(-nu_ * t, axis_body_) * omega0_;
    return;
  }
  const Phase p = phase(std::fma(lambda_, t, tau0_));
  const Eigen::Vector3d omega_w(amplitude_(0) * p.cn, amplitude_(1) * p.sn,
                                amplitude_(2) * p.dn);  // in units of omega_unit_
  if (q) {
    const double psi = rate_linear_ * t + rate_pi_ * (p.q - q0_phase_);
    const double Phi = psi - (p.gamma - gamma0_);
    const Eigen::Vector3d u = moments_.cwiseProduct(omega_w).normalized();
    *q = (left_ * rotz(Phi) * swing(u) * basis_q_.conjugate()).normalized();
  }
  if (omega_body) *omega_body = basis_ * (omega_unit_ * omega_w);
}

}  // namespace lieflow
