/// \file
/// Small command-line helpers of the `lieflow` command: the exit-status
/// contract and the usage error.
#pragma once

#include <stdexcept>
#include <string>

namespace lieflow {
namespace app {

/// Exit status contract (../shared/DESIGN.md): 0 success, 1 the computation
/// failed (non-convergence, blow-up), 2 bad input or usage.
enum ExitStatus : int { kSuccess = 0, kComputationFailed = 1, kBadInput = 2 };

/// A command-line usage error (exit status 2).
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace app
}  // namespace lieflow
