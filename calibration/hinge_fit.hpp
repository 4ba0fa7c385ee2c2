/// \file
/// `lieflow calibrate hinge`: the revolute axis of a joint in both bodies'
/// frames, j₁ (main) and j₂ (secondary), from the columns the recording has:
///
///  - gyroscopes only: GyroHingeResidual (Seel et al. 2012's constraint in
///    Sampson form), started from the minima of a global search
///    (hinge_search.hpp: the closed forms of hingeStartsFromRates and a grid
///    of 36 axis pairs, descended cheaply; Ceres refines the best and those
///    within Δχ² ≤ 30 of it, at most 4, for the solver's ambiguity check);
///    the relative sign from hingeRelativeSign;
///  - orientations only: OrientationHingeResidual, started from the exact
///    least-squares solution hingeAxesFromOrientations;
///  - both: OrientationHingeResidual and GyroHingeResidual, each weighted by
///    its estimated noise, started as with orientations. (The gyroscope
///    constraint involves no orientation, so the two kinds have independent,
///    homoscedastic noise; a relative-rate residual R₁ᵀR₂ω₂ − ω₁ ∥ j₁ would
///    carry orientation noise scaled by ‖ω‖, which one weight cannot whiten.)
///
/// With gyroscopes, their white noise is estimated from the rates' own third
/// differences (whiteNoiseFromDifferences, RMS of both bodies') and the fitted
/// residual is checked against it (AxisFitOptions::max_residual_to_noise).
///
/// Without AxisFitOptions::fit_gyro_bias the fit is repeated with the
/// biases (AxisFitOptions::check_gyro_bias): a gyroscope residual lower by
/// Δχ² > 30 marks it converged = false with a message to rerun with them (an
/// uncorrected 0.05 rad/s bias had left the axes many σ off unnoticed).
///
/// With AxisFitOptions::estimator = kLikelihood (gyroscopes only), the
/// constraint fit (its refusals included) starts the maximum-likelihood fit
/// over the joint angle (hinge_likelihood.hpp), whose axes and σ are reported.
///
/// Reported signs: R₁j₁ = R₂j₂ (from the data where they tell), and the
/// largest-magnitude component of j₁ positive (the hinge's own direction is a
/// convention: turning it over only negates the joint angle).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "calibration/fit_types.hpp"
#include "calibration/hinge_likelihood.hpp"
#include "calibration/hinge_segments.hpp"
#include "calibration/identifiability.hpp"
#include "calibration/joint_samples.hpp"

namespace lieflow {
namespace calibration {

/// Biases (SensorNuisanceEstimate) with AxisFitOptions::fit_gyro_bias:
/// perpendicular to the axis (the component along a hinge's axis leaves
/// ‖ω × j‖ unchanged: not observable, reported 0) — or, with the likelihood
/// estimator, as HingeLikelihoodFit says; the clock offset with fit_time_offset.
struct HingeFit : SensorNuisanceEstimate {
  Eigen::Vector3d axis_main;       ///< j₁, unit, main body frame
  Eigen::Vector3d axis_secondary;  ///< j₂, unit, secondary body frame
  double sigma_main_deg = 0.0;     ///< 1σ angle of j₁ (RMS angular error)
  double sigma_secondary_deg = 0.0;
  std::string sign;                ///< how the signs were fixed
  Eigen::Matrix4d covariance;      ///< rad², axis angles (j₁'s two, then j₂'s)
  /// With HingeEstimator::kLikelihood: the refinement (its σ is the
  /// Cramér–Rao bound at the estimate) and the constraint fit's σ it replaced.
  HingeLikelihoodFit likelihood;
  double constraint_sigma_main_deg = 0.0;
  double constraint_sigma_secondary_deg = 0.0;
  /// How well a hinge explains the data the fit used, as a fraction of the
  /// signal each residual compares: gyroscopes RMS(‖ω₁×j₁‖ − ‖ω₂×j₂‖) over
  /// the RMS of their mean, accelerometers RMS(j₁·f_c,1 − j₂·f_c,2) over the
  /// RMS of ‖f_c‖ at the joint centre (−1: not used). Noise alone gives about
  /// √2 σ/|ω⊥|; a real walking knee about 0.5 (gyroscopes) and 0.2.
  double gyro_misfit = -1.0;
  double accelerometer_misfit = -1.0;
  /// With AxisFitOptions::low_pass_hz: the cutoff and the filter's white-noise
  /// power gain (low_pass.hpp); 0 without a filter.
  double low_pass_hz = 0.0;
  double low_pass_noise_gain = 0.0;
  /// Why that filter, or none (asked for, or the wobble check's finding).
  std::string low_pass_reason;
  /// The model checked across segments of the recording (hinge_segments.hpp):
  /// when they disagree, sigma_*_deg above include their spread.
  ModelCheck model_check;
  AxisInformation information;
  AxisFitSummary summary;
  /// With several recordings and fit_gyro_bias or fit_time_offset: each
  /// recording's biases and clock offset, in the recordings' order (the
  /// fields of SensorNuisanceEstimate above hold the first's); empty otherwise.
  std::vector<SensorNuisanceEstimate> recording_nuisance;
  /// The estimator used (never kAuto) and why (hinge_estimator.hpp).
  HingeEstimator estimator = HingeEstimator::kConstraint;
  std::string estimator_reason;

  /// The larger of the two axes' σ: the `axis_sigma_deg` of the JSON output.
  double axisSigmaDeg() const { return sigma_main_deg > sigma_secondary_deg ? sigma_main_deg : sigma_secondary_deg; }
};

/// Throws lieflow::InvalidInput when the samples lack the columns the fit
/// needs (or that options.use asks for), NotIdentifiable when the data cannot
/// determine the axes.
HingeFit fitHinge(const JointSamples& samples, const AxisFitOptions& options = AxisFitOptions());

/// One axis pair from several recordings of the same joint (the same two
/// bodies, the same columns): each recording keeps its own time series (its
/// own filter, noise level, joint angle and sampling interval; no stencil
/// reaches from one into the next), and they share j₁ and j₂. With
/// fit_gyro_bias and fit_time_offset each recording's biases and clock
/// offset are its own (HingeFit::recording_nuisance); without biases, the
/// bias check runs on each. The
/// model check fits each recording alone (checkHingeAcrossRecordings): where
/// they disagree beyond their σ, σ includes their spread.
HingeFit fitHinge(const std::vector<JointSamples>& recordings, const AxisFitOptions& options = AxisFitOptions());

}  // namespace calibration
}  // namespace lieflow
