/// Tests of the exact free rigid-body flow against independent references: a
/// high-order Taylor-series integrator of the equations of motion written here, the
/// closed-form Abaqus benchmark, conservation laws and the group property of the flow.
#include "dynamics/rigid_body/exact_free_body.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace lieflow {
namespace {

using Eigen::Matrix3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;
using Real = long double;
constexpr double kTwoPi = 6.283185307179586476925286766559;

// ---------------------------------------------------------------------------------------
// Reference: Taylor-series integrator in long double (64-bit mantissa) of
//   I ω̇ = (I ω) × ω,   q̇ = ½ q ⊗ (0, ω),
// a polynomial ODE whose Taylor coefficients follow from Cauchy products. The solution
// is analytic in the strip of half-width ρ = K'/|λ| ≥ π/(2|ω|) (poles of sn, cn, dn; q
// solves a linear ODE with coefficient ω, so it has no other singularities). With the
// step h = kStepFraction/|ω| and order kTaylorOrder the truncation error is
// ~ (h/ρ)^20 ≤ 0.13^20 ≈ 1e-18 per step; rounding is ~1e-19 per step. Its error is
// measured by running it with steps h and h/2.
// ---------------------------------------------------------------------------------------
constexpr int kTaylorOrder = 20;
constexpr double kStepFraction = 0.2;

struct State {
  std::array<Real, 4> q;  // w, x, y, z
  std::array<Real, 3> w;
};

class TaylorReference {
 public:
  TaylorReference(const Matrix3d& inertia, const Quaterniond& q0, const Vector3d& w0)
      : inv_(inertia.inverse()) {
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) inertia_[i][j] = inertia(i, j);
    // Inverse in long double by one Newton refinement of the double inverse.
    Real prod[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        prod[i][j] = 0;
        for (int l = 0; l < 3; ++l) prod[i][j] += inertia_[i][l] * Real(inv_(l, j));
      }
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        Real corr = 0;  // X (2 − I X)
        for (int l = 0; l < 3; ++l) corr += Real(inv_(i, l)) * ((l == j ? 2 : 0) - prod[l][j]);
        inverse_[i][j] = corr;
      }
    s_.q = {q0.w(), q0.x(), q0.y(), q0.z()};
    s_.w = {w0.x(), w0.y(), w0.z()};
  }

  /// Advances from the current time to t with steps of at most h (h > 0).
  void advanceTo(double t, double h) {
    const Real span = Real(t) - time_;
    const long steps = std::max(1L, static_cast<long>(std::ceil(std::fabs(double(span)) / h)));
    const Real dt = span / steps;
    for (long i = 0; i < steps; ++i) step(dt);
    time_ = t;
  }
  Quaterniond q() const {
    return Quaterniond(double(s_.q[0]), double(s_.q[1]), double(s_.q[2]), double(s_.q[3]));
  }
  Vector3d omega() const { return Vector3d(double(s_.w[0]), double(s_.w[1]), double(s_.w[2])); }

 private:
  void step(Real dt) {
    constexpr int P = kTaylorOrder;
    Real w[3][P + 1], q[4][P + 1], l[3][P + 1];
    for (int i = 0; i < 3; ++i) w[i][0] = s_.w[i];
    for (int i = 0; i < 4; ++i) q[i][0] = s_.q[i];
    for (int m = 0; m < P; ++m) {
      for (int i = 0; i < 3; ++i)
        l[i][m] = inertia_[i][0] * w[0][m] + inertia_[i][1] * w[1][m] + inertia_[i][2] * w[2][m];
      Real cross[3] = {0, 0, 0};  // Σ ℓ_a × ω_{m−a}
      Real qd[4] = {0, 0, 0, 0};  // Σ q_a ⊗ (0, ω_{m−a})
      for (int a = 0; a <= m; ++a) {
        const int b = m - a;
        cross[0] += l[1][a] * w[2][b] - l[2][a] * w[1][b];
        cross[1] += l[2][a] * w[0][b] - l[0][a] * w[2][b];
        cross[2] += l[0][a] * w[1][b] - l[1][a] * w[0][b];
        const Real qw = q[0][a], qx = q[1][a], qy = q[2][a], qz = q[3][a];
        const Real x = w[0][b], y = w[1][b], z = w[2][b];
        qd[0] += -qx * x - qy * y - qz * z;
        qd[1] += qw * x + qy * z - qz * y;
        qd[2] += qw * y + qz * x - qx * z;
        qd[3] += qw * z + qx * y - qy * x;
      }
      for (int i = 0; i < 3; ++i)
        w[i][m + 1] =
            (inverse_[i][0] * cross[0] + inverse_[i][1] * cross[1] + inverse_[i][2] * cross[2]) /
            (m + 1);
      for (int i = 0; i < 4; ++i) q[i][m + 1] = qd[i] / (2 * (m + 1));
    }
    for (int i = 0; i < 3; ++i) {
      Real sum = w[i][P];
      for (int m = P - 1; m >= 0; --m) sum = sum * dt + w[i][m];
      s_.w[i] = sum;
    }
    for (int i = 0; i < 4; ++i) {
      Real sum = q[i][P];
      for (int m = P - 1; m >= 0; --m) sum = sum * dt + q[i][m];
      s_.q[i] = sum;
    }
  }

  Matrix3d inv_;
  Real inertia_[3][3], inverse_[3][3];
  State s_;
  Real time_ = 0;
};

