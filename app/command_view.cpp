/// \file
/// `lieflow view RUN.csv --scene SCENE|MODEL [--out FILE.html]`: a run as a
/// self-contained HTML page that replays it in any browser, offline
/// (replay/replay_page.hpp).
#include <iostream>

#include "app/arguments.hpp"
#include "app/cli.hpp"
#include "app/commands.hpp"
#include "app/replay_output.hpp"

namespace lieflow {
namespace app {

namespace {

constexpr const char* kViewUsage =
    "usage: lieflow view RUN.csv --scene SCENE [--out FILE.html] [--frames N]\n"
    "                    [--ignore LIST] [--keyframe K] [--floating-base] [--spin WX,WY,WZ]\n"
    "                    [--max-input-mb N] [--max-rows N] [--max-bodies N] [--quiet]\n"
    "\n"
    "Writes one self-contained HTML file (three.js from Debian's libjs-three inlined; it opens\n"
    "offline in any browser) that replays RUN.csv, a trajectory `lieflow simulate` wrote for SCENE\n"
    "(a JSON scene, a built-in scene or a model file, read with the same --ignore, --keyframe,\n"
    "--floating-base and --spin as the run). Each body is drawn as its model file's shapes (MJCF geoms\n"
    "as MuJoCo's compiler gives them, URDF visuals and the STL, COLLADA or OBJ meshes whose files\n"
    "resolve), otherwise as the solid box with its mass and principal moments; joints' anchors and\n"
    "axes, the ground frame and grid, trails of the centres of mass; play, pause, speed, a time\n"
    "slider, the time and a chosen column's value. Poses are drawn exactly as the CSV holds them\n"
    "(the last row at or before the time shown; no interpolation).\n"
    "  --out FILE.html  where to write it (default: RUN with .html for .csv)\n"
    "  --frames N       most frames the page holds (default 2000; a longer run keeps every k-th\n"
    "                   row and the last, and the page says so; also at most 2e6 numbers in all)\n"
    "  --quiet          no summary on stderr\n"
    "exit status: 0 written, 1 three.js missing (apt-get install libjs-three), 2 bad input (the\n"
    "run's columns do not match the scene, a non-numeric value: the message names the line and column)\n";

}  // namespace

int runView(int argc, char** argv) {
  std::set<std::string> flags = {"--scene", "--out", "--frames", "--max-rows"};
  flags.insert(runLimitFlags().begin(), runLimitFlags().end());
  std::set<std::string> switches = {"--quiet", "--verbose"};
  switches.insert(modelSwitches().begin(), modelSwitches().end());
  const Arguments args(argc, argv, flags, switches);
  if (args.help()) {
    std::cout << kViewUsage;
    return kSuccess;
  }
  if (args.positional().size() != 1) throw UsageError("view needs exactly one RUN.csv (see lieflow view --help)");
  if (!args.has("--scene")) throw UsageError("view: --scene SCENE is needed: the scene (or model file) the run is of");
  const std::string& run_path = args.positional()[0];
  replay::ReplayOptions options;
  options.frame_budget = static_cast<std::size_t>(args.boundedLong("--frames", replay::kDefaultFrameBudget, 2, 1000000));
  const SceneDescription scene = sceneFrom(args, args.value("--scene", ""));
  const replay::RunTable run = replay::readRunTable(run_path, options.frame_budget, resourceLimitsFrom(args));
  options.title = scene.name + ": " + run_path;
  writeReplayFile(args.value("--out", defaultReplayPath(run_path)), "--out", scene, run, options, args.has("--quiet"));
  return kSuccess;
}

}  // namespace app
}  // namespace lieflow
