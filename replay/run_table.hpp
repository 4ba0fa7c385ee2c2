/// \file
/// A run's trajectory CSV (../shared/DESIGN.md, "Trajectory and recording
/// CSV") read for the replay, decimated to a frame budget as it is read:
/// memory stays O(budget) whatever the file's length.
#pragma once

#include <cstddef>
#include <istream>
#include <string>
#include <vector>

#include "model/resource_limits.hpp"

namespace lieflow {
namespace replay {

/// Rows kept from a longer sequence: every `stride`-th row from the first,
/// and always the last one. Rows are offered one at a time; when more than
/// twice the budget are kept, the stride doubles and every other kept row
/// goes, so at most 2·budget + 1 rows are ever held.
class FrameDecimator {
 public:
  explicit FrameDecimator(std::size_t budget);
  void offer(const std::vector<double>& row);
  /// The kept rows (at most `budget`, first and last included), their
  /// stride in the offered sequence, and how many were offered.
  std::vector<std::vector<double>> frames() const;
  std::size_t stride() const;
  std::size_t offered() const { return offered_; }

 private:
  std::size_t extra() const;
  std::size_t budget_;
  std::size_t stride_ = 1;
  std::size_t offered_ = 0;
  std::vector<std::vector<double>> kept_;
  std::vector<double> last_;
};

/// A run as the replay takes it: the column names and the kept rows.
struct RunTable {
  std::string source;  ///< the file, for messages
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;  ///< decimated
  std::size_t total_rows = 0;             ///< rows in the file
  std::size_t stride = 1;                 ///< kept every stride-th row (and the last)
  /// The index of column `name`, or −1.
  int column(const std::string& name) const;
};

/// The rows a decimator kept, as the replay's table of `columns`.
RunTable tableOf(const FrameDecimator& frames, const std::vector<std::string>& columns, const std::string& source);

/// Reads the CSV at `path`, keeping at most `frame_budget` rows. Throws
/// InvalidInput naming the file, the line and the column for a missing,
/// non-numeric or non-finite value, a header without `t` first, a `t` that
/// does not increase, or no data rows; the file's size is held to
/// `limits.max_input_bytes` and its rows to `limits.max_rows`.
RunTable readRunTable(const std::string& path, std::size_t frame_budget, const ResourceLimits& limits);

/// The same from a stream (`source` names it in messages), at most
/// `max_rows` data rows.
RunTable parseRunTable(std::istream& in, const std::string& source, std::size_t frame_budget, long max_rows);

}  // namespace replay
}  // namespace lieflow
