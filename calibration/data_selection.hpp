/// \file
/// Which of a joint's recorded column groups a fit uses, and the per-sample
/// quantities the residuals share (relative orientation, relative rate).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "calibration/fit_types.hpp"
#include "calibration/joint_samples.hpp"

namespace lieflow {
namespace calibration {

struct DataSelection {
  bool orientations = false;
  bool rates = false;
  bool accelerometers = false;  ///< with rates (the centre's acceleration needs ω, ω̇)
  /// "gyroscopes", "orientations", "orientations+gyroscopes", each with
  /// "+accelerometers" when they are used.
  std::string name() const;
};

/// The groups `use` asks for (kAuto: all that both bodies have; the
/// accelerometers only where `accelerometers_used` — the hinge fit — and
/// with the gyroscopes). Throws lieflow::InvalidInput naming the recording,
/// the body and the missing columns when a requested group, or every group,
/// is missing, or when accelerometers are asked of a fit that does not use
/// them. `joint` names the fit in the message ("hinge").
DataSelection selectData(const JointSamples& samples, DataUse use, const std::string& joint,
                         bool accelerometers_used = false);

/// Before a fit that uses both: each body's quaternions must turn as its
/// gyroscopes say. The quaternions' rates u_k = log(R_kᵀR_{k+1})/Δt (body
/// frame) are compared with the gyroscopes' g_k = (ω_k + ω_{k+1})/2 through
/// the rotation C that best maps g onto u (Kabsch: C = U diag(1, 1, det) Vᵀ
/// from Σ u gᵀ = U S Vᵀ); noise averages out of Σ u gᵀ, so a C turned by more
/// than kFrameMismatchDeg that fits the rates significantly better than the
/// identity (Σ|u − g|² − Σ|u − Cg|² above kFrameSignificance times the
/// per-sample misfit Σ|u − Cg|²/(n − 1): a Δχ² that 3 parameters fitted to
/// noise do not reach; a motion about a single axis leaves C free about the
/// others, and C then fits no better than I) means the quaternions are not in the
/// gyroscopes' frame (a real sensor's fused orientation output can be in
/// another). Throws
/// lieflow::InvalidInput naming the recording, the body, the angle and axis of
/// C and what to do, instead of a fit that fails at the end ("residual far
/// above the noise"). Bodies that barely turn (RMS |g| below
/// kMinConsistencyRate) are not checked.
constexpr double kFrameMismatchDeg = 5.0;
constexpr double kFrameSignificance = 100.0;
constexpr double kMinConsistencyRate = 0.05;  // rad/s
void checkOrientationsAgreeWithRates(const JointSamples& samples);

/// R₁ᵀR₂ per sample (the secondary body's orientation in the main body's frame).
std::vector<Eigen::Matrix3d> relativeOrientations(const JointSamples& samples);

/// R₁ᵀR₂ω₂ − ω₁ per sample (the relative angular velocity in the main body's frame).
std::vector<Eigen::Vector3d> relativeRates(const JointSamples& samples, const std::vector<Eigen::Matrix3d>& R12);

/// The white noise σ of one axis of a recorded vector signal (a gyroscope's
/// rates), estimated without any model of the motion from third differences
/// along time: Δ³x = x₊₂ − 3x₊₁ + 3x − x₋₁ has variance 20σ² for white noise,
/// while a smooth motion contributes x⃛h³, far below it when the recording
/// samples the motion well (on the `hinge-pair` scene at 100 Hz the motion
/// adds < 0.2 % of σ = 0.01 rad/s; second differences would add 15 %, and
/// their motion term grows as ω³h²). Robust median form (1.4826 · median
/// |Δ³x| / √20, over all three axes), so outliers and a few jumps do not
/// count. Correlated noise (low-pass-filtered signals) is underestimated.
/// 0 with fewer than 4 samples.
double whiteNoiseFromDifferences(const std::vector<Eigen::Vector3d>& x);

/// The same for recorded orientations R exp(η), η white with σ per axis (rad):
/// the increments log(Rₖᵀ Rₖ₊₁) = (motion) + ηₖ₊₁ − ηₖ (to first order; the
/// turn ωh between samples mixes ηₖ by a negligible angle) are a vector
/// signal whose second differences are third differences of η.
double orientationNoiseFromDifferences(const std::vector<SO3d>& R);

}  // namespace calibration
}  // namespace lieflow
