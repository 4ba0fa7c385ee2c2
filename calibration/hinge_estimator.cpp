#include "calibration/hinge_estimator.hpp"

namespace lieflow {
namespace calibration {

HingeEstimatorChoice chooseHingeEstimator(const JointSamples& samples, const AxisFitOptions& options) {
  if (options.estimator != HingeEstimator::kAuto)
    return {options.estimator, std::string("asked for (`estimator` ") + hingeEstimatorName(options.estimator) + ")"};
  const HingeEstimator constraint = HingeEstimator::kConstraint;
  if (!samples.hasAngularVelocities())
    return {constraint, "the recording has no gyroscopes on both bodies (the likelihood fit models two gyroscopes)"};
  if (options.use != DataUse::kAuto && options.use != DataUse::kAngularVelocities)
    return {constraint, std::string("`use` ") + dataUseName(options.use) +
                            ": the likelihood fit models the two gyroscopes alone"};
  if (options.loss != RobustLoss::kNone)
    return {constraint, "a robust loss (`loss`) is asked for: the likelihood fit is plain least squares"};
  if (options.low_pass_hz > 0.0)
    return {constraint, "the rates are low-passed: the likelihood fit models white gyroscope noise sample by sample, "
                        "which the filter colours"};
  if (options.use == DataUse::kAuto) {
    const bool orientations = samples.hasOrientations();
    const bool accelerometers = samples.main.hasSpecificForce() && samples.secondary.hasSpecificForce();
    if (orientations || accelerometers)
      return {constraint, std::string("the recording has ") +
                              (orientations ? "both bodies' orientations" : "both bodies' accelerometers") +
                              ", which the constraint fit uses beside the gyroscopes (the likelihood fit takes the "
                              "gyroscopes alone: `use` gyroscopes `estimator` likelihood)"};
  }
  return {HingeEstimator::kLikelihood,
          "gyroscopes alone: maximum likelihood over the joint angle, at the Cramer-Rao bound (sigma about 1.5 times "
          "below the constraint fit's)"};
}

}  // namespace calibration
}  // namespace lieflow
