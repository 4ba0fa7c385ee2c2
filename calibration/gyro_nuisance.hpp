/// \file
/// The layout of the nuisance block shared by the gyroscope residuals of the
/// hinge and universal fits (residual_kind.hpp, kNuisanceSize): ν[0..1] the
/// main gyroscope's bias in the basis B₁, ν[2..3] the secondary's in B₂ (each
/// perpendicular to its body's axis: the part a joint observes), ν[4] the
/// fraction [s] of the secondary sensor's clock offset after whole samples.
#pragma once

#include <Eigen/Core>

#include "liegroup/scalar.hpp"

namespace lieflow {
namespace calibration {

/// The rates the nuisance says were true: v₁ = ω₁ − B₁ν₁ and
/// v₂ = ω₂ − ν₄ ω̇₂ − B₂ν₂ (the secondary's rate moved back to the main's time
/// by its slope ω̇₂, zero without a clock offset), for any scalar (ceres::Jet).
template <typename T>
void correctedRates(const Eigen::Vector3d& w1, const Eigen::Vector3d& w2, const Eigen::Vector3d& dw2,
                    const Eigen::Matrix<double, 3, 2>& B1, const Eigen::Matrix<double, 3, 2>& B2, const T* nu,
                    Vector3<T>* v1, Vector3<T>* v2) {
  for (int i = 0; i < 3; ++i) {
    (*v1)[i] = w1[i] - B1(i, 0) * nu[0] - B1(i, 1) * nu[1];
    (*v2)[i] = w2[i] - dw2[i] * nu[4] - B2(i, 0) * nu[2] - B2(i, 1) * nu[3];
  }
}

}  // namespace calibration
}  // namespace lieflow
