/// \file
/// Which of a joint's recorded column groups a fit uses, and the per-sample
/// quantities the residuals share (relative orientation, relative rate).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "calibration/fit_types.hpp"
#include "calibration/joint_samples.hpp"

namespace lieflow {
namespace calibration {

struct DataSelection {
  bool orientations = false;
  bool rates = false;
  /// "gyroscopes", "orientations" or "orientations+gyroscopes".
  std::string name() const;
};

/// The groups `use` asks for (kAuto: all that both bodies have). Throws
/// lieflow::InvalidInput naming the recording, the body and the missing
/// columns when a requested group, or every group, is missing. `joint` names
/// the fit in the message ("hinge").
DataSelection selectData(const JointSamples& samples, DataUse use, const std::string& joint);

/// R₁ᵀR₂ per sample (the secondary body's orientation in the main body's frame).
std::vector<Eigen::Matrix3d> relativeOrientations(const JointSamples& samples);

/// R₁ᵀR₂ω₂ − ω₁ per sample (the relative angular velocity in the main body's frame).
std::vector<Eigen::Vector3d> relativeRates(const JointSamples& samples, const std::vector<Eigen::Matrix3d>& R12);

}  // namespace calibration
}  // namespace lieflow
