/// \file
/// The universal-joint fit against the truth of analytic motions: the
/// issue's target (≤ 0.2° per axis at σ_ω = 0.01 rad/s plus 0.5° orientation
/// noise, 1000 samples at 100 Hz), orientations alone, the exact closed form,
/// any start, and the sign convention; the orientation noise estimate that
/// weights the relative-rate residual per sample; gyroscope biases as
/// nuisance parameters and the secondary sensor's clock offset (measured in
/// calibration/README.md, "Gyroscope biases and clock offsets").
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

/// No flag (issue 31): gyroscopes wobbling on soft tissue (1 rad/s at
/// 10–20 Hz) are found and left out — the fit weighs their residual by white
/// noise, which a filter would colour — and the orientations alone answer,
/// honest across 20 recordings; with --low-pass none the gyroscopes stay in
/// and the wobble they carry is read as the joint. The model check across the
/// quarters runs on 1000 samples and, on these recordings of one joint,
/// agrees.
TEST(CalibUniversal, DefaultsLeaveWobblingGyroscopesOut) {
  std::mt19937 gen(36);
  constexpr int kTrials = test::kSanitized ? 4 : 20;
  double ratio = 0.0;
  int checked = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    const UniversalMotion m = randomUniversalMotion(gen);
    RecordingNoise noise{0.01, 0.5 * kDeg, true, true};
    noise.wobble_rate = 1.0;
    const JointSamples s = recordMotion(m, kSamples, kRateHz, noise, gen);
    const UniversalFit fit = fitUniversal(s);
    SCOPED_TRACE(trial);
    EXPECT_EQ(fit.summary.data, "orientations");
    EXPECT_NE(fit.low_pass_reason.find("reads the orientations alone"), std::string::npos) << fit.low_pass_reason;
    const double e[2] = {lineErrorDeg(fit.axis1_main, m.axis1_main), lineErrorDeg(fit.axis2_secondary, m.axis2_secondary)};
    const double sigma[2] = {fit.sigma1_deg, fit.sigma2_deg};
    for (int a = 0; a < 2; ++a) {
      EXPECT_LE(e[a], 3.5 * sigma[a]) << a;
      ratio += e[a] * e[a] / (sigma[a] * sigma[a]) / 2.0;
    }
    checked += fit.model_check.ran && !fit.model_check.disagree;
    if (trial == 0) {
      AxisFitOptions none;
      none.low_pass_auto = false;
      const UniversalFit raw = fitUniversal(s, none);
      EXPECT_EQ(raw.summary.data, "orientations+gyroscopes");
      EXPECT_EQ(raw.low_pass_reason, "no filter: asked for (`low_pass` none)");
    }
  }
  ratio /= kTrials;
  std::printf("universal, gyroscopes wobbling 1 rad/s, no flag: mean (error/sigma)^2 %.2f, model check agreeing in %d "
              "of %d\n",
              ratio, checked, kTrials);
  // (Statistics over 20 recordings; the sanitized run's 4 only run the code.)
  if (!test::kSanitized) {
    EXPECT_GT(ratio, 0.4);
    EXPECT_LT(ratio, 1.8);
    EXPECT_GE(checked, kTrials - 2);
  }
  // Without a wobble the gyroscopes stay in, saying why.
  const UniversalFit plain =
      fitUniversal(recordMotion(randomUniversalMotion(gen), kSamples, kRateHz, RecordingNoise{0.01, 0.5 * kDeg, true, true}, gen));
  EXPECT_EQ(plain.summary.data, "orientations+gyroscopes");
  EXPECT_NE(plain.low_pass_reason.find("no gyroscope wobbles"), std::string::npos) << plain.low_pass_reason;
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

