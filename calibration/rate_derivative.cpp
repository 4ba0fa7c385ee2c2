#include "calibration/rate_derivative.hpp"

#include <Eigen/Cholesky>

namespace lieflow {
namespace calibration {

Eigen::Vector3d rateDerivative(const std::vector<double>& t, const std::vector<Eigen::Vector3d>& w, std::size_t k) {
  constexpr int kOrder = 3;
  constexpr int kPoints = 2 * kRateWindow + 1;
  Eigen::Matrix<double, kPoints, kOrder + 1> A;
  for (int i = 0; i < kPoints; ++i) {
    const double tau = t[k + i - kRateWindow] - t[k];
    double p = 1.0;
    for (int j = 0; j <= kOrder; ++j, p *= tau) A(i, j) = p;
  }
  // c = e₁ᵀ (AᵀA)⁻¹ Aᵀ: the weights of the fitted polynomial's slope at τ = 0.
  const Eigen::Matrix<double, kOrder + 1, kOrder + 1> AtA = A.transpose() * A;
  const Eigen::Matrix<double, kOrder + 1, kPoints> P = AtA.ldlt().solve(A.transpose());
  Eigen::Vector3d d = Eigen::Vector3d::Zero();
  for (int i = 0; i < kPoints; ++i) d += P(1, i) * w[k + i - kRateWindow];
  return d;
}

}  // namespace calibration
}  // namespace lieflow
