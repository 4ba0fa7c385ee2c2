/// \file
/// How often a long run reports progress: the command's progress lines, the
/// Python module's check for Ctrl-C, a study's heartbeat.
#pragma once

#include <chrono>

namespace lieflow {

/// Runs report progress (SimulationOptions::progress: the command's
/// progress lines, the Python module's check for Ctrl-C) about this often
/// [s] of run time, reading the clock every kProgressCheckSteps steps (a
/// clock read costs ~20 ns: 0.1 ‰ of a 200 ns step).
inline constexpr double kProgressSeconds = 0.25;
inline constexpr long kProgressCheckSteps = 256;

/// When a long run's next progress report is due.
class ProgressPacer {
 public:
  bool due(long k) {
    if (k == 0 || k % kProgressCheckSteps != 0) return false;
    const auto now = std::chrono::steady_clock::now();
    if (now < next_) return false;
    next_ = now + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                      std::chrono::duration<double>(kProgressSeconds));
    return true;
  }

 private:
  std::chrono::steady_clock::time_point next_ = std::chrono::steady_clock::now() +
                                                std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                    std::chrono::duration<double>(kProgressSeconds));
};

}  // namespace lieflow
