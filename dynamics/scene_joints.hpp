/// \file
/// A scene's joints as the constraint objects of dynamics/constraints/, with
/// the assembly checks both formulations make: the maximal-coordinate
/// assembly (dynamics/maximal/multibody_scene.hpp) imposes every joint with
/// them, the joint-coordinate one (dynamics/joint_space/articulated_scene.hpp)
/// its loop-closing joints and gears.
#pragma once

#include <cstddef>
#include <string>
#include <unordered_map>

#include "dynamics/constraints/body_pose.hpp"
#include "dynamics/joint_types.hpp"
#include "model/scene.hpp"

namespace lieflow {

/// The rows of scene joint k, a gear-type joint, with its bodies by scene
/// index (the same checks and InvalidInput fields as assembleMultibody);
/// `index` is scene.bodyIndices(), built once by the caller (per joint it
/// made the assembly of chain-100000 quadratic).
Gear sceneGear(const SceneDescription& scene, std::size_t k,
               const std::unordered_map<std::string, int>& index);

/// The constraint of scene joint k (not a gear-type joint) between bodies at
/// the poses pa, pb (main, secondary; groundPose() for the ground), assembled
/// there as assembleMultibody does (the same checks and InvalidInput fields):
/// the joint-coordinate formulation imposes a loop-closing joint with it.
JointConstraint sceneJointConstraint(const SceneDescription& scene, std::size_t k,
                                     const std::unordered_map<std::string, int>& index,
                                     const constraints::BodyPose<double>& pa,
                                     const constraints::BodyPose<double>& pb);

}  // namespace lieflow