/// Rotation angle between two unit quaternions (sign-independent).
double angleBetween(const Quaterniond& a, const Quaterniond& b) {
  const Quaterniond d = a.conjugate() * b;
  return 2.0 * std::atan2(d.vec().norm(), std::abs(d.w()));
}

/// Distance between quaternions as 4-vectors: the output is continuous in t, so
/// compare signs too.
double quaternionDistance(const Quaterniond& a, const Quaterniond& b) {
  return (a.coeffs() - b.coeffs()).norm();
}

Matrix3d rotated(const Vector3d& principal, const Vector3d& axis, double angle) {
  const Matrix3d R = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
  return R * principal.asDiagonal() * R.transpose();
}

const Quaterniond kQ0 = Quaterniond(0.8, -0.2, 0.5, 0.26).normalized();

struct Case {
  const char* name;
  Matrix3d inertia;
  Vector3d omega0;
  std::vector<double> times;  // increasing |t|, all of one sign
};

const std::vector<double> kForward = {0.37, 1.0, 3.3, 10.0, 31.7, 100.0};
const std::vector<double> kBackward = {-0.37, -1.0, -3.3, -10.0, -31.7, -100.0};
/// Accuracy target per radian turned, max(1, |ω0| |t|): ~10 ulps (a rotation by |ω| t
/// computed in double carries ~ulp · |ω| t of phase error; the elliptic integrals, the
/// reduction by periods and the diagonalization of the inertia add a few ulps each).
/// This is 2e-13 at |ω0| t = 100, where the measured errors are ≤ 7.3e-14.
constexpr double kTolPerRadian = 2e-15;
/// The initial data is perturbed by this many ulps (relative) to measure the
/// conditioning of the problem with the reference itself.
constexpr double kDataUlps = 2.0;
/// The exact flow is backward stable: its result is the exact solution for data within
/// a few ulps, so its error may reach the effect of such a perturbation (measured with
/// kDataUlps) times this factor. Only near the separatrix does that term matter.
constexpr double kConditioningFactor = 4.0;

