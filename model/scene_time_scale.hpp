/// \file
/// A scene's fastest time scale ω_c [rad/s], from its description alone: the
/// largest of each body's spin rate ‖ω₀‖, each body spring's √(k/I_min), and
/// each joint spring's frequency with its secondary body alone (√(k/I_a), I_a
/// the body's moment of inertia about the joint axis through the anchor at
/// t = 0 by parallel axes; a prismatic spring √(k/m)). The stability scan
/// measures steps in units of 1/ω_c; a scene without a step gets one from it
/// (app/run_setup.hpp).
#pragma once

#include "model/scene.hpp"

namespace lieflow {

/// ω_c of a scene (the file comment). Throws InvalidInput naming the scene
/// when it has no time scale (no spin, no spring).
double characteristicFrequency(const SceneDescription& scene);

}  // namespace lieflow
