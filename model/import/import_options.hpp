/// \file
/// What a model importer may leave out (`--ignore`): model_import.hpp.
#pragma once

#include <array>
#include <set>
#include <string>

namespace lieflow {

struct ModelImportOptions {
  /// Feature categories (ignorableFeatures(), model_import.hpp) the importer
  /// may leave out; each left-out element is listed in the scene's import_notes.
  std::set<std::string> ignore;
  /// An MJCF keyframe (`--keyframe NAME|INDEX`; empty: none) whose qpos and
  /// qvel are the scene's initial state; without it a model starts where
  /// MuJoCo's mj_resetData puts it, at qpos0 and at rest.
  std::string keyframe;
  /// A URDF's root link on a free joint to the world (`--floating-base`);
  /// without it the root is fixed to the world, as URDF's tools take it,
  /// and the import says so.
  bool floating_base = false;
  /// `--spin WX,WY,WZ` (rad/s, world axes): every free tree of the model
  /// turns rigidly about its centre of mass at this rate, added to its start
  /// (model/import/free_tree_spin.hpp; the MuJoCo peer starts the same).
  bool has_spin = false;
  std::array<double, 3> spin{{0.0, 0.0, 0.0}};
  bool ignores(const std::string& category) const { return ignore.count(category) > 0; }
};

}  // namespace lieflow
