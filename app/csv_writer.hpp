/// \file
/// Trajectory CSV output: one header row, then rows of numbers written with
/// 17 significant digits so that they round-trip to the same doubles. A row
/// holding a non-finite number is never written: `row` throws
/// NonFiniteOutput naming the column and the row's time instead.
#pragma once

#include <cmath>
#include <cstdio>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

namespace lieflow {
namespace app {

/// A value to be written was NaN or infinite (a computation failure: exit 1).
class NonFiniteOutput : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class CsvWriter {
 public:
  explicit CsvWriter(std::ostream& out) : out_(out) {}

  /// The header, written with the first row: a run refused or failed before
  /// its first row leaves nothing behind (no header on stdout, no
  /// FILE.partial holding only a header).
  void header(const std::vector<std::string>& columns) {
    columns_ = columns;
    header_pending_ = true;
  }

  /// Writes one row (values[0] is the time `t`).
  void row(const std::vector<double>& values) {
    for (std::size_t i = 0; i < values.size(); ++i)
      if (!std::isfinite(values[i])) {
        char t[32];
        std::snprintf(t, sizeof t, "%.17g", values.empty() ? 0.0 : values[0]);
        throw NonFiniteOutput("column " + (i < columns_.size() ? columns_[i] : std::to_string(i)) + " is " +
                              (std::isnan(values[i]) ? "NaN" : "infinite") + " in the row of t = " + t +
                              " (row " + std::to_string(rows_ + 1) + "); nothing of that row was written");
      }
    if (header_pending_) {
      for (std::size_t i = 0; i < columns_.size(); ++i) out_ << (i ? "," : "") << columns_[i];
      out_ << '\n';
      header_pending_ = false;
    }
    ++rows_;
    char buffer[32];
    for (std::size_t i = 0; i < values.size(); ++i) {
      std::snprintf(buffer, sizeof buffer, "%.17g", values[i]);
      if (i) out_ << ',';
      out_ << buffer;
    }
    out_ << '\n';
  }

 private:
  std::ostream& out_;
  std::vector<std::string> columns_;
  bool header_pending_ = false;
  long rows_ = 0;
};

}  // namespace app
}  // namespace lieflow
