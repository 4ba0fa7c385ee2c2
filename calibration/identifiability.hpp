/// \file
/// Whether data determine two unit axes: an analysis of the Fisher
/// information of the four axis angles (each axis turns about two directions
/// perpendicular to itself).
///
/// With J the Jacobian of the whitened residuals (each divided by the noise
/// scale σ̂ of its kind) with respect to those angles and s² the reduced
/// chi-square, H = JᵀJ = Σᵢ λᵢ vᵢvᵢᵀ gives per principal direction vᵢ the 1σ
/// uncertainty σᵢ = s/√λᵢ (rad).
///
/// That is not enough: a direction the motion does not reach still picks up
/// information from the noise itself (the residual's derivative is then noise
/// too), σ ≈ 1/√m rad for m noise components — about 2° for m = 1000, a
/// confident wrong answer if σ alone were checked. That part of J is white
/// noise from sample to sample, whereas the part the motion gives changes
/// smoothly when the recording samples the motion well, so second differences
/// along time (Δ²Jₖ = Jₖ₊₁ − 2Jₖ + Jₖ₋₁; Var Δ²n = 6 Var n for white n) estimate
/// the noise's share: H_noise = ⅙ Σ Δ²Jₖᵀ Δ²Jₖ (within each kind of residual),
/// and H_motion = H − H_noise. The generalized eigenvalues
/// ρ of H_motion v = ρ H_noise v measure, direction by direction, how much more
/// the motion tells than the noise: ≈ 0 (±√(1/m)) where only noise informs,
/// ≫ 1 for a well-excited direction.
///
/// All four directions must have λ not numerically zero, σ ≤ max_sigma_deg,
/// and ρ ≥ min_motion_to_noise.
///
/// These are local tests at the solution. Two global ones follow in the
/// solver (two_axis_solver.hpp, steps 6 and 7): another minimum that fits
/// as well, and a cost far from quadratic over the 3σ region — what short
/// recordings fail (0.5–1 s of the `hinge-pair` scene at 100 Hz passed the
/// local tests with σ of 1–2° and errors of 10–34°). The second-difference estimate assumes at
/// least ~10 samples per period of the motion's fastest component (slower
/// recordings look like noise and are refused).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "calibration/fit_types.hpp"

namespace lieflow {
namespace calibration {

/// λᵢ below this fraction of λ_max are numerically zero (the data carry no
/// information at all in that direction, e.g. exact data at rest).
constexpr double kInformationRankTolerance = 1e-10;

/// Names for the messages of NotIdentifiable.
struct IdentifiabilityContext {
  std::string axis1;  ///< e.g. "the axis in the main body 'A'"
  std::string axis2;
  std::string hint;   ///< what motion the fit needs
  /// Per nuisance block, the recording it belongs to (" [file]", as the
  /// residual kinds' names end); empty with one recording.
  std::vector<std::string> nuisance_blocks;
};

struct AxisInformation {
  Eigen::Matrix4d information = Eigen::Matrix4d::Zero();        ///< H, whitened, per rad²
  Eigen::Matrix4d noise_information = Eigen::Matrix4d::Zero();  ///< H_noise
  double reduced_chi_square = 0.0;                              ///< s²
  Eigen::Vector4d eigenvalues = Eigen::Vector4d::Zero();        ///< λ of H, ascending
  Eigen::Matrix4d directions = Eigen::Matrix4d::Zero();         ///< their v (columns)
  Eigen::Vector4d sigma_rad = Eigen::Vector4d::Zero();          ///< σ (∞ where λ = 0)
  Eigen::Vector4d motion_to_noise = Eigen::Vector4d::Zero();    ///< ρ, ascending
  Eigen::Matrix4d motion_directions = Eigen::Matrix4d::Zero();  ///< their v (columns)

  /// Directions of H that count as determined under `options` (all four
  /// fail when the smallest ρ is below the threshold).
  int determined(const AxisFitOptions& options) const;
};

AxisInformation analyseInformation(const Eigen::Matrix4d& information, const Eigen::Matrix4d& noise_information,
                                   double reduced_chi_square);

/// Throws NotIdentifiable when fewer than `options.min_samples` samples.
void requireEnoughSamples(int samples, const AxisFitOptions& options);

/// Throws NotIdentifiable, naming the weakest direction and the context's
/// hint, unless all four directions are determined.
void requireIdentifiable(const AxisInformation& info, const AxisFitOptions& options,
                         const IdentifiabilityContext& context);

}  // namespace calibration
}  // namespace lieflow
