/// \file
/// Closed-form hinge axes. For rich motions they start the refinement inside
/// the basin of the global minimum; short recordings can have several
/// basins, so the fit also descends from a grid (hinge_search.hpp).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "calibration/fit_types.hpp"

namespace lieflow {
namespace calibration {

/// From gyroscopes. With unit axes, ‖ω×j‖² = ωᵀ(I − jjᵀ)ω, so the hinge
/// constraint ‖ω₁×j₁‖² = ‖ω₂×j₂‖² is linear in the symmetric matrices
/// A = I − j₁j₁ᵀ, B = I − j₂j₂ᵀ: ω₁ᵀAω₁ − ω₂ᵀBω₂ = 0 for every sample. For a
/// motion that turns both bodies about more than the hinge, (A, B) ∝
/// (I − j₁j₁ᵀ, I − j₂j₂ᵀ) is the only solution of these 12 homogeneous linear
/// equations (A and B must be invariant under the joint's rotation and
/// annihilate the axis), so it is the null vector of the stacked rows
/// [sym(ω₁ω₁ᵀ), −sym(ω₂ω₂ᵀ)], each scaled by 1/(‖ω₁‖² + ‖ω₂‖²)^½ (Sampson
/// weighting, as the residual). jᵢ is the eigenvector of the smallest
/// eigenvalue of A or B (the sign of the null vector chosen so that their
/// traces are positive). The relative sign of j₁ and j₂ is not determined.
AxisPair hingeAxesFromRates(const std::vector<Eigen::Vector3d>& w1, const std::vector<Eigen::Vector3d>& w2);

/// The refinement's starts from gyroscopes: hingeAxesFromRates when its null
/// vector is well separated, else the best few unit combinations of the
/// near-null eigenvectors ranked by the Sampson cost of GyroHingeResidual
/// (nullspace_starts.hpp). Best first.
std::vector<AxisPair> hingeStartsFromRates(const std::vector<Eigen::Vector3d>& w1,
                                           const std::vector<Eigen::Vector3d>& w2);

/// From the accelerations at the joint centre (AccelerometerHingeResidual):
/// j₁·c₁ − j₂·c₂ = 0 is linear and homogeneous in x = (j₁, j₂), so x is the
/// null vector of the stacked rows [c₁ᵀ, −c₂ᵀ] (each scaled to unit norm), the
/// eigenvector of the smallest eigenvalue of their 6 × 6 Gram matrix, each
/// half then normalized. When the centre's acceleration stays in the plane
/// perpendicular to the axis (a knee in the sagittal plane) the null space is
/// (j₁, 0) and (0, j₂), and the two smallest eigenvectors mix them: each half
/// is taken from whichever of the two carries more of it. Both relative signs
/// are returned (the planar case does not fix it); the fit's cost decides.
std::vector<AxisPair> hingeStartsFromCentreForces(const std::vector<Eigen::Vector3d>& c1,
                                                  const std::vector<Eigen::Vector3d>& c2);

/// From orientations: Σₖ ‖j₁ − R₁₂ₖ j₂‖² = 2N − 2 j₁ᵀ(Σₖ R₁₂ₖ) j₂ over unit
/// axes is least at the first singular vectors of M = Σₖ R₁ᵀR₂ (the exact
/// least-squares solution; its sign gives R₁j₁ ≈ R₂j₂, since u₁ᵀMv₁ = σ₁ ≥ 0).
AxisPair hingeAxesFromOrientations(const std::vector<Eigen::Matrix3d>& R12);

}  // namespace calibration
}  // namespace lieflow
