/// \file
/// The hinge fit against the truth of analytic joint motions
/// (calibration/synthetic_motion.hpp): the accuracy targets from
/// gyroscopes (1000 samples at 100 Hz: ≤ 0.1° at σ = 0.01 rad/s, ≤ 0.5° at
/// σ = 0.1 rad/s, from any start), orientations and both, the exactness of the
/// closed-form starts, the sign conventions and the robust loss; short
/// recordings whose closed-form starts lie in the basin of a wrong minimum
/// (the global search), the check of the residual against the gyroscopes'
/// own noise, and that noise estimate.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>

#include "calibration/hinge_fit.hpp"
#include "calibration/hinge_residuals.hpp"
#include "calibration/residual_kind.hpp"
#include "calibration/universal_fit.hpp"
#include "calibration/universal_residuals.hpp"
#include "liegroup/so3.hpp"
#include "calibration/hinge_initial.hpp"
#include "calibration/hinge_search.hpp"
#include "calibration/hinge_sign.hpp"
#include "calibration/data_selection.hpp"
#include "calibration/recording.hpp"
#include "calibration/synthetic_motion.hpp"
#include "calibration_test_helpers.hpp"

namespace lieflow {
namespace calibration {
namespace {

using test::errorDeg;
using test::lineErrorDeg;
using test::simulatedJoint;

constexpr int kSamples = 1000;
constexpr double kRateHz = 100.0;

/// This file tests Seel's constraint fit (the likelihood fit, the default on
/// gyroscopes alone: hinge_likelihood_test.cpp).
HingeFit fitSeel(const JointSamples& s, AxisFitOptions options = AxisFitOptions()) {
  if (options.estimator == HingeEstimator::kAuto) options.estimator = HingeEstimator::kConstraint;
  return fitHinge(s, options);
}
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

/// A closed-form Jacobian (`evaluate`, what the fits use) against Ceres'
/// automatic derivative of the same functor at `trials` random axes of any
/// length (Ceres differentiates the ambient function before the manifold).
template <typename Functor, int kResiduals, typename Make>
void expectClosedFormMatchesJets(Make make, const char* name) {
  std::mt19937 gen(5);
  std::normal_distribution<double> normal;
  const auto random = [&] { return Eigen::Vector3d(normal(gen), normal(gen), normal(gen)); };
  const double weight = 1.7;
  for (int i = 0; i < 200; ++i) {
    Functor f = make(random);
    f.weight = &weight;
    const Eigen::Vector3d j1 = random(), j2 = random();
    const double* parameters[2] = {j1.data(), j2.data()};
    double r_auto[kResiduals], r_closed[kResiduals], d_auto[2][3 * kResiduals], d_closed[2][3 * kResiduals];
    double* jac_auto[2] = {d_auto[0], d_auto[1]};
    double* jac_closed[2] = {d_closed[0], d_closed[1]};
    ceres::AutoDiffCostFunction<Functor, kResiduals, 3, 3> automatic(new Functor(f));
    ASSERT_TRUE(automatic.Evaluate(parameters, r_auto, jac_auto));
    ClosedFormSampleCost<Functor, kResiduals> closed(f);
    ASSERT_TRUE(closed.Evaluate(parameters, r_closed, jac_closed));
    for (int k = 0; k < kResiduals; ++k) {
      const double scale = std::abs(r_auto[k]) + 1.0;
      EXPECT_NEAR(r_closed[k], r_auto[k], 1e-13 * scale) << name;
      for (int b = 0; b < 2; ++b)
        for (int c = 0; c < 3; ++c)
          EXPECT_NEAR(d_closed[b][3 * k + c], d_auto[b][3 * k + c], 1e-12 * scale) << name << " " << i << " " << b << c;
    }
  }
}

TEST(CalibHinge, ClosedFormJacobiansMatchJets) {
  const auto rotation = [](const Eigen::Vector3d& v) { return SO3d::exp(v).matrix(); };
  expectClosedFormMatchesJets<GyroHingeResidual, 1>(
      [](auto random) { return GyroHingeResidual(3.0 * random(), 3.0 * random()); }, "gyroscope hinge");
  expectClosedFormMatchesJets<AccelerometerHingeResidual, 1>(
      [](auto random) { return AccelerometerHingeResidual(9.0 * random(), 9.0 * random()); }, "accelerometer hinge");
  expectClosedFormMatchesJets<OrientationHingeResidual, 3>(
      [&](auto random) { return OrientationHingeResidual(rotation(random())); }, "orientation hinge");
  expectClosedFormMatchesJets<OrientationUniversalResidual, 1>(
      [&](auto random) { return OrientationUniversalResidual(rotation(random())); }, "orientation universal");
  expectClosedFormMatchesJets<RelativeRateUniversalResidual, 1>(
      [&](auto random) {
        RelativeRateUniversalResidual f(rotation(random()), 3.0 * random());
        f.scale = 0.7;
        return f;
      },
      "relative rate universal");
}

TEST(CalibHinge, GyroscopesLowNoiseWithinATenthOfADegree) {
  for (unsigned seed : {1u, 2u, 3u}) {
    std::mt19937 gen(seed);
    const HingeMotion m = randomHingeMotion(gen);
    const HingeFit fit = fitSeel(recordMotion(m, kSamples, kRateHz, gyroscopes(0.01), gen));
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
    const HingeFit fit = fitSeel(recordMotion(m, kSamples, kRateHz, gyroscopes(0.1), gen));
    SCOPED_TRACE(seed);
    expectHinge(fit, m, 0.5);
    EXPECT_NEAR(fit.summary.rms_residual, 0.1, 0.02);
  }
}

TEST(CalibHinge, AnyStartGivesTheSameAnswer) {
  std::mt19937 gen(7);
  const HingeMotion m = randomHingeMotion(gen);
  const JointSamples samples = recordMotion(m, 500, kRateHz, gyroscopes(0.1), gen);
  const HingeFit reference = fitSeel(samples);
  std::normal_distribution<double> normal;
  for (int trial = 0; trial < 8; ++trial) {
    AxisFitOptions options;
    options.extra_starts.push_back({Eigen::Vector3d(normal(gen), normal(gen), normal(gen)),
                                    Eigen::Vector3d(normal(gen), normal(gen), normal(gen))});
    const HingeFit fit = fitSeel(samples, options);
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
  const HingeFit fit = fitSeel(recordMotion(m, kSamples, kRateHz, orientations(0.5 * kDeg), gen));
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
      fitSeel(recordMotion(m, kSamples, kRateHz, RecordingNoise{0.01, 0.5 * kDeg, true, true}, gen));
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
  EXPECT_EQ(fitSeel(samples, options).summary.data, "gyroscopes");
  options.use = DataUse::kOrientations;
  EXPECT_EQ(fitSeel(samples, options).summary.data, "orientations");
  JointSamples gyro_only = samples;
  gyro_only.main.orientation.clear();
  EXPECT_THROW(fitSeel(gyro_only, options), InvalidInput);  // orientations asked for, main has none
  gyro_only.secondary.angular_velocity.clear();
  EXPECT_THROW(fitSeel(gyro_only), InvalidInput);  // nothing usable
}

TEST(CalibHinge, ReportedSignsFollowTheConvention) {
  for (unsigned seed : {12u, 13u, 14u, 15u}) {
    std::mt19937 gen(seed);
    const HingeMotion m = randomHingeMotion(gen);
    const HingeFit fit = fitSeel(recordMotion(m, 500, kRateHz, gyroscopes(0.01), gen));
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
  const HingeFit plain = fitSeel(samples);
  EXPECT_GT(lineErrorDeg(plain.axis_main, m.axis_main), 0.3);  // the outliers do hurt
  for (RobustLoss loss : {RobustLoss::kHuber, RobustLoss::kCauchy}) {
    AxisFitOptions options;
    options.loss = loss;
    const HingeFit fit = fitSeel(samples, options);
    SCOPED_TRACE(robustLossName(loss));
    expectHinge(fit, m, 0.1);
  }
}

/// Half a second (50 samples at 100 Hz) of random motions whose closed-form
/// starts all lie in the basin of a minimum 50–74° from the truth, which the
/// fit used to report as converged with σ of 0.4–3° (12–170 σ off); the grid
/// starts of the global search (hinge_search.hpp) reach the global minimum.
TEST(CalibHinge, ShortRecordingsEndInTheGlobalMinimum) {
  for (unsigned seed : {101u, 105u, 109u, 125u}) {
    SCOPED_TRACE(seed);
    std::mt19937 gen(seed);
    const HingeMotion m = randomHingeMotion(gen);
    const JointSamples s = recordMotion(m, 50, kRateHz, gyroscopes(0.01), gen);
    const HingeFit fit = fitSeel(s);
    EXPECT_TRUE(fit.summary.converged) << fit.summary.message;
    // No lower minimum around the truth: the fit's cost is at most the true axes'.
    const auto& w1 = s.main.angular_velocity;
    const auto& w2 = s.secondary.angular_velocity;
    EXPECT_LE(hingeRateCost(w1, w2, {fit.axis_main, fit.axis_secondary}),
              hingeRateCost(w1, w2, {m.axis_main, m.axisSecondary()}));
    EXPECT_LE(lineErrorDeg(fit.axis_main, m.axis_main), std::min(2.0, 3.0 * fit.sigma_main_deg));
    EXPECT_LE(lineErrorDeg(fit.axis_secondary, m.axisSecondary()), std::min(2.0, 3.0 * fit.sigma_secondary_deg));
    EXPECT_GT(fit.summary.search_starts, kGridStarts);  // the closed form(s) and the grid
  }
}

/// The reproduction study's failure (papers/hinge-axis-identification,
/// Table 5): 2 s of the `hinge-pair` scene at 100 Hz, σ = 0.01 rad/s, seeds
/// 9006, 9010, 9017. Its closed-form start and near-null alternatives all end
/// in a minimum 13° (main) and 5.4° (secondary) off, with an RMS residual of
/// 0.031 rad/s, reported as converged with σ ≈ 0.3°; from the true axes the
/// same data give 0.01 rad/s and < 0.23°.
TEST(CalibHinge, TwoSecondsOfHingePairEndInTheGlobalMinimum) {
  const Eigen::Vector3d j1 = Eigen::Vector3d(0.0, 0.6, 0.8);
  // j₂ = R₂ᵀR₁ j₁ at t = 0: the lower body starts turned 0.6 rad about x.
  const Eigen::Vector3d j2 = Eigen::AngleAxisd(-0.6, Eigen::Vector3d::UnitX()) * j1;
  for (int seed : {9006, 9010, 9017}) {
    SCOPED_TRACE(seed);
    const JointSamples s =
        simulatedJoint("hinge-pair --every 10 --t-end 1.99 --noise-gyro 0.01 --seed " + std::to_string(seed));
    ASSERT_EQ(s.size(), 200);
    AxisFitOptions options;
    options.use = DataUse::kAngularVelocities;
    const HingeFit fit = fitSeel(s, options);
    EXPECT_TRUE(fit.summary.converged) << fit.summary.message;
    EXPECT_LE(lineErrorDeg(fit.axis_main, j1), std::min(0.5, 3.0 * fit.sigma_main_deg));
    EXPECT_LE(lineErrorDeg(fit.axis_secondary, j2), std::min(0.5, 3.0 * fit.sigma_secondary_deg));
    EXPECT_NEAR(fit.summary.rms_residual, 0.01, 0.002);
    EXPECT_NEAR(fit.summary.residuals.front().residual_to_noise, 1.0, 0.3);
    EXPECT_LE(hingeRateCost(s.main.angular_velocity, s.secondary.angular_velocity, {fit.axis_main, fit.axis_secondary}),
              hingeRateCost(s.main.angular_velocity, s.secondary.angular_velocity, {j1, j2}));
  }
}

/// A residual far above the noise the gyroscopes show by themselves is no
/// confident answer: here the model is wrong (a bias of 0.05 rad/s per axis
/// on one gyroscope), the residual 5 times the noise.
TEST(CalibHinge, ResidualFarAboveTheGyroscopeNoiseIsNotConverged) {
  std::mt19937 gen(18);
  const HingeMotion m = randomHingeMotion(gen);
  JointSamples s = recordMotion(m, kSamples, kRateHz, gyroscopes(0.01), gen);
  const HingeFit honest = fitSeel(s);
  EXPECT_TRUE(honest.summary.converged);
  EXPECT_NEAR(honest.summary.residuals.front().independent_noise, 0.01, 0.0007);
  EXPECT_NEAR(honest.summary.residuals.front().residual_to_noise, 1.0, 0.1);
  for (Eigen::Vector3d& w : s.secondary.angular_velocity) w += Eigen::Vector3d(0.05, -0.05, 0.025);
  // The residual check alone (the bias check, next test, would name the cause).
  AxisFitOptions residual_only;
  residual_only.check_gyro_bias = false;
  const HingeFit biased = fitSeel(s, residual_only);
  EXPECT_FALSE(biased.summary.converged);
  EXPECT_GT(biased.summary.residuals.front().residual_to_noise, 4.0);
  EXPECT_NE(biased.summary.message.find("times the noise estimated independently"), std::string::npos)
      << biased.summary.message;
  AxisFitOptions off = residual_only;
  off.max_residual_to_noise = 0.0;
  EXPECT_TRUE(fitSeel(s, off).summary.converged);
}

/// The bias check (AxisFitOptions::check_gyro_bias): the same biased
/// recording is called biased, with the advice to fit the biases; over 50
/// random recordings with biases N(0, 0.05²) per axis at least 45 are (the
/// plain fit's axes were within 3σ in only 13 and 17 of 50,
/// gyro_nuisance_test.cpp), and over 50 without a bias at most 1.
TEST(CalibHinge, BiasCheckNamesTheBias) {
  std::mt19937 gen(18);
  const HingeMotion m = randomHingeMotion(gen);
  JointSamples s = recordMotion(m, kSamples, kRateHz, gyroscopes(0.01), gen);
  EXPECT_LT(fitSeel(s).summary.bias_check_delta_chi_square, 30.0);
  for (Eigen::Vector3d& w : s.secondary.angular_velocity) w += Eigen::Vector3d(0.05, -0.05, 0.025);
  const HingeFit biased = fitSeel(s);
  EXPECT_FALSE(biased.summary.converged);
  EXPECT_NE(biased.summary.message.find("`fit_gyro_bias`"), std::string::npos) << biased.summary.message;
  std::normal_distribution<double> normal;
  int flagged_biased = 0, flagged_clean = 0;
  for (int t = 0; t < 50; ++t) {
    const HingeMotion motion = randomHingeMotion(gen);
    RecordingNoise n = gyroscopes(0.01);
    const JointSamples clean = recordMotion(motion, kSamples, kRateHz, n, gen);
    n.gyro_bias_main = 0.05 * Eigen::Vector3d(normal(gen), normal(gen), normal(gen));
    n.gyro_bias_secondary = 0.05 * Eigen::Vector3d(normal(gen), normal(gen), normal(gen));
    const JointSamples dirty = recordMotion(motion, kSamples, kRateHz, n, gen);
    flagged_clean += fitSeel(clean).summary.bias_check_delta_chi_square > 30.0;
    flagged_biased += fitSeel(dirty).summary.bias_check_delta_chi_square > 30.0;
  }
  std::printf("bias check: %d of 50 biased recordings flagged, %d of 50 clean\n", flagged_biased, flagged_clean);
  EXPECT_GE(flagged_biased, 45);
  EXPECT_LE(flagged_clean, 1);
}

/// The gyroscopes' white noise from third differences of their own signals:
/// the motion (rates of 3–9 rad/s at 0.3–0.9 Hz, sampled at 100 Hz) adds
/// 1e-4 rad/s; the median form's own scatter is ±5 % for 1000 samples, and
/// 0.5 % of outliers shift it by ~1 %.
TEST(CalibHinge, GyroscopeNoiseFromThirdDifferences) {
  std::mt19937 gen(19);
  const HingeMotion m = randomHingeMotion(gen);
  const JointSamples exact = recordMotion(m, kSamples, kRateHz, RecordingNoise{0.0, 0.0, false, true}, gen);
  EXPECT_LT(whiteNoiseFromDifferences(exact.main.angular_velocity), 2e-4);
  EXPECT_LT(whiteNoiseFromDifferences(exact.secondary.angular_velocity), 2e-4);
  for (double sigma : {0.01, 0.1}) {
    SCOPED_TRACE(sigma);
    JointSamples s = recordMotion(m, kSamples, kRateHz, gyroscopes(sigma), gen);
    for (int k = 0; k < kSamples; k += 200) s.main.angular_velocity[k] += Eigen::Vector3d(3.0, -2.0, 5.0);
    EXPECT_NEAR(whiteNoiseFromDifferences(s.main.angular_velocity), sigma, 0.1 * sigma);
    EXPECT_NEAR(whiteNoiseFromDifferences(s.secondary.angular_velocity), sigma, 0.1 * sigma);
  }
  EXPECT_EQ(whiteNoiseFromDifferences({Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones()}), 0.0);
}

/// `seconds` is the wall time of the whole fit: the model check's segment
/// fits and the clock-offset profile included. (It counted only the final
/// solve: 4.0 ms of an 11.5 ms default fit, 3.4 ms of a 42 ms fit with a
/// clock offset.) Against a clock around the call: between half of it and
/// all of it, whatever the machine's speed.
TEST(CalibHinge, SecondsAreTheWholeFits) {
  std::mt19937 gen(17);
  const HingeMotion m = randomHingeMotion(gen);
  const JointSamples s = recordMotion(m, kSamples, kRateHz, gyroscopes(0.01), gen);
  AxisFitOptions with_offset;
  with_offset.fit_time_offset = true;
  for (const AxisFitOptions& o : {AxisFitOptions(), with_offset}) {
    const auto start = std::chrono::steady_clock::now();
    const HingeFit f = fitHinge(s, o);
    const double outside = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_LE(f.summary.seconds, outside);
    EXPECT_GE(f.summary.seconds, 0.5 * outside) << "offset " << o.fit_time_offset;
  }
  const UniversalMotion u = randomUniversalMotion(gen);
  const JointSamples us = recordMotion(u, kSamples, kRateHz, RecordingNoise{0.01, 0.005, true, true}, gen);
  const auto start = std::chrono::steady_clock::now();
  const UniversalFit f = fitUniversal(us, AxisFitOptions());
  const double outside = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LE(f.summary.seconds, outside);
  EXPECT_GE(f.summary.seconds, 0.5 * outside);
}

}  // namespace
}  // namespace calibration
}  // namespace lieflow
