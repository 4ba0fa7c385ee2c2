/// \file
/// Data that cannot determine the axes must be refused ("not identifiable",
/// exit 1 in the command), never answered with a confident wrong axis: no
/// motion, a body at rest (gyroscopes), the assembly turning rigidly about
/// the hinge axis, a joint that does not move (orientations), a universal
/// joint turned about one axis only, too few samples.
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "calibration/hinge_fit.hpp"
#include "calibration/synthetic_motion.hpp"
#include "calibration/universal_fit.hpp"
#include "calibration_test_helpers.hpp"

namespace lieflow {
namespace calibration {
namespace {

constexpr double kDeg = 1.0 / kRadToDeg;
constexpr int kSamples = 400;  // degenerate data are degenerate at any length
constexpr double kRateHz = 100.0;

/// Runs `fit` and expects NotIdentifiable whose reason contains `fragment`.
template <typename Fit>
void expectNotIdentifiable(Fit fit, const std::string& fragment) {
  try {
    fit();
    ADD_FAILURE() << "expected NotIdentifiable (" << fragment << ")";
  } catch (const NotIdentifiable& e) {
    EXPECT_EQ(std::string(e.what()).rfind("not identifiable: ", 0), 0u) << e.what();
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

void stopMain(SmoothRotation* r) { r->angle.amplitude.clear(); }

TEST(CalibIdentifiability, NoMotionAtAll) {
  for (double sigma : {0.0, 0.01, 0.1}) {
    std::mt19937 gen(20);
    HingeMotion m = randomHingeMotion(gen);
    stopMain(&m.main);
    m.angle.amplitude.clear();
    const JointSamples s = recordMotion(m, kSamples, kRateHz, RecordingNoise{sigma, sigma * 0.1, true, true}, gen);
    AxisFitOptions gyro, mocap;
    gyro.use = DataUse::kAngularVelocities;
    mocap.use = DataUse::kOrientations;
    SCOPED_TRACE(sigma);
    expectNotIdentifiable([&] { fitHinge(s, gyro); }, "determine");
    expectNotIdentifiable([&] { fitHinge(s, mocap); }, "the joint must move");
  }
}

TEST(CalibIdentifiability, GyroscopesWithTheMainBodyAtRest) {
  for (double sigma : {0.0, 0.01, 0.1}) {
    std::mt19937 gen(21);
    HingeMotion m = randomHingeMotion(gen);
    stopMain(&m.main);
    const JointSamples s = recordMotion(m, kSamples, kRateHz, RecordingNoise{sigma, 0.0, false, true}, gen);
    SCOPED_TRACE(sigma);
    // With exact data nothing at all is informative at the solution (ω₂ ∥ j₂
    // too); with noise the main body's axis is the one left undetermined.
    expectNotIdentifiable([&] { fitHinge(s); }, sigma > 0.0 ? "mostly the axis in the main body" : "determine");
  }
}

TEST(CalibIdentifiability, RigidRotationAboutTheHingeAxis) {
  for (double sigma : {0.0, 0.01, 0.1}) {
    std::mt19937 gen(22);
    HingeMotion m = randomHingeMotion(gen);
    // θ(t) ∥ j₁: the main body turns about the hinge axis only; φ constant.
    for (Eigen::Vector3d& a : m.main.angle.amplitude) a = a.norm() * m.axis_main;
    m.main.angle.offset = 0.3 * m.axis_main;
    m.angle.amplitude.clear();
    m.angle.offset = 0.7;
    const JointSamples s =
        recordMotion(m, kSamples, kRateHz, RecordingNoise{sigma, 0.5 * kDeg * (sigma > 0), true, true}, gen);
    AxisFitOptions gyro, mocap;
    gyro.use = DataUse::kAngularVelocities;
    mocap.use = DataUse::kOrientations;
    SCOPED_TRACE(sigma);
    expectNotIdentifiable([&] { fitHinge(s, gyro); }, "determine");
    expectNotIdentifiable([&] { fitHinge(s, mocap); }, "the joint must move");
    expectNotIdentifiable([&] { fitHinge(s); }, "the joint must move");
  }
}

TEST(CalibIdentifiability, UniversalJointTurnedAboutOneAxisOnly) {
  for (double sigma : {0.0, 0.5}) {
    std::mt19937 gen(23);
    UniversalMotion m = randomUniversalMotion(gen);
    m.angle2.amplitude.clear();
    m.angle2.offset = 0.4;
    const JointSamples s =
        recordMotion(m, kSamples, kRateHz, RecordingNoise{0.01 * (sigma > 0), sigma * kDeg, true, true}, gen);
    SCOPED_TRACE(sigma);
    expectNotIdentifiable([&] { fitUniversal(s); }, "both joint angles must move");
  }
}

TEST(CalibIdentifiability, UniversalFromGyroscopesAloneIsRefused) {
  std::mt19937 gen(24);
  const UniversalMotion m = randomUniversalMotion(gen);
  const JointSamples s = recordMotion(m, kSamples, kRateHz, RecordingNoise{0.01, 0.0, false, true}, gen);
  expectNotIdentifiable([&] { fitUniversal(s); }, "need both bodies' orientations");
}

TEST(CalibIdentifiability, TooFewSamples) {
  std::mt19937 gen(25);
  const HingeMotion m = randomHingeMotion(gen);
  // 19 exact samples at 10 Hz: the motion is there, the count is not.
  const JointSamples s = recordMotion(m, 19, 10.0, RecordingNoise{0.0, 0.0, false, true}, gen);
  expectNotIdentifiable([&] { fitHinge(s); }, "19 samples; at least 20");
  AxisFitOptions options;
  options.min_samples = 10;
  const HingeFit fit = fitHinge(s, options);
  EXPECT_LE(test::lineErrorDeg(fit.axis_main, m.axis_main), 1e-6);
}

}  // namespace
}  // namespace calibration
}  // namespace lieflow
