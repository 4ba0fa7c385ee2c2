/// \file
/// The ground truth of the calibration tests checks out independently: the
/// analytic body rates of calibration/synthetic_motion.hpp against central
/// finite differences of the orientations, the joint constraints they are
/// built to satisfy, and the noise they add.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>

#include "calibration/synthetic_motion.hpp"

namespace lieflow {
namespace calibration {
namespace {

/// ω ≈ log(R(t − h)ᵀ R(t + h)) / 2h (body frame), error O(h²).
Eigen::Vector3d finiteDifferenceRate(const std::function<SO3d(double)>& R, double t) {
  const double h = 1e-5;
  return (R(t - h).inverse() * R(t + h)).log() / (2.0 * h);
}

TEST(CalibSynthetic, HingeRatesMatchFiniteDifferencesAndTheJointHolds) {
  std::mt19937 gen(51);
  const HingeMotion m = randomHingeMotion(gen);
  const Eigen::Vector3d j1 = m.axis_main, j2 = m.axisSecondary();
  for (double t : {0.0, 0.37, 1.9, 4.2, 9.99}) {
    const TwoBodyState s = m.at(t);
    EXPECT_LE((s.w1 - finiteDifferenceRate([&](double x) { return m.at(x).R1; }, t)).norm(), 1e-6 * (1 + s.w1.norm()));
    EXPECT_LE((s.w2 - finiteDifferenceRate([&](double x) { return m.at(x).R2; }, t)).norm(), 1e-6 * (1 + s.w2.norm()));
    EXPECT_LE((s.R1 * j1 - s.R2 * j2).norm(), 1e-14);                        // one axis line
    EXPECT_LE((s.R2 * s.w2 - s.R1 * s.w1).cross(s.R1 * j1).norm(), 1e-12);  // relative rate along it
  }
}

TEST(CalibSynthetic, UniversalRatesMatchFiniteDifferencesAndTheJointHolds) {
  std::mt19937 gen(52);
  const UniversalMotion m = randomUniversalMotion(gen);
  EXPECT_NEAR((m.mount * m.axis2_secondary).dot(m.axis1_main), 0.0, 1e-15);
  for (double t : {0.0, 0.37, 1.9, 4.2, 9.99}) {
    const TwoBodyState s = m.at(t);
    EXPECT_LE((s.w2 - finiteDifferenceRate([&](double x) { return m.at(x).R2; }, t)).norm(), 1e-6 * (1 + s.w2.norm()));
    const Eigen::Vector3d a1 = s.R1 * m.axis1_main, a2 = s.R2 * m.axis2_secondary;
    EXPECT_NEAR(a1.dot(a2), 0.0, 1e-14);                                      // perpendicular in the world
    EXPECT_NEAR((s.R2 * s.w2 - s.R1 * s.w1).dot(a1.cross(a2)), 0.0, 1e-12);  // rate in their span
  }
}

TEST(CalibSynthetic, RecordingsCarryTheRequestedNoise) {
  std::mt19937 gen(53);
  const HingeMotion m = randomHingeMotion(gen);
  const int n = 4000;
  const JointSamples noisy = recordMotion(m, n, 100.0, RecordingNoise{0.1, 0.01, true, true}, gen);
  double rate_sq = 0.0, angle_sq = 0.0;
  for (int k = 0; k < n; ++k) {
    const TwoBodyState s = m.at(noisy.time[k]);
    rate_sq += (noisy.main.angular_velocity[k] - s.w1).squaredNorm();
    angle_sq += (s.R1.inverse() * noisy.main.orientation[k]).log().squaredNorm();
  }
  EXPECT_NEAR(std::sqrt(rate_sq / (3 * n)), 0.1, 0.005);
  EXPECT_NEAR(std::sqrt(angle_sq / (3 * n)), 0.01, 0.0005);
  EXPECT_EQ(noisy.time[1], 0.01);
  const JointSamples gyro = recordMotion(m, 10, 100.0, RecordingNoise{0.0, 0.0, false, true}, gen);
  EXPECT_FALSE(gyro.hasOrientations());
  EXPECT_TRUE(gyro.hasAngularVelocities());
}

}  // namespace
}  // namespace calibration
}  // namespace lieflow
