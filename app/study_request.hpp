/// \file
/// What `lieflow study` and `lieflow stability` are asked to do, resolved
/// from their arguments; shared by the commands (app/command_study.cpp,
/// app/command_stability.cpp) and the Python module, so that both read the
/// same flags the same way and refuse the same input with the same messages.
#pragma once

#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "app/arguments.hpp"
#include "app/stability.hpp"
#include "app/study.hpp"

namespace lieflow {
namespace app {

const std::set<std::string>& studyValueFlags();
const std::set<std::string>& studySwitches();

struct StudyRequest {
  std::unique_ptr<Simulation> simulation;
  double t_end = 0.0;
  StudyOptions options;
};

/// The scene is the one positional argument or, when given, `scene` (then no
/// positional argument is allowed). Throws UsageError / InvalidInput.
StudyRequest studyRequestFrom(const Arguments& args, std::optional<SceneDescription> scene = std::nullopt);

const std::set<std::string>& stabilityValueFlags();
const std::set<std::string>& stabilitySwitches();

struct StabilityRequest {
  /// The scenes: loaded from the positional arguments (default stiff-spring
  /// and fast-top) or the ones given.
  std::vector<Simulation> simulations;
  StabilityOptions options;
  std::string out_dir;
  bool plots = true;
};

StabilityRequest stabilityRequestFrom(const Arguments& args,
                                      std::vector<SceneDescription> scenes = {});

/// runStability over every scene of the request, rows in scene order.
std::vector<StabilityRow> runStability(const StabilityRequest& request);

}  // namespace app
}  // namespace lieflow
