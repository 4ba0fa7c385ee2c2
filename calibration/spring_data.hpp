/// \file
/// The recorded joint angles that `calibrate spring` fits: columns `J.phi`
/// (revolute joint J) or `J.phi1`, `J.phi2` (universal; either or both) of a
/// recording (recording.hpp), and local estimates of the state (φ, φ̇) from
/// them.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "calibration/recording.hpp"
#include "calibration/spring_joint.hpp"

namespace lieflow {
namespace calibration {

struct SpringData {
  std::string source;
  std::vector<double> time;
  /// Per joint coordinate: the recorded angles (one per time), or empty when
  /// that coordinate's column is absent.
  std::array<std::vector<double>, 2> angle;
  std::array<std::string, 2> column;  ///< the column names ("" when absent)

  int size() const { return static_cast<int>(time.size()); }
  bool has(int i) const { return !angle[i].empty(); }
  /// Number of recorded coordinates.
  int measured() const { return has(0) + has(1); }
};

/// The angle columns of `joint` in `recording`. Throws InvalidInput naming
/// the recording and the missing columns when the fitted coordinate
/// (`coordinate`, 0 or 1) has none.
SpringData selectSpringData(const Recording& recording, const SpringJoint& joint, int coordinate);

/// φ and φ̇ of coordinate i at sample j from a least-squares quadratic through
/// the samples within ±half_width of j (fewer at the ends).
Eigen::Vector2d localAngleAndRate(const SpringData& data, int i, int j, int half_width);

}  // namespace calibration
}  // namespace lieflow
