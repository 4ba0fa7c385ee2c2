/// \file
/// Which hinge estimator a recording gets by default (AxisFitOptions::
/// estimator = kAuto), and why: the JSON's `estimator` and
/// `estimator_reason`.
///
/// The likelihood fit over the joint angle (hinge_likelihood.hpp) uses the
/// phase of the rates as well as their lengths: on gyroscopes alone its σ is
/// the Cramér–Rao bound, about 1.5 times below the constraint fit's
/// (tests/calibration/hinge_likelihood_test.cpp: 50 recordings at 0.1 rad/s,
/// 1000 samples, all within 0.5° against 45 of 50). It models the two
/// gyroscopes' white noise sample by sample, so it is chosen when
///  - both bodies have gyroscopes and the fit uses them alone (--use auto on a
///    recording without orientations or accelerometers, or --use gyroscopes),
///  - no low-pass filter colours that noise (--low-pass),
///  - and no robust loss is asked for (--loss; the likelihood is least squares).
/// Otherwise the constraint fit, which also takes orientations and
/// accelerometers (the joint centre), and filtered rates.
#pragma once

#include <string>

#include "calibration/fit_types.hpp"
#include "calibration/joint_samples.hpp"

namespace lieflow {
namespace calibration {

struct HingeEstimatorChoice {
  HingeEstimator estimator = HingeEstimator::kConstraint;
  std::string reason;
};

/// options.estimator when it is not kAuto ("asked for"), else the rule above.
HingeEstimatorChoice chooseHingeEstimator(const JointSamples& samples, const AxisFitOptions& options);

}  // namespace calibration
}  // namespace lieflow