/// Compares ExactFreeRigidBody with the Taylor reference at the case's times. The
/// tolerance is derived from the reference:
///   tol(t) = kTolPerRadian · max(1, |ω0| |t|)            the accuracy target,
///          + 10 · |ref_h − ref_{h/2}|                      the reference's own error,
///          + 4 · |ref(ω0) − ref(ω0 ∘ (1 − 2ε, 1 + 2ε, 1 + 2ε))|   the conditioning: what
///            a few-ulp change of the data does to the solution (~1e-14 for generic
///            data, up to 1e-9 near the separatrix at t = 100; column "ref 2ulp").
/// Errors are |q − q_ref| (as 4-vectors, signs included) and |ω − ω_ref| / |ω0|.
void checkAgainstReference(const Case& c) {
  SCOPED_TRACE(c.name);
  const ExactFreeRigidBody exact(c.inertia, kQ0, c.omega0);
  const double h = kStepFraction / c.omega0.norm();
  const double e = kDataUlps * std::numeric_limits<double>::epsilon();
  // (1 − e, 1 + e, 1 + e) moves L² − 2E I2 (the separatrix distance) for diagonal I.
  const Vector3d perturbed = c.omega0.cwiseProduct(Vector3d(1 - e, 1 + e, 1 + e));
  TaylorReference coarse(c.inertia, kQ0, c.omega0), fine(c.inertia, kQ0, c.omega0),
      shifted(c.inertia, kQ0, perturbed);
  double worst_q = 0, worst_w = 0, worst_ref = 0, worst_cond = 0, worst_ratio = 0;
  for (const double t : c.times) {
    coarse.advanceTo(t, h);
    fine.advanceTo(t, 0.5 * h);
    shifted.advanceTo(t, h);
    const double ref_error = std::max(quaternionDistance(coarse.q(), fine.q()),
                                      (coarse.omega() - fine.omega()).norm() / c.omega0.norm());
    const double conditioning = std::max(quaternionDistance(shifted.q(), fine.q()),
                                         (shifted.omega() - fine.omega()).norm() / c.omega0.norm());
    Quaterniond q;
    Vector3d w;
    exact.evaluate(t, &q, &w);
    const double radians = std::max(1.0, c.omega0.norm() * std::abs(t));
    const double err_q = quaternionDistance(q, fine.q());
    const double err_w = (w - fine.omega()).norm() / c.omega0.norm();
    const double tol =
        kTolPerRadian * radians + 10 * ref_error + kConditioningFactor * conditioning;
    EXPECT_LE(err_q, tol) << "t = " << t;
    EXPECT_LE(err_w, tol) << "t = " << t;
    EXPECT_LE(angleBetween(q, fine.q()), tol) << "t = " << t;
    worst_q = std::max(worst_q, err_q);
    worst_w = std::max(worst_w, err_w);
    worst_ref = std::max(worst_ref, ref_error);
    worst_cond = std::max(worst_cond, conditioning);
    worst_ratio = std::max(worst_ratio, std::max(err_q, err_w) / tol);
  }
  std::printf(
      "[ measured ] %-38s k=%.9f |dq|=%.1e |dw|/|w0|=%.1e ref h:h/2=%.1e "
      "ref 2ulp=%.1e err/tol=%.2f\n",
      c.name, exact.modulus(), worst_q, worst_w, worst_ref, worst_cond, worst_ratio);
}

Vector3d diag(double a, double b, double c) { return Vector3d(a, b, c); }

TEST(ExactFreeBody, AsymmetricCirculatingAboutMajorAxis) {
  const Case c{"asymmetric L2>2E*I2", diag(1, 2, 3).asDiagonal(), Vector3d(0.3, 0.4, 1.0),
               kForward};
  EXPECT_EQ(ExactFreeRigidBody(c.inertia, kQ0, c.omega0).regime(),
            ExactFreeRigidBody::Regime::kElliptic);
  checkAgainstReference(c);
}

TEST(ExactFreeBody, AsymmetricCirculatingAboutMinorAxis) {
  checkAgainstReference(
      {"asymmetric L2<2E*I2", diag(1, 2, 3).asDiagonal(), Vector3d(1.0, 0.4, -0.3), kForward});
  checkAgainstReference({"asymmetric L2<2E*I2, w1<0", diag(0.7, 1.3, 1.9).asDiagonal(),
                         Vector3d(-1.2, -0.8, 0.1), kForward});
}

TEST(ExactFreeBody, NegativeTime) {
  checkAgainstReference({"asymmetric L2>2E*I2, t<0", diag(1, 2, 3).asDiagonal(),
                         Vector3d(0.3, 0.4, -1.0), kBackward});
  checkAgainstReference({"asymmetric L2<2E*I2, t<0", diag(1, 2, 3).asDiagonal(),
                         Vector3d(1.0, -0.4, 0.3), kBackward});
}

