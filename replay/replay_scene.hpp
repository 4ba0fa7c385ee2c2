/// \file
/// The scene half of a replay page (replay_scene.cpp): shapes, inertia
/// boxes and joint markers as the player's JSON. Internal to replay/.
#pragma once

#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "model/scene.hpp"

namespace lieflow {
namespace replay {

/// Bytes of mesh data a page may still take, and the file formats taken
/// (the page inlines a loader per format).
struct MeshBudget {
  std::uint64_t left = 0;
  std::set<std::string> formats;
};

struct SceneData {
  nlohmann::json bodies;  ///< [{name, shapes}], in the scene's order
  nlohmann::json ground;  ///< shapes fixed to the world
  nlohmann::json joints;  ///< [{name, body (−1: ground), anchor, axes}]
  std::vector<double> reach;  ///< per body: its shapes' farthest point from its centre of mass
  std::size_t boxes = 0;      ///< bodies drawn as their inertia's box
};

SceneData sceneData(const SceneDescription& scene, MeshBudget* budget, std::vector<std::string>* notes);

/// The solid box with `body`'s mass and principal moments, in body axes.
VisualShape inertiaBox(const BodyDescription& body);

/// One shape as the player's JSON, or null when it cannot be drawn (a mesh
/// file missing, of an unknown format or past the budget: `notes` says which).
nlohmann::json shapeData(const VisualShape& shape, MeshBudget* budget, std::vector<std::string>* notes);

/// RFC 4648 base64 of `size` bytes.
std::string base64(const void* data, std::size_t size);

}  // namespace replay
}  // namespace lieflow
