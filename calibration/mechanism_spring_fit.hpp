/// \file
/// `lieflow calibrate spring` on a mechanism: the stiffness and damping (and
/// optionally the rest angle) of every sprung or damped joint coordinate of a
/// scene at once — a double pendulum with both joints sprung, a chain of
/// three — from the recorded joint angles (`J.phi`, `J.phi1`, `J.phi2`) or
/// from the bodies' gyroscopes alone (`B.wx, B.wy, B.wz`).
///
/// Model: the tree in joint coordinates (mechanism_flow.hpp), templated
/// on the scalar, advanced between samples by classical RK4 (on ℝ²ⁿ, RKMK4 is
/// RK4) with `substeps` steps per interval, in ceres::Jet arithmetic: the
/// derivatives are those of the discrete integrator, exact.
///
/// Fit (as spring_fit.hpp for one joint): multiple shooting over segments of
/// about a quarter of the fastest period (each segment's initial state a
/// parameter, started from local quadratics of the recorded angles, or from
/// the scene's initial state advanced by the start model when only
/// gyroscopes are recorded), then single shooting from its result — the
/// maximum-likelihood estimate for white noise on what is recorded — whose
/// covariance (ceres::Covariance, scaled by σ̂² = 2·cost/(m − p)) gives σ. The
/// start is the inverse dynamics of the recorded angles when they are all
/// recorded (mechanism_spring_start.hpp: linear least squares, no use of the
/// scene's values), else the scene's values of the fitted coordinates. The
/// bodies' inertias, the geometry and gravity come from the scene (free
/// motion identifies stiffness and damping relative to them).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "calibration/fit_progress.hpp"
#include "calibration/recording.hpp"
#include "model/resource_limits.hpp"
#include "model/scene.hpp"

namespace lieflow {
namespace calibration {

/// What the mechanism fit compares with the model.
enum class MechanismData { kAuto, kAngles, kGyroscopes };
const char* mechanismDataName(MechanismData d);
MechanismData parseMechanismData(const std::string& text, const std::string& field);

/// Where the fit starts: the inverse dynamics of the recorded angles
/// (mechanism_spring_start.hpp), the scene's values, or (auto) the first
/// when every joint angle is recorded (and kInverseDynamicsMinSamples
/// samples), else the second.
enum class MechanismStartFrom { kAuto, kScene, kInverseDynamics };
MechanismStartFrom parseMechanismStart(const std::string& text, const std::string& field);

struct MechanismSpringOptions {
  MechanismData data = MechanismData::kAuto;
  MechanismStartFrom start = MechanismStartFrom::kAuto;
  bool fit_rest_angle = false;
  /// Fit the axis of every sprung or damped revolute joint too (unit, in the
  /// joint's main body's frame, started at the scene's).
  bool fit_axis = false;
  /// Multiple-shooting segments; 0: a quarter of the fastest period each
  /// (1: single shooting only).
  int segments = 0;
  /// RK4 steps per sample interval; 0: h·ω ≤ kMechanismStepTimesFrequency at
  /// the start's fastest frequency.
  int substeps = 0;
  long max_substeps = kMaxSubsteps;
  double continuity_weight = 30.0;
  int max_iterations = 200;
  double function_tolerance = 1e-12;
  double gradient_tolerance = 1e-12;
  double parameter_tolerance = 1e-12;
  int min_samples = 20;
  FitProgress progress;
  FitInterrupt interrupt;
};

/// h·ω of the automatic step (RK4's relative phase error (hω)⁴/120 ≈ 1e-6).
constexpr double kMechanismStepTimesFrequency = 0.1;

/// One fitted joint coordinate: the elements the scene gives it (a spring,
/// a dashpot or both; an absent one is held at 0, its σ 0).
struct CoordinateSpring {
  std::string joint;
  int coordinate = 1;  ///< 1 (revolute; universal φ₁) or 2
  bool stiffness_fitted = true, damping_fitted = true;
  double stiffness = 0.0, damping = 0.0, rest_angle = 0.0;
  double stiffness_sigma = 0.0, damping_sigma = 0.0, rest_angle_sigma = 0.0;
  double start_stiffness = 0.0, start_damping = 0.0;
  /// With MechanismSpringOptions::fit_axis on a revolute joint: its axis in
  /// the main body's frame (`axis_main`) and in the secondary's
  /// (`axis_secondary` = R_refᵀ axis_main, R_ref the scene's relative
  /// rotation at zero angle), and the RMS angle of its error [deg]. A
  /// gyroscope on the secondary body sees the secondary-frame axis; the
  /// main-frame one rests on the scene's zero-angle orientation.
  bool axis_fitted = false;
  Eigen::Vector3d axis = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis_secondary = Eigen::Vector3d::Zero();
  double axis_sigma_deg = 0.0;
};

struct MechanismSpringFit {
  std::vector<CoordinateSpring> coordinates;
  Eigen::MatrixXd covariance;  ///< of (k, c, φ₀) per coordinate, in that order
  std::string data;            ///< "angles" or "gyroscopes"
  double rms_residual = 0.0;   ///< per recorded component
  std::string residual_unit;   ///< "rad" or "rad/s"
  int samples = 0;
  int segments = 1, substeps = 1;
  int iterations = 0;
  bool converged = false;
  std::string message;
  std::vector<std::string> held_fixed;
  /// Where the start came from, and which of its values were left at the
  /// scene's (an inverse-dynamics estimate that was not positive).
  std::string start, start_note;
  double seconds = 0.0;
};

/// Fits every joint coordinate of `scene` that has a spring or a dashpot
/// (the elements it has; its rest angle too with fit_rest_angle when it has
/// a spring).
/// Throws InvalidInput for a scene the fit does not cover (not a tree of
/// revolute and universal joints from the ground, nothing sprung) or a
/// recording without the columns, NotIdentifiable when the data cannot
/// determine the parameters, FitFailed when the model cannot be integrated.
MechanismSpringFit fitMechanismSprings(const SceneDescription& scene, const Recording& recording,
                                       const MechanismSpringOptions& options);

}  // namespace calibration
}  // namespace lieflow