TEST(ExactFreeBody, NearSeparatrix) {
  // L² − 2E I2 = 3 ω3² − ω1² = ±1e-6: k'² ≈ 8e-7, K ≈ 8.4. The flow amplifies
  // perturbations of the data by up to ~1e6 by t = 100 (the "ref 2ulp" column).
  const double w1 = 1.0, w3 = std::sqrt((1.0 + 1e-6) / 3.0), w3m = std::sqrt((1.0 - 1e-6) / 3.0);
  checkAgainstReference(
      {"near separatrix, above", diag(1, 2, 3).asDiagonal(), Vector3d(w1, 0.5, w3), kForward});
  checkAgainstReference(
      {"near separatrix, below", diag(1, 2, 3).asDiagonal(), Vector3d(w1, 0.5, -w3m), kForward});
}

TEST(ExactFreeBody, OnSeparatrix) {
  // I = diag(1, 2, 2.25), ω = (0.75, 0.5, −1): L² − 2E I2 = 2.25·0.25 ω3² − 1·1 ω1² = 0
  // exactly in binary, so k = 1 (sech/tanh). Along the separatrix perturbations grow
  // like e^{λ t} (λ ≈ 0.87), which the conditioning term of the tolerance accounts for.
  const Case exact{"separatrix (k=1)",
                   diag(1, 2, 2.25).asDiagonal(),
                   Vector3d(0.75, 0.5, -1.0),
                   {0.37, 1.0, 3.3, 10.0, 31.7}};
  EXPECT_EQ(ExactFreeRigidBody(exact.inertia, kQ0, exact.omega0).regime(),
            ExactFreeRigidBody::Regime::kSeparatrix);
  checkAgainstReference(exact);
  checkAgainstReference({"separatrix (k=1), t<0",
                         exact.inertia,
                         Vector3d(-0.75, 0.5, 1.0),
                         {-0.37, -1.0, -3.3, -10.0, -31.7}});
  // One ulp off it: 3 ω3² − ω1² = 3 − fl(√3)² ≈ 4e-16, k' ≈ 1e-8.
  const Case off{"within 1 ulp of the separatrix",
                 diag(1, 2, 3).asDiagonal(),
                 Vector3d(std::sqrt(3.0), 0.5, -1.0),
                 {0.37, 1.0, 3.3, 10.0, 15.0}};
  EXPECT_EQ(ExactFreeRigidBody(off.inertia, kQ0, off.omega0).regime(),
            ExactFreeRigidBody::Regime::kElliptic);
  checkAgainstReference(off);
}

TEST(ExactFreeBody, Axisymmetric) {
  const Case prolate{"axisymmetric prolate", diag(1, 5, 5).asDiagonal(), Vector3d(2.0, 0.5, -0.3),
                     kForward};
  const Case oblate{"axisymmetric oblate", diag(2, 2, 3.5).asDiagonal(), Vector3d(0.3, -0.2, 1.5),
                    kForward};
  EXPECT_EQ(ExactFreeRigidBody(prolate.inertia, kQ0, prolate.omega0).regime(),
            ExactFreeRigidBody::Regime::kAxisymmetric);
  EXPECT_EQ(ExactFreeRigidBody(oblate.inertia, kQ0, oblate.omega0).regime(),
            ExactFreeRigidBody::Regime::kAxisymmetric);
  checkAgainstReference(prolate);
  checkAgainstReference(oblate);
  checkAgainstReference({"axisymmetric, non-diagonal",
                         rotated(diag(2, 2, 3.5), Vector3d(1, -2, 0.5), 0.9),
                         Vector3d(0.3, -0.2, 1.5), kBackward});
}

TEST(ExactFreeBody, Spherical) {
  checkAgainstReference(
      {"spherical", (2.0 * Matrix3d::Identity()), Vector3d(0.3, -0.7, 1.1), kForward});
}

