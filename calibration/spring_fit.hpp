/// \file
/// `lieflow calibrate spring`: the stiffness k, damping c and optionally the
/// rest angle φ₀ of one coordinate of a revolute or universal joint, from its
/// recorded angle, with the rest of the mechanism taken from a scene
/// (calibration/spring_joint.hpp: one body on the joint to ground).
///
/// Model: the one-body tree in the joint formulation's dynamics on any scalar
/// (dynamics/joint_space/scalar_dynamics.hpp, the mechanism fit's), advanced
/// between samples by lieflow's RKMK stepper (integrators/rkmk.hpp) with
/// `substeps` steps per sample interval, in ceres::Jet arithmetic, so that
/// the derivatives with respect to (k, c, φ₀) and the initial states are
/// those of the discrete integrator — exact, not finite differences.
///
/// Fit (Bock & Plitt 1984 multiple shooting, then single shooting):
///  1. Multiple shooting: the record is cut into S segments; each segment's
///     initial state s_i = (φ, φ̇)(t_i) is a parameter, started from a local
///     quadratic through the samples. Residuals: predicted − recorded angle
///     at every sample, plus the continuity defects w·(x(t_{i+1}; s_i) − s_{i+1})
///     (angles weighted by w, rates by w/ω). Short segments keep the problem
///     nearly linear, so that starts far from the truth still converge.
///  2. Single shooting from the result: (k, c, φ₀, s₀) only, one trajectory
///     through all samples — the maximum-likelihood estimate for white angle
///     noise, with exact continuity.
///  3. Covariance of the single-shooting problem (ceres::Covariance), scaled
///     by the residual variance σ̂² = 2·cost/(m − p).
/// Free decay identifies k/I and c/I only: the inertia I (and the gravity
/// moment) come from the scene, and the summary lists what was held fixed.
#pragma once

#include <optional>

#include "calibration/fit_progress.hpp"
#include "model/resource_limits.hpp"
#include <string>
#include <vector>

#include <Eigen/Core>

#include "calibration/spring_data.hpp"
#include "calibration/spring_joint.hpp"

namespace lieflow {
namespace calibration {

enum class Shooting { kMultiple, kSingle };

const char* shootingName(Shooting s);
/// "multiple" / "single"; InvalidInput naming `field` otherwise.
Shooting parseShooting(const std::string& text, const std::string& field);

struct SpringFitOptions {
  /// The fitted coordinate: 0 (revolute; universal φ₁) or 1 (universal φ₂).
  int coordinate = 0;
  bool fit_rest_angle = false;
  /// Hold the damping at --damping-start (or the scene's) instead of fitting it.
  bool hold_damping = false;
  /// Starts; when unset, from the recorded angle (spring_start.hpp), else
  /// from the scene's spring and dashpot.
  std::optional<double> stiffness_start, damping_start, rest_angle_start;
  Shooting shooting = Shooting::kMultiple;
  /// Multiple shooting segments; 0: a quarter of the start's period each.
  int segments = 0;
  /// "rkmk-euler", "rkmk-heun", "rkmk3" or "rkmk4".
  std::string integrator = "rkmk4";
  /// Steps per sample interval; 0: enough that h·ω ≤ kStepTimesFrequency at
  /// √3 times the start's frequency.
  int substeps = 0;
  /// Most integration substeps of one shooting pass over the record (the
  /// substeps per sample interval times the intervals); beyond it the fit is
  /// refused before it starts (InvalidInput naming --max-substeps): a time
  /// column in milliseconds or an absurd stiffness start would otherwise run
  /// without end.
  long max_substeps = kMaxSubsteps;
  /// Called at every solver iteration (fit_progress.hpp); may be empty.
  FitProgress progress;
  /// Asked at every solver iteration; true stops the solve (may be empty).
  FitInterrupt interrupt;
  /// Continuity weight w of the multiple-shooting defects.
  double continuity_weight = 30.0;
  // ceres::Solver::Options (Levenberg–Marquardt).
  int max_iterations = 200;
  double function_tolerance = 1e-12;
  double gradient_tolerance = 1e-12;
  double parameter_tolerance = 1e-12;
  // Identifiability: fewer samples, a 1σ of k above max_relative_sigma times
  // the restoring stiffness (k plus gravity's), or
  // a recorded motion whose RMS about equilibrium is below
  // min_motion_to_noise times the residual RMS, throw NotIdentifiable.
  int min_samples = 20;
  double max_relative_sigma = 0.5;
  double min_motion_to_noise = 1.5;
};

/// h·ω bound of the automatic step (rkmk4's relative frequency error is then
/// (hω)⁴/120 ≈ 1e-6).
constexpr double kStepTimesFrequency = 0.1;

struct SpringFit {
  double stiffness = 0.0, damping = 0.0, rest_angle = 0.0;
  double stiffness_sigma = 0.0, damping_sigma = 0.0, rest_angle_sigma = 0.0;
  double correlation_stiffness_damping = 0.0;
  /// 3×3 covariance of (k, c, φ₀) (zero row/column for a held φ₀).
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  /// Fitted state at the first sample: φ (N), φ̇ (N).
  Eigen::VectorXd initial_state;
  /// Generalized inertia of the coordinate at the fitted rest angle (kg m²)
  /// and what it implies: ω_n = √(k_eff/I), ζ = c / (2 I ω_n), with k_eff
  /// including the gravity stiffness there.
  double inertia = 0.0;
  double natural_frequency = 0.0, damping_ratio = 0.0;
  double rms_residual = 0.0;  ///< rad, per recorded angle
  int samples = 0;
  int iterations = 0;         ///< Levenberg–Marquardt iterations, both stages
  int multiple_shooting_iterations = 0, single_shooting_iterations = 0;
  bool converged = false;
  std::string message;
  std::vector<std::string> held_fixed;
  std::string start;          ///< where the start came from
  double start_stiffness = 0.0, start_damping = 0.0, start_rest_angle = 0.0;
  std::string shooting;
  int segments = 1;
  double max_continuity_defect = 0.0;  ///< after multiple shooting, rad
  std::string integrator;
  int substeps = 1;
  double seconds = 0.0;
};

/// Fits the spring and dashpot of `options.coordinate`. Throws InvalidInput
/// for bad options and NotIdentifiable when the data cannot determine them.
SpringFit fitSpring(const SpringJoint& joint, const SpringData& data, const SpringFitOptions& options);

}  // namespace calibration
}  // namespace lieflow
