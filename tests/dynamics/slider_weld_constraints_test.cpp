/// \file
/// The prismatic and fixed joints' constraints (dynamics/constraints/
/// prismatic.hpp, fixed.hpp and their building blocks dot_two_row.hpp,
/// align.hpp) against independent references, with the harness every joint
/// of dynamics/constraints/ passes (constraint_checks.hpp):
///  * Jacobians against central finite differences of residuals written out
///    here from the world-frame definitions (rotation matrices, not the
///    library's rows), and against ceres::Jet, near the manifold and far from it;
///  * the velocity form against d/dt Φ and the convective term against
///    d²Φ/dt² − J q̈ along random motions (also to ground);
///  * the prismatic coordinate x on configurations built from a known x, its
///    rate and convective term along motions that keep the joint;
///  * the fixed joint (a prismatic joint with its slide held): its six rows
///    vanish at the weld and have full rank;
///  * the align rows' directions on the manifold are orthonormal (singular
///    values of the rotation columns all 1);
///  * bad input names the field.
// GCC 12's false -Warray-bounds on Eigen's packet loads of 1-element dynamic
// vectors (as in constraints_test.cpp).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Warray-bounds"
#endif

#include <gtest/gtest.h>

#include <random>
#include <string>

#include <Eigen/SVD>

#include "dynamics/constraints/constraints.hpp"
#include "liegroup/invalid_input.hpp"
#include "tests/dynamics/constraint_checks.hpp"