TEST(ExactFreeBody, NearlyAxisymmetric) {
  checkAgainstReference({"nearly oblate (I2-I1=1e-9)", diag(2, 2 + 2e-9, 3.5).asDiagonal(),
                         Vector3d(0.3, -0.2, 1.5), kForward});
  checkAgainstReference({"nearly prolate (I3-I2=1e-9)", diag(1, 5, 5 + 5e-9).asDiagonal(),
                         Vector3d(2.0, 0.5, -0.3), kForward});
  // Nearly prolate body tumbling almost end over end: circulation about the symmetry
  // axis with λ ≈ 5e-4 ≪ |ω|, where the precession carries a factor 1/λ. (Diagonal
  // inertia: given as a rotated matrix, one ulp of its entries would move the nearly
  // degenerate principal axes by ~ulp/1e-10 and the solution by ~1e-13 at t = 100.)
  checkAgainstReference({"nearly prolate, tumbling (I3-I2=2e-10)",
                         diag(1, 2, 2 + 2e-10).asDiagonal(), Vector3d(1e-3, 0.5, 0.7), kForward});
  // Circulating about the nearly degenerate pair: |J3 − J2| = 2e-6 in the working frame.
  checkAgainstReference({"near pair circulation (I3-I2=2e-6)", diag(1, 2, 2 + 2e-6).asDiagonal(),
                         Vector3d(1e-4, 1.0, 1.0), kForward});
}

TEST(ExactFreeBody, ContinuousAcrossTheAxisymmetricThreshold) {
  // The axisymmetric closed form (I1 = I2 up to 8 ulps) and the elliptic one just
  // beyond must agree to the size of the inertia difference times |ω|² t.
  const Vector3d w0(0.3, -0.2, 1.5);
  const ExactFreeRigidBody sym(diag(2, 2, 3.5).asDiagonal(), kQ0, w0);
  const ExactFreeRigidBody near(diag(2, 2 * (1 + 1e-14), 3.5).asDiagonal(), kQ0, w0);
  ASSERT_EQ(sym.regime(), ExactFreeRigidBody::Regime::kAxisymmetric);
  ASSERT_EQ(near.regime(), ExactFreeRigidBody::Regime::kElliptic);
  for (const double t : {1.0, 10.0, 100.0}) {
    Quaterniond qa, qb;
    Vector3d wa, wb;
    sym.evaluate(t, &qa, &wa);
    near.evaluate(t, &qb, &wb);
    EXPECT_LE(quaternionDistance(qa, qb), 1e-14 * w0.squaredNorm() * t + 1e-14) << t;
    EXPECT_LE((wa - wb).norm(), 1e-14 * w0.squaredNorm() * t + 1e-14) << t;
  }
}

TEST(ExactFreeBody, NonDiagonalInertia) {
  checkAgainstReference({"non-diagonal, L2>2E*I2",
                         rotated(diag(1, 2, 3), Vector3d(0.3, 1, -0.4), 1.1),
                         Vector3d(0.5, -0.2, 0.9), kForward});
  checkAgainstReference({"non-diagonal, unsorted, L2<2E*I2",
                         rotated(diag(3.1, 1.2, 2.4), Vector3d(-1, 0.2, 0.7), 2.5),
                         Vector3d(-0.8, 0.6, 0.4), kForward});
}

TEST(ExactFreeBody, ScalesWithUnits) {
  // If ω solves Euler's equations for I, then s ω(s t) solves them for c I: check the
  // flow in extreme units (no intermediate overflow or underflow) against unit scales.
  const Matrix3d I = rotated(diag(3.1, 1.2, 2.4), Vector3d(-1, 0.2, 0.7), 2.5);
  for (const Vector3d& w0 : {Vector3d(-0.8, 0.6, 0.4), Vector3d(0.3, 0.4, 1.0)}) {
    const double s = 1e-200, c = 3e150;
    const ExactFreeRigidBody unit(I, kQ0, w0), scaled(c * I, kQ0, s * w0);
    for (const double t : {-2.0, 7.5}) {
      Quaterniond qa, qb;
      Vector3d wa, wb;
      unit.evaluate(t, &qa, &wa);
      scaled.evaluate(t / s, &qb, &wb);
      EXPECT_LE(quaternionDistance(qa, qb), 1e-13);
      EXPECT_LE((wa - wb / s).norm(), 1e-13 * w0.norm());
    }
  }
}

