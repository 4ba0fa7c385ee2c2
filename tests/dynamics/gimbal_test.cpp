/// \file
/// The gimbal joint's angles (dynamics/constraints/gimbal.hpp) against
/// configurations built from known angles, R_b = R_a exp(φ₁e₁) exp(φ₂e₂)
/// exp(φ₃e₃) R_ref, for orthonormal axes of either handedness, with φ₂
/// carried past ±90° by unwrapping; their Jacobians against central finite
/// differences of the angles (right perturbations of either body).
#include <gtest/gtest.h>

#include <random>

#include "dynamics/constraints/constraints.hpp"
#include "tests/dynamics/constraint_checks.hpp"

namespace lieflow {
namespace constraints {
namespace {

using namespace checks;  // NOLINT: the shared harness (constraint_checks.hpp)

struct GimbalCase {
  GimbalJoint<double> joint;
  Pose a;
  Pose at(const std::array<double, 3>& phi) const {
    const auto& e = joint.axes;
    return Pose{a.R * SO3d::exp(phi[0] * e[0]) * SO3d::exp(phi[1] * e[1]) * SO3d::exp(phi[2] * e[2]) * joint.reference,
                a.toWorld(joint.point.anchor_main)};
  }
};

GimbalCase randomCase(std::mt19937& gen, bool left_handed) {
  const Vec3 e1 = randomUnit(gen), e2 = randomUnitNormalTo(gen, e1);
  const Vec3 e3 = (left_handed ? -1.0 : 1.0) * e1.cross(e2);
  GimbalCase c;
  c.a = randomPose(gen);
  const Pose b0{SO3d::random(gen), c.a.p};
  c.joint = assembleGimbalJoint(c.a, b0, Vec3::Zero(), Vec3::Zero(), {{e1, e2, e3}}, {{0.0, 0.0, 0.0}});
  return c;
}

TEST(GimbalAngles, RecoverConstructionAnglesOfEitherHandednessAndPastNinetyDegrees) {
  std::mt19937 gen(9);
  double worst = 0.0;
  for (int i = 0; i < kSamples; ++i) {
    const GimbalCase c = randomCase(gen, i % 2 == 1);
    std::uniform_real_distribution<double> u(-3.0, 3.0), v(-1.4, 1.4);
    // From previous angles 0.3 rad off in each: the branch nearest them.
    const std::array<double, 3> phi{{u(gen), v(gen), u(gen)}};
    const auto got = gimbalAngles(c.joint, c.a, c.at(phi), {{phi[0] + 0.3, phi[1] - 0.3, phi[2] + 0.3}});
    for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(got.phi[k] - phi[k]));
    EXPECT_LE(worst, 1e-9) << "near the truth, sample " << i;
    // A path that takes φ₂ from 60° to 120° in small steps: the unwrapped
    // angles follow it (the other branch of the same rotation).
    std::array<double, 3> previous{{phi[0], 1.05, phi[2]}};
    for (int s = 0; s <= 60; ++s) {
      const std::array<double, 3> p{{phi[0] + 0.01 * s, 1.05 + 0.0175 * s, phi[2] - 0.01 * s}};
      previous = gimbalAngles(c.joint, c.a, c.at(p), previous).phi;
      if (std::abs(std::cos(p[1])) < 0.05) continue;  // at gimbal lock only φ₁ ± φ₃ is defined
      for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(previous[k] - p[k]));
      EXPECT_LE(worst, 1e-9) << "on the path, sample " << i << " step " << s;
    }
  }
  std::cout << "[ measured ] gimbal angle recovery, worst |error| = " << worst << " rad\n";
  EXPECT_LE(worst, 1e-9);
}

TEST(GimbalAngles, JacobiansAgainstFiniteDifferences) {
  std::mt19937 gen(10);
  double worst = 0.0;
  for (int i = 0; i < kSamples; ++i) {
    const GimbalCase c = randomCase(gen, i % 2 == 1);
    std::uniform_real_distribution<double> u(-2.0, 2.0), v(-1.2, 1.2);
    const std::array<double, 3> phi{{u(gen), v(gen), u(gen)}};
    const std::array<Pose, 2> X{c.a, c.at(phi)};
    const auto angles = [&](const std::array<Pose, 2>& Y) -> Eigen::VectorXd {
      const auto g = gimbalAngles(c.joint, Y[0], Y[1], phi);
      return Eigen::Vector3d(g.phi[0], g.phi[1], g.phi[2]);
    };
    const Eigen::MatrixXd J = stack(gimbalAngleJacobians(c.joint, X[0], X[1], phi));
    worst = std::max(worst, relative(fdJacobian(angles, X), J));
  }
  std::cout << "[ measured ] gimbal angle Jacobians vs FD, worst relative discrepancy = " << worst << "\n";
  EXPECT_LE(worst, kJacobianTolerance);
}

}  // namespace
}  // namespace constraints
}  // namespace lieflow
