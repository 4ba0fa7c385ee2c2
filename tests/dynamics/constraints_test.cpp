/// \file
/// The kinematic constraint library (dynamics/constraints/) against independent
/// references:
///  * every constraint Jacobian against central finite differences of the
///    right-perturbation definition, (Φ(q ⊕ h e_j) − Φ(q ⊕ −h e_j))/2h, applied
///    to the residual written out in this file from the world-frame formulas
///    (not the library's), and against ceres::Jet forward differentiation,
///    at random configurations, relative Frobenius discrepancy ≤ 1e-7;
///  * the velocity form against d/dt Φ and the convective term against
///    d²/dt² Φ − J q̈, by 4th-order finite differences in time along random
///    smooth motions R(t) = R₀ exp(ω t + ½ ω̇ t²), p(t) = p₀ + v t + ½ v̇ t²
///    (whose body velocity and acceleration at t = 0 are exactly (v, ω), (v̇, ω̇));
///  * joint angles against configurations built from known angles (across ±π
///    with unwrapping), their rates and convective terms along motions on the
///    constraint manifold, their Jacobians against finite differences, Jets
///    and the Abaqus form (−a, +a) on the manifold;
///  * the Cardan shaft: tan θ₂ = tan θ₁ / cos β and
///    ω₂/ω₁ = cos β / (1 − sin²β cos²θ₁) (θ₁ measured from the plane of the
///    shafts to the input yoke's hinge axis), by solving the universal-joint
///    constraint for the output angle with a 1-D Newton iteration;
///  * gear rows against the Radioss formulas written out here, motions that
///    satisfy them and motions that violate them;
///  * bad input.
// GCC 12 reports a false -Warray-bounds inside Eigen's SSE packet loads for
// the 1-element dynamic vectors of the angle checks below (a known GCC 12
// false positive); Eigen sizes the loads correctly, so it is silenced here.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Warray-bounds"
#endif

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <type_traits>

#include <gtest/gtest.h>

#include "dynamics/constraints/constraints.hpp"
#include "tests/dynamics/constraint_checks.hpp"

