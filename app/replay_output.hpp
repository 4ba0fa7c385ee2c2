/// \file
/// Writing a replay page (replay/) from the commands: `view`, `simulate
/// --view` and `study --view`, and the Python module's view().
#pragma once

#include <string>

#include "model/scene.hpp"
#include "replay/replay_page.hpp"
#include "replay/run_table.hpp"

namespace lieflow {
namespace app {

/// Writes the replay of `run` to `path` (as PATH.partial, renamed when
/// whole; InvalidInput naming `field` when it cannot be written) and says on
/// stderr what went into it unless `quiet`.
replay::ReplaySummary writeReplayFile(const std::string& path, const std::string& field, const SceneDescription& scene,
                                      const replay::RunTable& run, const replay::ReplayOptions& options, bool quiet);

/// `lieflow view`'s default output: RUN.csv → RUN.html (RUN + ".html"
/// when RUN has no .csv ending).
std::string defaultReplayPath(const std::string& run);

}  // namespace app
}  // namespace lieflow
