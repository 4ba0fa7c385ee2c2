/// \file
/// Gyroscope biases and a clock offset between the two sensors as nuisance
/// parameters of the hinge fit (AxisFitOptions::fit_gyro_bias,
/// fit_time_offset; GyroHingeNuisanceResidual): synthetic recordings with
/// known biases (0.05 rad/s per axis: an uncalibrated MEMS gyroscope) and
/// clock offsets (3.7 samples).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "calibration/hinge_fit.hpp"
#include "calibration/synthetic_motion.hpp"
#include "calibration/universal_fit.hpp"
#include "calibration_test_helpers.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {
namespace calibration {
namespace {

using test::lineErrorDeg;

/// 10 s at 100 Hz in every build: on 3 s recordings the clock offset's σ is
/// small by up to 1.5 (mean (error/σ)² 1.6–2.3, calibration/README.md). Under
/// the sanitizers 12 trials per case instead of 50, with bounds for 12.
constexpr int kSamples = 1000;
constexpr int kTrials = test::kSanitized ? 12 : 50;
/// Mean (error/σ)² bound: 1.6 for 50 trials; 12 trials scatter it more.
constexpr double kRatioBound = test::kSanitized ? 2.5 : 1.6;
constexpr double kRateHz = 100.0;



struct Outcome {
  double error_deg[2];
  double sigma_deg[2];
  double bias_error[2];
  double bias_sigma[2];
  double offset_error = 0.0, offset_sigma = 0.0;
};

/// One recording of a random hinge motion with the given gyroscope noise,
/// biases and clock offset, fitted with the given nuisance.
Outcome fitOnce(std::mt19937& gen, double sigma, const Eigen::Vector3d& b1, const Eigen::Vector3d& b2, double offset,
                bool fit_bias, bool fit_offset, bool check_segments) {
  const HingeMotion m = randomHingeMotion(gen);
  RecordingNoise n = test::gyroscopeNoise(sigma);
  n.gyro_bias_main = b1;
  n.gyro_bias_secondary = b2;
  n.secondary_clock_offset = offset;
  AxisFitOptions o;
  o.estimator = HingeEstimator::kConstraint;  // the constraint fit's nuisance models (the likelihood's: hinge_likelihood_test.cpp)
  o.fit_gyro_bias = fit_bias;
  o.fit_time_offset = fit_offset;
  o.check_segments = check_segments;
  const HingeFit f = fitHinge(recordMotion(m, kSamples, kRateHz, n, gen), o);
  Outcome out;
  out.error_deg[0] = lineErrorDeg(f.axis_main, m.axis_main);
  out.error_deg[1] = lineErrorDeg(f.axis_secondary, m.axisSecondary());
  out.sigma_deg[0] = f.sigma_main_deg;
  out.sigma_deg[1] = f.sigma_secondary_deg;
  if (fit_bias) {
    out.bias_error[0] = (f.gyro_bias_main - test::perpendicular(b1, m.axis_main)).norm();
    out.bias_error[1] = (f.gyro_bias_secondary - test::perpendicular(b2, m.axisSecondary())).norm();
    out.bias_sigma[0] = f.gyro_bias_main_sigma;
    out.bias_sigma[1] = f.gyro_bias_secondary_sigma;
  }
  if (fit_offset) {
    out.offset_error = f.time_offset - offset;
    out.offset_sigma = f.time_offset_sigma;
  }
  return out;
}

struct Tally {
  int answered = 0, refused = 0, covered[2] = {0, 0};
  double axis_ratio[2] = {0.0, 0.0}, bias_ratio[2] = {0.0, 0.0}, offset_ratio = 0.0;
};

/// kTrials recordings with random biases N(0, bias²) per axis and clock
/// offsets uniform in ±offset (s), fitted with the given nuisance.
/// check_segments: the hinge fit's model check across segments (off: the
/// fit alone, whose σ these tests are about).
Tally run(unsigned seed, double bias, double offset, bool fit_bias, bool fit_offset, int trials = kTrials,
          bool check_segments = false) {
  std::mt19937 gen(seed);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Tally t;
  for (int i = 0; i < trials; ++i) {
    const Eigen::Vector3d b1 = bias * Eigen::Vector3d(normal(gen), normal(gen), normal(gen));
    const Eigen::Vector3d b2 = bias * Eigen::Vector3d(normal(gen), normal(gen), normal(gen));
    const double d = offset * uniform(gen);
    try {
      const Outcome o = fitOnce(gen, 0.01, b1, b2, d, fit_bias, fit_offset, check_segments);
      ++t.answered;
      for (int a = 0; a < 2; ++a) {
        t.covered[a] += o.error_deg[a] <= 3.0 * o.sigma_deg[a];
        t.axis_ratio[a] += std::pow(o.error_deg[a] / o.sigma_deg[a], 2);
        if (fit_bias) t.bias_ratio[a] += std::pow(o.bias_error[a] / o.bias_sigma[a], 2);
      }
      if (fit_offset) t.offset_ratio += std::pow(o.offset_error / o.offset_sigma, 2);
    } catch (const NotIdentifiable&) {
      ++t.refused;
    }
  }
  if (t.answered > 0)
    for (double* x : {&t.axis_ratio[0], &t.axis_ratio[1], &t.bias_ratio[0], &t.bias_ratio[1], &t.offset_ratio})
      *x /= t.answered;
  std::printf("bias %.3f offset %.3f fit %d%d: answered %d refused %d within 3 sigma %d %d, mean (e/s)^2 axes %.2f %.2f "
              "bias %.2f %.2f offset %.2f\n",
              bias, offset, fit_bias, fit_offset, t.answered, t.refused, t.covered[0], t.covered[1], t.axis_ratio[0],
              t.axis_ratio[1], t.bias_ratio[0], t.bias_ratio[1], t.offset_ratio);
  return t;
}

/// An uncalibrated gyroscope's bias (0.05 rad/s per axis) makes the plain fit
/// a confident wrong answer (measured: 13 and 17 of 50 axes within 3σ, mean
/// (error/σ)² 40 / 30, and the residual check does not notice); fitted as a
/// nuisance, the axes are honest again (50 / 50, 1.06 / 1.12) and the biases
/// come out with honest σ (mean (error/σ)² 1.47 / 1.12).
TEST(CalibGyroNuisance, BiasesFitted) {
  const Tally plain = run(1, 0.05, 0.0, false, false);
  EXPECT_LT(plain.covered[0] + plain.covered[1], 6 * kTrials / 5);
  // The default model check across segments sees that the plain fit's
  // segments disagree and widens σ by their spread (measured: 99 of 100
  // axes within 3σ).
  const Tally checked = run(1, 0.05, 0.0, false, false, kTrials, true);
  EXPECT_GE(checked.covered[0] + checked.covered[1], 2 * checked.answered * 9 / 10);
  const Tally t = run(1, 0.05, 0.0, true, false);
  EXPECT_EQ(t.refused, 0);
  for (int a = 0; a < 2; ++a) {
    EXPECT_GE(t.covered[a], t.answered - 2);
    EXPECT_GT(t.axis_ratio[a], test::kSanitized ? 0.3 : 0.5);
    EXPECT_LT(t.axis_ratio[a], kRatioBound);
    EXPECT_GT(t.bias_ratio[a], test::kSanitized ? 0.3 : 0.5);
    EXPECT_LT(t.bias_ratio[a], 2.0);
  }
}

/// A clock offset of up to ±50 ms (±5 samples) between the sensors: plain,
/// 21 and 11 of 50 axes within 3σ (mean (error/σ)² 24 / 46); fitted (whole
/// samples by search and a profile of fits, the fraction by the fit), 50 and
/// 50 (1.16 / 1.23) and the offset's mean (error/σ)² 0.78.
TEST(CalibGyroNuisance, ClockOffsetFitted) {
  const Tally plain = run(2, 0.0, 0.05, false, false);
  EXPECT_LT(plain.covered[0] + plain.covered[1], 6 * kTrials / 5);
  // With the default check across segments (measured: 98 of 100 within 3σ).
  const Tally checked = run(2, 0.0, 0.05, false, false, kTrials, true);
  EXPECT_GE(checked.covered[0] + checked.covered[1], 2 * checked.answered * 9 / 10);
  const Tally t = run(2, 0.0, 0.05, false, true);
  EXPECT_EQ(t.refused, 0);
  for (int a = 0; a < 2; ++a) {
    EXPECT_GE(t.covered[a], t.answered - 2);
    EXPECT_GT(t.axis_ratio[a], test::kSanitized ? 0.3 : 0.5);
    EXPECT_LT(t.axis_ratio[a], kRatioBound);
  }
  EXPECT_GT(t.offset_ratio, test::kSanitized ? 0.2 : 0.4);
  EXPECT_LT(t.offset_ratio, kRatioBound);
}

/// Both at once (biases 0.05 rad/s per axis, offsets ±50 ms): measured axes
/// 50 and 49 within 3σ, mean (error/σ)² 1.30 / 1.32, biases 1.26 / 1.34, the
/// offset 0.67.
TEST(CalibGyroNuisance, BiasesAndClockOffsetTogether) {
  const Tally t = run(3, 0.05, 0.05, true, true);
  EXPECT_LE(t.refused, 2);
  for (int a = 0; a < 2; ++a) {
    EXPECT_GE(t.covered[a], t.answered - 2);
    EXPECT_LT(t.axis_ratio[a], kRatioBound);
    EXPECT_LT(t.bias_ratio[a], 2.0);
  }
  EXPECT_LT(t.offset_ratio, kRatioBound);
}

/// Fitting nuisance that is not there costs nothing in honesty (measured 1.41 /
/// 0.89 for the axes, 1.17 / 1.09 for the biases, 1.24 for the offset).
TEST(CalibGyroNuisance, AbsentNuisanceFittedStaysHonest) {
  const Tally t = run(4, 0.0, 0.0, true, true);
  for (int a = 0; a < 2; ++a) {
    EXPECT_GE(t.covered[a], t.answered - 2);
    EXPECT_GT(t.axis_ratio[a], test::kSanitized ? 0.3 : 0.5);
    EXPECT_LT(t.axis_ratio[a], kRatioBound);
    EXPECT_LT(t.bias_ratio[a], kRatioBound);
  }
  EXPECT_LT(t.offset_ratio, kRatioBound);
}

/// Exact data with a bias and an offset: both recovered, to the error of
/// interpolating the rates between samples (cubic: ~1e-4 rad/s on these
/// motions at 100 Hz; measured bias errors 5.4e-4 and 6.3e-4 rad/s).
TEST(CalibGyroNuisance, ExactData) {
  std::mt19937 gen(9);
  const Eigen::Vector3d b1(0.03, -0.02, 0.05), b2(-0.04, 0.01, 0.02);
  const Outcome o = fitOnce(gen, 0.0, b1, b2, 0.0237, true, true, false);
  EXPECT_LT(o.error_deg[0], 0.05);
  EXPECT_LT(o.error_deg[1], 0.05);
  EXPECT_LT(o.bias_error[0], 1.5e-3);
  EXPECT_LT(o.bias_error[1], 1.5e-3);
  EXPECT_LT(std::abs(o.offset_error), 5e-5);
}

/// Exact orientations beside biased, noisy gyroscopes (`lieflow simulate`
/// without --noise-quat writes them): the orientations' weight sits at the
/// noise floor, 1e20 above the biases' information. The covariance is judged
/// on the Jacobi-scaled information, so the fit answers, with the exact axes
/// (it had been refused as "rank deficient"), and with the gyroscopes alone
/// the biases are still found within 3.5σ.
TEST(CalibGyroNuisance, BiasesBesideExactOrientations) {
  std::mt19937 gen(13);
  const HingeMotion m = randomHingeMotion(gen);
  RecordingNoise n = test::gyroscopeNoise(0.02);
  n.orientations = true;
  n.orientation_sigma = 0.0;
  n.gyro_bias_main = Eigen::Vector3d(0.03, -0.02, 0.05);
  n.gyro_bias_secondary = Eigen::Vector3d(-0.04, 0.01, 0.02);
  const JointSamples s = recordMotion(m, kSamples, kRateHz, n, gen);
  AxisFitOptions o;
  o.fit_gyro_bias = true;
  o.use = DataUse::kBoth;
  const HingeFit f = fitHinge(s, o);
  EXPECT_LT(lineErrorDeg(f.axis_main, m.axis_main), 1e-9);
  EXPECT_LT(lineErrorDeg(f.axis_secondary, m.axisSecondary()), 1e-9);
  ASSERT_TRUE(f.fitted_gyro_bias);
  EXPECT_LT((f.gyro_bias_main - test::perpendicular(n.gyro_bias_main, m.axis_main)).norm(),
            3.5 * f.gyro_bias_main_sigma);
  EXPECT_LT((f.gyro_bias_secondary - test::perpendicular(n.gyro_bias_secondary, m.axisSecondary())).norm(),
            3.5 * f.gyro_bias_secondary_sigma);
}

/// Half a second (50 samples) of exact orientations and noisy gyroscopes
/// (0.05 rad/s), the biases asked for (their truth 0): the gyroscopes'
/// constraint sees a bias only through the rates' changing direction, which
/// half a second barely turns, and the cost can fall lower in a narrow valley
/// tenths of rad/s from the truth whose curvature claims a σ of hundredths
/// (0.8 rad/s at σ 0.03). The check of step 7b (two_axis_solver.hpp) refuses
/// most of those: of 100 such fits, 22 answered more than 4σ from the truth
/// without it (up to 47σ), 8 with it (up to 10σ; calibration/README.md says
/// so). Measured here: at most 12 of 100 beyond 4σ.
TEST(CalibGyroNuisance, ShortRecordingsFarFromTheirBiasesAreRefused) {
  std::mt19937 gen(29);
  int answered = 0, refused = 0, beyond = 0;
  for (int trial = 0; trial < 100; ++trial) {
    const HingeMotion m = randomHingeMotion(gen);
    RecordingNoise n = test::gyroscopeNoise(0.05);
    n.orientations = true;
    n.orientation_sigma = 0.0;
    const JointSamples s = recordMotion(m, 50, kRateHz, n, gen);
    AxisFitOptions o;
    o.fit_gyro_bias = true;
    o.use = DataUse::kBoth;
    try {
      const HingeFit f = fitHinge(s, o);
      ++answered;
      EXPECT_LT(lineErrorDeg(f.axis_main, m.axis_main), 1e-6);
      if (f.gyro_bias_main.norm() > 4.0 * f.gyro_bias_main_sigma ||
          f.gyro_bias_secondary.norm() > 4.0 * f.gyro_bias_secondary_sigma)
        ++beyond;
    } catch (const NotIdentifiable&) {
      ++refused;
    }
  }
  std::printf("50 samples, biases asked for: %d answered (%d beyond 4 sigma), %d refused\n", answered, beyond,
              refused);
  EXPECT_LE(beyond, 12);
  EXPECT_GE(answered, 50);
}

/// A recording too short for its own biases beside a long one is refused,
/// naming it (it answered 0.8 rad/s at σ 0.03 for a truth of 0).
TEST(CalibGyroNuisance, ARecordingTooShortForItsOwnBiasesIsNamed) {
  std::mt19937 gen(31);
  const HingeMotion m = randomHingeMotion(gen);
  std::vector<JointSamples> runs = {recordMotion(m, kSamples, kRateHz, test::gyroscopeNoise(0.02), gen),
                                    recordMotion(m, 11, kRateHz, test::gyroscopeNoise(0.02), gen)};
  runs[0].source = "long.csv";
  runs[1].source = "brief.csv";
  AxisFitOptions o;
  o.fit_gyro_bias = true;
  try {
    fitHinge(runs, o);
    ADD_FAILURE() << "an 11-sample recording's own biases were answered";
  } catch (const NotIdentifiable& e) {
    EXPECT_NE(std::string(e.what()).find("brief.csv: 11 samples"), std::string::npos) << e.what();
  }
  o.fit_gyro_bias = false;
  o.fit_time_offset = true;
  EXPECT_THROW(fitHinge(runs, o), NotIdentifiable);
}

TEST(CalibGyroNuisance, RefusedWhereItCannotApply) {
  std::mt19937 gen(10);
  const HingeMotion m = randomHingeMotion(gen);
  const JointSamples both = recordMotion(m, 200, kRateHz, RecordingNoise{0.01, 0.01, true, true}, gen);
  AxisFitOptions o;
  o.fit_time_offset = true;
  o.use = DataUse::kOrientations;
  EXPECT_THROW(fitHinge(both, o), InvalidInput);
  o.use = DataUse::kBoth;
  EXPECT_THROW(fitHinge(both, o), InvalidInput);
  o.use = DataUse::kAuto;  // auto: the gyroscopes alone
  EXPECT_EQ(fitHinge(both, o).summary.data, "gyroscopes");
  AxisFitOptions u;
  u.use = DataUse::kOrientations;  // biases and offsets need the gyroscopes in the fit
  u.fit_gyro_bias = true;
  EXPECT_THROW(fitUniversal(both, u), InvalidInput);
  u.fit_gyro_bias = false;
  u.fit_time_offset = true;
  EXPECT_THROW(fitUniversal(both, u), InvalidInput);
  JointSamples uneven = recordMotion(m, 200, kRateHz, RecordingNoise{0.01, 0.0, false, true}, gen);
  uneven.time[100] += 0.003;
  AxisFitOptions t;
  t.fit_time_offset = true;
  EXPECT_THROW(fitHinge(uneven, t), InvalidInput);
}

}  // namespace
}  // namespace calibration
}  // namespace lieflow
