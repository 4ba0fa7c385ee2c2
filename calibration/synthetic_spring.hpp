/// \file
/// Recordings of joint angles for the spring/dashpot fit's tests and
/// benchmarks, made by the maximal-coordinate multibody path (independent of
/// the reduced model the fit integrates) exactly as
/// `lieflow simulate SCENE --integrator rkmk4 --dt 0.001 --every 10` writes
/// them: 100 Hz, plus Gaussian angle noise as `--noise-angle` adds it.
#pragma once

#include <string>

#include "calibration/spring_data.hpp"
#include "model/scene.hpp"

namespace lieflow {
namespace calibration {

/// A body on a universal joint to ground under gravity with a spring and a
/// dashpot on both coordinates (k₁ = 6, c₁ = 0.05; k₂ = 10 N m/rad,
/// φ₀₂ = 0.1 rad, c₂ = 0.08 N m s/rad), released at (0.4, −0.5) rad. Joint
/// "cross", body "pod".
extern const char* const kSpringUniversalSceneJson;

/// The clean angles of joint `joint` (`coordinates` = 1: J.phi; 2: J.phi1,
/// J.phi2) at 100 Hz over [0, t_end] (rkmk4, h = 1e-3, every 10th step).
SpringData simulatedJointAngles(const SceneDescription& scene, const std::string& joint, int coordinates,
                                double t_end);

/// `data` with N(0, σ²) added to every recorded angle, coordinate by
/// coordinate in time order, from std::mt19937_64(seed).
SpringData withAngleNoise(SpringData data, double sigma, unsigned seed);

}  // namespace calibration
}  // namespace lieflow
