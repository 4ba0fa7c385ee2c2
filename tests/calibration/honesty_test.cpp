/// \file
/// The reported 1σ is honest: over 50 noisy trials per kind of data (a new
/// motion and new noise each time), the axis error is within 3σ in at least
/// 95 % of them, and the mean of (error/σ)² is near 1 — σ is the RMS angle, so
/// E[error²/σ²] = 1 whatever the shape of the 2×2 covariance; a σ twice too
/// large or too small (e.g. SphereManifold's tangent taken for radians, see
/// calibration/unit_axis.hpp) would give 0.25 or 4.
///
/// Trials of 1000 samples at 100 Hz; 300 under AddressSanitizer (CI's Debug
/// build), which keeps the same 50 trials and tolerances within the time.
///
/// Short recordings (50 and 100 samples) may be refused; the fits that are
/// answered must be as honest. The universal joint of the `universal-pair`
/// scene (rates growing from 1 to 6 rad/s, so the orientation noise that the
/// relative-rate residual carries varies 5-fold from sample to sample) checks
/// the per-sample weights of that residual.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <random>
#include <string>

#include "calibration/hinge_fit.hpp"
#include "calibration/recording.hpp"
#include "calibration/synthetic_motion.hpp"
#include "calibration/universal_fit.hpp"
#include "calibration_test_helpers.hpp"

