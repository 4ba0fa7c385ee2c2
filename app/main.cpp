/// \file
/// `lieflow`: the command-line entry point. Dispatches to one function per
/// subcommand; with no arguments it runs the main job.
#include <cstring>
#include <exception>
#include <iostream>
#include <string>

#include "app/cli.hpp"
#include "bench/support/liegroup_measure.hpp"
#include "liegroup/invalid_input.hpp"

namespace {

using lieflow::app::ExitStatus;

constexpr const char* kUsage =
    "usage: lieflow [COMMAND] [OPTIONS]\n"
    "\n"
    "Geometric integration of constrained rigid bodies on Lie groups.\n"
    "\n"
    "With no COMMAND, runs the main job: the liegroup precision and speed summary.\n"
    "\n"
    "commands:\n"
    "  liegroup [--samples N] [--seconds S]\n"
    "                 precision table (max error per angle band) and speed table\n"
    "                 (ratios to Eigen baselines measured in the same run)\n"
    "  --help         this text; every command also takes --help\n"
    "\n"
    "exit status: 0 success, 1 computation failed, 2 bad input or usage\n";

constexpr const char* kLiegroupUsage =
    "usage: lieflow liegroup [--samples N] [--seconds S]\n"
    "\n"
    "Prints the precision of SO(3)/SE(3) exp/log round trips and Jacobians per\n"
    "angle band (N random samples per band, default 20000) and the time per\n"
    "operation beside its Eigen baseline (S seconds per operation, default 0.05).\n";

int parsePositiveInt(const std::string& flag, const char* text) {
  char* end = nullptr;
  const long v = std::strtol(text, &end, 10);
  if (end == text || *end != '\0' || v <= 0 || v > 100000000)
    throw lieflow::app::UsageError(flag + ": expected a positive integer, got '" + text + "'");
  return static_cast<int>(v);
}

double parsePositiveDouble(const std::string& flag, const char* text) {
  char* end = nullptr;
  const double v = std::strtod(text, &end);
  if (end == text || *end != '\0' || !(v > 0.0) || !(v < 1e6))
    throw lieflow::app::UsageError(flag + ": expected a positive number, got '" + text + "'");
  return v;
}

/// The liegroup summary: precision bands, then speed ratios.
int runLiegroupSummary(int argc, char** argv) {
  int samples = 20000;
  double seconds = 0.05;
  for (int i = 0; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      std::cout << kLiegroupUsage;
      return ExitStatus::kSuccess;
    }
    if ((arg == "--samples" || arg == "--seconds") && i + 1 >= argc)
      throw lieflow::app::UsageError(arg + ": missing value");
    if (arg == "--samples") {
      samples = parsePositiveInt(arg, argv[++i]);
    } else if (arg == "--seconds") {
      seconds = parsePositiveDouble(arg, argv[++i]);
    } else {
      throw lieflow::app::UsageError("unknown option '" + arg + "' (see lieflow liegroup --help)");
    }
  }
  std::cout << "# lieflow liegroup summary\n\n## Precision (" << samples
            << " random samples per band)\n\n";
  lieflow::measure::printPrecisionTable(std::cout,
                                        lieflow::measure::measurePrecision(samples, 20261122));
  std::cout << "\n## Speed (ratio to the Eigen baseline, same run)\n\n";
  lieflow::measure::printSpeedTable(std::cout, lieflow::measure::measureSpeed(seconds));
  return ExitStatus::kSuccess;
}

int dispatch(int argc, char** argv) {
  if (argc <= 1) return runLiegroupSummary(0, nullptr);
  const std::string command = argv[1];
  if (command == "--help" || command == "-h" || command == "help") {
    std::cout << kUsage;
    return ExitStatus::kSuccess;
  }
  if (command == "liegroup") return runLiegroupSummary(argc - 2, argv + 2);
  throw lieflow::app::UsageError("unknown command '" + command + "' (see lieflow --help)");
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return dispatch(argc, argv);
  } catch (const lieflow::app::UsageError& e) {
    std::cerr << "lieflow: " << e.what() << "\n";
    return ExitStatus::kBadInput;
  } catch (const lieflow::InvalidInput& e) {
    std::cerr << "lieflow: " << e.what() << "\n";
    return ExitStatus::kBadInput;
  } catch (const std::exception& e) {
    std::cerr << "lieflow: error: " << e.what() << "\n";
    return ExitStatus::kComputationFailed;
  }
}
