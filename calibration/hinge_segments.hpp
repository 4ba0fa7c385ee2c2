/// \file
/// The hinge fit checks its own model across the recording (issue 31): the
/// recording is split by time into kModelSegments segments, each fitted alone
/// with the same options; if one hinge describes the recording, each
/// segment's axes scatter about the whole fit's by their own σ, so
///   χ² = Σ_segments (d₁,ᵢ/σ₁,ᵢ)² + (d₂,ᵢ/σ₂,ᵢ)²
/// (d the angle between a segment's axis and the whole fit's, σ the
/// segment's RMS angle: each term 1 on average) stays near 2K. Above
/// kSegmentChiSquare × 2K the segments disagree: the excess spread
///   s² = max(0, mean(d²) − mean(σ²)) per axis
/// is what one hinge leaves unexplained across the recording, and the whole
/// fit's σ becomes √(σ² + s²) (`model_spread_deg` = the larger s). The
/// segments' spans and axes are reported either way (`segments`). A fit
/// over several recordings takes the recordings as its segments.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "calibration/fit_types.hpp"
#include "calibration/joint_samples.hpp"

namespace lieflow {
namespace calibration {

/// Segments by time.
constexpr int kModelSegments = 4;
/// Fewest samples a segment must have for the check to run.
constexpr int kMinModelSegmentSamples = 250;
/// χ² over its mean (2 per segment that answered) above which the segments
/// disagree (χ² of 8 degrees of freedom: 3.3 times its mean is the 0.1 %
/// tail; the segments' σ are estimates, so the bound is kept wide).
constexpr double kSegmentChiSquare = 3.0;

struct SegmentFit {
  double t_start = 0.0, t_end = 0.0;
  std::string source;  ///< the recording (a fit over several recordings: one segment per recording)
  bool answered = false;
  std::string why;  ///< why not, when it did not answer
  Eigen::Vector3d axis_main = Eigen::Vector3d::Zero(), axis_secondary = Eigen::Vector3d::Zero();
  double sigma_main_deg = 0.0, sigma_secondary_deg = 0.0;
  double apart_main_deg = 0.0, apart_secondary_deg = 0.0;  ///< from the whole fit's axes
};

struct ModelCheck {
  bool ran = false;
  std::string note;  ///< why it did not run, or what it found
  std::vector<SegmentFit> segments;
  double chi_square = 0.0;  ///< over its mean
  bool disagree = false;
  double spread_main_deg = 0.0, spread_secondary_deg = 0.0;  ///< s of each axis (0 unless disagree)
};

/// The check for a fit of `samples` with `options` (the filter and the
/// estimator already chosen) whose axes are `axis_main`, `axis_secondary`.
ModelCheck checkHingeAcrossSegments(const JointSamples& samples, const AxisFitOptions& options,
                                    const Eigen::Vector3d& axis_main, const Eigen::Vector3d& axis_secondary);

/// The same check for a fit over several recordings of one joint
/// (fitHinge's recordings overload): each recording is a segment, fitted
/// alone (its own clock, biases and noise), whatever its length.
ModelCheck checkHingeAcrossRecordings(const std::vector<JointSamples>& recordings, const AxisFitOptions& options,
                                      const Eigen::Vector3d& axis_main, const Eigen::Vector3d& axis_secondary);

}  // namespace calibration
}  // namespace lieflow