namespace lieflow {
namespace constraints {
namespace {

using namespace checks;  // NOLINT: the shared harness (constraint_checks.hpp)

/// A prismatic joint's data; built for any scalar.
struct PrismaticSpec {
  Vec3 s_a, s_b, axis;
  SO3d reference;
  template <typename S>
  PrismaticJoint<S> build() const {
    return makePrismaticJoint<S>(castV<S>(s_a), castV<S>(s_b), castV<S>(axis), reference.cast<S>());
  }
};

PrismaticSpec randomPrismatic(std::mt19937& gen) {
  return PrismaticSpec{randomVector(gen), randomVector(gen), randomUnit(gen), SO3d::random(gen)};
}

/// The secondary pose on the prismatic manifold at slide x:
/// R_b = R_a R_ref, x_b = x_a + x R_a a.
Pose prismaticPose(const PrismaticSpec& s, const Pose& a, double x) {
  Pose b;
  b.R = a.R * s.reference;
  b.p = a.toWorld(s.s_a) + x * (a.R * s.axis) - b.R * s.s_b;
  return b;
}

/// Reference residual from the definitions, with the library's triad
/// (u, v) ⟂ a as the only shared data: the anchors' separation projected on
/// the main body's u and v, and R_a u, R_a v against R_b R_ref⁻¹ (a, v).
Eigen::VectorXd refPrismatic(const PrismaticJoint<double>& j, const PrismaticSpec& s, const std::array<Pose, 2>& X) {
  const Mat3 Ra = X[0].R.matrix(), Rb = X[1].R.matrix(), Rref = s.reference.matrix();
  const Vec3 D = X[1].p + Rb * s.s_b - X[0].p - Ra * s.s_a;
  const Vec3 U = Ra * j.align.u_main, V = Ra * j.align.v_main;
  const Vec3 A2 = Rb * Rref.transpose() * s.axis, V2 = Rb * Rref.transpose() * j.align.v_main;
  Eigen::VectorXd r(5);
  r << U.dot(D), V.dot(D), U.dot(A2), V.dot(A2), U.dot(V2);
  return r;
}


TEST(SliderWeldConstraints, JacobiansAgainstFiniteDifferencesAndJets) {
  std::mt19937 gen(20261126);
  Worst worst;
  for (int i = 0; i < kSamples; ++i) {
    {
      const PrismaticSpec spec = randomPrismatic(gen);
      const auto joint = spec.build<double>();
      const auto ref = [&](const std::array<Pose, 2>& X) -> Eigen::VectorXd { return refPrismatic(joint, spec, X); };
      const auto lib_jet = [&](const auto& X) {
        using S = typename std::decay_t<decltype(X[0].p)>::Scalar;
        return spec.build<S>().residual(X[0], X[1]);
      };
      const Pose a = randomPose(gen);
      const double x = std::uniform_real_distribution<double>(-2.0, 2.0)(gen);
      checkJacobians(worst, "prismatic", joint, {a, nudge(gen, prismaticPose(spec, a, x), 0.3)}, ref, lib_jet);
      checkJacobians(worst, "prismatic", joint, {randomPose(gen), randomPose(gen)}, ref, lib_jet);
      // The coordinate row x = (R_a a)·(x_b − x_a).
      const auto xrow = joint.position();
      const auto xref = [&](const std::array<Pose, 2>& X) -> Eigen::VectorXd {
        const Vec3 D = X[1].p + X[1].R.matrix() * spec.s_b - X[0].p - X[0].R.matrix() * spec.s_a;
        return Eigen::VectorXd::Constant(1, (X[0].R.matrix() * spec.axis).dot(D));
      };
      const std::array<Pose, 2> X{randomPose(gen), randomPose(gen)};
      worst.add("prismatic x row J vs FD(reference)", relative(fdJacobian(xref, X), stack(xrow.jacobians(X[0], X[1]))));
    }
    {
      const Vec3 s_a = randomVector(gen), s_b = randomVector(gen);
      const SO3d reference = SO3d::random(gen);
      const auto joint = makeFixedJoint<double>(s_a, s_b, reference);
      // A prismatic joint along the main frame's z whose slide is held.
      const PrismaticSpec spec{s_a, s_b, Vec3::UnitZ(), reference};
      const auto ref = [&](const std::array<Pose, 2>& X) -> Eigen::VectorXd { return refPrismatic(joint, spec, X); };
      const auto lib_jet = [&](const auto& X) {
        using S = typename std::decay_t<decltype(X[0].p)>::Scalar;
        return makeFixedJoint<S>(castV<S>(s_a), castV<S>(s_b), reference.cast<S>()).residual(X[0], X[1]);
      };
      const Pose a = randomPose(gen);
      Pose b;
      b.R = a.R * reference;
      b.p = a.toWorld(s_a) - b.R * s_b;
      checkJacobians(worst, "fixed", joint, {a, nudge(gen, b, 0.3)}, ref, lib_jet);
      checkJacobians(worst, "fixed", joint, {randomPose(gen), randomPose(gen)}, ref, lib_jet);
      // Welded: the five rows and the held slide vanish, and the six rows
      // together have full rank 6 (their directions are orthonormal).
      Eigen::Matrix<double, 6, 12> J6;
      const auto J = joint.jacobians(a, b);
      const auto Jx = joint.position().jacobians(a, b);
      J6.topLeftCorner<5, 6>() = J[0];
      J6.topRightCorner<5, 6>() = J[1];
      J6.bottomLeftCorner<1, 6>() = Jx[0];
      J6.bottomRightCorner<1, 6>() = Jx[1];
      EXPECT_LE(joint.residual(a, b).norm() + std::abs(joint.position().value(a, b)), 1e-13);
      const Eigen::VectorXd sv = Eigen::JacobiSVD<Eigen::MatrixXd>(J6.rightCols<6>()).singularValues();
      EXPECT_GT(sv.minCoeff(), 1e-3);
    }
  }
  worst.print("prismatic and fixed joint Jacobians");
  worst.expectAllBelow(kJacobianTolerance);
}

TEST(SliderWeldConstraints, VelocityFormAndConvectiveTermAlongMotions) {
  std::mt19937 gen(11);
  Worst worst;
  const Motion ground{groundPose<double>(), groundVelocity<double>(), Vec6::Zero()};
  for (int i = 0; i < kSamples; ++i) {
    const Motion ma = randomMotion(gen, randomPose(gen));
    const Motion mb = randomMotion(gen, randomPose(gen));
    checkTimeDerivatives(worst, "prismatic", randomPrismatic(gen).build<double>(), ma, mb);
    checkTimeDerivatives(worst, "prismatic to ground", randomPrismatic(gen).build<double>(), ground, mb);
    const auto fixed = makeFixedJoint<double>(randomVector(gen), randomVector(gen), SO3d::random(gen));
    checkTimeDerivatives(worst, "fixed", fixed, ma, mb);
    checkTimeDerivatives(worst, "fixed to ground", fixed, ground, mb);
    // The coordinate row: rate and convective term of x along the motion.
    const auto xrow = randomPrismatic(gen).build<double>().position();
    const auto x = [&](double t) -> Eigen::VectorXd { return Eigen::VectorXd::Constant(1, xrow.value(ma.at(t), mb.at(t))); };
    const auto [d1, d2] = timeDerivatives(x);
    const Pose a = ma.at(0.0), b = mb.at(0.0);
    const auto J = xrow.jacobians(a, b);
    const double acc_part = (J[0] * ma.acc + J[1] * mb.acc)(0, 0);
    const double rate = xrow.rate(a, b, ma.V0, mb.V0), conv = xrow.convective(a, b, ma.V0, mb.V0);
    worst.add("prismatic x rate vs d/dt x", std::abs(d1[0] - rate) / std::max(std::abs(rate), 1.0));
    worst.add("prismatic x convective vs d²x/dt² − J q̈",
              std::abs(d2[0] - acc_part - conv) / std::max({std::abs(conv), std::abs(acc_part), 1.0}));
  }
  worst.print("prismatic and fixed: velocity form and convective term (4th-order time FD, h = 2e-3)");
  worst.expectAllBelow(kTimeTolerance);
}

TEST(PrismaticCoordinate, RecoversTheSlideOfConstructedConfigurations) {
  std::mt19937 gen(5);
  double worst = 0.0, worst_residual = 0.0;
  for (int i = 0; i < kSamples; ++i) {
    const PrismaticSpec spec = randomPrismatic(gen);
    const auto joint = spec.build<double>();
    const Pose a = randomPose(gen);
    const double x = std::uniform_real_distribution<double>(-5.0, 5.0)(gen);
    const Pose b = prismaticPose(spec, a, x);
    worst = std::max(worst, std::abs(joint.position().value(a, b) - x));
    worst_residual = std::max(worst_residual, joint.residual(a, b).lpNorm<Eigen::Infinity>());
  }
  std::cout << "[ measured ] prismatic x recovery, worst |error| = " << worst << " m; residual on the manifold "
            << worst_residual << "\n";
  EXPECT_LE(worst, 1e-13);
  EXPECT_LE(worst_residual, 1e-13);
}

TEST(AlignRows, DirectionsOnTheManifoldAreOrthonormal) {
  // On R_b = R_a R_ref the three rows' rotation columns (main side, body
  // frame) are (u × a, v × a, u × v)ᵀ = (−v, u, a)ᵀ: singular values all 1.
  std::mt19937 gen(3);
  for (int i = 0; i < 10; ++i) {
    const SO3d reference = SO3d::random(gen);
    const auto joint = makeFixedJoint<double>(Vec3::Zero(), Vec3::Zero(), reference);
    const Pose a = randomPose(gen);
    const Pose b{a.R * reference, a.p};
    const auto J = joint.jacobians(a, b);
    const Eigen::Matrix3d Jr = J[0].bottomRightCorner<3, 3>();
    const Eigen::Vector3d sv = Eigen::JacobiSVD<Eigen::Matrix3d>(Jr).singularValues();
    EXPECT_NEAR(sv.maxCoeff(), 1.0, 1e-14);
    EXPECT_NEAR(sv.minCoeff(), 1.0, 1e-14);
  }
}

TEST(SliderWeldConstraintInput, BadAxesAndAnchorsNameTheField) {
  auto field = [](const auto& make) {
    try {
      make();
    } catch (const InvalidInput& e) {
      return std::string(e.field());
    }
    return std::string("(accepted)");
  };
  const SO3d I = SO3d::identity();
  EXPECT_EQ(field([&] { makePrismaticJoint<double>(Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), I, "j"); }),
            "j.axis_main");
  EXPECT_EQ(field([&] { makePrismaticJoint<double>(Vec3::Zero(), Vec3::Zero(), Vec3(0, 0, 2), I, "j"); }),
            "j.axis_main");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(field([&] { makePrismaticJoint<double>(Vec3(nan, 0, 0), Vec3::Zero(), Vec3::UnitX(), I, "j"); }),
            "j.anchor_main");
  EXPECT_EQ(field([&] { makeFixedJoint<double>(Vec3::Zero(), Vec3(0, nan, 0), I, "w"); }), "w.anchor_secondary");
}

}  // namespace
}  // namespace constraints
}  // namespace lieflow