TEST(ExactFreeBody, SteadyRotations) {
  const Matrix3d I = diag(1, 2, 3).asDiagonal();
  for (const Vector3d& w0 :
       {Vector3d(1.3, 0, 0), Vector3d(0, -0.7, 0), Vector3d(0, 0, 2.0), Vector3d(0, 0, 0)}) {
    const ExactFreeRigidBody body(I, kQ0, w0);
    EXPECT_EQ(body.regime(), ExactFreeRigidBody::Regime::kSteady);
    for (const double t : {-3.0, 0.5, 100.0}) {
      Quaterniond q;
      Vector3d w;
      body.evaluate(t, &q, &w);
      const Vector3d angle = t * w0;
      const double a = angle.norm();
      const Quaterniond expected =
          a == 0 ? kQ0 : kQ0 * Quaterniond(Eigen::AngleAxisd(a, angle / a));
      EXPECT_LE(angleBetween(q, expected), 1e-14 * (1 + a));
      EXPECT_EQ(w, w0);
    }
  }
}

TEST(ExactFreeBody, AbaqusBenchmark) {
  // I = diag(1, 1, 2), ω0 = (0.25, 0, 2π): ω⊥ turns at (I3 − I1)/I1 ω3 = 2π rad/s:
  // ω = (0.25 cos 2πt, 0.25 sin 2πt, 2π).
  const ExactFreeRigidBody body(Vector3d(1, 1, 2).asDiagonal(), Quaterniond::Identity(),
                                Vector3d(0.25, 0, kTwoPi));
  double worst = 0;
  for (int i = 0; i <= 200; ++i) {
    const double t = 0.05 * i;
    Vector3d w;
    body.evaluate(t, nullptr, &w);
    const Vector3d expected(0.25 * std::cos(kTwoPi * t), 0.25 * std::sin(kTwoPi * t), kTwoPi);
    worst = std::max(worst, (w - expected).cwiseAbs().maxCoeff());
  }
  EXPECT_LE(worst, 1e-13);
  std::printf("[ measured ] Abaqus benchmark max|w - w_exact| on [0,10]: %.1e\n", worst);
}

TEST(ExactFreeBody, ConservesEnergyAndMomentumOverLongTimes) {
  const std::vector<std::pair<Matrix3d, Vector3d>> cases = {
      {diag(1, 2, 3).asDiagonal(), Vector3d(0.3, 0.4, 1.0)},
      {rotated(diag(3.1, 1.2, 2.4), Vector3d(-1, 0.2, 0.7), 2.5), Vector3d(-0.8, 0.6, 0.4)},
      {diag(1, 2, 3).asDiagonal(), Vector3d(1.0, 0.5, std::sqrt((1.0 + 1e-6) / 3.0))},
      {diag(2, 2, 3.5).asDiagonal(), Vector3d(0.3, -0.2, 1.5)}};
  for (const auto& [I, w0] : cases) {
    const ExactFreeRigidBody body(I, kQ0, w0);
    const double E0 = body.energy();
    const Vector3d L0 = body.spatialAngularMomentum();
    EXPECT_NEAR(E0, 0.5 * w0.dot(I * w0), 1e-15 * E0);
    double drift_e = 0, drift_l = 0;
    for (int i = 0; i <= 1000; ++i) {
      const double t = 1.0 * i + 0.123;
      Quaterniond q;
      Vector3d w;
      body.evaluate(t, &q, &w);
      drift_e = std::max(drift_e, std::abs(0.5 * w.dot(I * w) - E0) / E0);
      drift_l = std::max(drift_l, (q * (I * w) - L0).norm() / L0.norm());
    }
    EXPECT_LE(drift_e, 1e-14);
    EXPECT_LE(drift_l, 1e-14);
    std::printf("[ measured ] conservation on [0,1000]: max dE/E=%.1e max |dL|/|L|=%.1e\n", drift_e,
                drift_l);
  }
}

