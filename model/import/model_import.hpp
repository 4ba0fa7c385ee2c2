/// \file
/// Model files as scenes (DESIGN.md Additions, "Model files"): wherever a
/// SCENE is accepted, a path ending in `.xml` is read as a MuJoCo MJCF model
/// (through MuJoCo's own compiler, Debian libmujoco-dev) and one ending in
/// `.urdf` as a URDF robot (through urdfdom, liburdfdom-dev). Either library
/// is optional: without it the format is refused naming the package.
///
/// What lieflow cannot represent (contacts, joint limits, friction,
/// actuators, armature, tendons, other equality constraints) is refused with
/// the list of the elements, by name and line, unless the user lets it go
/// (`--ignore contacts,limits,...`); then SceneDescription::import_notes
/// lists what was left out and the commands print it. Never silently.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "model/import/import_options.hpp"
#include "model/resource_limits.hpp"
#include "model/scene.hpp"

namespace lieflow {

/// The categories `--ignore` takes, each with what it covers.
const std::vector<std::pair<std::string, std::string>>& ignorableFeatures();

/// Options from `--ignore LIST` ("contacts,limits"; "all" for every
/// category). Throws InvalidInput (field "`ignore`") naming an unknown category.
ModelImportOptions parseIgnoreList(const std::string& list);

/// Whether `path` names a model file (ends in .xml or .urdf, any case).
bool isModelFile(const std::string& path);
/// Whether `path` names a URDF (ends in .urdf).
bool isUrdfFile(const std::string& path);

/// Whether this build reads MJCF (MuJoCo found) and URDF (urdfdom found).
bool canReadMjcf();
bool canReadUrdf();

/// The scene of a model file. Throws InvalidInput naming the file, the
/// element (with its line where known) and the reason: unreadable or broken
/// XML, an unknown or unsupported joint type, missing or zero mass, a loop the
/// importer cannot close, features not represented (unless ignored), a
/// format whose library this build lacks (naming the Debian package).
SceneDescription importModel(const std::string& path, const ModelImportOptions& options,
                             const ResourceLimits& limits = ResourceLimits());

}  // namespace lieflow
