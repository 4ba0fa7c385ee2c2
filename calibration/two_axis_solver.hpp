/// \file
/// The refinement shared by the hinge and universal-joint fits: two unit axes
/// on ceres::SphereManifold<3>, residual kinds weighted by their estimated
/// noise, multi-start, identifiability, and the covariance.
///
///  1. Noise scales: at the first start, σ̂ₖ² = median‖r‖² / median χ²_d per
///     kind k (d its noise components per sample; robust to outliers and to
///     the start's own error). Each kind is weighted by 1/σ̂ₖ, so residuals of
///     different units combine and the robust loss threshold is in noise σ's.
///  2. Levenberg–Marquardt (dense QR) from every start; the lowest cost wins,
///     and every end point is kept for step 6.
///  3. With several kinds or a robust loss, σ̂ₖ are re-estimated at the
///     solution (RMS with the degrees of freedom shared out, or the median
///     form under a robust loss) and the problem re-solved until they settle
///     (≤ kMaxReweightings times).
///     A kind whose noise is known independently of the fit
///     (ResidualKind::independentNoise: the gyroscopes' third differences)
///     is compared with it: a residual scale (median form) above
///     max_residual_to_noise times it marks the fit converged = false, with
///     the reason as the message (a local minimum no start escaped, or a
///     model that does not describe the data).
///  4. Identifiability (identifiability.hpp) from the Jacobian at the solution.
///  5. Covariance: the inverse of step 4's information JᵀJ (the axes per
///     radian of rotation and the nuisance; refused below an eigenvalue ratio
///     of 1e-14, as Ceres' covariance, of JᵀJ scaled to a unit diagonal: the
///     axes and the nuisance differ in units), scaled by the reduced chi-square s²
///     (the information is of unit noise). It replaced ceres::Covariance
///     (dense SVD of a second Jacobian of the same problem), which it matches
///     to 2.8e-11 relative over the 9093 fits of tests/calibration.
///     An axis's σ is √trace of its 2×2 block: the RMS angle between the
///     estimate and the truth.
///  6. Ambiguity: another end point more than distinct_minimum_sigmas σ from
///     the best whose cost exceeds the best's by Δχ² = 2Δcost/s² <
///     ambiguity_chi_square (χ²₄ 99 %) throws NotIdentifiable ("two axis
///     pairs N° apart fit the data equally well"). s² is the larger of the
///     fit's and the independently known noise (short recordings let the fit
///     absorb noise, seen down to 0.7 of it, which would inflate Δχ²).
///  7. The 3σ region: Δχ² at ±3σ along the four principal directions of the
///     covariance against 9. More than (1 + quadratic_tolerance) · 9 (a
///     curved valley: the error along it can be tens of σ) throws
///     NotIdentifiable; less than kSecantBand · 9 (a cost flatter than the
///     Gauss–Newton curvature, e.g. at large noise) widens σ in that
///     direction to the actual rise (below kFlatSecant · 9: NotIdentifiable).
///     The cost is evaluated by the kinds' functors directly (ResidualKind::cost).
///  7b. The nuisance (biases, clock fraction), per recording: where the
///     estimate ν̂ lies more than kNuisanceCheckSigmas σ from zero, the
///     cost's rise from it to zero (the axes held) against its curvature's
///     prediction ν̂ᵀH_νν ν̂/s²; below kFlatSecant of it (a short recording
///     whose biases turn its few rate directions to fit the noise: a narrow
///     valley far from the truth) NotIdentifiable. Not under a robust loss.
///  8. Under a robust loss (a joint that is not an ideal hinge: soft tissue,
///     a real knee) or on low-passed signals (LowPassNoise), σ is a sandwich, H⁻¹ M H⁻¹ (Huber 1967; White 1980):
///     H = J̃ᵀJ̃ of the robustified, whitened residuals (Ceres' corrector) and
///     M the covariance of the score Σ J̃ᵀr̃ estimated by batch means
///     (kSandwichBatches contiguous stretches of each kind's samples:
///     M = B/(B−1) Σ_b (S_b − S̄)(S_b − S̄)ᵀ, S_b the batch's summed score),
///     so that misfit and residuals correlated over anything shorter than a
///     batch (a gait cycle) count, without a noise model. The larger (by
///     trace) of it and the Gauss–Newton covariance is reported: on white
///     noise both are right on average, and the sandwich, estimated from B
///     batch sums, scatters (mean (error/σ)² 1.52 alone on 50 recordings).
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
/// Batches of the sandwich covariance (step 8); fewer when a kind has
/// fewer than kSandwichMinBatchSamples samples per batch.
constexpr int kSandwichBatches = 16;
constexpr int kSandwichMinBatchSamples = 10;
/// Below this step (rad) the quadratic check (AxisFitOptions::quadratic_tolerance) is skipped.
constexpr double kQuadraticCheckFloor = 1e-6;
/// Where the cost rises by less than this fraction of its quadratic value at
/// ±quadratic_check_sigmas σ, σ is widened to the actual rise; closer to
/// quadratic, the Gauss–Newton σ stands (tests/calibration/unit_axis_test.cpp
/// checks it against finite differences to 1e-4).
constexpr double kSecantBand = 0.9;
/// The quadratic check refuses a cost that rises by less than this fraction
/// of its quadratic value at ±quadratic_check_sigmas σ (σ would grow by > 2).
constexpr double kFlatSecant = 0.25;
/// The nuisance check (step 7b) looks at estimates more than this many σ
/// (its conditional σ, the axes held) from zero.
constexpr double kNuisanceCheckSigmas = 3.0;
/// Noise scales are floored here so that exact data give finite weights.
constexpr double kNoiseScaleFloor = 1e-12;