TEST(ExactFreeBody, InitialStateAndGroupProperty) {
  const std::vector<std::pair<Matrix3d, Vector3d>> cases = {
      {diag(1, 2, 3).asDiagonal(), Vector3d(0.3, 0.4, 1.0)},
      {diag(1, 2, 3).asDiagonal(), Vector3d(1.0, 0.4, -0.3)},
      {rotated(diag(3.1, 1.2, 2.4), Vector3d(-1, 0.2, 0.7), 2.5), Vector3d(-0.8, 0.6, 0.4)},
      {diag(1, 5, 5).asDiagonal(), Vector3d(2.0, 0.5, -0.3)},
      {diag(1, 2, 2.25).asDiagonal(), Vector3d(0.75, 0.5, -1.0)}};
  for (const auto& [I, w0] : cases) {
    const ExactFreeRigidBody body(I, kQ0, w0);
    Quaterniond q;
    Vector3d w;
    body.evaluate(0.0, &q, &w);
    EXPECT_LE(quaternionDistance(q, kQ0), 1e-15);  // a few ulps
    EXPECT_LE((w - w0).norm(), 1e-15 * w0.norm());
    for (const auto& [t1, t2] :
         {std::pair{0.7, 2.9}, std::pair{13.0, -5.5}, std::pair{-4.2, 1.3}}) {
      Quaterniond q1, q12, q2;
      Vector3d w1, w12, w2;
      body.evaluate(t1, &q1, &w1);
      body.evaluate(t1 + t2, &q12, &w12);
      ExactFreeRigidBody(I, q1.normalized(), w1).evaluate(t2, &q2, &w2);
      const double radians = w0.norm() * (std::abs(t1) + std::abs(t2));
      EXPECT_LE(quaternionDistance(q12, q2), kTolPerRadian * radians) << t1 << " " << t2;
      EXPECT_LE((w12 - w2).norm() / w0.norm(), kTolPerRadian * radians) << t1 << " " << t2;
    }
  }
}

/// Expects the constructor to throw std::invalid_argument whose message names
/// `argument` and contains `reason`.
void expectThrowsNaming(const Matrix3d& I, const Quaterniond& q, const Vector3d& w,
                        const std::string& argument, const std::string& reason) {
  try {
    ExactFreeRigidBody body(I, q, w);
    ADD_FAILURE() << "no exception; expected one naming " << argument;
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(argument), std::string::npos) << message;
    EXPECT_NE(message.find(reason), std::string::npos) << message;
  }
}

TEST(ExactFreeBody, RejectsBadInput) {
  const Matrix3d I = Vector3d(1, 2, 3).asDiagonal();
  const Quaterniond q = Quaterniond::Identity();
  const Vector3d w(0.1, 0.2, 0.3);
  const double nan = std::nan("");
  Matrix3d bad = I;
  bad(1, 2) = nan;
  expectThrowsNaming(bad, q, w, "inertia_body", "finite");
  bad = I;
  bad(0, 1) = 1e-3;
  expectThrowsNaming(bad, q, w, "inertia_body", "symmetric");
  expectThrowsNaming(Vector3d(1, -2, 3).asDiagonal(), q, w, "inertia_body", "positive definite");
  expectThrowsNaming(Vector3d(1, 1, 2.5).asDiagonal(), q, w, "inertia_body", "triangle");
  expectThrowsNaming(I, Quaterniond(1, 0, 0, 1e-4), w, "q0", "norm");
  expectThrowsNaming(I, Quaterniond(nan, 0, 0, 0), w, "q0", "finite");
  expectThrowsNaming(I, q, Vector3d(0, std::numeric_limits<double>::infinity(), 0), "omega0_body",
                     "finite");
  // Accepted limits: the triangle inequality as an equality, a quaternion 1e-10 off unit.
  EXPECT_NO_THROW(
      ExactFreeRigidBody(Vector3d(1, 2, 3).asDiagonal(), Quaterniond(1 + 1e-10, 0, 0, 0), w));
}

}  // namespace
}  // namespace lieflow