namespace lieflow {
namespace calibration {
namespace {

struct BiasTally {
  int answered = 0, covered[2] = {0, 0}, bias_covered[2] = {0, 0}, offset_covered = 0;
  double axis_ratio[2] = {0.0, 0.0}, bias_ratio[2] = {0.0, 0.0}, offset_ratio = 0.0, offset_error = 0.0;
};

/// Universal-joint recordings (gyroscopes 0.01 rad/s, orientations 0.2°,
/// 1000 samples at 100 Hz) whose gyroscopes carry biases N(0, 0.05²) per axis.
/// With `offset`, the secondary sensor's clock is also off by δ uniform in ±offset [s].
BiasTally universalBiasTrials(bool fit_bias, int trials, double bias = 0.05, double offset = 0.0,
                              bool fit_offset = false, bool check_segments = true) {
  std::mt19937 gen(77);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  BiasTally t;
  for (int i = 0; i < trials; ++i) {
    const UniversalMotion m = randomUniversalMotion(gen);
    RecordingNoise n{0.01, 0.2 * kDeg, true, true};
    n.gyro_bias_main = bias * Eigen::Vector3d(normal(gen), normal(gen), normal(gen));
    n.gyro_bias_secondary = bias * Eigen::Vector3d(normal(gen), normal(gen), normal(gen));
    n.secondary_clock_offset = offset * uniform(gen);
    AxisFitOptions o;
    o.fit_gyro_bias = fit_bias;
    o.fit_time_offset = fit_offset;
    o.check_segments = check_segments;
    try {
      const UniversalFit f = fitUniversal(recordMotion(m, kSamples, kRateHz, n, gen), o);
      ++t.answered;
      const double e[2] = {lineErrorDeg(f.axis1_main, m.axis1_main), lineErrorDeg(f.axis2_secondary, m.axis2_secondary)};
      const double s[2] = {f.sigma1_deg, f.sigma2_deg};
      for (int a = 0; a < 2; ++a) {
        t.covered[a] += e[a] <= 3.0 * s[a];
        t.axis_ratio[a] += (e[a] / s[a]) * (e[a] / s[a]) / trials;
      }
      if (fit_offset) {
        const double e = f.time_offset - n.secondary_clock_offset;
        t.offset_covered += std::abs(e) <= 3.0 * f.time_offset_sigma;
        t.offset_ratio += (e / f.time_offset_sigma) * (e / f.time_offset_sigma) / trials;
        t.offset_error = std::max(t.offset_error, std::abs(e));
      }
      if (fit_bias) {
        const double be[2] = {(f.gyro_bias_main - test::perpendicular(n.gyro_bias_main, m.axis1_main)).norm(),
                              (f.gyro_bias_secondary - test::perpendicular(n.gyro_bias_secondary, m.axis2_secondary))
                                  .norm()};
        const double bs[2] = {f.gyro_bias_main_sigma, f.gyro_bias_secondary_sigma};
        for (int a = 0; a < 2; ++a) {
          t.bias_covered[a] += be[a] <= 3.0 * bs[a];
          t.bias_ratio[a] += (be[a] / bs[a]) * (be[a] / bs[a]) / trials;
        }
      }
    } catch (const NotIdentifiable&) {
    }
  }
  std::printf("universal, biases %.2f rad/s, offsets within %.3f s, fitted %d%d: answered %d/%d, axes within 3 sigma "
              "%d %d, mean (e/s)^2 %.2f %.2f; biases within 3 sigma %d %d, mean (e/s)^2 %.2f %.2f; offset within 3 "
              "sigma %d, mean (e/s)^2 %.2f, largest error %.2e s\n",
              bias, offset, fit_bias, fit_offset, t.answered, trials, t.covered[0], t.covered[1], t.axis_ratio[0],
              t.axis_ratio[1], t.bias_covered[0], t.bias_covered[1], t.bias_ratio[0], t.bias_ratio[1],
              t.offset_covered, t.offset_ratio, t.offset_error);
  return t;
}

TEST(CalibUniversal, GyroscopeBiasesFitted) {
  constexpr int kTrials = test::kSanitized ? 10 : 50;
  const BiasTally plain = test::kSanitized ? BiasTally() : universalBiasTrials(false, kTrials, 0.05, 0.0, false, false);
  // (The check's tally repeats the plain one with four more fits each: not under the sanitizers.)
  const BiasTally checked = test::kSanitized ? BiasTally() : universalBiasTrials(false, kTrials);
  const BiasTally fitted = universalBiasTrials(true, kTrials);
  EXPECT_EQ(fitted.answered, kTrials);
  for (int a = 0; a < 2; ++a) {
    EXPECT_GE(fitted.covered[a], kTrials - 2);
    EXPECT_GT(fitted.axis_ratio[a], test::kSanitized ? 0.3 : 0.5);
    EXPECT_LT(fitted.axis_ratio[a], test::kSanitized ? 2.5 : 1.6);
    EXPECT_GE(fitted.bias_covered[a], kTrials - 2);
    EXPECT_LT(fitted.bias_ratio[a], test::kSanitized ? 2.5 : 1.6);
  }
  // Unmodelled, the biases leave σ too small by about 1.6 (measured: mean
  // (error/σ)² 2.67 / 2.88 without the check); the default check across the
  // quarters sees them disagree and widens σ by their spread (measured:
  // 1.03 / 1.25, 50 and 48 of 50 within 3σ).
  if (!test::kSanitized) {
    EXPECT_GT(plain.axis_ratio[0] + plain.axis_ratio[1], 2.0 * 1.6);
    for (int a = 0; a < 2; ++a) {
      EXPECT_GE(checked.covered[a], kTrials - 3);
      EXPECT_LT(checked.axis_ratio[a], 1.6);
    }
  }
}

/// The secondary sensor's clock off by up to ±50 ms (±5 samples), without biases.
TEST(CalibUniversal, ClockOffsetFitted) {
  constexpr int kTrials = test::kSanitized ? 10 : 50;
  const BiasTally plain =
      test::kSanitized ? BiasTally() : universalBiasTrials(false, kTrials, 0.0, 0.05, false, false);
  const BiasTally checked = test::kSanitized ? BiasTally() : universalBiasTrials(false, kTrials, 0.0, 0.05, false);
  const BiasTally fitted = universalBiasTrials(false, kTrials, 0.0, 0.05, true);
  EXPECT_EQ(fitted.answered, kTrials);
  for (int a = 0; a < 2; ++a) {
    EXPECT_GE(fitted.covered[a], kTrials - 2);
    EXPECT_LT(fitted.axis_ratio[a], test::kSanitized ? 2.5 : 1.6);
  }
  EXPECT_GE(fitted.offset_covered, kTrials - 3);
  EXPECT_GT(fitted.offset_ratio, test::kSanitized ? 0.3 : 0.5);
  EXPECT_LT(fitted.offset_ratio, test::kSanitized ? 2.5 : 1.6);
  // Unmodelled, the offset leaves the axes tens of σ off (measured: 77 / 85
  // without the check); the default check across the quarters widens σ to
  // cover them (measured: 50 of 50 within 3σ, mean (error/σ)² 0.18 / 0.20).
  if (!test::kSanitized) {
    EXPECT_GT(plain.axis_ratio[0] + plain.axis_ratio[1], 2.0 * 10.0);
    for (int a = 0; a < 2; ++a) {
      EXPECT_GE(checked.covered[a], kTrials - 3);
      EXPECT_LT(checked.axis_ratio[a], 1.6);
    }
  }
  // Biases and the offset together.
  const BiasTally both = universalBiasTrials(true, kTrials, 0.05, 0.05, true);
  EXPECT_EQ(both.answered, kTrials);
  for (int a = 0; a < 2; ++a) {
    EXPECT_GE(both.covered[a], kTrials - 2);
    EXPECT_LT(both.axis_ratio[a], test::kSanitized ? 2.5 : 1.6);
    EXPECT_LT(both.bias_ratio[a], test::kSanitized ? 2.5 : 1.6);
  }
  EXPECT_GE(both.offset_covered, kTrials - 3);
  EXPECT_LT(both.offset_ratio, test::kSanitized ? 2.5 : 1.6);
}

}  // namespace
}  // namespace calibration
}  // namespace lieflow
