/// \file
/// The hinge fit on a real recording: two 5 s windows of a walking right knee
/// (thigh and shank IMUs at 100 Hz, qmt's full-body example data, MIT;
/// tests/data/qmt/README.md). The windows are of the same joint with the same
/// sensors, so honest answers must agree within max(3°, 3σ) (σ of the
/// difference: both windows' σ in quadrature).
///
/// Measured: gyroscopes alone refuse both windows (the weakest direction draws
/// < 1 times as much information from the motion as from the noise); with the
/// accelerometers both answer, thigh axes 4.1° apart and shank axes 7.1° apart
/// with σ 2.4–3.0°, and the fit says the hinge model does not describe the
/// data (gyroscope residual 6–8 times the sensors' noise from third
/// differences: converged = false, exit 1 on the command line).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "calibration/hinge_fit.hpp"
#include "calibration/recording.hpp"
#include "calibration/wobble_check.hpp"
#include "calibration_test_helpers.hpp"

namespace lieflow {
namespace calibration {
namespace {

JointSamples window(const std::string& start) {
  return selectJoint(
      readRecording(std::string(LIEFLOW_SOURCE_DIR) + "/tests/data/qmt/right_knee_walking_" + start + "s.csv"),
      "thigh", "shank");
}

/// The fits without a filter (`--low-pass none`): the wobble check's default
/// filters these windows (CalibRealKnee.DefaultsFilterTheWobbleByThemselves).
AxisFitOptions unfiltered() {
  AxisFitOptions o;
  o.low_pass_auto = false;
  return o;
}

TEST(CalibRealKnee, GyroscopesAloneRefuseWalkingWindows) {
  AxisFitOptions gyro = unfiltered();
  gyro.use = DataUse::kAngularVelocities;
  for (const char* start : {"95", "100"}) {
    SCOPED_TRACE(start);
    EXPECT_THROW(fitHinge(window(start), gyro), NotIdentifiable);
  }
}

TEST(CalibRealKnee, WithAccelerometersWindowsAgreeAndTheMisfitIsSaid) {
  const HingeFit a = fitHinge(window("95"), unfiltered()), b = fitHinge(window("100"), unfiltered());
  for (const HingeFit* f : {&a, &b}) {
    EXPECT_EQ(f->summary.data, "gyroscopes+accelerometers");
    EXPECT_FALSE(f->summary.converged);
    EXPECT_GT(f->summary.residuals.front().residual_to_noise, 2.0);
    EXPECT_NE(f->summary.message.find("does not describe the data"), std::string::npos) << f->summary.message;
  }
  const double main_apart = angleBetweenLines(a.axis_main, b.axis_main) * kRadToDeg;
  const double secondary_apart = angleBetweenLines(a.axis_secondary, b.axis_secondary) * kRadToDeg;
  const double main_bound = std::max(3.0, 3.0 * std::hypot(a.sigma_main_deg, b.sigma_main_deg));
  const double secondary_bound = std::max(3.0, 3.0 * std::hypot(a.sigma_secondary_deg, b.sigma_secondary_deg));
  EXPECT_LT(main_apart, main_bound);
  EXPECT_LT(secondary_apart, secondary_bound);
  testing::Test::RecordProperty("thigh_axes_apart_deg", std::to_string(main_apart));
  testing::Test::RecordProperty("shank_axes_apart_deg", std::to_string(secondary_apart));
  std::printf("thigh axes %.2f deg apart (bound %.2f), shank %.2f deg (bound %.2f)\n", main_apart, main_bound,
              secondary_apart, secondary_bound);
}

/// Two 25 s walking windows of the same knee (t = 90–115 s and 115–140 s).
JointSamples quarter(const std::string& start) {
  return selectJoint(readRecording(std::string(LIEFLOW_SOURCE_DIR) + "/tests/data/qmt/right_knee_walking_" + start +
                                   "s_25s.csv"),
                     "thigh", "shank");
}

/// The thigh gyroscope's x axis (along the segment) carries ±5–10 rad/s at
/// 7–50 Hz while walking: without a filter the fit reads that wobble as the
/// hinge (the thigh axis within 10° of x) and says the model does not fit;
/// low-passed at 4 Hz both windows answer, agree within max(3°, 3σ), and put
/// the thigh axis near z, 10–12° from the axis the thigh turned about when the
/// subject stood up (the gyroscopes integrated over t = 56–87 s: ±(0.02, 0.33, 0.94)).
TEST(CalibRealKnee, LowPassedWalkingWindowsAgree) {
  AxisFitOptions raw = unfiltered();
  AxisFitOptions filtered;
  filtered.low_pass_hz = 4.0;
  const Eigen::Vector3d stood_up(0.025, 0.328, 0.944);
  HingeFit fits[2];
  int i = 0;
  for (const char* start : {"90", "115"}) {
    SCOPED_TRACE(start);
    const HingeFit plain = fitHinge(quarter(start), raw);
    EXPECT_FALSE(plain.summary.converged);
    EXPECT_LT(angleBetweenLines(plain.axis_main, Eigen::Vector3d::UnitX()) * kRadToDeg, 15.0);
    const HingeFit f = fitHinge(quarter(start), filtered);
    EXPECT_TRUE(f.summary.converged) << f.summary.message;
    EXPECT_EQ(f.summary.data, "gyroscopes+accelerometers");
    EXPECT_EQ(f.low_pass_hz, 4.0);
    // The hinge leaves half of the perpendicular rates unexplained; the accelerometers fit better.
    EXPECT_GT(f.gyro_misfit, 0.3);
    EXPECT_LT(f.accelerometer_misfit, f.gyro_misfit);
    EXPECT_LT(angleBetweenLines(f.axis_main, stood_up) * kRadToDeg, 20.0);
    std::printf("window %s s: thigh axis %.3f %.3f %.3f (sigma %.2f deg), shank %.3f %.3f %.3f (sigma %.2f deg), "
                "%s, gyro misfit %.2f, accelerometer misfit %.2f\n",
                start, f.axis_main.x(), f.axis_main.y(), f.axis_main.z(), f.sigma_main_deg, f.axis_secondary.x(),
                f.axis_secondary.y(), f.axis_secondary.z(), f.sigma_secondary_deg, f.summary.sigma_method.c_str(),
                f.gyro_misfit, f.accelerometer_misfit);
    fits[i++] = f;
  }
  const double main_apart = angleBetweenLines(fits[0].axis_main, fits[1].axis_main) * kRadToDeg;
  const double secondary_apart = angleBetweenLines(fits[0].axis_secondary, fits[1].axis_secondary) * kRadToDeg;
  EXPECT_LT(main_apart, std::max(3.0, 3.0 * std::hypot(fits[0].sigma_main_deg, fits[1].sigma_main_deg)));
  EXPECT_LT(secondary_apart, std::max(3.0, 3.0 * std::hypot(fits[0].sigma_secondary_deg, fits[1].sigma_secondary_deg)));
  std::printf("low-passed walking windows: thigh axes %.2f deg apart, shank %.2f deg\n", main_apart, secondary_apart);
}

/// No flag (issue 31): the wobble check finds the thigh gyroscope's wobble
/// (its power above 7 Hz 14-21 times its white noise's) and low-passes at
/// 4 Hz by itself, saying so. Measured: the two 25 s windows and the second
/// 5 s window answer and agree within max(3 deg, 3 sigma) (thigh axes within
/// 2.5 deg); the first 5 s window finds two valleys (not identifiable), where
/// without the filter all four used to say the hinge does not fit (exit 1).
TEST(CalibRealKnee, DefaultsFilterTheWobbleByThemselves) {
  std::vector<HingeFit> fits;
  const std::vector<JointSamples> windows = {window("95"), window("100"), quarter("90"), quarter("115")};
  for (const JointSamples& w : windows) {
    try {
      const HingeFit f = fitHinge(w, AxisFitOptions());
      EXPECT_EQ(f.low_pass_hz, kWobbleCutoffHz);
      EXPECT_NE(f.low_pass_reason.find("wobbles on soft tissue"), std::string::npos) << f.low_pass_reason;
      EXPECT_TRUE(f.summary.converged) << f.summary.message;
      EXPECT_EQ(f.estimator, HingeEstimator::kConstraint);
      fits.push_back(f);
    } catch (const NotIdentifiable& e) {
      std::printf("window of %s: not identifiable (%s)\n", w.source.c_str(), e.what());
    }
  }
  EXPECT_GE(fits.size(), 3u);
  for (std::size_t i = 0; i < fits.size(); ++i)
    for (std::size_t j = i + 1; j < fits.size(); ++j) {
      const double apart = angleBetweenLines(fits[i].axis_main, fits[j].axis_main) * kRadToDeg;
      EXPECT_LT(apart, std::max(3.0, 3.0 * std::hypot(fits[i].sigma_main_deg, fits[j].sigma_main_deg)));
      const double apart2 = angleBetweenLines(fits[i].axis_secondary, fits[j].axis_secondary) * kRadToDeg;
      EXPECT_LT(apart2, std::max(3.0, 3.0 * std::hypot(fits[i].sigma_secondary_deg, fits[j].sigma_secondary_deg)));
      std::printf("defaults: windows %zu and %zu: thigh axes %.2f deg apart, shank %.2f deg\n", i, j, apart, apart2);
    }
}

/// The four windows as four recordings of one knee (`calibrate hinge A.csv
/// B.csv ...`), no flag: one axis pair from all, whose σ is below every
/// window's own, and the check across the recordings (each fitted alone)
/// finds those that answer within their σ of it. Measured: thigh σ 1.39°,
/// shank 0.96°; the first 5 s window, not identifiable alone (two valleys),
/// is resolved by the others; the three that answer alone lie 0.5–1.6° from
/// the joint axes, χ² 0.34 times its mean.
TEST(CalibRealKnee, FourWindowsAsFourRecordingsOfOneKnee) {
  const std::vector<JointSamples> windows = {window("95"), window("100"), quarter("90"), quarter("115")};
  const HingeFit f = fitHinge(windows, AxisFitOptions());
  EXPECT_TRUE(f.summary.converged) << f.summary.message;
  EXPECT_EQ(f.low_pass_hz, kWobbleCutoffHz);
  ASSERT_EQ(f.model_check.segments.size(), windows.size());
  EXPECT_TRUE(f.model_check.ran) << f.model_check.note;
  EXPECT_FALSE(f.model_check.disagree) << f.model_check.note;
  int answered = 0;
  for (const SegmentFit& s : f.model_check.segments) {
    EXPECT_FALSE(s.source.empty());
    if (!s.answered) continue;
    ++answered;
    EXPECT_LT(f.sigma_main_deg, s.sigma_main) << s.source;
    EXPECT_LT(f.sigma_secondary_deg, s.sigma_secondary) << s.source;
    EXPECT_LT(s.apart_main, std::max(3.0, 3.0 * s.sigma_main)) << s.source;
    EXPECT_LT(s.apart_secondary, std::max(3.0, 3.0 * s.sigma_secondary)) << s.source;
  }
  EXPECT_GE(answered, 3);
  std::printf("four windows as recordings: thigh %.3f %.3f %.3f (sigma %.2f deg), shank %.3f %.3f %.3f (sigma %.2f "
              "deg); %s\n",
              f.axis_main.x(), f.axis_main.y(), f.axis_main.z(), f.sigma_main_deg, f.axis_secondary.x(),
              f.axis_secondary.y(), f.axis_secondary.z(), f.sigma_secondary_deg, f.model_check.note.c_str());
}

}  // namespace
}  // namespace calibration
}  // namespace lieflow
