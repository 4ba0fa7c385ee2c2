/// \file
/// Assembly of a scene with joints into a MultibodySystem
/// (dynamics/maximal/multibody_system.hpp): bodies in scene order, holonomic
/// joints (spherical, revolute, universal) with the drives of their
/// coordinates, gear-type joints, and a consistent initial state.
///
/// Assembly rules (README "Scene file"):
///  * the bodies' positions and orientations at t = 0 must satisfy every
///    joint (anchors coincide to 1e-6 relative; revolute axes aligned and
///    universal axes orthogonal to 1e-6); the joint angle at t = 0 is
///    `initial_angle(s)` (default 0), which fixes the angle origin;
///  * the initial state is then projected onto the position rows (prescribed
///    motion at t = 0 included) and the velocities onto all velocity rows, in
///    the mass metric: given velocities need only be approximately
///    consistent;
///  * redundant or conflicting constraints (a singular J M⁻¹ Jᵀ at t = 0)
///    are bad input naming the joint.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "dynamics/maximal/multibody_system.hpp"
#include "model/scene.hpp"

namespace lieflow {

struct MultibodyScene {
  std::unique_ptr<multibody::MultibodySystem> system;
  multibody::MultibodyGroupState y0;
  /// Scene joint index of each holonomic model joint.
  std::vector<int> scene_joint;
  /// How far the initial state was moved by the projections (max |Δ| over
  /// position rows, and the largest velocity change).
  double initial_position_correction = 0.0;
  double initial_velocity_correction = 0.0;
  /// The scene carries loads from a program (SceneDescription::user_loads).
  bool has_user_loads = false;
};

/// Whether the scene needs the multibody path (anything but one body with at
/// most one spherical joint to ground, or any scene with loads from a
/// program: they act through the multibody system's forces).
bool needsMultibody(const SceneDescription& scene);

/// Builds the system; throws InvalidInput "SOURCE: joints[k] (name).field"
/// with the reason for bad joint input.
std::unique_ptr<MultibodyScene> assembleMultibody(const SceneDescription& scene);

}  // namespace lieflow
