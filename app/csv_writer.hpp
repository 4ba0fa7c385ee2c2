/// \file
/// Trajectory CSV output: one header row, then rows of numbers written with
/// 17 significant digits so that they round-trip to the same doubles.
#pragma once

#include <cstdio>
#include <ostream>
#include <string>
#include <vector>

namespace lieflow {
namespace app {

class CsvWriter {
 public:
  explicit CsvWriter(std::ostream& out) : out_(out) {}

  void header(const std::vector<std::string>& columns) {
    for (std::size_t i = 0; i < columns.size(); ++i) out_ << (i ? "," : "") << columns[i];
    out_ << '\n';
  }

  void row(const std::vector<double>& values) {
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
};

}  // namespace app
}  // namespace lieflow
