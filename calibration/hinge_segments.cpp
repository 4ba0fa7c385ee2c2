#include "calibration/hinge_segments.hpp"

#include <string>

#include "calibration/hinge_fit.hpp"

namespace lieflow {
namespace calibration {

namespace {

/// A segment's hinge fit with the whole fit's options, without a filter
/// choice or a check of its own.
PieceFit hingePieceFit(const AxisFitOptions& options) {
  AxisFitOptions piece = options;
  piece.check_segments = false;
  piece.low_pass_auto = false;  // the whole fit's filter (options.low_pass_hz) or none
  // A piece answers its axes and σ only: the bias check's verdict (the
  // summary's `converged` and message) would be dropped, so it is not
  // computed (about a sixth of a default fit's time on 1000 samples).
  piece.check_gyro_bias = false;
  piece.progress = nullptr;
  return [piece](const JointSamples& samples) {
    const HingeFit f = fitHinge(samples, piece);
    return PieceAnswer{f.axis_main, f.axis_secondary, f.sigma_main_deg, f.sigma_secondary_deg};
  };
}

}  // namespace

ModelCheck checkHingeAcrossSegments(const JointSamples& samples, const AxisFitOptions& options,
                                    const Eigen::Vector3d& axis_main, const Eigen::Vector3d& axis_secondary) {
  return checkAcrossRecording(samples, hingePieceFit(options), lineDistanceDeg, axis_main, axis_secondary, "hinge");
}

ModelCheck checkHingeAcrossRecordings(const std::vector<JointSamples>& recordings, const AxisFitOptions& options,
                                      const Eigen::Vector3d& axis_main, const Eigen::Vector3d& axis_secondary) {
  return checkAcrossPieces(recordings, hingePieceFit(options), lineDistanceDeg, axis_main, axis_secondary, "hinge",
                           "recordings", "all the recordings", "recording");
}

}  // namespace calibration
}  // namespace lieflow
