/// \file
/// A model (model_description.hpp) as a lieflow scene: welded links merged
/// into one rigid body each, every other joint written in the frames of the
/// bodies it joins.
///
/// Welding costs nothing at run time ("leave out what a scene does not
/// need"): links joined by fixed joints become one body with the combined
/// mass m = Σ mᵢ, centre c = Σ mᵢ cᵢ / m and inertia about c
///   I = Σ ( Iᵢ + mᵢ (‖dᵢ‖² 1 − dᵢ dᵢᵀ) ),  dᵢ = cᵢ − c   (parallel-axis theorem, world axes),
/// written in the frame of the group's root link (the one nearest the model's
/// root), whose name the body takes. Links welded to the world are part of
/// the ground. A model's joint becomes the scene joint of the same name with
/// the parent's body as `main` and the child's as `secondary`; a free joint
/// leaves its child a free body; URDF mimic / MJCF joint equalities between
/// two revolute joints of one parent become gear rows (α = −multiplier).
#pragma once

#include "model/import/model_description.hpp"
#include "model/scene.hpp"

namespace lieflow {
namespace model_import {

/// The scene of `model`. Throws InvalidInput naming the model's file, the
/// element (and its line) and the reason: a moving body without mass or with
/// a singular inertia, a joint between links welded together, a coupling
/// that is not a gear between revolute joints of one parent.
SceneDescription sceneFromModel(const ModelDescription& model);

/// "link 'NAME' (line N)": how messages name a model element.
std::string elementLabel(const std::string& kind, const std::string& name, int line);

}  // namespace model_import
}  // namespace lieflow
