/// \file
/// Closed-form universal-joint axes from orientations.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "calibration/fit_types.hpp"

namespace lieflow {
namespace calibration {

/// The constraint a₁ᵀ R₁₂ₖ a₂ = 0 is linear in X = a₁a₂ᵀ: ⟨R₁₂ₖ, X⟩_F = 0. With
/// R₁₂ = exp(φ₁a₁) C exp(φ₂a₂), ⟨R₁₂, X⟩ expands in the 9 products of
/// {1, cos φ₁, sin φ₁} and {1, cos φ₂, sin φ₂}; when both angles move these are
/// independent, the constant one vanishes for X = a₁a₂ᵀ (C a₂ ⟂ a₁), and the
/// other 8 leave X unique up to scale. So X is the null vector of the stacked
/// vec(R₁₂ₖ) (smallest eigenvector of their 9×9 Gram matrix) and a₁, a₂ its
/// first singular vectors (the nearest rank-one matrix). Signs are free.
AxisPair universalAxesFromOrientations(const std::vector<Eigen::Matrix3d>& R12);

/// The refinement's starts: universalAxesFromOrientations when its null
/// vector is well separated, else the best few unit combinations of the
/// near-null eigenvectors ranked by Σ(a₁ᵀR₁₂a₂)² (nullspace_starts.hpp).
std::vector<AxisPair> universalStartsFromOrientations(const std::vector<Eigen::Matrix3d>& R12);

}  // namespace calibration
}  // namespace lieflow
