/// \file
/// libFuzzer target: any bytes as the run CSV of `lieflow view`.
/// parseRunTable must return a table (at most the frame budget of rows,
/// first and last included) or throw lieflow::InvalidInput.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>

#include "liegroup/invalid_input.hpp"
#include "replay/run_table.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  constexpr std::size_t kBudget = 7;  // small: the stride doubling runs often
  try {
    const lieflow::replay::RunTable t = lieflow::replay::parseRunTable(in, "fuzz.csv", kBudget, 100000);
    if (t.rows.empty() || t.rows.size() > kBudget) std::abort();
    for (const auto& row : t.rows)
      if (row.size() != t.columns.size()) std::abort();
  } catch (const lieflow::InvalidInput&) {
  }
  return 0;
}
