/// \file
/// An aligned markdown table printer shared by the precision and speed tables
/// (internal to lieflow_measure and bench/).
#pragma once

#include <algorithm>
#include <cstddef>
#include <ostream>
#include <string>
#include <vector>

namespace lieflow {
namespace measure {
namespace detail {

/// Width of a UTF-8 string in code points (the tables hold a few θ, π, ‖ ‖).
inline std::size_t displayWidth(const std::string& s) {
  std::size_t n = 0;
  for (unsigned char c : s)
    if ((c & 0xC0) != 0x80) ++n;
  return n;
}

/// Prints `header` and `rows` as a markdown table with padded columns. Columns
/// whose index is in `right` are right-aligned (numbers).
inline void printMarkdownTable(std::ostream& out, const std::vector<std::string>& header,
                               const std::vector<std::vector<std::string>>& rows,
                               const std::vector<std::size_t>& right = {}) {
  std::vector<std::size_t> width(header.size());
  for (std::size_t c = 0; c < header.size(); ++c) {
    width[c] = std::max<std::size_t>(3, displayWidth(header[c]));
    for (const auto& row : rows)
      if (c < row.size()) width[c] = std::max(width[c], displayWidth(row[c]));
  }
  auto isRight = [&](std::size_t c) {
    return std::find(right.begin(), right.end(), c) != right.end();
  };
  auto line = [&](const std::vector<std::string>& cells) {
    out << "|";
    for (std::size_t c = 0; c < header.size(); ++c) {
      const std::string s = c < cells.size() ? cells[c] : std::string();
      const std::string fill(width[c] - displayWidth(s), ' ');
      out << " " << (isRight(c) ? fill + s : s + fill) << " |";
    }
    out << "\n";
  };
  line(header);
  out << "|";
  for (std::size_t c = 0; c < header.size(); ++c)
    out << (isRight(c) ? " " + std::string(width[c] - 1, '-') + ": |"
                       : " " + std::string(width[c], '-') + " |");
  out << "\n";
  for (const auto& row : rows) line(row);
}

}  // namespace detail
}  // namespace measure
}  // namespace lieflow
