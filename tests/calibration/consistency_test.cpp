/// \file
/// The check that a recording's quaternions turn as its gyroscopes say
/// (calibration/data_selection.hpp, checkOrientationsAgreeWithRates), before
/// a fit that uses both: noisy but consistent data pass; quaternions given in
/// a frame turned by a constant rotation (as a real sensor's fused output can
/// be) are refused naming the body and the rotation, and either group alone
/// still fits.
#include <gtest/gtest.h>

#include <string>

#include "calibration/data_selection.hpp"
#include "calibration/hinge_fit.hpp"
#include "calibration_test_helpers.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {
namespace calibration {
namespace {

using test::simulatedJoint;

TEST(CalibConsistency, NoisyConsistentDataPass) {
  const JointSamples joint = simulatedJoint("hinge-pair --every 10 --noise-gyro 0.02 --noise-quat 0.01 --seed 2");
  EXPECT_NO_THROW(checkOrientationsAgreeWithRates(joint));
  EXPECT_NO_THROW(fitHinge(joint));
}

TEST(CalibConsistency, QuaternionsInAnotherFrameAreNamed) {
  JointSamples joint = simulatedJoint("hinge-pair --every 10 --noise-gyro 0.01 --noise-quat 0.005 --seed 3");
  // The lower body's quaternions describe a frame turned 30° about (1, 1, 0)
  // from its gyroscopes' frame: R' = R C.
  const SO3d C = SO3d::exp(Eigen::Vector3d(1.0, 1.0, 0.0).normalized() * (30.0 * 3.141592653589793 / 180.0));
  for (SO3d& R : joint.secondary.orientation) R = R * C;
  try {
    checkOrientationsAgreeWithRates(joint);
    ADD_FAILURE() << "not refused";
  } catch (const InvalidInput& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("body 'lower'"), std::string::npos) << what;
    EXPECT_NE(what.find("30"), std::string::npos) << what;  // 30.0 degrees, to 3 digits
    EXPECT_NE(what.find("`use` gyroscopes"), std::string::npos) << what;
  }
  EXPECT_THROW(fitHinge(joint), InvalidInput);
  AxisFitOptions gyroscopes;
  gyroscopes.use = DataUse::kAngularVelocities;
  const HingeFit fit = fitHinge(joint, gyroscopes);
  EXPECT_LT(test::lineErrorDeg(fit.axis_main, Eigen::Vector3d(0.0, 0.6, 0.8)), 0.5);
}

}  // namespace
}  // namespace calibration
}  // namespace lieflow