namespace lieflow {
namespace constraints {
namespace {

using namespace checks;  // NOLINT: the shared harness (constraint_checks.hpp)

// ---- joint specifications (double data, built for any scalar) -------------------------

struct SphericalSpec {
  Vec3 s_a, s_b;
  template <typename S>
  SphericalJoint<S> build() const {
    return makeSphericalJoint<S>(castV<S>(s_a), castV<S>(s_b));
  }
};

struct RevoluteSpec {
  Vec3 s_a, s_b, a_a, a_b;
  SO3d reference;
  template <typename S>
  RevoluteJoint<S> build() const {
    return makeRevoluteJoint<S>(castV<S>(s_a), castV<S>(s_b), castV<S>(a_a), castV<S>(a_b),
                                reference.cast<S>());
  }
};

struct UniversalSpec {
  Vec3 s_a, s_b, a1, a2;
  SO3d reference;
  template <typename S>
  UniversalJoint<S> build() const {
    return makeUniversalJoint<S>(castV<S>(s_a), castV<S>(s_b), castV<S>(a1), castV<S>(a2),
                                 reference.cast<S>());
  }
};

RevoluteSpec randomRevolute(std::mt19937& gen) {
  RevoluteSpec s;
  s.s_a = randomVector(gen);
  s.s_b = randomVector(gen);
  s.a_a = randomUnit(gen);
  s.reference = SO3d::random(gen);
  s.a_b = s.reference.inverse() * s.a_a;
  return s;
}

UniversalSpec randomUniversal(std::mt19937& gen) {
  UniversalSpec s;
  s.s_a = randomVector(gen);
  s.s_b = randomVector(gen);
  s.a1 = randomUnit(gen);
  s.reference = SO3d::random(gen);
  s.a2 = s.reference.inverse() * randomUnitNormalTo(gen, s.a1);
  return s;
}

/// Secondary pose on the revolute manifold: R_b = R_a exp(φ a_a) R_ref, the
/// anchors coincident.
Pose revolutePose(const RevoluteSpec& s, const Pose& a, double phi) {
  Pose b;
  b.R = a.R * SO3d::exp(phi * s.a_a) * s.reference;
  b.p = a.toWorld(s.s_a) - b.R * s.s_b;
  return b;
}

/// Secondary pose on the universal manifold: R_b = R_a exp(φ₁ e₁) exp(φ₂ e₂) R_ref.
Pose universalPose(const UniversalSpec& s, const Pose& a, double phi1, double phi2) {
  const Vec3 e2 = s.reference * s.a2;
  Pose b;
  b.R = a.R * SO3d::exp(phi1 * s.a1) * SO3d::exp(phi2 * e2) * s.reference;
  b.p = a.toWorld(s.s_a) - b.R * s.s_b;
  return b;
}


// ---- 1. holonomic constraints: Jacobians ---------------------------------------------------

TEST(JointConstraints, JacobiansAgainstFiniteDifferencesAndJets) {
  std::mt19937 gen(20240401);
  Worst worst;
  for (int i = 0; i < kSamples; ++i) {
    // Spherical, at arbitrary (violated) configurations; also to ground.
    {
      const SphericalSpec spec{randomVector(gen), randomVector(gen)};
      const auto joint = spec.build<double>();
      const auto ref = [&](const std::array<Pose, 2>& X) -> Eigen::VectorXd {
        return refSpherical<double>(spec.s_a, spec.s_b, X);
      };
      const auto lib_jet = [&](const auto& X) {
        using S = typename std::decay_t<decltype(X[0].p)>::Scalar;
        return spec.build<S>().residual(X[0], X[1]);
      };
      checkJacobians(worst, "spherical", joint, {randomPose(gen), randomPose(gen)}, ref, lib_jet);
      const std::array<Pose, 2> to_ground{groundPose<double>(), randomPose(gen)};
      const Eigen::MatrixXd J = stack(joint.jacobians(to_ground[0], to_ground[1]));
      worst.add("spherical to ground J_b vs FD",
                relative(fdJacobian(ref, to_ground).rightCols<6>(), J.rightCols<6>()));
    }
    // Revolute, near the manifold (random nudges of 0.3) and far from it.
    {
      const RevoluteSpec spec = randomRevolute(gen);
      const auto joint = spec.build<double>();
      const auto ref = [&](const std::array<Pose, 2>& X) -> Eigen::VectorXd {
        Eigen::VectorXd r(5);
        r << refSpherical<double>(spec.s_a, spec.s_b, X), refDot(joint.u_main, spec.a_b, X),
            refDot(joint.v_main, spec.a_b, X);
        return r;
      };
      const auto lib_jet = [&](const auto& X) {
        using S = typename std::decay_t<decltype(X[0].p)>::Scalar;
        return spec.build<S>().residual(X[0], X[1]);
      };
      const Pose a = randomPose(gen);
      const double phi = std::uniform_real_distribution<double>(-4.0, 4.0)(gen);
      checkJacobians(worst, "revolute", joint, {a, nudge(gen, revolutePose(spec, a, phi), 0.3)}, ref,
                     lib_jet);
      checkJacobians(worst, "revolute", joint, {randomPose(gen), randomPose(gen)}, ref, lib_jet);
    }
    // Universal.
    {
      const UniversalSpec spec = randomUniversal(gen);
      const auto joint = spec.build<double>();
      const auto ref = [&](const std::array<Pose, 2>& X) -> Eigen::VectorXd {
        Eigen::VectorXd r(4);
        r << refSpherical<double>(spec.s_a, spec.s_b, X), refDot(spec.a1, spec.a2, X);
        return r;
      };
      const auto lib_jet = [&](const auto& X) {
        using S = typename std::decay_t<decltype(X[0].p)>::Scalar;
        return spec.build<S>().residual(X[0], X[1]);
      };
      const Pose a = randomPose(gen);
      checkJacobians(worst, "universal", joint,
                     {a, nudge(gen, universalPose(spec, a, 2.0 * randomVector(gen)[0],
                                                  2.0 * randomVector(gen)[0]),
                               0.3)},
                     ref, lib_jet);
      checkJacobians(worst, "universal", joint, {randomPose(gen), randomPose(gen)}, ref, lib_jet);
    }
  }
  worst.print("holonomic constraint Jacobians");
  worst.expectAllBelow(kJacobianTolerance);
}

// ---- 2. velocity form and convective term ------------------------------------------------------

TEST(JointConstraints, VelocityFormAndConvectiveTermAlongMotions) {
  std::mt19937 gen(7);
  Worst worst;
  for (int i = 0; i < kSamples; ++i) {
    const Motion ma = randomMotion(gen, randomPose(gen));
    const Motion mb = randomMotion(gen, randomPose(gen));
    checkTimeDerivatives(worst, "spherical", SphericalSpec{randomVector(gen), randomVector(gen)}.build<double>(),
                         ma, mb);
    checkTimeDerivatives(worst, "revolute", randomRevolute(gen).build<double>(), ma, mb);
    checkTimeDerivatives(worst, "universal", randomUniversal(gen).build<double>(), ma, mb);
    // Ground as the main body: a motionless identity pose.
    const Motion ground{groundPose<double>(), groundVelocity<double>(), Vec6::Zero()};
    checkTimeDerivatives(worst, "revolute to ground", randomRevolute(gen).build<double>(), ground, mb);
  }
  worst.print("velocity form and convective term (4th-order time FD, h = 2e-3)");
  worst.expectAllBelow(kTimeTolerance);
}

// ---- 3. revolute joint angle ---------------------------------------------------------------------

TEST(RevoluteAngle, RecoversTheConstructionAngleAcrossPiWithUnwrapping) {
  std::mt19937 gen(11);
  double worst = 0.0;
  for (int i = 0; i < 10; ++i) {
    const RevoluteSpec spec = randomRevolute(gen);
    const auto joint = spec.build<double>();
    const Pose a = randomPose(gen);
    // A sweep from −7 to 7 rad in steps of 0.1 (crossing ±π and ±3π):
    // the principal value is the wrapped angle, the unwrapped one is φ itself.
    double previous = -7.0;
    for (double phi = -7.0; phi <= 7.0; phi += 0.1) {
      const Pose b = revolutePose(spec, a, phi);
      const double principal = revoluteAngle(joint, a, b);
      const double unwrapped = revoluteAngle(joint, a, b, previous);
      worst = std::max(worst, std::abs(unwrapped - phi));
      worst = std::max(worst, std::abs(principal - wrapToPi(phi)));
      EXPECT_LE(std::abs(principal), kPi + 1e-15);
      previous = unwrapped;
    }
  }
  std::cout << "[ measured ] revolute φ_J recovery, worst |error| = " << worst << " rad\n";
  EXPECT_LE(worst, 1e-13);

  // Zero at assembly unless a reference angle is given.
  for (int i = 0; i < 10; ++i) {
    const Pose a0 = randomPose(gen), b0 = randomPose(gen);
    const Vec3 axis_main = randomUnit(gen);
    const Vec3 axis_secondary = b0.R.inverse() * (a0.R * axis_main);
    const auto j0 = assembleRevoluteJoint(a0, b0, Vec3(randomVector(gen)), Vec3(randomVector(gen)),
                                          axis_main, axis_secondary);
    EXPECT_NEAR(revoluteAngle(j0, a0, b0), 0.0, 1e-14);
    const auto j1 = assembleRevoluteJoint(a0, b0, Vec3::Zero().eval(), Vec3::Zero().eval(), axis_main,
                                          axis_secondary, 0.7);
    EXPECT_NEAR(revoluteAngle(j1, a0, b0), 0.7, 1e-14);
    // Turning the secondary by 0.2 about the axis moves the angle by 0.2.
    const Pose b1{SO3d::exp(0.2 * (a0.R * axis_main)) * b0.R, b0.p};
    EXPECT_NEAR(revoluteAngle(j1, a0, b1), 0.9, 1e-14);
  }
}

TEST(RevoluteAngle, RateJacobianAndConvectiveTerm) {
  std::mt19937 gen(12);
  Worst worst;
  for (int i = 0; i < kSamples; ++i) {
    const RevoluteSpec spec = randomRevolute(gen);
    const auto joint = spec.build<double>();
    const Motion ma = randomMotion(gen, randomPose(gen));

    // On the manifold: R_b(t) = R_a(t) exp(φ(t) a) R_ref with φ quadratic in t.
    const double phi0 = std::uniform_real_distribution<double>(-4.0, 4.0)(gen);
    const double phid = randomVector(gen)[0], phidd = randomVector(gen)[0];
    const auto phi_of = [&](double t) { return phi0 + phid * t + 0.5 * phidd * t * t; };
    const auto pose_b = [&](double t) { return revolutePose(spec, ma.at(t), phi_of(t)); };
    const Pose a = ma.at(0.0), b = pose_b(0.0);
    // Ω_b = Ω_a + φ̇ A, Ω̇_b = Ω̇_a + φ̈ A + φ̇ Ω_a × A, body ω_b = R_bᵀ Ω_b, ω̇_b = R_bᵀ Ω̇_b.
    const Vec3 A = a.R * spec.a_a;
    const Vec3 Oa = a.R * ma.V0.omega;
    const Vec3 Oa_dot = a.R * ma.acc.tail<3>();
    const Vel vb{Vec3::Zero(), b.R.inverse() * (Oa + phid * A)};
    const Vec3 ob_dot = b.R.inverse() * (Oa_dot + phidd * A + phid * Oa.cross(A));

    const auto angle = [&](double t) -> Eigen::VectorXd {
      return Eigen::VectorXd::Constant(1, revoluteAngle(joint, ma.at(t), pose_b(t), phi0));
    };
    const auto [d1, d2] = timeDerivatives(angle);
    const double rate = revoluteAngleRate(joint, a, b, ma.V0, vb);
    const auto J = revoluteAngleJacobians(joint, a, b);
    worst.add("rate vs d/dt φ_J (manifold)", std::abs(d1[0] - rate) / std::max(std::abs(rate), 1.0));
    worst.add("rate vs φ̇ of the construction", std::abs(rate - phid) / std::max(std::abs(phid), 1.0));
    const double acc_part = J[0].rightCols<3>().dot(ma.acc.tail<3>()) + J[1].rightCols<3>().dot(ob_dot);
    const double conv = revoluteAngleConvective(joint, a, b, ma.V0, vb);
    worst.add("convective vs d²φ_J/dt² − J q̈ (manifold)",
              std::abs(d2[0] - acc_part - conv) / std::max({std::abs(conv), std::abs(acc_part), 1.0}));

    // Abaqus form on the manifold: J_a = (0, −R_aᵀ A), J_b = (0, R_bᵀ A): a joint moment M
    // acts as −M a on the main body and +M a on the secondary.
    Eigen::Matrix<double, 1, 6> Ja, Jb;
    Ja << 0, 0, 0, -(a.R.inverse() * A).transpose();
    Jb << 0, 0, 0, (b.R.inverse() * A).transpose();
    worst.add("J on manifold vs Abaqus (−a, +a)",
              std::max(relative(J[0], Ja), relative(J[1], Jb)));

    // Off the manifold: the Jacobian is the exact gradient (FD, Jet) and
    // J q̇ is the exact rate of the angle function.
    const std::array<Pose, 2> X{a, nudge(gen, b, 0.3)};
    const auto f = [&](const std::array<Pose, 2>& Y) -> Eigen::VectorXd {
      return Eigen::VectorXd::Constant(1, revoluteAngle(joint, Y[0], Y[1], revoluteAngle(joint, X[0], X[1])));
    };
    const Eigen::MatrixXd Jx = stack(revoluteAngleJacobians(joint, X[0], X[1]));
    worst.add("J vs FD (off manifold)", relative(fdJacobian(f, X), Jx));
#ifdef LIEFLOW_HAVE_CERES
    const auto fj = [&](const auto& Y) {
      using S = typename std::decay_t<decltype(Y[0].p)>::Scalar;
      return Eigen::Matrix<S, 1, 1>(revoluteAngle(spec.build<S>(), Y[0], Y[1]));
    };
    worst.add("J vs Jet (off manifold)", relative(jetJacobian(fj, X), Jx));
#endif
    const Motion mb = randomMotion(gen, X[1]);
    const auto angle_off = [&](double t) -> Eigen::VectorXd {
      return Eigen::VectorXd::Constant(1, revoluteAngle(joint, ma.at(t), mb.at(t), revoluteAngle(joint, X[0], X[1])));
    };
    const double exact_rate =
        Jx.row(0).head<6>().dot(ma.V0.twist()) + Jx.row(0).tail<6>().dot(mb.V0.twist());
    const double fd_rate = timeDerivatives(angle_off).first[0];
    worst.add("J q̇ vs d/dt φ_J (off manifold)", std::abs(fd_rate - exact_rate) / std::max(std::abs(exact_rate), 1.0));
  }
  worst.print("revolute joint angle");
  worst.expectAllBelow(kJacobianTolerance);
}

// ---- 4. universal joint angles --------------------------------------------------------------------

TEST(UniversalAngles, RecoverTheConstructionAnglesWithUnwrapping) {
  std::mt19937 gen(21);
  double worst = 0.0;
  for (int i = 0; i < 10; ++i) {
    const UniversalSpec spec = randomUniversal(gen);
    const auto joint = spec.build<double>();
    const Pose a = randomPose(gen);
    // φ₁ sweeps −7 → 7 while φ₂ sweeps 7 → −7 (both cross ±π and ±3π).
    double prev1 = -7.0, prev2 = 7.0;
    for (double s = 0.0; s <= 14.0; s += 0.1) {
      const double phi1 = -7.0 + s, phi2 = 7.0 - 0.9 * s;
      const Pose b = universalPose(spec, a, phi1, phi2);
      const auto principal = universalAngles(joint, a, b);
      const auto unwrapped = universalAngles(joint, a, b, prev1, prev2);
      worst = std::max({worst, std::abs(unwrapped.phi1 - phi1), std::abs(unwrapped.phi2 - phi2),
                        std::abs(principal.phi1 - wrapToPi(phi1)),
                        std::abs(principal.phi2 - wrapToPi(phi2))});
      // The bend: cos φ₁ cos φ₂.
      EXPECT_NEAR(principal.cos_bend, std::cos(phi1) * std::cos(phi2), 1e-12);
      prev1 = unwrapped.phi1;
      prev2 = unwrapped.phi2;
    }
  }
  std::cout << "[ measured ] universal φ₁, φ₂ recovery, worst |error| = " << worst << " rad\n";
  EXPECT_LE(worst, 1e-12);

  // Assembly with given initial angles.
  for (int i = 0; i < 10; ++i) {
    const Pose a0 = randomPose(gen), b0 = randomPose(gen);
    const Vec3 a1 = randomUnit(gen);
    const Vec3 a2 = b0.R.inverse() * randomUnitNormalTo(gen, a0.R * a1);
    const auto j0 = assembleUniversalJoint(a0, b0, Vec3::Zero().eval(), Vec3::Zero().eval(), a1, a2);
    const auto g0 = universalAngles(j0, a0, b0);
    EXPECT_NEAR(g0.phi1, 0.0, 1e-14);
    EXPECT_NEAR(g0.phi2, 0.0, 1e-14);
    const auto j1 = assembleUniversalJoint(a0, b0, Vec3::Zero().eval(), Vec3::Zero().eval(), a1, a2,
                                           0.4, -1.1);
    const auto g1 = universalAngles(j1, a0, b0);
    EXPECT_NEAR(g1.phi1, 0.4, 1e-14);
    EXPECT_NEAR(g1.phi2, -1.1, 1e-14);
  }
}

TEST(UniversalAngles, RatesJacobiansAndConvectiveTerms) {
  std::mt19937 gen(22);
  Worst worst;
  for (int i = 0; i < kSamples; ++i) {
    const UniversalSpec spec = randomUniversal(gen);
    const auto joint = spec.build<double>();
    const Motion ma = randomMotion(gen, randomPose(gen));
    std::uniform_real_distribution<double> angle(-4.0, 4.0);
    const double p10 = angle(gen), p20 = angle(gen);
    const double p1d = randomVector(gen)[0], p2d = randomVector(gen)[0];
    const double p1dd = randomVector(gen)[0], p2dd = randomVector(gen)[0];
    const auto pose_b = [&](double t) {
      return universalPose(spec, ma.at(t), p10 + p1d * t + 0.5 * p1dd * t * t,
                           p20 + p2d * t + 0.5 * p2dd * t * t);
    };
    const Pose a = ma.at(0.0), b = pose_b(0.0);
    // Ω_b = Ω_a + φ̇₁ A₁ + φ̇₂ A₂, A₁ = R_a e₁, A₂ = R_a exp(φ₁ e₁) e₂ (= R_b a₂);
    // Ȧ₁ = Ω_a × A₁, Ȧ₂ = (Ω_a + φ̇₁ A₁) × A₂.
    const Vec3 A1 = a.R * spec.a1;
    const Vec3 A2 = b.R * spec.a2;
    const Vec3 Oa = a.R * ma.V0.omega;
    const Vec3 Oa_dot = a.R * ma.acc.tail<3>();
    const Vec3 Ob = Oa + p1d * A1 + p2d * A2;
    const Vec3 Ob_dot = Oa_dot + p1dd * A1 + p1d * Oa.cross(A1) + p2dd * A2 +
                        p2d * (Oa + p1d * A1).cross(A2);
    const Vel vb{Vec3::Zero(), b.R.inverse() * Ob};
    const Vec3 ob_dot = b.R.inverse() * Ob_dot;

    const auto angles = [&](double t) -> Eigen::VectorXd {
      const auto g = universalAngles(joint, ma.at(t), pose_b(t), p10, p20);
      return Eigen::Vector2d(g.phi1, g.phi2);
    };
    const auto [d1, d2] = timeDerivatives(angles);
    const Eigen::Vector2d rates = universalAngleRates(joint, a, b, ma.V0, vb);
    const auto J = universalAngleJacobians(joint, a, b);
    worst.add("rates vs d/dt (φ₁, φ₂) (manifold)", (d1 - rates).norm() / std::max(rates.norm(), 1.0));
    worst.add("rates vs (φ̇₁, φ̇₂) of the construction",
              (rates - Eigen::Vector2d(p1d, p2d)).norm() / std::max(rates.norm(), 1.0));
    const Eigen::Vector2d acc_part = J[0].rightCols<3>() * ma.acc.tail<3>() + J[1].rightCols<3>() * ob_dot;
    const Eigen::Vector2d conv = universalAngleConvective(joint, a, b, ma.V0, vb);
    worst.add("convective vs d²φ/dt² − J q̈ (manifold)",
              (d2 - acc_part - conv).norm() / std::max({conv.norm(), acc_part.norm(), 1.0}));
    // Abaqus form on the manifold: rows (0, ∓R_ᵀA_k).
    Eigen::Matrix<double, 2, 6> Ja = Eigen::Matrix<double, 2, 6>::Zero(), Jb = Ja;
    Ja.block<1, 3>(0, 3) = -(a.R.inverse() * A1).transpose();
    Ja.block<1, 3>(1, 3) = -(a.R.inverse() * A2).transpose();
    Jb.block<1, 3>(0, 3) = (b.R.inverse() * A1).transpose();
    Jb.block<1, 3>(1, 3) = (b.R.inverse() * A2).transpose();
    worst.add("J on manifold vs Abaqus (∓a₁, ∓a₂)", std::max(relative(J[0], Ja), relative(J[1], Jb)));

    // Off the manifold: exact gradients.
    const std::array<Pose, 2> X{a, nudge(gen, b, 0.3)};
    const auto g0 = universalAngles(joint, X[0], X[1]);
    const auto f = [&](const std::array<Pose, 2>& Y) -> Eigen::VectorXd {
      const auto g = universalAngles(joint, Y[0], Y[1], g0.phi1, g0.phi2);
      return Eigen::Vector2d(g.phi1, g.phi2);
    };
    const Eigen::MatrixXd Jx = stack(universalAngleJacobians(joint, X[0], X[1]));
    worst.add("J vs FD (off manifold)", relative(fdJacobian(f, X), Jx));
#ifdef LIEFLOW_HAVE_CERES
    const auto fj = [&](const auto& Y) {
      using S = typename std::decay_t<decltype(Y[0].p)>::Scalar;
      const auto g = universalAngles(spec.build<S>(), Y[0], Y[1]);
      return Eigen::Matrix<S, 2, 1>(g.phi1, g.phi2);
    };
    worst.add("J vs Jet (off manifold)", relative(jetJacobian(fj, X), Jx));
#endif
  }
  worst.print("universal joint angles");
  worst.expectAllBelow(kJacobianTolerance);
}

TEST(UniversalAngles, NinetyDegreeSingularityIsReportedByTheConditionNumber) {
  std::mt19937 gen(23);
  const UniversalSpec spec = randomUniversal(gen);
  const auto joint = spec.build<double>();
  const Pose a = randomPose(gen);
  const auto at = [&](double phi1, double phi2) {
    return universalAngles(joint, a, universalPose(spec, a, phi1, phi2));
  };
  // Straight: κ = 1. Moderate angles: κ = 1 / min(cos φ₁, cos φ₂), small.
  EXPECT_NEAR(at(0.0, 0.0).condition, 1.0, 1e-14);
  EXPECT_NEAR(at(0.3, 0.5).condition, 1.0 / std::cos(0.5), 1e-12);
  EXPECT_FALSE(at(0.3, 0.5).nearSingular());
  EXPECT_FALSE(at(1.2, -0.4).nearSingular());
  // Approaching 90° on either hinge: κ ≈ 1/δ.
  for (double delta : {1e-2, 1e-4, 1e-6}) {
    // κ = 1 / sin δ.
    for (const auto& g : {at(kPi / 2 - delta, 0.2), at(0.2, kPi / 2 - delta),
                          at(-0.1, -kPi / 2 + delta)}) {
      EXPECT_NEAR(g.condition * std::sin(delta), 1.0, 1e-9) << "delta " << delta;
      EXPECT_EQ(g.nearSingular(), delta < 1.0 / kUniversalNearSingularCondition) << "delta " << delta;
      EXPECT_NEAR(g.cos_bend, std::cos(g.phi1) * std::cos(g.phi2), 1e-12);
    }
  }
  // At 90° exactly (both hinges, the fully locked cross): κ at the rounding level.
  EXPECT_GT(at(kPi / 2, kPi / 2).condition, 1e12);
  EXPECT_GT(at(kPi / 2, -kPi / 2).condition, 1e12);
  EXPECT_TRUE(at(kPi / 2, 0.0).nearSingular());
  // The angles themselves stay exact through the singularity (the map
  // (φ₁, φ₂) → relative rotation is one-to-one).
  const auto g = at(kPi / 2, -kPi / 2);
  EXPECT_NEAR(g.phi1, kPi / 2, 1e-14);
  EXPECT_NEAR(g.phi2, -kPi / 2, 1e-14);
}

TEST(JointAngles, JacobiansAtSpecialAngles) {
  // On the manifold at the seams and quarter turns: φ_J = ±π (q_w = 0),
  // φ₁, φ₂ ∈ {0, ±π/2, π}. FD (with unwrapping), Jets and the Abaqus form.
  std::mt19937 gen(24);
  Worst worst;
  const RevoluteSpec rs = randomRevolute(gen);
  const auto rj = rs.build<double>();
  for (double phi : {0.0, kPi / 2, kPi, -kPi, 3 * kPi / 2}) {
    const Pose a = randomPose(gen);
    const std::array<Pose, 2> X{a, revolutePose(rs, a, phi)};
    const double ref = revoluteAngle(rj, X[0], X[1]);
    const auto f = [&](const std::array<Pose, 2>& Y) -> Eigen::VectorXd {
      return Eigen::VectorXd::Constant(1, revoluteAngle(rj, Y[0], Y[1], ref));
    };
    const Eigen::MatrixXd J = stack(revoluteAngleJacobians(rj, X[0], X[1]));
    worst.add("revolute φ_J: J vs FD", relative(fdJacobian(f, X), J));
    Eigen::Matrix<double, 1, 12> abaqus = Eigen::Matrix<double, 1, 12>::Zero();
    const Vec3 A = a.R * rs.a_a;
    abaqus.segment<3>(3) = -(a.R.inverse() * A).transpose();
    abaqus.segment<3>(9) = (X[1].R.inverse() * A).transpose();
    worst.add("revolute φ_J: J vs Abaqus (−a, +a)", relative(abaqus, J));
#ifdef LIEFLOW_HAVE_CERES
    const auto fj = [&](const auto& Y) {
      using S = typename std::decay_t<decltype(Y[0].p)>::Scalar;
      return Eigen::Matrix<S, 1, 1>(revoluteAngle(rs.build<S>(), Y[0], Y[1]));
    };
    worst.add("revolute φ_J: J vs Jet", relative(jetJacobian(fj, X), J));
#endif
  }
  const UniversalSpec us = randomUniversal(gen);
  const auto uj = us.build<double>();
  for (const auto& [p1, p2] : std::array<std::pair<double, double>, 6>{
           {{0.0, 0.0}, {kPi / 2, 0.0}, {0.0, kPi / 2}, {kPi / 2, -kPi / 2}, {kPi, 0.3}, {-0.4, kPi}}}) {
    const Pose a = randomPose(gen);
    const std::array<Pose, 2> X{a, universalPose(us, a, p1, p2)};
    const auto g0 = universalAngles(uj, X[0], X[1]);
    const auto f = [&](const std::array<Pose, 2>& Y) -> Eigen::VectorXd {
      const auto g = universalAngles(uj, Y[0], Y[1], g0.phi1, g0.phi2);
      return Eigen::Vector2d(g.phi1, g.phi2);
    };
    const Eigen::MatrixXd J = stack(universalAngleJacobians(uj, X[0], X[1]));
    worst.add("universal φ₁, φ₂: J vs FD", relative(fdJacobian(f, X), J));
#ifdef LIEFLOW_HAVE_CERES
    const auto fj = [&](const auto& Y) {
      using S = typename std::decay_t<decltype(Y[0].p)>::Scalar;
      const auto g = universalAngles(us.build<S>(), Y[0], Y[1]);
      return Eigen::Matrix<S, 2, 1>(g.phi1, g.phi2);
    };
    worst.add("universal φ₁, φ₂: J vs Jet", relative(jetJacobian(fj, X), J));
#endif
  }
  worst.print("joint-angle Jacobians at φ = 0, ±π/2, ±π");
  worst.expectAllBelow(kJacobianTolerance);
}

// ---- 5. the Cardan shaft ---------------------------------------------------------------------------

/// Input shaft a turning by θ₁ about the world z axis, R_a = Rz(θ₁); output
/// shaft b at the bend angle β in the x-z plane, R_b = Ry(β) Rz(θ₂); the cross
/// at the origin, its first arm a₁ = x in the input's frame, its second arm
/// a₂ = y in the output's frame, the joint referenced to straight shafts
/// (R_ref = I: φ₁ = φ₂ = 0 when both arms are in their θ = 0 position with β = 0).
/// θ₁ = 0 when the input arm lies in the plane of the shafts (the x-z plane).
struct CardanShaft {
  double beta;
  double length = 0.5;
  UniversalJoint<double> joint =
      makeUniversalJoint<double>(Vec3(0, 0, 0.5), Vec3(0, 0, -0.5), Vec3::UnitX(), Vec3::UnitY(),
                                 SO3d::identity());
  Pose input(double theta1) const {
    return Pose{SO3d::exp(theta1 * Vec3::UnitZ()), Vec3(0, 0, -length)};
  }
  Pose output(double theta2) const {
    const SO3d bend = SO3d::exp(beta * Vec3::UnitY());
    return Pose{bend * SO3d::exp(theta2 * Vec3::UnitZ()), bend * Vec3(0, 0, length)};
  }
  /// Newton on the dot row g(θ₂) = (R_a a₁)·(R_b a₂) with g' from the
  /// library Jacobian (δθ_b along the output's body z, column 5 of J_b).
  double solveOutput(double theta1, int* iterations = nullptr) const {
    double theta2 = theta1;
    int it = 0;
    for (; it < 50; ++it) {
      const Pose a = input(theta1), b = output(theta2);
      const double g = joint.residual(a, b)[3];
      if (std::abs(g) < 1e-15) break;
      theta2 -= g / joint.jacobians(a, b)[1](3, 5);
    }
    if (iterations) *iterations = it;
    return theta2;
  }
};

TEST(CardanShaft, OutputAngleAndSpeedRatioFromTheUniversalConstraint) {
  Worst worst;
  int max_iterations = 0;
  for (double beta : {0.1, 0.35, 0.7, 1.0, 1.3}) {
    const CardanShaft shaft{beta};
    for (double theta1 : {0.0, 0.25, 0.6, kPi / 4, 1.2, kPi / 2, 2.0, 2.9, 3.6, 4.4, 5.2, 6.0}) {
      int iterations = 0;
      const double theta2 = shaft.solveOutput(theta1, &iterations);
      max_iterations = std::max(max_iterations, iterations);
      const Pose a = shaft.input(theta1), b = shaft.output(theta2);
      EXPECT_LE(shaft.joint.residual(a, b).norm(), 1e-14);
      // tan θ₂ = tan θ₁ / cos β, in the quadrant of θ₁: θ₂ = atan2(sin θ₁, cos β cos θ₁).
      const double closed = std::atan2(std::sin(theta1), std::cos(beta) * std::cos(theta1));
      worst.add("θ₂ vs atan2(sin θ₁, cos β cos θ₁)", std::abs(wrapToPi(theta2 - closed)));
      if (std::abs(std::cos(theta1)) > 0.1)
        worst.add("tan θ₂ vs tan θ₁/cos β",
                  std::abs(std::tan(theta2) - std::tan(theta1) / std::cos(beta)) /
                      std::abs(std::tan(theta1) / std::cos(beta)) / 1.0);
      const double sb = std::sin(beta), c1 = std::cos(theta1);
      const double ratio = std::cos(beta) / (1.0 - sb * sb * c1 * c1);
      // (i) from the velocity form: J_a (0, ω₁ z) + J_b (0, ω₂ z) = 0 (row 3).
      const auto J = shaft.joint.jacobians(a, b);
      const double ratio_velocity = -J[0](3, 5) / J[1](3, 5);
      // (ii) by differentiating the Newton solutions θ₂(θ₁) (4th-order FD).
      const double h = 1e-3;
      const double ratio_fd = (shaft.solveOutput(theta1 - 2 * h) - 8 * shaft.solveOutput(theta1 - h) +
                               8 * shaft.solveOutput(theta1 + h) - shaft.solveOutput(theta1 + 2 * h)) /
                              (12 * h);
      // (iii) from the joint angles: ω₂/ω₁ = cos φ₁ / cos φ₂, cos β = cos φ₁ cos φ₂.
      const auto g = universalAngles(shaft.joint, a, b);
      const double ratio_angles = std::cos(g.phi1) / std::cos(g.phi2);
      worst.add("ω₂/ω₁ velocity form vs formula", std::abs(ratio_velocity - ratio) / ratio);
      worst.add("ω₂/ω₁ d θ₂/dθ₁ (Newton, FD) vs formula", std::abs(ratio_fd - ratio) / ratio);
      worst.add("ω₂/ω₁ cos φ₁/cos φ₂ vs formula", std::abs(ratio_angles - ratio) / ratio);
      worst.add("cos φ₁ cos φ₂ vs cos β", std::abs(g.cos_bend - std::cos(beta)));
      // κ = 1/min(cos φ₁, cos φ₂) ∈ [max(ω₂/ω₁, ω₁/ω₂), 1/cos β].
      EXPECT_GE(g.condition, std::max(ratio, 1 / ratio) * (1 - 1e-12));
      EXPECT_LE(g.condition, 1.0 / std::cos(beta) * (1 + 1e-12));
    }
    // At θ₁ = 0 the ratio is 1/cos β (maximum), at θ₁ = π/2 it is cos β (minimum).
    const auto J0 = shaft.joint.jacobians(shaft.input(0.0), shaft.output(shaft.solveOutput(0.0)));
    EXPECT_NEAR(-J0[0](3, 5) / J0[1](3, 5), 1.0 / std::cos(beta), 1e-12);
  }
  std::cout << "[ measured ] Cardan shaft: Newton on the dot row converged in at most "
            << max_iterations << " iterations\n";
  worst.print("Cardan shaft against tan θ₂ = tan θ₁/cos β and ω₂/ω₁ = cos β/(1 − sin²β cos²θ₁)");
  EXPECT_LE(worst["θ₂ vs atan2(sin θ₁, cos β cos θ₁)"], 1e-14);
  EXPECT_LE(worst["tan θ₂ vs tan θ₁/cos β"], 1e-13);
  EXPECT_LE(worst["ω₂/ω₁ velocity form vs formula"], 1e-13);
  EXPECT_LE(worst["ω₂/ω₁ cos φ₁/cos φ₂ vs formula"], 1e-13);
  EXPECT_LE(worst["cos φ₁ cos φ₂ vs cos β"], 1e-14);
  EXPECT_LE(worst["ω₂/ω₁ d θ₂/dθ₁ (Newton, FD) vs formula"], 1e-9);
}

TEST(CardanShaft, BendTowardNinetyDegreesIsReportedAsSingular) {
  // β → 90°: the speed ratio peaks at 1/cos β and κ follows it; the Newton
  // derivative ∂g/∂θ₂ ∝ cos φ₂ vanishes.
  for (double delta : {1e-1, 1e-2, 1e-3, 1e-4}) {
    const CardanShaft shaft{kPi / 2 - delta};
    const Pose a = shaft.input(0.0), b = shaft.output(shaft.solveOutput(0.0));
    const auto g = universalAngles(shaft.joint, a, b);
    EXPECT_NEAR(g.condition * std::cos(shaft.beta), 1.0, 1e-9);
    EXPECT_EQ(g.nearSingular(), 1.0 / std::cos(shaft.beta) >= kUniversalNearSingularCondition);
    EXPECT_NEAR(std::abs(shaft.joint.jacobians(a, b)[1](3, 5)), std::cos(shaft.beta), 1e-12);
  }
  // At 90° the output is locked: tan θ₂ = tan θ₁ / cos β = ∞, θ₂ = ±90° for
  // every input angle away from θ₁ = 0 (where it is undetermined).
  const CardanShaft locked{kPi / 2};
  EXPECT_NEAR(std::cos(locked.solveOutput(0.3)), 0.0, 1e-12);
  EXPECT_NEAR(std::cos(locked.solveOutput(2.0)), 0.0, 1e-12);
  EXPECT_TRUE(universalAngles(locked.joint, locked.input(0.0), locked.output(0.0)).nearSingular());
}

// ---- 6. gear rows ---------------------------------------------------------------------------------

NodeAxes<double> randomNodeAxes(std::mt19937& gen) {
  const Mat3 m = SO3d::random(gen).matrix();
  return makeNodeAxes<double>(m.col(0), m.col(1), m.col(2));
}

/// The Radioss rows written out with world vectors (independent of gear_terms.hpp).
template <typename S, std::size_t N>
Vector3<S> relSpin(const std::array<BodyPose<S>, N>& X, const std::array<BodyVelocity<S>, N>& V,
                   std::size_t i) {
  return X[i].R.matrix() * V[i].omega - X[0].R.matrix() * V[0].omega;
}
template <typename S, std::size_t N>
Vector3<S> relVelocity(const std::array<BodyPose<S>, N>& X, const std::array<BodyVelocity<S>, N>& V,
                       std::size_t i) {
  return V[i].v - V[0].v - (X[0].R.matrix() * V[0].omega).cross(X[i].p - X[0].p);
}
template <typename S, std::size_t N>
Vector3<S> world(const std::array<BodyPose<S>, N>& X, std::size_t i, const Vec3& x) {
  return X[i].R.matrix() * x.cast<S>();
}

template <typename S>
Eigen::Matrix<S, 5, 1> refGear(const GearJoint<double>& j, const std::array<BodyPose<S>, 3>& X,
                               const std::array<BodyVelocity<S>, 3>& V) {
  const Vector3<S> d1 = relSpin(X, V, 1), d2 = relSpin(X, V, 2);
  Eigen::Matrix<S, 5, 1> r;
  r << S(j.ratio) * d1.dot(world(X, 1, j.node1.r)) + d2.dot(world(X, 2, j.node2.r)),
      d1.dot(world(X, 1, j.node1.s)), d1.dot(world(X, 1, j.node1.t)), d2.dot(world(X, 2, j.node2.s)),
      d2.dot(world(X, 2, j.node2.t));
  return r;
}

template <typename S>
Eigen::Matrix<S, 2, 1> refRackPinion(const RackPinionJoint<double>& j,
                                     const std::array<BodyPose<S>, 3>& X,
                                     const std::array<BodyVelocity<S>, 3>& V) {
  const Vector3<S> d1 = relSpin(X, V, 1), dv = relVelocity(X, V, 2);
  return Eigen::Matrix<S, 2, 1>(
      S(j.ratio) * d1.dot(world(X, 1, j.pinion.s)) + dv.dot(world(X, 2, j.rack.s)),
      S(j.ratio) * d1.dot(world(X, 1, j.pinion.t)) + dv.dot(world(X, 2, j.rack.t)));
}

template <typename S>
Eigen::Matrix<S, 3, 1> refDifferential(const DifferentialJoint<double>& j,
                                       const std::array<BodyPose<S>, 4>& X,
                                       const std::array<BodyVelocity<S>, 4>& V) {
  Eigen::Matrix<S, 3, 1> r;
  for (int k = 0; k < 3; ++k)
    r[k] = S(j.ratio) * relSpin(X, V, 1).dot(world(X, 1, DifferentialJoint<double>::axis(j.node1, k))) +
           relSpin(X, V, 2).dot(world(X, 2, DifferentialJoint<double>::axis(j.node2, k))) +
           relSpin(X, V, 3).dot(world(X, 3, DifferentialJoint<double>::axis(j.node3, k)));
  return r;
}

/// A coupling's row written out: each node's rate relative to its own
/// carrier (the Radioss terms above with that carrier in the place of N0).
template <typename S>
Eigen::Matrix<S, 1, 1> refCoupling(const CouplingJoint<double>& j, const std::array<BodyPose<S>, 4>& X,
                                   const std::array<BodyVelocity<S>, 4>& V) {
  const auto rate = [&](std::size_t carrier, std::size_t node, const Vec3& x, bool slide) {
    const std::array<BodyPose<S>, 2> Xc{X[carrier], X[node]};
    const std::array<BodyVelocity<S>, 2> Vc{V[carrier], V[node]};
    return (slide ? relVelocity(Xc, Vc, 1) : relSpin(Xc, Vc, 1)).dot(world(Xc, 1, x));
  };
  return Eigen::Matrix<S, 1, 1>(S(j.ratio) * rate(j.slot[0], j.slot[1], j.axis1, j.slide1) +
                                rate(j.slot[2], j.slot[3], j.axis2, j.slide2));
}

/// B against ∂(reference rows)/∂q̇ (Jet and FD), B q̇ against the reference,
/// and the convective term against d/dt(B q̇) − B q̈ along random motions.
template <std::size_t N, typename JointD, typename Ref>
void checkGearRows(Worst& worst, const std::string& name, const JointD& joint, const Ref& ref,
                   std::mt19937& gen) {
  std::array<Motion, N> m;
  std::array<Pose, N> X;
  std::array<Vel, N> V;
  for (std::size_t k = 0; k < N; ++k) {
    m[k] = randomMotion(gen, randomPose(gen));
    X[k] = m[k].X0;
    V[k] = m[k].V0;
  }
  const auto B = joint.rows(X);
  const Eigen::MatrixXd Bs = stack(B);
  // ∂(reference)/∂q̇ by central differences (the rows are linear in q̇).
  Eigen::MatrixXd Bfd(Bs.rows(), 6 * N);
  for (std::size_t k = 0; k < N; ++k)
    for (int j = 0; j < 6; ++j) {
      std::array<Vel, N> Vp = V, Vm = V;
      Vp[k] = Vel::fromTwist(V[k].twist() + Vec6::Unit(j));
      Vm[k] = Vel::fromTwist(V[k].twist() - Vec6::Unit(j));
      Bfd.col(6 * k + j) = (ref(X, Vp) - ref(X, Vm)) / 2.0;
    }
  worst.add(name + " B vs FD in q̇ of the Radioss rows", relative(Bfd, Bs));
#ifdef LIEFLOW_HAVE_CERES
  {
    using J = ceres::Jet<double, 6 * N>;
    std::array<BodyPose<J>, N> XJ;
    std::array<BodyVelocity<J>, N> VJ;
    for (std::size_t k = 0; k < N; ++k) {
      XJ[k] = BodyPose<J>{X[k].R.template cast<J>(), X[k].p.template cast<J>()};
      Vector6<J> tw;
      for (int j = 0; j < 6; ++j) tw[j] = J(V[k].twist()[j], static_cast<int>(6 * k) + j);
      VJ[k] = BodyVelocity<J>::fromTwist(tw);
    }
    const auto y = ref(XJ, VJ);
    Eigen::MatrixXd Bjet(y.size(), 6 * N);
    for (int r = 0; r < y.size(); ++r)
      for (int c = 0; c < static_cast<int>(6 * N); ++c) Bjet(r, c) = y[r].v[c];
    worst.add(name + " B vs Jet in q̇ of the Radioss rows", relative(Bjet, Bs));
  }
#endif
  const Eigen::VectorXd bq = joint.velocity(X, V);
  worst.add(name + " B q̇ vs Radioss rows", (bq - ref(X, V)).norm() / std::max(bq.norm(), 1.0));
  // Convective: d/dt[B(q(t)) q̇(t)] − B q̈.
  const auto rows_along = [&](double t) -> Eigen::VectorXd {
    std::array<Pose, N> Xt;
    std::array<Vel, N> Vt;
    for (std::size_t k = 0; k < N; ++k) {
      Xt[k] = m[k].at(t);
      Vt[k] = m[k].velocityAt(t);
    }
    return ref(Xt, Vt);
  };
  const Eigen::VectorXd d1 = timeDerivatives(rows_along).first;
  Eigen::VectorXd acc_part = Eigen::VectorXd::Zero(Bs.rows());
  for (std::size_t k = 0; k < N; ++k) acc_part += B[k] * m[k].acc;
  const Eigen::VectorXd conv = joint.convective(X, V);
  worst.add(name + " convective vs d/dt(B q̇) − B q̈",
            (d1 - acc_part - conv).norm() / std::max({conv.norm(), acc_part.norm(), 1.0}));
}

TEST(GearRows, BlocksAndConvectiveTermsAgainstTheRadiossFormulas) {
  std::mt19937 gen(31);
  Worst worst;
  for (int i = 0; i < kSamples; ++i) {
    const double alpha = randomVector(gen)[0] * 3.0;
    const auto gear = makeGearJoint(alpha, randomNodeAxes(gen), randomNodeAxes(gen));
    checkGearRows<3>(
        worst, "gear", gear, [&](const auto& X, const auto& V) { return refGear(gear, X, V); }, gen);
    const auto rack = makeRackPinionJoint(alpha, randomNodeAxes(gen), randomNodeAxes(gen));
    checkGearRows<3>(
        worst, "rack_pinion", rack, [&](const auto& X, const auto& V) { return refRackPinion(rack, X, V); },
        gen);
    const auto diff =
        makeDifferentialJoint(alpha, randomNodeAxes(gen), randomNodeAxes(gen), randomNodeAxes(gen));
    checkGearRows<4>(
        worst, "differential", diff,
        [&](const auto& X, const auto& V) { return refDifferential(diff, X, V); }, gen);
    // Couplings: turn-turn, turn-slide, slide-turn, slide-slide; siblings
    // (one carrier, slot 3 unused), joints on four bodies, and a follower
    // hung from the leader's node (node 1 is carrier 2).
    const std::array<std::array<std::size_t, 4>, 3> layouts = {{{{0, 1, 0, 2}}, {{0, 1, 2, 3}}, {{0, 1, 1, 2}}}};
    const auto coupling = makeCouplingJoint<double>(alpha, randomNodeAxes(gen).r, i % 2 == 1,
                                                    randomNodeAxes(gen).r, (i / 2) % 2 == 1, layouts[i % 3]);
    checkGearRows<4>(
        worst, "coupling", coupling, [&](const auto& X, const auto& V) { return refCoupling(coupling, X, V); },
        gen);
  }
  worst.print("gear rows");
  worst.expectAllBelow(kJacobianTolerance);
}

/// max_r |(B q̇)_r| / Σ_k Σ_c |B_k(r, c) q̇_k(c)|: the residual relative to the
/// size of the terms it sums (the rounding scale of the row).
template <typename M, std::size_t N>
double relativeToTerms(const std::array<M, N>& B, const std::array<Vel, N>& V) {
  double worst = 0.0;
  for (int r = 0; r < B[0].rows(); ++r) {
    double sum = 0.0, scale = 0.0;
    for (std::size_t k = 0; k < N; ++k) {
      const Vec6 tw = V[k].twist();
      for (int c = 0; c < 6; ++c) {
        sum += B[k](r, c) * tw[c];
        scale += std::abs(B[k](r, c) * tw[c]);
      }
    }
    worst = std::max(worst, std::abs(sum) / scale);
  }
  return worst;
}

TEST(GearRows, SatisfiedByGearedMotionsAndViolatedOtherwise) {
  std::mt19937 gen(32);
  double worst_gear = 0.0, worst_rack = 0.0, worst_diff = 0.0;  // |B q̇|
  double rel_gear = 0.0, rel_rack = 0.0, rel_diff = 0.0;        // relative to its terms
  for (int i = 0; i < kSamples; ++i) {
    const double alpha = 0.5 + std::uniform_real_distribution<double>(0.0, 2.0)(gen);
    // Carrier: any pose and motion (also ground, every 4th sample).
    const bool ground = i % 4 == 0;
    const Pose X0 = ground ? groundPose<double>() : randomPose(gen);
    const Vel V0 = ground ? groundVelocity<double>() : Vel{randomVector(gen), randomVector(gen)};
    const Vec3 O0 = X0.R * V0.omega;

    // Gear: each gear spins relative to the carrier about its r axis,
    // φ̇₂ = −α φ̇₁, so α(Δω₁·r₁) + Δω₂·r₂ = 0 and the s, t rows vanish.
    {
      const auto gear = makeGearJoint(alpha, randomNodeAxes(gen), randomNodeAxes(gen));
      const Pose X1 = randomPose(gen), X2 = randomPose(gen);
      const double phid1 = randomVector(gen)[0], phid2 = -alpha * phid1;
      const auto spin = [&](const Pose& X, const Vec3& r, double rate) {
        return Vel{randomVector(gen), X.R.inverse() * O0 + rate * r};
      };
      const std::array<Pose, 3> X{X0, X1, X2};
      const std::array<Vel, 3> V{V0, spin(X1, gear.node1.r, phid1), spin(X2, gear.node2.r, phid2)};
      const Eigen::Matrix<double, 5, 1> bq = gear.velocity(X, V);
      worst_gear = std::max(worst_gear, bq.cwiseAbs().maxCoeff());
      rel_gear = std::max(rel_gear, relativeToTerms(gear.rows(X), V));
      // Violations: a wrong ratio, and a wobble about s₁.
      std::array<Vel, 3> Vbad = V;
      Vbad[2].omega += 1e-3 * gear.node2.r;
      EXPECT_NEAR(gear.velocity(X, Vbad)[0], 1e-3, 1e-12);
      Vbad = V;
      Vbad[1].omega += 1e-3 * gear.node1.s;
      EXPECT_NEAR(gear.velocity(X, Vbad)[1], 1e-3, 1e-12);
      EXPECT_NEAR(gear.velocity(X, Vbad)[0], 0.0, 1e-14);
    }
    // Rack and pinion: the pinion spins about s₁ relative to the carrier at θ̇,
    // the rack slides along s₂ relative to the carrier at −α θ̇.
    {
      const auto rp = makeRackPinionJoint(alpha, randomNodeAxes(gen), randomNodeAxes(gen));
      const Pose X1 = randomPose(gen), X2 = randomPose(gen);
      const double thetad = randomVector(gen)[0];
      const Vec3 S2 = X2.R * rp.rack.s;
      const Vel V1{randomVector(gen), X1.R.inverse() * O0 + thetad * rp.pinion.s};
      const Vel V2{V0.v + O0.cross(X2.p - X0.p) - alpha * thetad * S2, X2.R.inverse() * O0};
      const std::array<Pose, 3> X{X0, X1, X2};
      const std::array<Vel, 3> V{V0, V1, V2};
      worst_rack = std::max(worst_rack, rp.velocity(X, V).cwiseAbs().maxCoeff());
      rel_rack = std::max(rel_rack, relativeToTerms(rp.rows(X), V));
      std::array<Vel, 3> Vbad = V;
      Vbad[2].v += 1e-3 * S2;  // the rack slips
      EXPECT_NEAR(rp.velocity(X, Vbad)[0], 1e-3, 1e-12);
    }
    // Differential: spins about the r axes with α φ̇₁ + φ̇₂ + φ̇₃ = 0.
    {
      const auto df =
          makeDifferentialJoint(alpha, randomNodeAxes(gen), randomNodeAxes(gen), randomNodeAxes(gen));
      const Pose X1 = randomPose(gen), X2 = randomPose(gen), X3 = randomPose(gen);
      const double p1 = randomVector(gen)[0], p2 = randomVector(gen)[0], p3 = -alpha * p1 - p2;
      const std::array<Pose, 4> X{X0, X1, X2, X3};
      const std::array<Vel, 4> V{V0, Vel{Vec3::Zero(), X1.R.inverse() * O0 + p1 * df.node1.r},
                                 Vel{Vec3::Zero(), X2.R.inverse() * O0 + p2 * df.node2.r},
                                 Vel{Vec3::Zero(), X3.R.inverse() * O0 + p3 * df.node3.r}};
      worst_diff = std::max(worst_diff, df.velocity(X, V).cwiseAbs().maxCoeff());
      rel_diff = std::max(rel_diff, relativeToTerms(df.rows(X), V));
      std::array<Vel, 4> Vbad = V;
      Vbad[3].omega += 1e-3 * df.node3.r;
      EXPECT_NEAR(df.velocity(X, Vbad)[0], 1e-3, 1e-12);
    }
  }
  std::cout << "[ measured ] |B q̇| of geared motions (velocities ~1, α ≤ 2.5): gear " << worst_gear
            << ", rack_pinion " << worst_rack << ", differential " << worst_diff
            << "\n             relative to the sum of |terms| of the row: gear " << rel_gear
            << ", rack_pinion " << rel_rack << ", differential " << rel_diff << "\n";
  EXPECT_LE(rel_gear, 1e-15);
  EXPECT_LE(rel_rack, 1e-15);
  EXPECT_LE(rel_diff, 1e-15);
  EXPECT_LE(std::max({worst_gear, worst_rack, worst_diff}), 1e-14);
}

// ---- 7. bad input ---------------------------------------------------------------------------------

/// Runs f, expects InvalidInput with this field and a reason containing `words`.
template <typename F>
void expectInvalid(const F& f, const std::string& field, const std::string& words) {
  try {
    f();
    ADD_FAILURE() << "no InvalidInput for " << field;
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.field(), field);
    EXPECT_NE(e.reason().find(words), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).rfind(field, 0), 0u) << e.what();
  }
}

TEST(JointConstraintInput, BadAxesRatiosAndAnchorsAreRejectedWithTheFieldName) {
  const Vec3 z = Vec3::Zero();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const SO3d I = SO3d::identity();
  // Axes: zero, non-finite, far from unit.
  expectInvalid([&] { makeRevoluteJoint<double>(z, z, z, Vec3::UnitZ(), I, "joints[0]"); },
                "joints[0].axis_main", "zero");
  expectInvalid([&] { makeRevoluteJoint<double>(z, z, Vec3(nan, 0, 1), Vec3::UnitZ(), I, "joints[0]"); },
                "joints[0].axis_main", "non-finite");
  expectInvalid([&] { makeRevoluteJoint<double>(z, z, Vec3::UnitZ(), Vec3(0, 0, 1.01), I, "hinge"); },
                "hinge.axis_secondary", "not within 1e-06 of 1");
  expectInvalid([&] { makeRevoluteJoint<double>(z, z, Vec3(0, 0, 2e-6 + 1), Vec3::UnitZ(), I, "hinge"); },
                "hinge.axis_main", "not within");
  // Within 1e-6 of unit: normalized.
  const auto near = makeRevoluteJoint<double>(z, z, Vec3(0, 0, 1 + 5e-7), Vec3(0, 1e-7, 1), I, "hinge");
  EXPECT_NEAR(near.axis_main.norm(), 1.0, 1e-15);
  EXPECT_NEAR(near.axis_secondary.norm(), 1.0, 1e-15);
  // Revolute axes not aligned in the reference configuration.
  expectInvalid([&] { makeRevoluteJoint<double>(z, z, Vec3::UnitZ(), Vec3::UnitX(), I, "hinge"); },
                "hinge.axis_secondary", "not aligned");
  // Anchors must be finite.
  expectInvalid([&] { makeSphericalJoint<double>(Vec3(inf, 0, 0), z, "ball"); }, "ball.anchor_main",
                "non-finite");
  expectInvalid([&] { makeRevoluteJoint<double>(z, Vec3(0, nan, 0), Vec3::UnitZ(), Vec3::UnitZ(), I, "h"); },
                "h.anchor_secondary", "non-finite");
  // Universal axes not orthogonal (beyond 1e-6), in the reference and at assembly.
  expectInvalid(
      [&] { makeUniversalJoint<double>(z, z, Vec3::UnitX(), Vec3(1e-3, 1, 0).normalized(), I, "cardan"); },
      "cardan.axis2_secondary", "not orthogonal");
  expectInvalid(
      [&] {
        assembleUniversalJoint<double>(groundPose<double>(), Pose{SO3d::exp(Vec3(0, 0, 0.3)), z}, z, z,
                                       Vec3::UnitX(), Vec3::UnitX(), 0.0, 0.0, "cardan");
      },
      "cardan.axis2_secondary", "not orthogonal");
  expectInvalid([&] { makeUniversalJoint<double>(z, z, Vec3::UnitX(), z, I, "cardan"); },
                "cardan.axis2_secondary", "zero");
  // Within tolerance: made exactly orthogonal.
  const auto u = makeUniversalJoint<double>(z, z, Vec3::UnitX(), Vec3(5e-7, 1, 0), I, "cardan");
  EXPECT_LE(std::abs(u.axis1_main.dot(u.reference * u.axis2_secondary)), 1e-16);
  // Gear ratio 0 or non-finite.
  const auto n = makeNodeAxes<double>(Vec3::UnitX(), Vec3::UnitY());
  expectInvalid([&] { makeGearJoint(0.0, n, n, "joints[4]"); }, "joints[4].ratio", "0");
  expectInvalid([&] { makeGearJoint(nan, n, n, "joints[4]"); }, "joints[4].ratio", "not finite");
  expectInvalid([&] { makeRackPinionJoint(inf, n, n, "rp"); }, "rp.ratio", "not finite");
  expectInvalid([&] { makeDifferentialJoint(0.0, n, n, n, "diff"); }, "diff.ratio", "0");
  EXPECT_NO_THROW(makeGearJoint(-2.5, n, n, "joints[4]"));
  // Node axes: zero, not orthogonal, left-handed.
  expectInvalid([&] { makeNodeAxes<double>(z, Vec3::UnitY(), "joints[4].node1"); }, "joints[4].node1.r",
                "zero");
  expectInvalid([&] { makeNodeAxes<double>(Vec3::UnitX(), Vec3(0.1, 1, 0).normalized(), "n1"); }, "n1.s",
                "not orthogonal");
  expectInvalid([&] { makeNodeAxes<double>(Vec3::UnitX(), Vec3::UnitY(), -Vec3::UnitZ(), "n1"); }, "n1.t",
                "not r × s");
}

// The fused RevoluteJoint::evaluate (the multibody hot path) against the
// three separate calls, whose formulas the tests above check against finite
// differences and Jets: equal to a few ulps of the largest entry.
TEST(JointConstraints, FusedRevoluteEvaluationMatchesTheSeparateCalls) {
  std::mt19937 gen(2026);
  double worst = 0.0;
  for (int trial = 0; trial < 200; ++trial) {
    const RevoluteJoint<double> joint = randomRevolute(gen).build<double>();
    const Pose a = trial % 7 == 0 ? groundPose<double>() : randomPose(gen), b = randomPose(gen);
    const Vel va = trial % 7 == 0 ? groundVelocity<double>() : randomVelocity(gen), vb = randomVelocity(gen);
    RevoluteJoint<double>::Residual phi, c;
    RevoluteJoint<double>::Blocks J;
    joint.evaluate(a, b, &va, &vb, &phi, &J, &c);
    const auto phi0 = joint.residual(a, b);
    const auto J0 = joint.jacobians(a, b);
    const auto c0 = joint.convective(a, b, va, vb);
    auto rel = [](const auto& x, const auto& y) { return (x - y).cwiseAbs().maxCoeff() / (1.0 + y.cwiseAbs().maxCoeff()); };
    worst = std::max({worst, rel(phi, phi0), rel(J[0], J0[0]), rel(J[1], J0[1]), rel(c, c0)});
  }
  EXPECT_LE(worst, 1e-14);
}

}  // namespace
}  // namespace constraints
}  // namespace lieflow
