/// \file
/// Assembly of a scene into joint coordinates (`--formulation joint`,
/// dynamics/joint_space/articulated_system.hpp): the bodies ordered as a tree
/// from the ground, one joint each to its parent, the joints' angles and the
/// velocities projected in the mass metric (the maximal formulation's
/// projection, so both start from the same motion).
///
/// What the joint formulation covers: scenes whose revolute, universal and
/// spherical joints connect every body to the ground, with the joints'
/// springs, dashpots, moments and prescribed motion, gravity and loads from a
/// program. The tree's joints are a spanning forest chosen with the joints
/// that carry force elements or prescribed motion first; every other joint
/// closes a loop and is kept as constraint rows with multipliers
/// (ArticulatedClosure; it has no coordinate, so a loop whose every joint
/// carries a force element or prescribed motion is refused).
/// Gear-type joints (gear, rack and pinion, differential) are kept as their
/// velocity rows with multipliers too. Bodies not connected to the ground
/// (nor rotation-only) have no joint coordinate to live on: those scenes are
/// refused (InvalidInput naming --formulation, the element and the reason)
/// and run in maximal coordinates.
#pragma once

#include <memory>
#include <string>

#include "dynamics/joint_space/articulated_system.hpp"
#include "model/scene.hpp"

namespace lieflow {

struct ArticulatedScene {
  std::unique_ptr<articulated::ArticulatedSystem> system;
  articulated::ArticulatedState y0;
};

/// Whether the joint formulation covers the scene; if not, `why` says which
/// element it cannot represent and why.
bool articulatedCovers(const SceneDescription& scene, std::string* why);

/// Builds the tree; throws InvalidInput (field "`formulation`") when
/// articulatedCovers is false.
std::unique_ptr<ArticulatedScene> assembleArticulated(const SceneDescription& scene);

}  // namespace lieflow
