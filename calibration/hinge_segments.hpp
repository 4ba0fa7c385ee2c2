/// \file
/// The hinge fit's check of its own model (model_check.hpp): by time, the
/// recording's quarters, and by activity, its parts between rests;
/// over several recordings, each recording alone.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "calibration/fit_types.hpp"
#include "calibration/joint_samples.hpp"
#include "calibration/model_check.hpp"

namespace lieflow {
namespace calibration {

/// The check for a fit of `samples` with `options` (the filter and the
/// estimator already chosen) whose axes are `axis_main`, `axis_secondary`:
/// each quarter and each part fitted alone (no filter choice or check of its
/// own).
ModelCheck checkHingeAcrossSegments(const JointSamples& samples, const AxisFitOptions& options,
                                    const Eigen::Vector3d& axis_main, const Eigen::Vector3d& axis_secondary);

/// The same check for a fit over several recordings of one joint
/// (fitHinge's recordings overload): each recording is a segment, fitted
/// alone (its own clock, biases and noise), whatever its length.
ModelCheck checkHingeAcrossRecordings(const std::vector<JointSamples>& recordings, const AxisFitOptions& options,
                                      const Eigen::Vector3d& axis_main, const Eigen::Vector3d& axis_secondary);

}  // namespace calibration
}  // namespace lieflow
