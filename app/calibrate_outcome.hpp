/// \file
/// `lieflow calibrate` as a function: the fit's JSON object, the exit status
/// and the reason it failed, without printing. The command
/// (app/command_calibrate.cpp) prints them; the Python module returns them.
/// Defined only in builds with Ceres (LIEFLOW_HAVE_CERES).
#pragma once

#include <functional>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "app/arguments.hpp"
#include "app/cli.hpp"

namespace lieflow {
namespace app {

/// What a command computed: its JSON object (null when it produced none), the
/// exit status (kSuccess or kComputationFailed) and, when it failed, why.
struct CommandOutcome {
  nlohmann::ordered_json json;
  int status = kSuccess;
  std::string error;
};

/// The flags of `lieflow calibrate` that take a value, and its switches.
const std::set<std::string>& calibrateValueFlags();
const std::set<std::string>& calibrateSwitches();

/// Runs `lieflow calibrate KIND RECORDING [flags]` (args hold KIND and
/// RECORDING as positional arguments). Bad input throws UsageError or
/// InvalidInput naming the flag or field; a fit that cannot identify its
/// parameters, fails or does not converge comes back with kComputationFailed
/// and the reason (with the JSON, when the solver stopped without converging).
/// `interrupted` (may be empty) is asked at every solver iteration; true
/// stops the solve (the outcome then says the fit did not converge or failed).
CommandOutcome calibrate(const Arguments& args, const std::function<bool()>& interrupted = {});

}  // namespace app
}  // namespace lieflow
