/// \file
/// The offset universal joint (dynamics/constraints/offset_universal.hpp: two
/// orthogonal hinges whose axes do not meet) against independent references,
/// with the harness of every joint (constraint_checks.hpp):
///  * configurations built as MuJoCo builds a body with two hinges at two
///    points — T_b = T_a T_ref Rot(φ₁, a₁ @ r₁) Rot(φ₂, a₂ @ r₂) — satisfy
///    the rows, and the universal angles recover (φ₁, φ₂);
///  * Jacobians against finite differences of the residual written out here
///    and against ceres::Jet; velocity form and convective term against
///    time derivatives along random motions.
#include <gtest/gtest.h>

#include <random>

#include "dynamics/constraints/constraints.hpp"
#include "tests/dynamics/constraint_checks.hpp"

namespace lieflow {
namespace constraints {
namespace {

using namespace checks;  // NOLINT: the shared harness (constraint_checks.hpp)

/// Two hinges of the secondary body: axis a₁ through r₁ and axis a₂ ⟂ a₁
/// through r₂, both in the secondary frame at φ = 0, the secondary placed at
/// T_ref = (Q, t) in the main frame.
struct HingePair {
  Vec3 a1, a2, r1, r2;
  SO3d Q;
  Vec3 t;
  /// The secondary's pose for (φ₁, φ₂) as MuJoCo composes it.
  Pose secondary(const Pose& main, double phi1, double phi2) const {
    auto rot = [](const Vec3& axis, const Vec3& point, double phi) {  // about the line through point
      const SO3d R = SO3d::exp(phi * axis);
      return std::make_pair(R, Vec3(point - (R * point)));
    };
    const auto [R1, p1] = rot(a1, r1, phi1);
    const auto [R2, p2] = rot(a2, r2, phi2);
    // T = T_main T_ref T1 T2, T_ref = (Q, t).
    const SO3d R = main.R * Q * R1 * R2;
    const Vec3 p = main.toWorld(t + Q * (p1 + R1 * p2));
    return Pose{R, p};
  }
};

HingePair randomPair(std::mt19937& gen) {
  HingePair h;
  h.a1 = randomUnit(gen);
  h.a2 = randomUnitNormalTo(gen, h.a1);
  h.r1 = randomVector(gen, 0.3);
  h.r2 = randomVector(gen, 0.3);
  h.Q = SO3d::random(gen);
  h.t = randomVector(gen);
  return h;
}

/// The joint assembled at φ = 0 between `main` and the pair's secondary,
/// anchors at r₁ (main frame, through T_ref) and r₂ (secondary frame), with
/// its body poses' CoMs at the frame origins.
OffsetUniversalJoint<double> assemble(const HingePair& h, const Pose& main) {
  const Pose sec = h.secondary(main, 0.0, 0.0);
  const Vec3 anchor_main = h.t + h.Q * h.r1, axis_main = h.Q * h.a1;
  return assembleOffsetUniversalJoint<double>(main, sec, anchor_main, h.r2, axis_main, h.a2);
}

TEST(OffsetUniversal, HingePairConfigurationsSatisfyTheRowsAndGiveTheirAngles) {
  std::mt19937 gen(77);
  double worst_residual = 0.0, worst_angle = 0.0;
  for (int i = 0; i < kSamples; ++i) {
    const HingePair h = randomPair(gen);
    const Pose main = randomPose(gen);
    const auto joint = assemble(h, main);
    std::uniform_real_distribution<double> u(-1.4, 1.4);
    const double phi1 = u(gen), phi2 = u(gen);
    const Pose sec = h.secondary(main, phi1, phi2);
    worst_residual = std::max(worst_residual, joint.residual(main, sec).lpNorm<Eigen::Infinity>());
    const auto ang = universalAngles(joint.cross, main, sec);
    worst_angle = std::max({worst_angle, std::abs(ang.phi1 - phi1), std::abs(ang.phi2 - phi2)});
  }
  std::cout << "[ measured ] offset universal on MuJoCo-built configurations: residual " << worst_residual
            << ", angles " << worst_angle << " rad\n";
  EXPECT_LE(worst_residual, 1e-13);
  EXPECT_LE(worst_angle, 1e-13);
}

TEST(OffsetUniversal, JacobiansVelocityFormAndConvectiveTerm) {
  std::mt19937 gen(78);
  Worst worst;
  for (int i = 0; i < kSamples; ++i) {
    const HingePair h = randomPair(gen);
    const Pose main = randomPose(gen);
    const auto joint = assemble(h, main);
    // Reference residual from the definitions (rotation matrices).
    const auto ref = [&](const std::array<Pose, 2>& X) -> Eigen::VectorXd {
      const Mat3 Ra = X[0].R.matrix(), Rb = X[1].R.matrix();
      const Vec3 A1 = Ra * joint.cross.axis1_main, A2 = Rb * joint.cross.axis2_secondary;
      const Vec3 D = X[1].p + Rb * joint.cross.point.anchor_secondary - X[0].p - Ra * joint.cross.point.anchor_main;
      Eigen::VectorXd r(4);
      r << joint.offset[0] * A1 + joint.offset[1] * A2 + joint.offset[2] * A1.cross(A2) - D, A1.dot(A2);
      return r;
    };
    const auto lib_jet = [&](const auto& X) {
      using S = typename std::decay_t<decltype(X[0].p)>::Scalar;
      OffsetUniversalJoint<S> js;
      js.cross = makeUniversalJoint<S>(castV<S>(joint.cross.point.anchor_main), castV<S>(joint.cross.point.anchor_secondary),
                                       castV<S>(joint.cross.axis1_main), castV<S>(joint.cross.axis2_secondary),
                                       joint.cross.reference.template cast<S>());
      js.offset = castV<S>(joint.offset);
      return js.residual(X[0], X[1]);
    };
    checkJacobians(worst, "offset universal", joint, {main, nudge(gen, h.secondary(main, 0.5, -0.3), 0.3)}, ref,
                   lib_jet);
    checkJacobians(worst, "offset universal", joint, {randomPose(gen), randomPose(gen)}, ref, lib_jet);
    const Motion ma = randomMotion(gen, randomPose(gen)), mb = randomMotion(gen, randomPose(gen));
    checkTimeDerivatives(worst, "offset universal", joint, ma, mb);
    const Motion ground{groundPose<double>(), groundVelocity<double>(), Vec6::Zero()};
    checkTimeDerivatives(worst, "offset universal to ground", joint, ground, mb);
  }
  worst.print("offset universal joint");
  worst.expectAllBelow(kJacobianTolerance);
}

}  // namespace
}  // namespace constraints
}  // namespace lieflow
