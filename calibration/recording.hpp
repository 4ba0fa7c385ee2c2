/// \file
/// The recording CSV of ../shared/DESIGN.md ("Trajectory and recording CSV"):
/// one header row, then one row per time. Columns: `t`; per body B any of the
/// groups `B.qw,B.qx,B.qy,B.qz` (Hamilton quaternion, R maps body → world),
/// `B.wx,B.wy,B.wz` (angular velocity in the body frame) and `B.ax,B.ay,B.az`
/// (accelerometer: specific force in the body frame), and the other
/// trajectory columns (`B.x`, `J.phi`, `energy`, ...), which are checked but not
/// used by the axis fits. Bodies are discovered from the column prefixes of the
/// body columns; the columns that are neither `t` nor body columns (`J.phi`,
/// `energy`, ...) are kept by name for the fits that use them (the spring fit
/// reads the joint angles).
///
/// Every value must be present, numeric and finite; `t` must increase; a
/// quaternion must be unit to kQuaternionNormTolerance (it is then normalized).
/// Violations throw lieflow::InvalidInput naming the file, line and column.
#pragma once

#include <istream>
#include <string>
#include <vector>

#include "calibration/joint_samples.hpp"
#include "model/resource_limits.hpp"

namespace lieflow {
namespace calibration {

/// A quaternion in a recording may deviate this much from unit norm (data
/// exported with 6 significant digits are off by ~1e-6); it is normalized.
constexpr double kQuaternionNormTolerance = 1e-3;

/// One recorded column that is not `t` and not a body column.
struct ScalarColumn {
  std::string name;
  std::vector<double> values;  ///< one per time
};

/// All bodies of one recording, in the order their columns first appear.
struct Recording {
  std::string source;
  std::vector<double> time;
  std::vector<BodySamples> bodies;
  std::vector<ScalarColumn> scalars;  ///< in column order

  /// The scalar column of that name, or nullptr.
  const std::vector<double>* column(const std::string& name) const;

  /// The body of that name, or nullptr.
  const BodySamples* body(const std::string& name) const;
  /// "A, B, C" for messages.
  std::string bodyList() const;
};

/// Parses a recording from `in`; `source` names it in error messages. More
/// than `max_rows` data rows is an error naming the limit and --max-rows.
Recording parseRecording(std::istream& in, const std::string& source, long max_rows = kMaxRecordingRows);

/// Reads the recording file at `path` (InvalidInput if it cannot be opened),
/// within limits.max_input_bytes and limits.max_rows.
Recording readRecording(const std::string& path, const ResourceLimits& limits = ResourceLimits());

/// The joint between bodies `main` and `secondary`. An empty name may be
/// left out when the recording has exactly two bodies: it is then the body
/// the other name does not take (main = the first body in column order).
/// Unknown or equal names throw InvalidInput.
JointSamples selectJoint(const Recording& recording, std::string main, std::string secondary);

}  // namespace calibration
}  // namespace lieflow
