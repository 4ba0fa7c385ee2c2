/// \file
/// What `lieflow simulate` is asked to do, resolved from its arguments: the
/// scene assembled for simulation, the run options and the recording noise.
/// Shared by the command (app/command_simulate.cpp) and the Python module
/// (python/module_simulate.cpp), so that both read the same flags the same
/// way and refuse the same input with the same messages.
#pragma once

#include <memory>
#include <optional>
#include <set>
#include <string>

#include "app/arguments.hpp"
#include "app/recording_noise.hpp"
#include "simulation/simulation.hpp"

namespace lieflow {
namespace app {

/// The one scene of `command` (simulate, study): its positional argument (a
/// scene file or a built-in name) or, when given, `scene` (then no positional
/// argument is allowed), assembled for simulation. Throws UsageError /
/// InvalidInput.
std::unique_ptr<Simulation> simulationFrom(const Arguments& args, std::optional<SceneDescription> scene,
                                           const std::string& command);

/// The flags of `lieflow simulate` that take a value, and its switches.
const std::set<std::string>& simulateValueFlags();
const std::set<std::string>& simulateSwitches();

struct SimulateRequest {
  std::unique_ptr<Simulation> simulation;
  SimulationOptions options;
  NoiseOptions noise;
};

/// Resolves the request. The scene is the one positional argument (a file or
/// a built-in name) or, when `scene` is given, that scene (then no
/// positional argument is allowed). Throws UsageError / InvalidInput naming
/// the flag or field and the reason.
SimulateRequest simulateRequestFrom(const Arguments& args, std::optional<SceneDescription> scene = std::nullopt);

}  // namespace app
}  // namespace lieflow
