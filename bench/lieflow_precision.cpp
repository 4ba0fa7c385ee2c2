/// \file
/// lieflow_precision: prints the precision table of liegroup/ (largest error
/// per angle band per operation, against the targets; see bench/README.md).
///
///   lieflow_precision [--samples N] [--seed S] [--strict]
///
/// Exit status: 0, or 1 with --strict when a target is missed; 2 on bad usage.
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

#include "liegroup_measure/liegroup_measure.hpp"

namespace {

constexpr const char* kUsage =
    "usage: lieflow_precision [--samples N] [--seed S] [--strict]\n"
    "\n"
    "Prints the largest error of SO(3)/SE(3) exp/log round trips, of SO(3) exp\n"
    "against a long-double reference and of Jr*JrInv - I, per angle band, beside\n"
    "Eigen's AngleAxis round trip. N random samples per band (default 100000),\n"
    "seed S (default 20261122). --strict: exit status 1 when a target is missed.\n";

bool parseUnsigned(const char* text, unsigned long long max, unsigned long long* value) {
  char* end = nullptr;
  const unsigned long long v = std::strtoull(text, &end, 10);
  if (end == text || *end != '\0' || text[0] == '-' || v == 0 || v > max) return false;
  *value = v;
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  unsigned long long samples = 100000;
  unsigned long long seed = 20261122;
  bool strict = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      std::cout << kUsage;
      return 0;
    }
    if (arg == "--strict") {
      strict = true;
    } else if (arg == "--samples" || arg == "--seed") {
      if (i + 1 >= argc) {
        std::cerr << "lieflow_precision: " << arg << ": missing value\n";
        return 2;
      }
      const char* value = argv[++i];
      unsigned long long* target = arg == "--samples" ? &samples : &seed;
      const unsigned long long max = arg == "--samples" ? 1000000000ULL : ~0ULL;
      if (!parseUnsigned(value, max, target)) {
        std::cerr << "lieflow_precision: " << arg << ": expected a positive integer"
                  << (arg == "--samples" ? " up to 1e9" : "") << ", got '" << value << "'\n";
        return 2;
      }
    } else {
      std::cerr << "lieflow_precision: unknown option '" << arg << "'\n" << kUsage;
      return 2;
    }
  }
  const std::vector<lieflow::measure::PrecisionRow> rows =
      lieflow::measure::measurePrecision(static_cast<int>(samples), seed);
  std::cout << "# liegroup precision (" << samples << " samples per band, seed " << seed
            << ")\n\n";
  lieflow::measure::printPrecisionTable(std::cout, rows);
  int missed = 0;
  for (const auto& row : rows)
    if (!row.pass()) ++missed;
  std::cout << "\n" << (missed == 0 ? "all targets met" : std::to_string(missed) + " (operation, band) cells MISS their target")
            << "\n";
  return strict && missed > 0 ? 1 : 0;
}
