/// \file
/// A replay of a run: one self-contained HTML file (three.js from Debian's
/// libjs-three inlined, no network) that draws each body of the scene at the
/// poses the run's CSV holds, with the joints' anchors and axes, the ground
/// frame, trails of the centres of mass, play/pause, speed, a time slider and
/// one chosen column's value. Bodies are drawn as the scene gives their
/// shapes (model files: model/visual_shape.hpp), otherwise as the box with
/// their inertia (the solid box of the same mass and principal moments).
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "model/scene.hpp"
#include "replay/run_table.hpp"

namespace lieflow {
namespace replay {

/// Where Debian's libjs-three puts three.js (LIEFLOW_THREE_DIR overrides it).
constexpr const char* kThreeDir = "/usr/share/javascript/three";
/// Most frames a page holds by default: smooth at 60 frames per second over
/// 30 s of replay, a few MB of page.
constexpr std::size_t kDefaultFrameBudget = 2000;
/// Most numbers (frames × kept columns) a page holds: 16 MB of float64
/// (21 MB of base64); beyond it, fewer frames.
constexpr std::size_t kValueBudget = 2000000;
/// Fewest frames a page keeps whatever the value budget says.
constexpr std::size_t kMinFrames = 100;
/// Most bytes of mesh files inlined; later meshes are drawn as boxes.
constexpr std::uint64_t kMeshBudgetBytes = 64ull << 20;

struct ReplayOptions {
  std::size_t frame_budget = kDefaultFrameBudget;
  /// The folder holding build/three.min.js and examples/js/ (empty:
  /// $LIEFLOW_THREE_DIR, else kThreeDir).
  std::string three_dir;
  /// The page's title line ("heavy-top: run.csv").
  std::string title;
};

/// What went into a page, for the command to say.
struct ReplaySummary {
  std::size_t frames = 0;      ///< frames in the page
  std::size_t rows = 0;        ///< rows of the run
  std::size_t stride = 1;      ///< every stride-th row (and the last)
  std::size_t columns = 0;     ///< columns kept (t, poses, the scalar columns)
  std::size_t left_out = 0;    ///< columns left out (body velocities, sensors)
  std::size_t boxes = 0;       ///< bodies drawn as their inertia's box
  std::uint64_t bytes = 0;     ///< size of the page
  std::vector<std::string> notes;  ///< one sentence each; the page shows them too
};

/// three.js (and its loaders) are not where the replay looks for them.
struct ReplayUnavailable : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// The HTML page. Throws InvalidInput naming `run.source` and the column
/// when a body of `scene` has no pose columns in the run (a run of another
/// scene), ReplayUnavailable when three.js cannot be read.
std::string replayPage(const SceneDescription& scene, const RunTable& run, const ReplayOptions& options,
                       ReplaySummary* summary);

}  // namespace replay
}  // namespace lieflow
