/// \file
/// The universal-joint fit against the truth of analytic motions: the
/// issue's target (≤ 0.2° per axis at σ_ω = 0.01 rad/s plus 0.5° orientation
/// noise, 1000 samples at 100 Hz), orientations alone, the exact closed form,
/// any start, and the sign convention; the orientation noise estimate that
/// weights the relative-rate residual per sample.
#include <gtest/gtest.h>

#include <random>

#include "calibration/data_selection.hpp"
#include "calibration/synthetic_motion.hpp"
#include "calibration/universal_fit.hpp"
#include "calibration/universal_initial.hpp"
#include "calibration_test_helpers.hpp"

namespace lieflow {
namespace calibration {
namespace {

using test::errorDeg;
using test::lineErrorDeg;

constexpr int kSamples = 1000;
constexpr double kRateHz = 100.0;
constexpr double kDeg = 1.0 / kRadToDeg;

TEST(CalibUniversal, GyroscopesAndOrientationsWithinTwoTenthsOfADegree) {
  for (unsigned seed : {31u, 32u, 33u}) {
    std::mt19937 gen(seed);
    const UniversalMotion m = randomUniversalMotion(gen);
    const UniversalFit fit =
        fitUniversal(recordMotion(m, kSamples, kRateHz, RecordingNoise{0.01, 0.5 * kDeg, true, true}, gen));
    SCOPED_TRACE(seed);
    EXPECT_LE(lineErrorDeg(fit.axis1_main, m.axis1_main), 0.2);
    EXPECT_LE(lineErrorDeg(fit.axis2_secondary, m.axis2_secondary), 0.2);
    EXPECT_TRUE(fit.summary.converged) << fit.summary.message;
    EXPECT_EQ(fit.summary.data, "orientations+gyroscopes");
    ASSERT_EQ(fit.summary.residuals.size(), 2u);
    EXPECT_NEAR(fit.summary.reduced_chi_square, 1.0, 0.15);
    // (R₁a₁)·(R₂a₂) with both orientations perturbed by 0.5° per axis: σ ≈ 0.5°·√2.
    EXPECT_NEAR(fit.summary.rms_residual, 0.5 * kDeg * std::sqrt(2.0), 0.1 * kDeg);
  }
}

TEST(CalibUniversal, OrientationsOnly) {
  std::mt19937 gen(34);
  const UniversalMotion m = randomUniversalMotion(gen);
  const UniversalFit fit =
      fitUniversal(recordMotion(m, kSamples, kRateHz, RecordingNoise{0.0, 0.5 * kDeg, true, false}, gen));
  EXPECT_LE(lineErrorDeg(fit.axis1_main, m.axis1_main), 0.2);
  EXPECT_LE(lineErrorDeg(fit.axis2_secondary, m.axis2_secondary), 0.2);
  EXPECT_EQ(fit.summary.data, "orientations");
}

TEST(CalibUniversal, ClosedFormIsExactOnExactData) {
  std::mt19937 gen(35);
  const UniversalMotion m = randomUniversalMotion(gen);
  const JointSamples exact = recordMotion(m, 300, kRateHz, RecordingNoise{}, gen);
  const AxisPair start = universalAxesFromOrientations(relativeOrientations(exact));
  EXPECT_LE(lineErrorDeg(start.axis1, m.axis1_main), 1e-6);
  EXPECT_LE(lineErrorDeg(start.axis2, m.axis2_secondary), 1e-6);
  const UniversalFit fit = fitUniversal(exact);
  EXPECT_LE(lineErrorDeg(fit.axis1_main, m.axis1_main), 1e-6);
  EXPECT_LE(lineErrorDeg(fit.axis2_secondary, m.axis2_secondary), 1e-6);
}

TEST(CalibUniversal, AnyStartGivesTheSameAnswer) {
  std::mt19937 gen(36);
  const UniversalMotion m = randomUniversalMotion(gen);
  const JointSamples samples = recordMotion(m, 500, kRateHz, RecordingNoise{0.01, 0.5 * kDeg, true, true}, gen);
  const UniversalFit reference = fitUniversal(samples);
  std::normal_distribution<double> normal;
  for (int trial = 0; trial < 8; ++trial) {
    AxisFitOptions options;
    options.extra_starts.push_back({Eigen::Vector3d(normal(gen), normal(gen), normal(gen)),
                                    Eigen::Vector3d(normal(gen), normal(gen), normal(gen))});
    const UniversalFit fit = fitUniversal(samples, options);
    EXPECT_LE(errorDeg(fit.axis1_main, reference.axis1_main), 1e-4) << trial;
    EXPECT_LE(errorDeg(fit.axis2_secondary, reference.axis2_secondary), 1e-4) << trial;
  }
}

TEST(CalibUniversal, EachAxisFollowsTheSignConvention) {
  for (unsigned seed : {37u, 38u, 39u}) {
    std::mt19937 gen(seed);
    const UniversalMotion m = randomUniversalMotion(gen);
    const UniversalFit fit =
        fitUniversal(recordMotion(m, 400, kRateHz, RecordingNoise{0.0, 0.5 * kDeg, true, false}, gen));
    for (const Eigen::Vector3d& a : {fit.axis1_main, fit.axis2_secondary}) {
      Eigen::Index i;
      a.cwiseAbs().maxCoeff(&i);
      EXPECT_GT(a[i], 0.0) << seed;
      EXPECT_NEAR(a.norm(), 1.0, 1e-12);
    }
  }
}

/// The orientation noise R exp(η) from the recorded orientations alone:
/// second differences of the increments log(RₖᵀRₖ₊₁) are third differences
/// of η; the motion adds < 1e-4 rad at 100 Hz.
TEST(CalibUniversal, OrientationNoiseFromThirdDifferences) {
  std::mt19937 gen(36);
  const UniversalMotion m = randomUniversalMotion(gen);
  const JointSamples exact = recordMotion(m, kSamples, kRateHz, RecordingNoise{0.0, 0.0, true, false}, gen);
  EXPECT_LT(orientationNoiseFromDifferences(exact.main.orientation), 1e-4);
  EXPECT_LT(orientationNoiseFromDifferences(exact.secondary.orientation), 1e-4);
  for (double sigma : {0.1 * kDeg, 0.5 * kDeg, 2.0 * kDeg}) {
    SCOPED_TRACE(sigma);
    const JointSamples s = recordMotion(m, kSamples, kRateHz, RecordingNoise{0.0, sigma, true, false}, gen);
    EXPECT_NEAR(orientationNoiseFromDifferences(s.main.orientation), sigma, 0.1 * sigma);
    EXPECT_NEAR(orientationNoiseFromDifferences(s.secondary.orientation), sigma, 0.1 * sigma);
  }
}

}  // namespace
}  // namespace calibration
}  // namespace lieflow
