/// \file
/// `lieflow import MODEL [--out SCENE.json] [--ignore LIST] [--keyframe K]`: a MuJoCo MJCF
/// or URDF model as the lieflow scene it becomes (model/import/), written so
/// that it can be read and edited, then run like any scene file.
#include <iostream>

#include "app/arguments.hpp"
#include "app/cli.hpp"
#include "app/commands.hpp"
#include "app/output_files.hpp"
#include "model/import/model_import.hpp"
#include "model/scene_writer.hpp"

namespace lieflow {
namespace app {

int runImport(int argc, char** argv) {
  const Arguments args(argc, argv, {"--out", "--ignore", "--keyframe", "--spin", "--max-input-mb", "--max-bodies"},
                       modelSwitches());
  if (args.help()) {
    std::cout << "usage: lieflow import MODEL.xml|MODEL.urdf [--out SCENE.json] [--ignore LIST] [--keyframe K]\n"
                 "                      [--floating-base] [--spin WX,WY,WZ] [--verbose]\n\n"
                 "Writes the lieflow scene a model file becomes (to stdout without --out). MJCF is read by\n"
                 "MuJoCo's compiler (libmujoco-dev: " << (canReadMjcf() ? "present" : "absent in this build")
              << "), URDF by urdfdom (liburdfdom-dev: " << (canReadUrdf() ? "present" : "absent in this build")
              << ").\nWelded links are merged into one body; a URDF's root link is fixed to the world (the import\n"
                 "says so), or with --floating-base a body on a free joint (a legged robot's trunk). What lieflow\n"
                 "cannot represent is refused with the list of elements, unless --ignore names its category:\n";
    for (const auto& [name, what] : ignorableFeatures()) std::cout << "  " << name << ": " << what << "\n";
    std::cout << "  all: every category above\nWhat was ignored is printed to stderr, one line per category with the count\n"
                 "and the first elements (--verbose: every element). An MJCF model starts at qpos0 "
                 "and at rest, as\nMuJoCo's mj_resetData puts it, or at the qpos and qvel of --keyframe NAME|INDEX.\n"
                 "--spin WX,WY,WZ adds to every free tree (a body on a free joint and what hangs from it) a rigid\n"
                 "turn at that rate (rad/s, world axes) about the tree's centre of mass, its joints' rates\n"
                 "unchanged: a floating robot set tumbling, whose limbs the turn flings (from rest in uniform\n"
                 "gravity a floating tree does not move relative to itself); --with-mujoco starts MuJoCo the same.\n"
                 "The same --ignore, --keyframe, --floating-base, --spin and --verbose work on simulate, study and stability, which take\nmodel files "
                 "wherever they take a SCENE.\n";
    return kSuccess;
  }
  if (args.positional().size() != 1) throw UsageError("import needs exactly one MODEL (see lieflow import --help)");
  const std::string& model = args.positional()[0];
  if (!isModelFile(model)) throw UsageError("import: '" + model + "' is not a model file (.xml for MJCF, .urdf)");
  const std::string text = sceneToJson(sceneFrom(args, model));
  if (!args.has("--out")) {
    std::cout << text;
    return kSuccess;
  }
  AtomicOutputFile out(args.value("--out", ""), "--out");
  out.stream() << text;
  out.commit();
  return kSuccess;
}

}  // namespace app
}  // namespace lieflow