namespace lieflow {
namespace calibration {
namespace {

using test::lineErrorDeg;
using test::simulatedJoint;

constexpr int kTrials = 50;
constexpr int kSamples = test::kSanitized ? 300 : 1000;
constexpr double kRateHz = 100.0;
constexpr double kDeg = 1.0 / kRadToDeg;

/// Errors and σ of both axes in one trial (degrees).
struct Trial {
  double error[2];
  double sigma[2];
};

/// Over kTrials trials, both axes' errors are within 3σ in all but 2 of the
/// answered ones and the mean (error/σ)² is near 1. A refusal (NotIdentifiable:
/// e.g. two equally good minima on the 300-sample recordings of the sanitizer
/// build) is an honest answer, not an error, but must stay rare (≤ 5).
void expectHonest(const std::string& label, const std::function<Trial(std::mt19937&)>& run, unsigned seed,
                  double max_ratio = 1.6, int max_misses = 2) {
  std::mt19937 gen(seed);
  int covered[2] = {0, 0}, answered = 0, refused = 0;
  double ratio_sq[2] = {0.0, 0.0};
  for (int t = 0; t < kTrials; ++t) {
    Trial trial;
    try {
      trial = run(gen);
    } catch (const NotIdentifiable&) {
      ++refused;
      continue;
    }
    ++answered;
    for (int a = 0; a < 2; ++a) {
      covered[a] += trial.error[a] <= 3.0 * trial.sigma[a];
      ratio_sq[a] += trial.error[a] * trial.error[a] / (trial.sigma[a] * trial.sigma[a]);
    }
  }
  EXPECT_LE(refused, 5) << refused << " of " << kTrials << " trials refused";
  ASSERT_GT(answered, 0);
  for (int a = 0; a < 2; ++a) {
    SCOPED_TRACE(a == 0 ? "axis in the main body" : "axis in the secondary body");
    ratio_sq[a] /= answered;
    EXPECT_GE(covered[a], answered - max_misses) << "errors within 3 sigma in " << covered[a] << " of " << answered
                                        << " answered trials";
    EXPECT_GT(ratio_sq[a], 0.5) << "sigma too large: mean (error/sigma)^2 = " << ratio_sq[a];
    EXPECT_LT(ratio_sq[a], max_ratio) << "sigma too small: mean (error/sigma)^2 = " << ratio_sq[a];
    std::printf("%s axis %d: within 3 sigma %d of %d, mean (error/sigma)^2 %.2f\n", label.c_str(), a, covered[a],
                answered, ratio_sq[a]);
    const std::string key = label + (a == 0 ? "_main" : "_secondary");
    testing::Test::RecordProperty("covered_" + key, covered[a]);
    testing::Test::RecordProperty("refused_" + key, refused);
    testing::Test::RecordProperty("mean_error_over_sigma_squared_" + key, std::to_string(ratio_sq[a]));
  }
}

TEST(CalibHonesty, HingeFromGyroscopes) {
  for (double sigma : {0.01, 0.1}) {
    SCOPED_TRACE(sigma);
    expectHonest(
        sigma < 0.05 ? "gyro_0.01" : "gyro_0.1", [&](std::mt19937& gen) {
          const HingeMotion m = randomHingeMotion(gen);
          const HingeFit f = fitHinge(recordMotion(m, kSamples, kRateHz, RecordingNoise{sigma, 0.0, false, true}, gen));
          return Trial{{lineErrorDeg(f.axis_main, m.axis_main), lineErrorDeg(f.axis_secondary, m.axisSecondary())},
                       {f.sigma_main_deg, f.sigma_secondary_deg}};
        },
        41);
  }
}

/// Under a robust loss σ is the larger of the Gauss–Newton one and the
/// sandwich (two_axis_solver.hpp step 8): honest on white gyroscope noise
/// (0.01 rad/s; mean (error/σ)² 1.01 / 1.07), and nearly so on noise correlated
/// over 0.1 s (AR(1), a = 0.9 per sample at 100 Hz, stationary σ 0.02 rad/s
/// on top of the white 0.01), where the Gauss–Newton σ, which takes the
/// samples as independent, is 3-4 times too small (measured with --loss
/// none: mean (error/σ)² 15.3 / 10.4, within 3σ in 27 and 30 of 48; with
/// the sandwich 2.10 / 1.22, 49 and 50 of 50: its 16 batch sums leave σ
/// somewhat small there, hence the bound 2.5 and at most 4 misses of 3σ).
TEST(CalibHonesty, HingeFromGyroscopesRobustLossSandwich) {
  for (bool correlated : {false, true}) {
    SCOPED_TRACE(correlated ? "correlated noise" : "white noise");
    expectHonest(
        correlated ? "huber_correlated" : "huber_white", [&](std::mt19937& gen) {
          const HingeMotion m = randomHingeMotion(gen);
          // 1000 samples also under the sanitizers: the batches must be long
          // against the noise's correlation (300 samples gave 3.2).
          JointSamples s = recordMotion(m, 1000, kRateHz, RecordingNoise{0.01, 0.0, false, true}, gen);
          if (correlated) {
            std::normal_distribution<double> normal;
            constexpr double a = 0.9, sigma = 0.02;
            const double drive = sigma * std::sqrt(1.0 - a * a);
            for (auto* w : {&s.main.angular_velocity, &s.secondary.angular_velocity}) {
              Eigen::Vector3d e(sigma * normal(gen), sigma * normal(gen), sigma * normal(gen));
              for (Eigen::Vector3d& x : *w) {
                x += e;
                e = a * e + drive * Eigen::Vector3d(normal(gen), normal(gen), normal(gen));
              }
            }
          }
          AxisFitOptions o;
          o.loss = RobustLoss::kHuber;
          o.max_residual_to_noise = 0.0;  // the correlated noise is "misfit" to the third differences
          const HingeFit f = fitHinge(s, o);
          EXPECT_NE(f.summary.sigma_method.find("sandwich"), std::string::npos);
          return Trial{{lineErrorDeg(f.axis_main, m.axis_main), lineErrorDeg(f.axis_secondary, m.axisSecondary())},
                       {f.sigma_main_deg, f.sigma_secondary_deg}};
        },
        correlated ? 47 : 46, correlated ? 2.5 : 1.6, correlated ? 4 : 2);
  }
}

TEST(CalibHonesty, HingeFromOrientations) {
  expectHonest(
      "orientations", [](std::mt19937& gen) {
        const HingeMotion m = randomHingeMotion(gen);
        const HingeFit f =
            fitHinge(recordMotion(m, kSamples, kRateHz, RecordingNoise{0.0, 0.5 * kDeg, true, false}, gen));
        return Trial{{lineErrorDeg(f.axis_main, m.axis_main), lineErrorDeg(f.axis_secondary, m.axisSecondary())},
                     {f.sigma_main_deg, f.sigma_secondary_deg}};
      },
      42);
}

TEST(CalibHonesty, HingeFromBoth) {
  expectHonest(
      "both", [](std::mt19937& gen) {
        const HingeMotion m = randomHingeMotion(gen);
        const HingeFit f =
            fitHinge(recordMotion(m, kSamples, kRateHz, RecordingNoise{0.01, 0.5 * kDeg, true, true}, gen));
        return Trial{{lineErrorDeg(f.axis_main, m.axis_main), lineErrorDeg(f.axis_secondary, m.axisSecondary())},
                     {f.sigma_main_deg, f.sigma_secondary_deg}};
      },
      43);
}

TEST(CalibHonesty, UniversalFromOrientationsAndGyroscopes) {
  expectHonest(
      "universal", [](std::mt19937& gen) {
        const UniversalMotion m = randomUniversalMotion(gen);
        const UniversalFit f =
            fitUniversal(recordMotion(m, kSamples, kRateHz, RecordingNoise{0.01, 0.5 * kDeg, true, true}, gen));
        return Trial{{lineErrorDeg(f.axis1_main, m.axis1_main), lineErrorDeg(f.axis2_secondary, m.axis2_secondary)},
                     {f.sigma1_deg, f.sigma2_deg}};
      },
      44);
}

/// Half a second and one second of gyroscope data (50 and 100 samples at
/// 100 Hz, σ = 0.01 rad/s, a new random motion per trial). The fit used to
/// answer 84 and 98 of 100 such recordings with 39 and 9 of them beyond 3σ
/// (mean (error/σ)² of 1200 and 99): local minima, second minima that fit as
/// well, curved valleys. Now those are found or refused; what is answered
/// holds its σ, and one second is still answered in most trials.
TEST(CalibHonesty, HingeFromGyroscopesShortRecordings) {
  for (int samples : {50, 100}) {
    SCOPED_TRACE(samples);
    std::mt19937 gen(45 + samples);
    int fitted = 0, covered = 0;
    double ratio_sq = 0.0;
    for (int t = 0; t < kTrials; ++t) {
      const HingeMotion m = randomHingeMotion(gen);
      const JointSamples s = recordMotion(m, samples, kRateHz, RecordingNoise{0.01, 0.0, false, true}, gen);
      try {
        const HingeFit f = fitHinge(s);
        const double e1 = lineErrorDeg(f.axis_main, m.axis_main), e2 = lineErrorDeg(f.axis_secondary, m.axisSecondary());
        ++fitted;
        covered += e1 <= 3.0 * f.sigma_main_deg && e2 <= 3.0 * f.sigma_secondary_deg;
        ratio_sq += (e1 * e1 / (f.sigma_main_deg * f.sigma_main_deg) +
                     e2 * e2 / (f.sigma_secondary_deg * f.sigma_secondary_deg)) / 2.0;
      } catch (const NotIdentifiable&) {
      }
    }
    EXPECT_GE(covered, 0.95 * fitted) << covered << " of " << fitted << " fits within 3 sigma";
    EXPECT_GE(fitted, samples == 100 ? 40 : 10) << "answered";
    if (fitted > 0) {
      EXPECT_LT(ratio_sq / fitted, 1.6) << "mean (error/sigma)^2";
    }
    testing::Test::RecordProperty("fitted_" + std::to_string(samples), fitted);
    testing::Test::RecordProperty("covered_" + std::to_string(samples), covered);
  }
}

/// The reproduction study's universal joint (papers/hinge-axis-identification,
/// Table 4): `universal-pair`, a₁ = x in `upper`, a₂ = y in `lower`, gyroscopes
/// σ = 0.01 rad/s and orientations 0.5°, the noise drawn here per trial. With
/// one noise scale for the relative-rate residual, mean (error/σ)² was 2.04
/// (2.60 for a₁) and 3 of 50 fits beyond 3σ.
TEST(CalibHonesty, UniversalPairFromOrientationsAndGyroscopes) {
  const JointSamples exact = simulatedJoint("universal-pair --every 10 --t-end " +
                                              std::to_string((kSamples - 1) / kRateHz));
  ASSERT_EQ(exact.size(), kSamples);
  expectHonest(
      "universal_pair", [&](std::mt19937& gen) {
        std::normal_distribution<double> normal;
        JointSamples s = exact;
        for (BodySamples* b : {&s.main, &s.secondary}) {
          for (Eigen::Vector3d& w : b->angular_velocity) w += 0.01 * Eigen::Vector3d(normal(gen), normal(gen), normal(gen));
          for (SO3d& R : b->orientation)
            R = R * SO3d::exp(0.5 * kDeg * Eigen::Vector3d(normal(gen), normal(gen), normal(gen)));
        }
        const UniversalFit f = fitUniversal(s);
        return Trial{{lineErrorDeg(f.axis1_main, Eigen::Vector3d::UnitX()),
                      lineErrorDeg(f.axis2_secondary, Eigen::Vector3d::UnitY())},
                     {f.sigma1_deg, f.sigma2_deg}};
      },
      46);
}

}  // namespace
}  // namespace calibration
}  // namespace lieflow
