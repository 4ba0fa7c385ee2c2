/// \file
/// One hinge's axes from several recordings (`calibrate hinge A.csv B.csv`,
/// fitHinge's recordings overload): each recording keeps its own time series
/// and noise, they share the axes; the model check fits each alone.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "calibration/hinge_fit.hpp"
#include "calibration/synthetic_motion.hpp"
#include "calibration/unit_axis.hpp"
#include "calibration_test_helpers.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {
namespace calibration {
namespace {

using test::lineErrorDeg;

constexpr int kSamples = test::kSanitized ? 300 : 1000;

JointSamples named(JointSamples s, const std::string& source) {
  s.source = source;
  return s;
}

/// Two recordings of one hinge fitted together: the axes within 3σ of the
/// truth, σ below each recording's own (the information adds), the model
/// check over the two recordings run and agreeing; over 20 pairs at
/// 0.1 rad/s the mean (error/σ)² is near 1 (σ honest across recordings).
TEST(CalibHingeRecordings, TwoRecordingsOfOneHingeShareItsAxes) {
  std::mt19937 gen(71);
  const int pairs = test::kSanitized ? 3 : 20;
  double ratio = 0.0;
  int answered = 0;
  for (int trial = 0; trial < pairs; ++trial) {
    const HingeMotion m = randomHingeMotion(gen);
    const HingeMotion m2 = test::sameHingeOtherMotion(m, gen);
    const std::vector<JointSamples> recordings = {
        named(recordMotion(m, kSamples, 100.0, test::gyroscopeNoise(0.1), gen), "a.csv"),
        named(recordMotion(m2, kSamples / 2, 50.0, test::gyroscopeNoise(0.1), gen), "b.csv")};
    HingeFit both, alone[2];
    try {
      both = fitHinge(recordings, AxisFitOptions());
      for (int r = 0; r < 2; ++r) alone[r] = fitHinge(recordings[r], AxisFitOptions());
    } catch (const NotIdentifiable&) {
      continue;
    }
    ++answered;
    EXPECT_EQ(both.estimator, HingeEstimator::kLikelihood) << both.estimator_reason;
    EXPECT_EQ(both.summary.samples, kSamples + kSamples / 2);
    const double e[2] = {lineErrorDeg(both.axis_main, m.axis_main), lineErrorDeg(both.axis_secondary, m.axisSecondary())};
    const double sigma[2] = {both.sigma_main_deg, both.sigma_secondary_deg};
    for (int a = 0; a < 2; ++a) {
      EXPECT_LE(e[a], 3.5 * sigma[a]) << "trial " << trial << " axis " << a;
      ratio += e[a] * e[a] / (sigma[a] * sigma[a]) / 2.0;
    }
    if (!both.model_check.disagree) {
      EXPECT_LT(both.sigma_main_deg, std::min(alone[0].sigma_main_deg, alone[1].sigma_main_deg)) << trial;
      EXPECT_LT(both.sigma_secondary_deg, std::min(alone[0].sigma_secondary_deg, alone[1].sigma_secondary_deg))
          << trial;
    }
    ASSERT_EQ(both.model_check.segments.size(), 2u);
    EXPECT_EQ(both.model_check.segments[0].source, "a.csv");
    EXPECT_EQ(both.model_check.segments[1].source, "b.csv");
    EXPECT_TRUE(both.model_check.ran) << both.model_check.note;
  }
  ASSERT_GE(answered, pairs - 1);
  ratio /= answered;
  std::printf("two recordings of one hinge: %d pairs, mean (error/sigma)^2 %.2f\n", answered, ratio);
  if (!test::kSanitized) {
    EXPECT_GT(ratio, 0.5);
    EXPECT_LT(ratio, 1.8);
  }
}

/// One recording cut in two, the second half's clock restarted at 0: the
/// fit over the two halves is the fit of the whole but for the one joint
/// angle link across the cut, so its axes lie within a fifth of σ of the
/// whole's and its σ within 10 %. (A stencil reaching across the cut would
/// read the restarted clock as a jump.)
TEST(CalibHingeRecordings, ARecordingCutInTwoFitsAsTheWhole) {
  std::mt19937 gen(5);
  const HingeMotion m = randomHingeMotion(gen);
  const JointSamples whole = named(recordMotion(m, 2 * kSamples, 100.0, test::gyroscopeNoise(0.1), gen), "whole.csv");
  std::vector<JointSamples> halves(2);
  for (int h = 0; h < 2; ++h) {
    JointSamples& s = halves[h];
    s.source = h == 0 ? "first.csv" : "second.csv";
    const int begin = h * kSamples, end = begin + kSamples;
    for (int k = begin; k < end; ++k) s.time.push_back(whole.time[k] - whole.time[begin]);
    s.main.name = whole.main.name;
    s.secondary.name = whole.secondary.name;
    s.main.angular_velocity.assign(whole.main.angular_velocity.begin() + begin, whole.main.angular_velocity.begin() + end);
    s.secondary.angular_velocity.assign(whole.secondary.angular_velocity.begin() + begin,
                                        whole.secondary.angular_velocity.begin() + end);
  }
  AxisFitOptions o;
  o.check_segments = false;
  const HingeFit w = fitHinge(whole, o), split = fitHinge(halves, o);
  ASSERT_EQ(w.estimator, HingeEstimator::kLikelihood);
  ASSERT_EQ(split.estimator, HingeEstimator::kLikelihood);
  EXPECT_LE(lineErrorDeg(split.axis_main, w.axis_main), 0.2 * w.sigma_main_deg);
  EXPECT_LE(lineErrorDeg(split.axis_secondary, w.axis_secondary), 0.2 * w.sigma_secondary_deg);
  EXPECT_NEAR(split.sigma_main_deg, w.sigma_main_deg, 0.1 * w.sigma_main_deg);
  EXPECT_NEAR(split.sigma_secondary_deg, w.sigma_secondary_deg, 0.1 * w.sigma_secondary_deg);
  // The constraint estimator's residuals are per sample: the same fit but
  // for each half's own noise estimate and weight (measured 0.07 σ apart).
  o.estimator = HingeEstimator::kConstraint;
  const HingeFit wc = fitHinge(whole, o), sc = fitHinge(halves, o);
  EXPECT_LE(lineErrorDeg(sc.axis_main, wc.axis_main), 0.15 * wc.sigma_main_deg);
  EXPECT_LE(lineErrorDeg(sc.axis_secondary, wc.axis_secondary), 0.15 * wc.sigma_secondary_deg);
}

/// Two recordings of two different hinges (the secondary sensor remounted
/// 8° apart): each alone is fitted to a fraction of a degree, so the check
/// across the recordings finds they disagree, reports the spread, and the
/// answer's σ includes it (≥ the half-distance of the two axes, roughly).
TEST(CalibHingeRecordings, RecordingsOfTwoHingesDisagreeAndSigmaSaysSo) {
  std::mt19937 gen(9);
  const HingeMotion m = randomHingeMotion(gen);
  HingeMotion m2 = test::sameHingeOtherMotion(m, gen);
  m2.mount = m.mount * SO3d::exp(8.0 * M_PI / 180.0 * orthogonalUnit(m.axisSecondary()));
  const std::vector<JointSamples> recordings = {
      named(recordMotion(m, kSamples, 100.0, test::gyroscopeNoise(0.01), gen), "a.csv"),
      named(recordMotion(m2, kSamples, 100.0, test::gyroscopeNoise(0.01), gen), "b.csv")};
  const HingeFit f = fitHinge(recordings, AxisFitOptions());
  ASSERT_TRUE(f.model_check.ran) << f.model_check.note;
  EXPECT_TRUE(f.model_check.disagree) << f.model_check.note;
  EXPECT_NE(f.model_check.note.find("all the recordings"), std::string::npos) << f.model_check.note;
  const double apart = lineErrorDeg(m.axisSecondary(), m2.axisSecondary());
  EXPECT_NEAR(apart, 8.0, 1e-9);
  EXPECT_GT(f.model_check.spread_secondary, 0.25 * apart);
  EXPECT_GE(f.sigma_secondary_deg, f.model_check.spread_secondary);
  std::printf("two hinges 8 deg apart: spread %.2f deg, sigma %.2f deg, chi-square %.1f times its mean\n",
              f.model_check.spread_secondary, f.sigma_secondary_deg, f.model_check.chi_square);
}

/// What a fit over several recordings refuses, naming the recording: a
/// clock offset on non-uniform times, other bodies, other columns.
TEST(CalibHingeRecordings, RefusesWhatItCannotFitNamingTheRecording) {
  std::mt19937 gen(3);
  const HingeMotion m = randomHingeMotion(gen);
  RecordingNoise rates = test::gyroscopeNoise(0.05);
  const JointSamples a = named(recordMotion(m, 400, 100.0, rates, gen), "a.csv");
  const JointSamples b = named(recordMotion(m, 400, 100.0, rates, gen), "b.csv");
  // A clock offset needs uniform times in every recording: refused naming the one that has not.
  JointSamples jittered = b;
  jittered.time[200] += 0.004;
  AxisFitOptions offset;
  offset.fit_time_offset = true;
  try {
    fitHinge(std::vector<JointSamples>{a, jittered}, offset);
    FAIL() << "a clock offset on non-uniform times";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("b.csv"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("uniformly sampled"), std::string::npos) << e.what();
  }
  JointSamples renamed = b;
  renamed.secondary.name = "other";
  try {
    fitHinge(std::vector<JointSamples>{a, renamed}, AxisFitOptions());
    FAIL() << "another joint";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("b.csv"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("'other'"), std::string::npos) << e.what();
  }
  RecordingNoise with_orientations = rates;
  with_orientations.orientations = true;
  // The first recording's orientations choose the constraint fit over
  // orientations and gyroscopes: the second has no orientations.
  const JointSamples c = named(recordMotion(m, 400, 100.0, with_orientations, gen), "c.csv");
  try {
    fitHinge(std::vector<JointSamples>{c, a}, AxisFitOptions());
    FAIL() << "other columns";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("a.csv"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("`use`"), std::string::npos) << e.what();
  }
  // The same samples twice (a file given twice, or its copy) would count
  // their information twice: refused, naming both.
  try {
    fitHinge(std::vector<JointSamples>{a, b, named(a, "copy.csv")}, AxisFitOptions());
    FAIL() << "a recording twice";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("copy.csv"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("same samples as a.csv"), std::string::npos) << e.what();
  }
  // With --use gyroscopes the two give the fit the same columns.
  AxisFitOptions gyros;
  gyros.use = DataUse::kAngularVelocities;
  EXPECT_NO_THROW(fitHinge(std::vector<JointSamples>{c, a}, gyros));
}

/// With fit_gyro_bias each recording's gyroscopes have their own biases
/// (a sensor restarted between recordings settles at another bias): pairs
/// of recordings of one hinge at 0.1 rad/s, each with its own biases
/// N(0, 0.05²) per component. The likelihood fit (the default) and the
/// constraint fit each estimate both recordings' biases: the axes and every
/// recording's biases within 3.5σ of the truth, and over 20 pairs the mean
/// (error/σ)² of the axes and the biases near 1. (The likelihood's main
/// bias holds the two biases' difference along the axis, the constraint
/// fit's only what is perpendicular to it: hinge_fit.hpp.)
TEST(CalibHingeRecordings, EachRecordingsBiasesAreItsOwn) {
  std::mt19937 gen(29);
  std::normal_distribution<double> normal;
  const int pairs = test::kSanitized ? 2 : 20;
  const HingeEstimator estimators[2] = {HingeEstimator::kAuto, HingeEstimator::kConstraint};
  double axis_ratio[2] = {0.0, 0.0}, bias_ratio[2] = {0.0, 0.0};
  int answered[2] = {0, 0};
  for (int trial = 0; trial < pairs; ++trial) {
    const HingeMotion m = randomHingeMotion(gen);
    const HingeMotion m2 = test::sameHingeOtherMotion(m, gen);
    RecordingNoise noise[2] = {test::gyroscopeNoise(0.1), test::gyroscopeNoise(0.1)};
    for (RecordingNoise& n : noise) {
      n.gyro_bias_main = 0.05 * Eigen::Vector3d(normal(gen), normal(gen), normal(gen));
      n.gyro_bias_secondary = 0.05 * Eigen::Vector3d(normal(gen), normal(gen), normal(gen));
    }
    const std::vector<JointSamples> recordings = {named(recordMotion(m, kSamples, 100.0, noise[0], gen), "a.csv"),
                                                  named(recordMotion(m2, kSamples, 100.0, noise[1], gen), "b.csv")};
    const Eigen::Vector3d j1 = m.axis_main, j2 = m.axisSecondary();
    for (int e = 0; e < 2; ++e) {
      AxisFitOptions o;
      o.fit_gyro_bias = true;
      o.estimator = estimators[e];
      HingeFit f;
      try {
        f = fitHinge(recordings, o);
      } catch (const NotIdentifiable&) {
        continue;
      }
      ++answered[e];
      const bool likelihood = f.estimator == HingeEstimator::kLikelihood;
      EXPECT_EQ(likelihood, e == 0) << f.estimator_reason;
      ASSERT_EQ(f.recording_nuisance.size(), 2u);
      const double error[2] = {lineErrorDeg(f.axis_main, j1), lineErrorDeg(f.axis_secondary, j2)};
      const double sigma[2] = {f.sigma_main_deg, f.sigma_secondary_deg};
      for (int a = 0; a < 2; ++a) {
        EXPECT_LE(error[a], 3.5 * sigma[a]) << "trial " << trial << " estimator " << e << " axis " << a;
        axis_ratio[e] += error[a] * error[a] / (sigma[a] * sigma[a]) / 2.0;
      }
      for (int r = 0; r < 2; ++r) {
        const SensorNuisanceEstimate& b = f.recording_nuisance[r];
        Eigen::Vector3d main_truth = test::perpendicular(noise[r].gyro_bias_main, j1);
        if (likelihood) main_truth += (noise[r].gyro_bias_main.dot(j1) - noise[r].gyro_bias_secondary.dot(j2)) * j1;
        const double db[2] = {(b.gyro_bias_main - main_truth).norm(),
                              (b.gyro_bias_secondary - test::perpendicular(noise[r].gyro_bias_secondary, j2)).norm()};
        const double sb[2] = {b.gyro_bias_main_sigma, b.gyro_bias_secondary_sigma};
        for (int g = 0; g < 2; ++g) {
          EXPECT_LE(db[g], 3.5 * sb[g]) << "trial " << trial << " estimator " << e << " recording " << r;
          bias_ratio[e] += db[g] * db[g] / (sb[g] * sb[g]) / 4.0;
        }
      }
      EXPECT_EQ(f.gyro_bias_main, f.recording_nuisance[0].gyro_bias_main);
    }
  }
  // Without fit_gyro_bias the bias check runs on each recording and names
  // the one whose gyroscopes carry a bias (here b.csv's secondary, 0.1 rad/s).
  const HingeMotion m = randomHingeMotion(gen);
  RecordingNoise biased = test::gyroscopeNoise(0.01);
  biased.gyro_bias_secondary = Eigen::Vector3d(0.1, -0.05, 0.07);
  const std::vector<JointSamples> one_biased = {
      named(recordMotion(m, kSamples, 100.0, test::gyroscopeNoise(0.01), gen), "a.csv"),
      named(recordMotion(test::sameHingeOtherMotion(m, gen), kSamples, 100.0, biased, gen), "b.csv")};
  const HingeFit plain = fitHinge(one_biased, AxisFitOptions());
  EXPECT_FALSE(plain.summary.converged);
  EXPECT_NE(plain.summary.message.find("gyroscopes of b.csv carry a constant bias"), std::string::npos)
      << plain.summary.message;
  EXPECT_NE(plain.summary.message.find("rerun with `fit_gyro_bias` (each recording's biases its own)"),
            std::string::npos)
      << plain.summary.message;

  for (int e = 0; e < 2; ++e) {
    ASSERT_GE(answered[e], pairs - 1) << e;
    std::printf("each recording's biases, %s: %d of %d pairs answered, mean (error/sigma)^2 axes %.2f, biases %.2f\n",
                e == 0 ? "likelihood" : "constraint", answered[e], pairs, axis_ratio[e] / answered[e],
                bias_ratio[e] / answered[e]);
    if (test::kSanitized) continue;
    EXPECT_GT(axis_ratio[e] / answered[e], 0.5);
    EXPECT_LT(axis_ratio[e] / answered[e], 1.6);
    EXPECT_GT(bias_ratio[e] / answered[e], 0.5);
    EXPECT_LT(bias_ratio[e] / answered[e], 1.6);
  }
}

/// With fit_time_offset each recording's secondary sensor has its own clock
/// offset (a recording session's own synchronisation), uniform in ±50 ms,
/// and with fit_gyro_bias its own biases N(0, 0.05²): pairs of recordings
/// of one hinge at 0.1 rad/s. Each recording's offset comes from its own
/// profile, then one fit over both (the default estimator: the likelihood).
/// The axes and every recording's offset within 3.5σ of the truth; over
/// the pairs the mean (error/σ)² of the axes near 1.
TEST(CalibHingeRecordings, EachRecordingsClockOffsetIsItsOwn) {
  std::mt19937 gen(41);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> uniform(-0.05, 0.05);
  const int pairs = test::kSanitized ? 1 : 12;
  double axis_ratio = 0.0, offset_ratio = 0.0;
  int answered = 0;
  for (int trial = 0; trial < pairs; ++trial) {
    const HingeMotion m = randomHingeMotion(gen);
    const HingeMotion m2 = test::sameHingeOtherMotion(m, gen);
    const bool biases = trial % 2 == 1;
    RecordingNoise noise[2] = {test::gyroscopeNoise(0.1), test::gyroscopeNoise(0.1)};
    for (RecordingNoise& n : noise) {
      n.secondary_clock_offset = uniform(gen);
      if (!biases) continue;
      n.gyro_bias_main = 0.05 * Eigen::Vector3d(normal(gen), normal(gen), normal(gen));
      n.gyro_bias_secondary = 0.05 * Eigen::Vector3d(normal(gen), normal(gen), normal(gen));
    }
    const std::vector<JointSamples> recordings = {named(recordMotion(m, kSamples, 100.0, noise[0], gen), "a.csv"),
                                                  named(recordMotion(m2, kSamples, 100.0, noise[1], gen), "b.csv")};
    AxisFitOptions o;
    o.fit_time_offset = true;
    o.fit_gyro_bias = biases;
    HingeFit f;
    try {
      f = fitHinge(recordings, o);
    } catch (const NotIdentifiable&) {
      continue;
    }
    ++answered;
    EXPECT_EQ(f.estimator, HingeEstimator::kLikelihood) << f.estimator_reason;
    ASSERT_EQ(f.recording_nuisance.size(), 2u);
    const double error[2] = {lineErrorDeg(f.axis_main, m.axis_main), lineErrorDeg(f.axis_secondary, m.axisSecondary())};
    const double sigma[2] = {f.sigma_main_deg, f.sigma_secondary_deg};
    for (int a = 0; a < 2; ++a) {
      EXPECT_LE(error[a], 3.5 * sigma[a]) << "trial " << trial << " axis " << a;
      axis_ratio += error[a] * error[a] / (sigma[a] * sigma[a]) / 2.0;
    }
    for (int r = 0; r < 2; ++r) {
      const SensorNuisanceEstimate& e = f.recording_nuisance[r];
      ASSERT_TRUE(e.fitted_time_offset);
      EXPECT_EQ(e.fitted_gyro_bias, biases);
      const double d = e.time_offset - noise[r].secondary_clock_offset;
      EXPECT_LE(std::abs(d), 3.5 * e.time_offset_sigma) << "trial " << trial << " recording " << r;
      offset_ratio += d * d / (e.time_offset_sigma * e.time_offset_sigma) / 2.0;
    }
  }
  ASSERT_GE(answered, pairs - 1);
  std::printf("each recording's clock offset: %d of %d pairs answered, mean (error/sigma)^2 axes %.2f, offsets %.2f\n",
              answered, pairs, axis_ratio / answered, offset_ratio / answered);
  if (test::kSanitized) return;
  EXPECT_GT(axis_ratio / answered, 0.5);
  EXPECT_LT(axis_ratio / answered, 1.6);
  EXPECT_LT(offset_ratio / answered, 2.5);
}

}  // namespace
}  // namespace calibration
}  // namespace lieflow
