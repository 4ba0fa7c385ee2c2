/// \file
/// `lieflow calibrate spherical`: a ball joint's centre in both sensors'
/// frames (joint_centre.hpp), with the choices the hinge fit makes by itself:
///  - the filter from the data: gyroscopes that wobble on soft tissue
///    (wobble_check.hpp) are low-passed with the accelerometers at
///    kWobbleCutoffHz, saying so (`low_pass_hz`, `low_pass_reason`);
///    AxisFitOptions::low_pass_hz forces a cutoff, low_pass_auto = false none;
///  - the model checked across the recording (model_check.hpp): each quarter
///    fitted alone, its anchors compared with the whole fit's by their
///    distance [m]; where the quarters disagree beyond their σ, the anchors'
///    σ include their spread (`model_spread_m`).
#pragma once

#include <string>

#include "calibration/fit_types.hpp"
#include "calibration/joint_centre.hpp"
#include "calibration/joint_samples.hpp"
#include "calibration/model_check.hpp"

namespace lieflow {
namespace calibration {

/// Fewest samples a quarter must have for the centre's check: the joint
/// centre's σ holds from about 1000 samples (10 s at 100 Hz: mean (error/σ)²
/// 0.5–1.6, tests/calibration/joint_centre_test.cpp) and is small by √2 or
/// more on 3 s; on quarters of 2.5 s the check called 13 of 25 recordings of
/// one ball joint inconsistent.
constexpr int kMinCentreSegmentSamples = 1000;

struct SphericalFit {
  JointCentreFit centre;          ///< its sigma_main, sigma_secondary include the model check's spread
  double low_pass_hz = 0.0;       ///< 0: unfiltered
  double low_pass_noise_gain = 0.0;
  std::string low_pass_reason;
  ModelCheck model_check;
};

/// Reads options.low_pass_hz, low_pass_auto and check_segments. Throws
/// InvalidInput without both bodies' gyroscopes and accelerometers,
/// NotIdentifiable when the motion cannot place the centre.
SphericalFit fitSpherical(const JointSamples& samples, const AxisFitOptions& options = AxisFitOptions());

}  // namespace calibration
}  // namespace lieflow