/// Which coordinates of the nuisance block (residual_kind.hpp) the fit
/// estimates; the others stay 0. With any, the axes' covariance, information
/// and 3σ region are marginal over them: the covariance inverts the whole
/// information matrix, the identifiability analysis takes the Schur
/// complement H_aa − H_an H_nn⁻¹ H_na, and the quadratic check moves the
/// nuisance along its regression on the axes (δν = −H_nn⁻¹ H_na δa, the
/// linearized profile).
struct NuisanceSelection {
  bool active[kNuisanceSize] = {false, false, false, false, false};
  int count() const {
    int n = 0;
    for (bool a : active) n += a;
    return n;
  }
};

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
  /// The nuisance blocks at the solution, one after the other (kNuisanceSize
  /// each: one, or one per recording with ResidualKind::nuisanceBlock), and
  /// their covariance (zero where not estimated).
  Eigen::VectorXd nuisance = Eigen::VectorXd::Zero(kNuisanceSize);
  Eigen::MatrixXd nuisance_covariance = Eigen::MatrixXd::Zero(kNuisanceSize, kNuisanceSize);
  AxisInformation information;
  AxisFitSummary summary;             ///< all but data, samples and seconds
};

/// Kinds built from low-pass-filtered signals (low_pass.hpp): the filter's
/// white-noise power gain g and the same kinds (same order and blocks, same
/// joint centre) built from the unfiltered signals. The residuals then have
/// variance g σ² and are correlated over ~f_s/2f_c samples, so the reduced
/// chi-square s² is divided by g wherever it stands for the noise (the
/// covariance, every Δχ², the identifiability σ), H_noise is the unfiltered
/// problem's times g (after the filter, second differences cannot tell noise
/// from motion), and σ is the larger of that and the sandwich (step 8), which
/// also counts the misfit of a joint that is not ideal.
struct LowPassNoise {
  double power_gain = 1.0;
  std::vector<const ResidualKind*> raw_kinds;
};

/// Fits the axes to `kinds` (the first is the primary one of the summary's
/// rms_residual) from `starts` (at least one; the first sets the noise
/// scales). Throws NotIdentifiable.
TwoAxisSolution solveTwoAxes(const std::vector<const ResidualKind*>& kinds, const std::vector<NamedStart>& starts,
                             const AxisFitOptions& options, const IdentifiabilityContext& context,
                             const NuisanceSelection& nuisance = NuisanceSelection(),
                             const LowPassNoise* low_pass = nullptr);

}  // namespace calibration
}  // namespace lieflow
