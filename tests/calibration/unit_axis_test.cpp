/// \file
/// The units of the reported uncertainty: what Ceres 2.1's SphereManifold
/// does to a unit axis (it turns by half the tangent norm, so tangent
/// covariances are in (2 rad)²), and the fit's σ against an independent
/// computation of the covariance (central finite differences of the residuals
/// in plain axis-angle coordinates). Plus the sign convention.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <ceres/sphere_manifold.h>
#include <Eigen/Cholesky>

#include "calibration/hinge_fit.hpp"
#include "calibration/hinge_residuals.hpp"
#include "calibration/synthetic_motion.hpp"
#include "calibration/unit_axis.hpp"

namespace lieflow {
namespace calibration {
namespace {

TEST(CalibUnitAxis, SphereManifoldTurnsAnAxisByHalfTheTangentNorm) {
  const ceres::SphereManifold<3> sphere;
  std::mt19937 gen(61);
  std::normal_distribution<double> normal;
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Vector3d x = Eigen::Vector3d(normal(gen), normal(gen), normal(gen)).normalized();
    const Eigen::Vector2d delta = 0.3 * Eigen::Vector2d(normal(gen), normal(gen));
    Eigen::Vector3d y;
    ASSERT_TRUE(sphere.Plus(x.data(), delta.data(), y.data()));
    EXPECT_NEAR(y.norm(), 1.0, 1e-15);
    EXPECT_NEAR(angleBetween(x, y), delta.norm() / kSphereTangentPerRadian, 1e-14);
    Eigen::Matrix<double, 3, 2, Eigen::RowMajor> J;
    ASSERT_TRUE(sphere.PlusJacobian(x.data(), J.data()));
    // Orthogonal columns of norm ½, both ⟂ x.
    EXPECT_TRUE((J.transpose() * J).isApprox(Eigen::Matrix2d::Identity() / 4.0, 1e-14));
    EXPECT_NEAR((J.transpose() * x).norm(), 0.0, 1e-15);
  }
}

TEST(CalibUnitAxis, SigmaAgreesWithAFiniteDifferenceCovarianceInAxisAngles) {
  std::mt19937 gen(62);
  const HingeMotion m = randomHingeMotion(gen);
  const JointSamples s = recordMotion(m, 1000, 100.0, RecordingNoise{0.05, 0.0, false, true}, gen);
  AxisFitOptions constraint;  // Seel's cost, whose covariance this checks
  constraint.estimator = HingeEstimator::kConstraint;
  const HingeFit fit = fitHinge(s, constraint);

  // The same residuals, whitened by the fit's noise scale, differentiated by
  // central differences with respect to turning each axis by an angle about
  // two directions perpendicular to it.
  const double weight = 1.0 / fit.summary.residuals.front().noise_scale;
  const Eigen::Vector3d axes[2] = {fit.axis_main, fit.axis_secondary};
  Eigen::Vector3d basis[2][2];
  for (int a = 0; a < 2; ++a) {
    basis[a][0] = orthogonalUnit(axes[a]);
    basis[a][1] = axes[a].cross(basis[a][0]);
  }
  auto residual = [&](int k, const Eigen::Vector4d& angles) {
    Eigen::Vector3d j[2];
    for (int a = 0; a < 2; ++a)
      j[a] = SO3d::exp(angles[2 * a] * basis[a][0] + angles[2 * a + 1] * basis[a][1]) * axes[a];
    GyroHingeResidual r(s.main.angular_velocity[k], s.secondary.angular_velocity[k]);
    r.weight = &weight;
    double value;
    r(j[0].data(), j[1].data(), &value);
    return value;
  };
  const double h = 1e-6;
  Eigen::Matrix4d H = Eigen::Matrix4d::Zero();
  double cost = 0.0;
  for (int k = 0; k < s.size(); ++k) {
    Eigen::Vector4d row;
    for (int i = 0; i < 4; ++i) {
      const Eigen::Vector4d e = h * Eigen::Vector4d::Unit(i);
      row[i] = (residual(k, e) - residual(k, -e)) / (2 * h);
    }
    H += row * row.transpose();
    cost += 0.5 * std::pow(residual(k, Eigen::Vector4d::Zero()), 2);
  }
  const double s2 = 2.0 * cost / (s.size() - 4);
  EXPECT_NEAR(s2, fit.summary.reduced_chi_square, 1e-9 * s2);
  const Eigen::Matrix4d covariance = s2 * H.ldlt().solve(Eigen::Matrix4d::Identity());
  const double sigma_main = std::sqrt(covariance.topLeftCorner<2, 2>().trace()) * kRadToDeg;
  const double sigma_secondary = std::sqrt(covariance.bottomRightCorner<2, 2>().trace()) * kRadToDeg;
  EXPECT_NEAR(fit.sigma_main_deg, sigma_main, 1e-4 * sigma_main);
  EXPECT_NEAR(fit.sigma_secondary_deg, sigma_secondary, 1e-4 * sigma_secondary);
}

TEST(CalibUnitAxis, CanonicalSignMakesTheLargestComponentPositive) {
  EXPECT_EQ(canonicalSign(Eigen::Vector3d(0.1, -0.9, 0.3)), -1.0);
  EXPECT_EQ(canonicalSign(Eigen::Vector3d(0.1, 0.2, 0.9)), 1.0);
  EXPECT_EQ(canonicalSign(Eigen::Vector3d(-0.6, 0.6, 0.0)), -1.0);  // ties: the first
  EXPECT_NEAR(angleBetweenLines(Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(-1, 1e-9, 0)), 1e-9, 1e-20);
}

}  // namespace
}  // namespace calibration
}  // namespace lieflow
