/// \file
/// The likelihood hinge fit and the Cramér–Rao bound (hinge_likelihood.hpp)
/// on synthetic recordings (synthetic_motion.hpp), the bound computed at the
/// true motion.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "calibration/hinge_fit.hpp"
#include "calibration/hinge_likelihood.hpp"
#include "calibration/synthetic_motion.hpp"
#include "calibration_test_helpers.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {
namespace calibration {
namespace {

using test::lineErrorDeg;


constexpr int kSamples = test::kSanitized ? 300 : 1000;

/// 50 random hinge recordings, gyroscopes σ = 0.1 rad/s, 10 s at 100 Hz:
/// the likelihood fit's σ is the Cramér–Rao bound of the recording (computed
/// at the true motion) within 10 % on every one, it is honest, and its axes
/// are within 0.5° in ≥ 95 % (measured: 50 of 50; σ/bound 0.959–1.033; mean
/// (error/σ)² 0.92 / 0.89), where the constraint fit reaches 0.5° in 45 of 50
/// with σ 1.52 times the bound on average.
TEST(CalibHingeLikelihood, AtTheCramerRaoBoundAndHonest) {
  std::mt19937 gen(3);
  int within_half = 0, constraint_half = 0, answered = 0, covered[2] = {0, 0};
  double ratio[2] = {0.0, 0.0}, efficiency_min = 1e9, efficiency_max = 0.0, constraint_excess = 0.0;
  for (int trial = 0; trial < 50; ++trial) {
    const HingeMotion m = randomHingeMotion(gen);
    const JointSamples s = recordMotion(m, kSamples, 100.0, test::gyroscopeNoise(0.1), gen);
    AxisFitOptions o;
    o.estimator = HingeEstimator::kLikelihood;
    o.check_segments = false;  // the fit's own σ against the bound (the check's: DefaultsReach...)
    HingeFit f;
    try {
      f = fitHinge(s, o);
    } catch (const NotIdentifiable&) {
      continue;
    }
    ++answered;
    const HingeBound bound = hingeCramerRao(hingeTruth(m, kSamples, 100.0), 0.1);
    const double error[2] = {lineErrorDeg(f.axis_main, m.axis_main), lineErrorDeg(f.axis_secondary, m.axisSecondary())};
    const double sigma[2] = {f.sigma_main_deg, f.sigma_secondary_deg};
    const double crb[2] = {bound.sigma_main_deg, bound.sigma_secondary_deg};
    const double constraint[2] = {f.constraint_sigma_main_deg, f.constraint_sigma_secondary_deg};
    for (int a = 0; a < 2; ++a) {
      covered[a] += error[a] <= 3.0 * sigma[a];
      ratio[a] += error[a] * error[a] / (sigma[a] * sigma[a]);
      efficiency_min = std::min(efficiency_min, sigma[a] / crb[a]);
      efficiency_max = std::max(efficiency_max, sigma[a] / crb[a]);
      constraint_excess += constraint[a] / crb[a] / 2.0;
      EXPECT_NEAR(sigma[a] / crb[a], 1.0, 0.1) << "trial " << trial << " axis " << a;
    }
    within_half += std::max(error[0], error[1]) <= 0.5;
    AxisFitOptions c;
    c.estimator = HingeEstimator::kConstraint;
    const HingeFit plain = fitHinge(s, c);
    constraint_half += std::max(lineErrorDeg(plain.axis_main, m.axis_main),
                                lineErrorDeg(plain.axis_secondary, m.axisSecondary())) <= 0.5;
  }
  ASSERT_GE(answered, 48);
  for (int a = 0; a < 2; ++a) {
    ratio[a] /= answered;
    EXPECT_GE(covered[a], answered - 2);
    EXPECT_GT(ratio[a], 0.5);
    EXPECT_LT(ratio[a], 1.6);
  }
  if (!test::kSanitized) {
    EXPECT_GE(within_half, answered * 95 / 100) << within_half << " of " << answered;
  }
  std::printf("likelihood: %d of %d within 0.5 deg (constraint %d); sigma/bound %.3f..%.3f (constraint %.2f on "
              "average); mean (error/sigma)^2 %.2f / %.2f\n",
              within_half, answered, constraint_half, efficiency_min, efficiency_max, constraint_excess / answered,
              ratio[0], ratio[1]);
}

/// Issue 31's targets with the defaults only (AxisFitOptions() is the
/// command's `calibrate hinge REC.csv`): 50 random gyroscope recordings of
/// 1000 samples at 0.01 and at 0.1 rad/s get the likelihood fit, mean
/// (error/sigma)^2 in 0.7-1.5, and their axes within 0.1 and 0.5 degrees on
/// all but at most one per level — measured: 50 of 50 at 0.01 rad/s (worst
/// 0.090 deg), 47 of 48 answered at 0.1 rad/s (worst 0.593 deg, on a weakly
/// exciting motion whose sigma says 0.888 deg: 0.67 sigma; 2 of 50 refused
/// as not identifiable) — and any miss within 3 sigma.
TEST(CalibHingeLikelihood, DefaultsReachTheTargetsAndHonest) {
  for (const double noise : {0.01, 0.1}) {
    std::mt19937 gen(noise < 0.05 ? 31 : 32);
    const double bound = noise < 0.05 ? 0.1 : 0.5;
    int answered = 0, within = 0;
    double ratio = 0.0, worst = 0.0;
    for (int trial = 0; trial < 50; ++trial) {
      const HingeMotion m = randomHingeMotion(gen);
      const JointSamples s = recordMotion(m, kSamples, 100.0, test::gyroscopeNoise(noise), gen);
      HingeFit f;
      try {
        f = fitHinge(s, AxisFitOptions());
      } catch (const NotIdentifiable&) {
        continue;
      }
      ++answered;
      EXPECT_EQ(f.estimator, HingeEstimator::kLikelihood) << f.estimator_reason;
      const double e[2] = {lineErrorDeg(f.axis_main, m.axis_main), lineErrorDeg(f.axis_secondary, m.axisSecondary())};
      const double sigma[2] = {f.sigma_main_deg, f.sigma_secondary_deg};
      for (int a = 0; a < 2; ++a) ratio += e[a] * e[a] / (sigma[a] * sigma[a]) / 2.0;
      within += std::max(e[0], e[1]) <= bound;
      worst = std::max({worst, e[0], e[1]});
      for (int a = 0; a < 2; ++a)
        if (e[a] > bound) {
          EXPECT_LE(e[a], 3.0 * sigma[a]) << "noise " << noise << " trial " << trial << " axis " << a;
          std::printf("defaults at %g rad/s: trial %d axis %d off by %.3f deg, sigma %.3f deg\n", noise, trial, a, e[a],
                      sigma[a]);
        }
    }
    ASSERT_GE(answered, 48) << noise;
    ratio /= answered;
    if (!test::kSanitized) {
      EXPECT_GE(within, answered - 1) << "noise " << noise << ": worst axis " << worst << " deg";
      EXPECT_GT(ratio, 0.7) << noise;
      EXPECT_LT(ratio, 1.5) << noise;
    }
    std::printf("defaults at %g rad/s: %d of %d within %g deg (worst %.3f deg), mean (error/sigma)^2 %.2f\n", noise,
                within, answered, bound, worst, ratio);
  }
}

/// Exact data: the likelihood fit lands on the axes (to the five-point
/// difference's truncation) and the relative sign from the joint angle.
TEST(CalibHingeLikelihood, ExactData) {
  std::mt19937 gen(4);
  const HingeMotion m = randomHingeMotion(gen);
  RecordingNoise noise;
  noise.orientations = false;
  const JointSamples s = recordMotion(m, 500, 100.0, noise, gen);
  AxisFitOptions o;
  o.estimator = HingeEstimator::kLikelihood;
  const HingeFit f = fitHinge(s, o);
  EXPECT_LT(lineErrorDeg(f.axis_main, m.axis_main), 1e-4);
  EXPECT_LT(lineErrorDeg(f.axis_secondary, m.axisSecondary()), 1e-4);
  EXPECT_LT(std::abs(test::errorDeg(f.axis_secondary, m.axisSecondary()) - test::errorDeg(f.axis_main, m.axis_main)),
            1e-3);
  EXPECT_TRUE(f.summary.converged) << f.summary.message;
}

TEST(CalibHingeLikelihood, RefusedWithOtherData) {
  std::mt19937 gen(5);
  const HingeMotion m = randomHingeMotion(gen);
  const JointSamples s = recordMotion(m, 200, 100.0, RecordingNoise{0.01, 0.01, true, true}, gen);
  AxisFitOptions o;
  o.estimator = HingeEstimator::kLikelihood;
  o.use = DataUse::kBoth;
  EXPECT_THROW(fitHinge(s, o), InvalidInput);
  o.use = DataUse::kAuto;
  EXPECT_EQ(fitHinge(s, o).summary.data, "gyroscopes");
  o.use = DataUse::kBoth;
  o.fit_time_offset = true;
  EXPECT_THROW(fitHinge(s, o), InvalidInput);
}

/// How honest a quantity's σ is over the recordings: within 3σ, and the mean
/// of (error/σ)².
struct Honesty {
  int covered = 0, count = 0;
  double ratio_sum = 0.0;
  void add(double error, double sigma) {
    covered += std::abs(error) <= 3.0 * sigma;
    ratio_sum += error * error / (sigma * sigma);
    ++count;
  }
  double ratio() const { return ratio_sum / count; }
  /// At most `misses` outside 3σ, and (with enough recordings) the mean
  /// (error/σ)² in (0.5, ratio_bound).
  void expect(const char* what, int misses, double ratio_bound) const {
    EXPECT_GE(covered, count - misses) << what;
    if (!test::kSanitized) {
      EXPECT_GT(ratio(), 0.5) << what;
      EXPECT_LT(ratio(), ratio_bound) << what;
    }
  }
};

/// Random hinge recordings (σ = 0.1 rad/s, 10 s at 100 Hz; 50, 10 under the
/// sanitizers) with nuisance set by `disturb(gen, &noise)`, fitted by the
/// likelihood fit with `options` and judged by `judge(fit, motion, noise)`;
/// the axes' honesty is tallied here. Returns how many were answered.
template <typename Disturb, typename Judge>
int likelihoodTrials(unsigned seed, const AxisFitOptions& options, Disturb disturb, Judge judge, Honesty axes[2]) {
  const int trials = test::kSanitized ? 10 : 50;
  std::mt19937 gen(seed);
  int answered = 0;
  for (int trial = 0; trial < trials; ++trial) {
    const HingeMotion m = randomHingeMotion(gen);
    RecordingNoise noise = test::gyroscopeNoise(0.1);
    disturb(gen, &noise);
    const JointSamples s = recordMotion(m, kSamples, 100.0, noise, gen);
    HingeFit f;
    try {
      f = fitHinge(s, options);
    } catch (const NotIdentifiable&) {
      continue;
    }
    ++answered;
    axes[0].add(lineErrorDeg(f.axis_main, m.axis_main), f.sigma_main_deg);
    axes[1].add(lineErrorDeg(f.axis_secondary, m.axisSecondary()), f.sigma_secondary_deg);
    judge(f, m, noise, s);
  }
  EXPECT_GE(answered, trials - 2);
  return answered;
}

/// A clock offset between the sensors as an unknown of the likelihood fit
/// (--fit-time-offset): the secondary sensor runs up to ±50 ms off; the whole
/// samples nearest the constraint fit's estimate (moved while the
/// likelihood's fraction exceeds half a sample), the fraction and its σ from
/// the likelihood. Measured: axes 50 / 50 within 3σ, mean (error/σ)² 1.43 /
/// 1.13; the offset 49 of 50 within 3σ, mean (error/σ)² 1.43 (refined at the
/// constraint profile's shift, which can be a sample from its own estimate,
/// 47 and 1.79).
TEST(CalibHingeLikelihood, ClockOffsetAsUnknown) {
  AxisFitOptions o;
  o.estimator = HingeEstimator::kLikelihood;
  o.fit_time_offset = true;
  std::uniform_real_distribution<double> uniform(-0.05, 0.05);
  Honesty axes[2], offset;
  double sigma_sum = 0.0;
  const int answered = likelihoodTrials(
      9, o, [&](std::mt19937& gen, RecordingNoise* noise) { noise->secondary_clock_offset = uniform(gen); },
      [&](const HingeFit& f, const HingeMotion&, const RecordingNoise& noise, const JointSamples&) {
        ASSERT_TRUE(f.likelihood.fitted_time_offset);
        offset.add(f.time_offset - noise.secondary_clock_offset, f.time_offset_sigma);
        sigma_sum += f.time_offset_sigma;
      },
      axes);
  axes[0].expect("axis main", 2, 1.6);
  axes[1].expect("axis secondary", 2, 1.6);
  offset.expect("offset", 2, 1.8);
  std::printf("likelihood with a clock offset: %d answered, axes within 3 sigma %d / %d, mean (error/sigma)^2 "
              "%.2f / %.2f; offset within 3 sigma %d, mean (error/sigma)^2 %.2f, mean sigma %.3g ms\n",
              answered, axes[0].covered, axes[1].covered, axes[0].ratio(), axes[1].ratio(), offset.covered,
              offset.ratio(), 1e3 * sigma_sum / answered);
}

/// Gyroscope biases as unknowns of the likelihood fit (--fit-gyro-bias):
/// biases N(0, 0.05²) per axis (an uncalibrated MEMS gyroscope). The axes and
/// the observable biases (the secondary's perpendicular to its axis, the main
/// one's perpendicular part and the difference along the axis) within 3σ,
/// mean (error/σ)² near 1; without the biases the same recordings' axes are
/// not (printed).
TEST(CalibHingeLikelihood, GyroscopeBiasesAsUnknowns) {
  AxisFitOptions o;
  o.estimator = HingeEstimator::kLikelihood;
  o.fit_gyro_bias = true;
  AxisFitOptions plain;
  plain.estimator = HingeEstimator::kLikelihood;
  plain.check_gyro_bias = false;
  std::normal_distribution<double> normal;
  Honesty axes[2], bias[2];
  int plain_covered = 0, within_half = 0;
  const int answered = likelihoodTrials(
      8, o,
      [&](std::mt19937& gen, RecordingNoise* noise) {
        noise->gyro_bias_main = 0.05 * Eigen::Vector3d(normal(gen), normal(gen), normal(gen));
        noise->gyro_bias_secondary = 0.05 * Eigen::Vector3d(normal(gen), normal(gen), normal(gen));
      },
      [&](const HingeFit& f, const HingeMotion& m, const RecordingNoise& noise, const JointSamples& s) {
        ASSERT_TRUE(f.likelihood.fitted_gyro_bias);
        // Along the axis only the difference is observable (hinge_likelihood.hpp).
        const Eigen::Vector3d j1 = m.axis_main.normalized(), j2 = m.axisSecondary().normalized();
        const Eigen::Vector3d main_truth = test::perpendicular(noise.gyro_bias_main, j1) +
                                           (noise.gyro_bias_main.dot(j1) - noise.gyro_bias_secondary.dot(j2)) * j1;
        bias[0].add((f.gyro_bias_main - main_truth).norm(), f.gyro_bias_main_sigma);
        bias[1].add((f.gyro_bias_secondary - test::perpendicular(noise.gyro_bias_secondary, j2)).norm(),
                    f.gyro_bias_secondary_sigma);
        within_half += std::max(lineErrorDeg(f.axis_main, m.axis_main),
                                lineErrorDeg(f.axis_secondary, m.axisSecondary())) <= 0.5;
        try {
          const HingeFit g = fitHinge(s, plain);
          plain_covered += lineErrorDeg(g.axis_main, m.axis_main) <= 3.0 * g.sigma_main_deg &&
                           lineErrorDeg(g.axis_secondary, m.axisSecondary()) <= 3.0 * g.sigma_secondary_deg;
        } catch (const NotIdentifiable&) {
        }
      },
      axes);
  axes[0].expect("axis main", 2, 1.6);
  axes[1].expect("axis secondary", 2, 1.6);
  bias[0].expect("bias main", 2, 1.6);
  bias[1].expect("bias secondary", 2, 1.6);
  std::printf("likelihood with biases: %d answered, axes within 3 sigma %d / %d, mean (error/sigma)^2 %.2f / %.2f, "
              "within 0.5 deg %d; biases within 3 sigma %d / %d, mean (error/sigma)^2 %.2f / %.2f; without the "
              "biases both axes within 3 sigma in %d\n",
              answered, axes[0].covered, axes[1].covered, axes[0].ratio(), axes[1].ratio(), within_half,
              bias[0].covered, bias[1].covered, bias[0].ratio(), bias[1].ratio(), plain_covered);
}

}  // namespace
}  // namespace calibration
}  // namespace lieflow
