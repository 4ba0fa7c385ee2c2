/// \file
/// A scene as the JSON text of a scene file (docs/scene-format.md): the
/// inverse of parseScene, used by `lieflow import MODEL --out SCENE.json` so
/// that an imported model can be read and edited. Numbers are written so
/// that they round-trip (parseScene of the text gives the same doubles).
#pragma once

#include <string>

#include "model/scene.hpp"

namespace lieflow {

/// The scene file of `scene` (two-space indentation, keys in the order of
/// docs/scene-format.md). Loads a program supplies (UserLoads) have no JSON
/// form and are not written.
std::string sceneToJson(const SceneDescription& scene);

}  // namespace lieflow
