/// \file
/// Shared helpers of the calibration tests: angles between fitted and true
/// axes, recordings written by `lieflow simulate`, and the sanitizer switch
/// for the sample counts of the slow tests.
#pragma once

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>

#include <Eigen/Core>

#include "calibration/recording.hpp"
#include "calibration/synthetic_motion.hpp"
#include "calibration/unit_axis.hpp"

namespace lieflow {
namespace calibration {
namespace test {

/// Angle in degrees between a fitted axis and the true one, up to sign.
inline double lineErrorDeg(const Eigen::Vector3d& fitted, const Eigen::Vector3d& truth) {
  return angleBetweenLines(fitted, truth) * kRadToDeg;
}

/// Angle in degrees between a fitted axis and the true one, sign included.
inline double errorDeg(const Eigen::Vector3d& fitted, const Eigen::Vector3d& truth) {
  return angleBetween(fitted, truth) * kRadToDeg;
}

/// `lieflow simulate ARGS` (with whatever noise ARGS ask for), read back as
/// the joint of the recording's two bodies. The file is named after the
/// running test (ctest runs tests in parallel processes) and removed.
inline JointSamples simulatedJoint(const std::string& args) {
  const testing::TestInfo* info = testing::UnitTest::GetInstance()->current_test_info();
  const std::string file = testing::TempDir() + "lieflow_" + info->test_suite_name() + "_" + info->name() + ".csv";
  const std::string command = std::string(LIEFLOW_BINARY_DIR) + "/app/lieflow simulate " + args + " --out " + file;
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
  JointSamples s = selectJoint(readRecording(file), "", "");
  std::remove(file.c_str());
  return s;
}

/// The Monte Carlo tests run fewer samples per trial under AddressSanitizer
/// (CI's Debug -O1 + ASan/UBSan build, ~20× slower); the trial counts, the
/// tolerances and what they check stay the same.
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kSanitized = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif
#else
constexpr bool kSanitized = false;
#endif

/// Gyroscopes alone, white noise σ per axis [rad/s] (no orientations).
inline RecordingNoise gyroscopeNoise(double sigma) {
  RecordingNoise n;
  n.rate_sigma = sigma;
  n.orientations = false;
  return n;
}

/// The part of a bias a hinge's constraint can observe: perpendicular to the axis.
inline Eigen::Vector3d perpendicular(const Eigen::Vector3d& b, const Eigen::Vector3d& axis) {
  const Eigen::Vector3d a = axis.normalized();
  return b - b.dot(a) * a;
}

/// Another motion of the same hinge: its own main-body rotation and joint
/// angle, the same axis j₁ and mount C (so the same j₂).
inline HingeMotion sameHingeOtherMotion(const HingeMotion& m, std::mt19937& gen) {
  HingeMotion other = randomHingeMotion(gen);
  other.axis_main = m.axis_main;
  other.mount = m.mount;
  return other;
}

}  // namespace test
}  // namespace calibration
}  // namespace lieflow
