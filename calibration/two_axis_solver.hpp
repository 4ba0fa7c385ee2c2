/// \file
/// The refinement shared by the hinge and universal-joint fits: two unit axes
/// on ceres::SphereManifold<3>, residual kinds weighted by their estimated
/// noise, multi-start, identifiability, and the covariance.
///
///  1. Noise scales: at the first start, σ̂ₖ² = median‖r‖² / median χ²_d per
///     kind k (d its noise components per sample; robust to outliers and to
///     the start's own error). Each kind is weighted by 1/σ̂ₖ, so residuals of
///     different units combine and the robust loss threshold is in noise σ's.
///  2. Levenberg–Marquardt (dense QR) from every start; the lowest cost wins.
///  3. With several kinds or a robust loss, σ̂ₖ are re-estimated at the
///     solution (RMS with the degrees of freedom shared out, or the median
///     form under a robust loss) and the problem re-solved until they settle
///     (≤ kMaxReweightings times).
///  4. Identifiability (identifiability.hpp) from the Jacobian at the solution.
///  5. Covariance: ceres::Covariance (dense SVD) in SphereManifold tangent
///     coordinates, scaled by the reduced chi-square s² (Ceres assumes unit
///     noise), then converted to axis angles (÷ kSphereTangentPerRadian²).
///     An axis's σ is √trace of its 2×2 block: the RMS angle between the
///     estimate and the truth.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "calibration/fit_types.hpp"
#include "calibration/identifiability.hpp"
#include "calibration/residual_kind.hpp"

namespace lieflow {
namespace calibration {

/// Re-solves after re-estimating the noise scales, at most.
constexpr int kMaxReweightings = 3;
/// Relative change of a noise scale that triggers a re-solve.
constexpr double kReweightTolerance = 0.02;
/// Noise scales are floored here so that exact data give finite weights.
constexpr double kNoiseScaleFloor = 1e-12;

/// A start and where it came from (for the summary).
struct NamedStart {
  AxisPair axes;
  std::string origin;
};

struct TwoAxisSolution {
  AxisPair axes;                      ///< unit axes, signs as the solver left them
  Eigen::Matrix4d covariance;         ///< rad², the two axis angles of each axis (tangent order)
  Eigen::Matrix3d covariance1;        ///< of the unit vector axis 1 (ambient, ≈ rad²)
  Eigen::Matrix3d covariance2;
  double sigma1_rad = 0.0;            ///< √trace of axis 1's angle covariance
  double sigma2_rad = 0.0;
  AxisInformation information;
  AxisFitSummary summary;             ///< all but data, samples and seconds
};

/// Fits the axes to `kinds` (the first is the primary one of the summary's
/// rms_residual) from `starts` (at least one; the first sets the noise
/// scales). Throws NotIdentifiable.
TwoAxisSolution solveTwoAxes(const std::vector<const ResidualKind*>& kinds, const std::vector<NamedStart>& starts,
                             const AxisFitOptions& options, const IdentifiabilityContext& context);

}  // namespace calibration
}  // namespace lieflow
