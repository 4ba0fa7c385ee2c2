/// \file
/// `lieflow calibrate universal`: the two axes of a universal joint, a₁ in the
/// main body's frame and a₂ in the secondary's, from
///
///  - orientations: OrientationUniversalResidual ((R₁a₁)·(R₂a₂) = 0), started
///    from the closed form universalAxesFromOrientations;
///  - orientations and gyroscopes: that and RelativeRateUniversalResidual
///    (the relative angular velocity lies in span{R₁a₁, R₂a₂}), each weighted
///    by its estimated noise; the relative-rate residual also per sample, by
///    the noise it carries from both gyroscopes and both orientations (the
///    latter scaled by the rates, 5-fold across the `universal-pair` scene),
///    from noise levels estimated from the recorded signals themselves
///    (universal_fit.cpp: relativeRateScales). With one weight for all
///    samples σ was 1.6 times too small on that scene.
///
/// The solver's further checks (two_axis_solver.hpp) apply: a second minimum
/// that fits as well, a cost far from quadratic over the 3σ region.
///
/// Gyroscopes alone are refused (NotIdentifiable): the joint leaves the
/// bodies 4 relative degrees of freedom per sample (φ₁, φ₂, φ̇₁, φ̇₂) against 3
/// measured relative rates, so there is no instantaneous constraint; the axes
/// would need the joint angles integrated over time, which this fit does not
/// do. Each axis's sign is a convention (largest-magnitude component positive):
/// the constraints are even in a₁ and in a₂ separately.
#pragma once

#include <string>

#include <Eigen/Core>

#include "calibration/fit_types.hpp"
#include "calibration/identifiability.hpp"
#include "calibration/joint_samples.hpp"
#include "calibration/model_check.hpp"

namespace lieflow {
namespace calibration {

/// Biases (SensorNuisanceEstimate) with AxisFitOptions::fit_gyro_bias:
/// perpendicular to each body's axis (a bias along a₁ or a₂ leaves the
/// relative-rate residual unchanged: reported 0); the clock offset with
/// fit_time_offset.
struct UniversalFit : SensorNuisanceEstimate {
  Eigen::Vector3d axis1_main;       ///< a₁, unit, main body frame
  Eigen::Vector3d axis2_secondary;  ///< a₂, unit, secondary body frame
  double sigma1_deg = 0.0;          ///< 1σ angle of a₁ (RMS angular error)
  double sigma2_deg = 0.0;
  Eigen::Matrix4d covariance;       ///< rad², axis angles (a₁'s two, then a₂'s)
  AxisInformation information;
  AxisFitSummary summary;
  /// The gyroscopes checked for a wobble on soft tissue (wobble_check.hpp):
  /// the universal fit weighs its relative-rate residual by the rates' white
  /// noise, which a filter would colour, so a wobbling recording (with
  /// `use` auto) is fitted from its orientations alone; this says what was
  /// found and done (never filtered: `low_pass_hz` is null).
  std::string low_pass_reason;
  /// The model checked across the recording's quarters (model_check.hpp):
  /// when they disagree, sigma1_deg and sigma2_deg include their spread.
  ModelCheck model_check;
};

/// Throws lieflow::InvalidInput when columns are missing, NotIdentifiable
/// when the data cannot determine the axes (including gyroscopes only).
UniversalFit fitUniversal(const JointSamples& samples, const AxisFitOptions& options = AxisFitOptions());

}  // namespace calibration
}  // namespace lieflow
