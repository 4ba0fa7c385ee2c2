/// \file
/// The hinge axis from two gyroscopes by maximum likelihood over the whole
/// motion, and the Cramér–Rao bound of a recording.
///
/// Seel's constraint ‖ω₁ × j₁‖ = ‖ω₂ × j₂‖ (hinge_residuals.hpp) keeps only the
/// lengths of the rates perpendicular to the axis; their phase is lost. A
/// hinge tells more: with R₂ = R₁ exp(φ j₁) C (C j₂ = j₁) the secondary's rate is
///   ω₂ = Cᵀ exp(−φ j₁) ω₁ + φ̇ Cᵀ j₁,                                  (1)
/// so the joint angle φ(t), which the rates about the axis integrate to,
/// turns the main body's perpendicular rate into the secondary's. The model:
/// unknowns the true ω₁,k (3 per sample), φ_k (1 per sample), j₁ (unit,
/// SphereManifold) and C (unit quaternion); measurements ω₁,k + n and ω₂,k + n
/// with white noise σ per axis; φ̇_k the five-point central difference of φ
/// (error h⁴φ⁽⁵⁾/30, below 1e-7 rad/s on 100 Hz recordings of the motions
/// here), so (1) holds at samples 2 … n − 3; φ₀ is held (the rotation of C
/// about j₁ and an offset of φ are one freedom). j₂ = Cᵀ j₁.
///
/// Least squares of the whitened residuals is the maximum-likelihood
/// estimate; its Gauss–Newton covariance of (j₁, C), marginal over the 4n
/// nuisance unknowns, is the Cramér–Rao bound evaluated at the estimate.
/// hingeCramerRao evaluates the same at the true motion: the bound of the
/// recording. Solved from a constraint fit's axes (fitHinge) with the ω₁,k
/// eliminated in closed form and the joint angles' banded normal equations
/// (hinge_likelihood_problem.hpp): the whole problem's minimum and
/// covariance, O(n) per iteration.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "calibration/fit_progress.hpp"
#include "calibration/fit_types.hpp"
#include "calibration/joint_samples.hpp"
#include "liegroup/so3.hpp"

namespace lieflow {
namespace calibration {

/// With fit_gyro_bias, a constant bias per gyroscope is an unknown too (the
/// measurements are ω + b), started at the given values (a constraint fit's
/// biases). Unlike Seel's constraint, the joint angle sees the biases along
/// the axis, but only their difference: the same rate about the axis on both
/// gyroscopes is the whole hinge turning. So the secondary's bias is fitted
/// perpendicular to the start's j₂, and the main one's whole, its component
/// along j₁ being the difference (main − secondary) of the two.
///
/// With fit_time_offset, the secondary sensor's clock offset δ (its sample
/// stamped t was taken at t + δ) is an unknown too: its whole samples
/// `offset_shift` pair main sample k with secondary sample k − shift (a
/// constraint fit's profile chose them), and the fraction ν beyond them moves
/// the secondary's rates back by their slope, ω₂(t_k) ≈ m₂,k−shift − ν ṁ₂
/// (rate_derivative.hpp, as the constraint fit), started at
/// offset_fraction_start.
struct HingeLikelihoodOptions {
  bool fit_gyro_bias = false;
  Eigen::Vector3d gyro_bias_main_start = Eigen::Vector3d::Zero();       ///< rad/s, main body axes
  Eigen::Vector3d gyro_bias_secondary_start = Eigen::Vector3d::Zero();  ///< rad/s, secondary body axes
  /// Several recordings, each with its own biases (fit_gyro_bias) and clock
  /// offset (fit_time_offset), started here: one entry per recording, in
  /// order, and each one's whole samples of offset. Empty: one set of biases
  /// shared by all, started at the two values above (and a clock offset
  /// only on one recording).
  std::vector<SensorNuisanceEstimate> recording_starts;
  std::vector<int> recording_shifts;
  bool fit_time_offset = false;
  int offset_shift = 0;                ///< whole samples
  double offset_fraction_start = 0.0;  ///< s
  /// Each solver iteration's (number, cost), and whether to stop (the
  /// command's progress lines, the Python module's Ctrl-C): fit_progress.hpp.
  FitProgress progress;
  FitInterrupt interrupt;
};

/// Biases (SensorNuisanceEstimate) with HingeLikelihoodOptions::fit_gyro_bias:
/// the secondary's perpendicular to its axis, the main one's along its axis
/// the difference of the two; the axes' σ marginal over them. The clock
/// offset with fit_time_offset: δ = shift · h + ν and ν's σ.
struct HingeLikelihoodFit : SensorNuisanceEstimate {
  Eigen::Vector3d axis_main;       ///< j₁, unit
  Eigen::Vector3d axis_secondary;  ///< j₂ = Cᵀ j₁ (sign: R₁ j₁ = R₂ j₂)
  double sigma_main_deg = 0.0;     ///< RMS angle: √trace of j₁'s ambient covariance
  double sigma_secondary_deg = 0.0;
  double noise_sigma = 0.0;        ///< σ of one gyroscope axis, from the residuals [rad/s]
  int iterations = 0;
  bool converged = false;
  std::string message;             ///< why the solve stopped (solverStopMessage)
  /// With HingeLikelihoodOptions::recording_starts: each recording's biases
  /// and clock offset (the fields of SensorNuisanceEstimate hold the first's).
  std::vector<SensorNuisanceEstimate> recording_nuisance;
};

/// Maximum likelihood from both bodies' gyroscopes, started at a hinge fit's
/// axes (any sign). Throws lieflow::InvalidInput without both bodies'
/// gyroscopes or with non-uniform times, FitFailed when the solve fails.
HingeLikelihoodFit fitHingeLikelihood(const JointSamples& samples, const Eigen::Vector3d& axis_main,
                                      const Eigen::Vector3d& axis_secondary, const HingeLikelihoodOptions& options = {});

/// The same over several recordings of one joint: one j₁ and C (and the
/// biases with fit_gyro_bias: shared, or each recording's own with
/// recording_starts, as its clock offset), each recording's joint angle its
/// own (its samples are not neighbours of another's in time, its sampling
/// interval its own). InvalidInput with fit_time_offset, several recordings
/// and no recording_starts.
HingeLikelihoodFit fitHingeLikelihood(const std::vector<const JointSamples*>& recordings,
                                      const Eigen::Vector3d& axis_main, const Eigen::Vector3d& axis_secondary,
                                      const HingeLikelihoodOptions& options = {});

/// The true motion of a hinge recording, for the bound.
struct HingeTruthSamples {
  std::vector<double> time;
  std::vector<Eigen::Vector3d> main_rate;  ///< true ω₁,k
  std::vector<double> angle;               ///< φ_k
  Eigen::Vector3d axis_main;               ///< j₁
  SO3d mount;                              ///< C
};

/// The Cramér–Rao bound of a recording: the RMS angle σ of j₁ and j₂ that
/// no unbiased estimator from these gyroscopes (noise σ per axis) beats.
struct HingeBound {
  double sigma_main_deg = 0.0;
  double sigma_secondary_deg = 0.0;
};
HingeBound hingeCramerRao(const HingeTruthSamples& truth, double rate_sigma);

}  // namespace calibration
}  // namespace lieflow
