/// \file
/// `--spin WX,WY,WZ`: a model's free trees set turning. Every tree of bodies
/// with no joint to the ground (a free root and what hangs from it) gets the
/// rigid rotation ω (world axes, rad/s) about its own centre of mass added to
/// its velocities:
///   ωᵢ ← ωᵢ + Rᵢᵀ ω   (body axes),   vᵢ ← vᵢ + ω × (cᵢ − c),   c = Σ mⱼ cⱼ / Σ mⱼ,
/// so the joints' rates are unchanged and the tree's centre of mass keeps its
/// velocity: a start in motion for a floating robot, whose limbs a turn
/// flings apart (from rest in uniform gravity a floating tree does not move
/// relative to itself). The MuJoCo peer adds the same motion to its free
/// joints' qvel (peers/mujoco/mujoco_peer.cpp).
#pragma once

#include <string>

#include <Eigen/Core>

#include "model/scene.hpp"

namespace lieflow {
namespace model_import {

/// Adds the turn ω to every free tree of `scene`. Throws InvalidInput
/// naming `path`'s --spin when the scene has no free tree.
void spinFreeTrees(const Eigen::Vector3d& omega, const std::string& path, SceneDescription* scene);

}  // namespace model_import
}  // namespace lieflow
