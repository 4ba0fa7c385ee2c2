#include "app/replay_output.hpp"

#include <iostream>

#include "app/output_files.hpp"

namespace lieflow {
namespace app {

replay::ReplaySummary writeReplayFile(const std::string& path, const std::string& field, const SceneDescription& scene,
                                      const replay::RunTable& run, const replay::ReplayOptions& options, bool quiet) {
  AtomicOutputFile out(path, field);
  replay::ReplaySummary summary;
  try {
    out.stream() << replay::replayPage(scene, run, options, &summary);
  } catch (...) {
    out.abandon();
    throw;
  }
  out.commit();
  if (!quiet) {
    std::cerr << "lieflow: wrote the replay " << path << " (" << summary.frames << " frames of " << summary.rows
              << " rows, " << (summary.bytes + (1u << 19)) / (1u << 20) << " MB)\n";
    for (const std::string& note : summary.notes) std::cerr << "lieflow: replay: " << note << "\n";
  }
  return summary;
}

std::string defaultReplayPath(const std::string& run) {
  const std::string ending = ".csv";
  if (run.size() > ending.size() && run.compare(run.size() - ending.size(), ending.size(), ending) == 0)
    return run.substr(0, run.size() - ending.size()) + ".html";
  return run + ".html";
}

}  // namespace app
}  // namespace lieflow
