/// \file
/// The hinge fit against the truth of analytic joint motions
/// (calibration/synthetic_motion.hpp): the accuracy targets from
/// gyroscopes (1000 samples at 100 Hz: ≤ 0.1° at σ = 0.01 rad/s, ≤ 0.5° at
/// σ = 0.1 rad/s, from any start), orientations and both, the exactness of the
/// closed-form starts, the sign conventions and the robust loss.
#include <gtest/gtest.h>

#include <random>

#include "calibration/hinge_fit.hpp"
#include "calibration/hinge_initial.hpp"
#include "calibration/hinge_sign.hpp"
#include "calibration/data_selection.hpp"
#include "calibration/synthetic_motion.hpp"
#include "calibration_test_helpers.hpp"

namespace lieflow {
namespace calibration {
namespace {

using test::errorDeg;
using test::lineErrorDeg;

constexpr int kSamples = 1000;
constexpr double kRateHz = 100.0;
constexpr double kDeg = 1.0 / kRadToDeg;

RecordingNoise gyroscopes(double sigma) { return {sigma, 0.0, false, true}; }
RecordingNoise orientations(double sigma) { return {0.0, sigma, true, false}; }

/// Both axes within `tolerance_deg` of the truth, and the relative sign right
/// (R₁j₁ = R₂j₂): flipping the fitted pair onto the true j₁ must put j₂ on the
/// true j₂ too.
void expectHinge(const HingeFit& fit, const HingeMotion& m, double tolerance_deg) {
  const double s = fit.axis_main.dot(m.axis_main) < 0.0 ? -1.0 : 1.0;
  EXPECT_LE(errorDeg(s * fit.axis_main, m.axis_main), tolerance_deg);
  EXPECT_LE(errorDeg(s * fit.axis_secondary, m.axisSecondary()), tolerance_deg);
  EXPECT_NEAR(fit.axis_main.norm(), 1.0, 1e-12);
  EXPECT_NEAR(fit.axis_secondary.norm(), 1.0, 1e-12);
  EXPECT_TRUE(fit.summary.converged) << fit.summary.message;
}

TEST(CalibHinge, GyroscopesLowNoiseWithinATenthOfADegree) {
  for (unsigned seed : {1u, 2u, 3u}) {
    std::mt19937 gen(seed);
    const HingeMotion m = randomHingeMotion(gen);
    const HingeFit fit = fitHinge(recordMotion(m, kSamples, kRateHz, gyroscopes(0.01), gen));
    SCOPED_TRACE(seed);
    expectHinge(fit, m, 0.1);
    EXPECT_EQ(fit.summary.data, "gyroscopes");
    EXPECT_NEAR(fit.summary.rms_residual, 0.01, 0.002);  // Sampson residual: σ of one gyroscope axis
    EXPECT_NE(fit.sign.find("phase"), std::string::npos) << fit.sign;
  }
}

TEST(CalibHinge, GyroscopesHighNoiseWithinHalfADegree) {
  for (unsigned seed : {4u, 5u, 6u}) {
    std::mt19937 gen(seed);
    const HingeMotion m = randomHingeMotion(gen);
    const HingeFit fit = fitHinge(recordMotion(m, kSamples, kRateHz, gyroscopes(0.1), gen));
    SCOPED_TRACE(seed);
    expectHinge(fit, m, 0.5);
    EXPECT_NEAR(fit.summary.rms_residual, 0.1, 0.02);
  }
}

TEST(CalibHinge, AnyStartGivesTheSameAnswer) {
  std::mt19937 gen(7);
  const HingeMotion m = randomHingeMotion(gen);
  const JointSamples samples = recordMotion(m, 500, kRateHz, gyroscopes(0.1), gen);
  const HingeFit reference = fitHinge(samples);
  std::normal_distribution<double> normal;
  for (int trial = 0; trial < 8; ++trial) {
    AxisFitOptions options;
    options.extra_starts.push_back({Eigen::Vector3d(normal(gen), normal(gen), normal(gen)),
                                    Eigen::Vector3d(normal(gen), normal(gen), normal(gen))});
    const HingeFit fit = fitHinge(samples, options);
    EXPECT_EQ(fit.summary.starts, reference.summary.starts + 1);
    EXPECT_LE(errorDeg(fit.axis_main, reference.axis_main), 1e-4) << trial;
    EXPECT_LE(errorDeg(fit.axis_secondary, reference.axis_secondary), 1e-4) << trial;
  }
}

TEST(CalibHinge, ClosedFormStartsAreExactOnExactDataAndCloseOnNoisyData) {
  std::mt19937 gen(8);
  const HingeMotion m = randomHingeMotion(gen);
  const JointSamples exact = recordMotion(m, 300, kRateHz, RecordingNoise{}, gen);
  const AxisPair from_rates = hingeAxesFromRates(exact.main.angular_velocity, exact.secondary.angular_velocity);
  EXPECT_LE(lineErrorDeg(from_rates.axis1, m.axis_main), 1e-6);
  EXPECT_LE(lineErrorDeg(from_rates.axis2, m.axisSecondary()), 1e-6);
  const AxisPair from_orientations = hingeAxesFromOrientations(relativeOrientations(exact));
  // The orientation closed form fixes the relative sign as well.
  const double s = from_orientations.axis1.dot(m.axis_main) < 0.0 ? -1.0 : 1.0;
  EXPECT_LE(errorDeg(s * from_orientations.axis1, m.axis_main), 1e-6);
  EXPECT_LE(errorDeg(s * from_orientations.axis2, m.axisSecondary()), 1e-6);

  // Noisy: the gyroscope closed form is biased by the noise, but lands well
  // inside the basin of the refinement (a few degrees at most).
  const JointSamples noisy = recordMotion(m, kSamples, kRateHz, gyroscopes(0.1), gen);
  const AxisPair start = hingeAxesFromRates(noisy.main.angular_velocity, noisy.secondary.angular_velocity);
  EXPECT_LE(lineErrorDeg(start.axis1, m.axis_main), 3.0);
  EXPECT_LE(lineErrorDeg(start.axis2, m.axisSecondary()), 3.0);
}

TEST(CalibHinge, OrientationsOnly) {
  std::mt19937 gen(9);
  const HingeMotion m = randomHingeMotion(gen);
  const HingeFit fit = fitHinge(recordMotion(m, kSamples, kRateHz, orientations(0.5 * kDeg), gen));
  expectHinge(fit, m, 0.1);
  EXPECT_EQ(fit.summary.data, "orientations");
  EXPECT_EQ(fit.summary.residuals.front().unit, "rad");
  // R1 j1 − R2 j2 with both orientations perturbed by 0.5° per axis: σ ≈ 0.5°·√2 per component.
  EXPECT_NEAR(fit.summary.rms_residual, 0.5 * kDeg * std::sqrt(2.0), 0.1 * kDeg);
}

TEST(CalibHinge, OrientationsAndGyroscopes) {
  std::mt19937 gen(10);
  const HingeMotion m = randomHingeMotion(gen);
  const HingeFit fit =
      fitHinge(recordMotion(m, kSamples, kRateHz, RecordingNoise{0.01, 0.5 * kDeg, true, true}, gen));
  expectHinge(fit, m, 0.1);
  EXPECT_EQ(fit.summary.data, "orientations+gyroscopes");
  ASSERT_EQ(fit.summary.residuals.size(), 2u);
  EXPECT_NEAR(fit.summary.reduced_chi_square, 1.0, 0.15);
}

TEST(CalibHinge, DataSelectionFollowsTheOption) {
  std::mt19937 gen(11);
  const HingeMotion m = randomHingeMotion(gen);
  const JointSamples samples = recordMotion(m, 400, kRateHz, RecordingNoise{0.01, 0.5 * kDeg, true, true}, gen);
  AxisFitOptions options;
  options.use = DataUse::kAngularVelocities;
  EXPECT_EQ(fitHinge(samples, options).summary.data, "gyroscopes");
  options.use = DataUse::kOrientations;
  EXPECT_EQ(fitHinge(samples, options).summary.data, "orientations");
  JointSamples gyro_only = samples;
  gyro_only.main.orientation.clear();
  EXPECT_THROW(fitHinge(gyro_only, options), InvalidInput);  // orientations asked for, main has none
  gyro_only.secondary.angular_velocity.clear();
  EXPECT_THROW(fitHinge(gyro_only), InvalidInput);  // nothing usable
}

TEST(CalibHinge, ReportedSignsFollowTheConvention) {
  for (unsigned seed : {12u, 13u, 14u, 15u}) {
    std::mt19937 gen(seed);
    const HingeMotion m = randomHingeMotion(gen);
    const HingeFit fit = fitHinge(recordMotion(m, 500, kRateHz, gyroscopes(0.01), gen));
    Eigen::Index i;
    fit.axis_main.cwiseAbs().maxCoeff(&i);
    EXPECT_GT(fit.axis_main[i], 0.0) << seed;
  }
}

TEST(CalibHinge, RelativeSignFromThePhaseOfThePerpendicularRates) {
  std::mt19937 gen(17);
  const HingeMotion m = randomHingeMotion(gen);
  const JointSamples s = recordMotion(m, kSamples, kRateHz, gyroscopes(0.1), gen);
  const auto& w1 = s.main.angular_velocity;
  const auto& w2 = s.secondary.angular_velocity;
  const HingeSignEvidence same = hingeRelativeSign(s.time, w1, w2, m.axis_main, m.axisSecondary());
  EXPECT_TRUE(same.decided);
  EXPECT_EQ(same.relative_sign, 1);
  EXPECT_LT(same.spread_same, 0.05);
  EXPECT_GT(same.spread_flipped, 0.5);
  const HingeSignEvidence flipped = hingeRelativeSign(s.time, w1, w2, m.axis_main, -m.axisSecondary());
  EXPECT_TRUE(flipped.decided);
  EXPECT_EQ(flipped.relative_sign, -1);
  // Nothing to read when the main body's perpendicular rate is zero.
  const std::vector<Eigen::Vector3d> rest(w1.size(), Eigen::Vector3d::Zero());
  const HingeSignEvidence blind = hingeRelativeSign(s.time, rest, w2, m.axis_main, m.axisSecondary());
  EXPECT_FALSE(blind.decided);
  EXPECT_EQ(blind.relative_sign, 1);
}

TEST(CalibHinge, RobustLossRejectsOutliers) {
  std::mt19937 gen(16);
  const HingeMotion m = randomHingeMotion(gen);
  JointSamples samples = recordMotion(m, kSamples, kRateHz, gyroscopes(0.01), gen);
  // 5 % of the samples of the secondary gyroscope replaced by garbage.
  std::uniform_real_distribution<double> garbage(-3.0, 3.0);
  for (int k = 0; k < kSamples; k += 20)
    samples.secondary.angular_velocity[k] = Eigen::Vector3d(garbage(gen), garbage(gen), garbage(gen));
  const HingeFit plain = fitHinge(samples);
  EXPECT_GT(lineErrorDeg(plain.axis_main, m.axis_main), 0.3);  // the outliers do hurt
  for (RobustLoss loss : {RobustLoss::kHuber, RobustLoss::kCauchy}) {
    AxisFitOptions options;
    options.loss = loss;
    const HingeFit fit = fitHinge(samples, options);
    SCOPED_TRACE(robustLossName(loss));
    expectHinge(fit, m, 0.1);
  }
}

}  // namespace
}  // namespace calibration
}  // namespace lieflow
