#include "calibration/universal_initial.hpp"

#include "calibration/nullspace_starts.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

namespace lieflow {
namespace calibration {

namespace {

using Vector9d = Eigen::Matrix<double, 9, 1>;
using Matrix9d = Eigen::Matrix<double, 9, 9>;

/// G = Σ vec(R₁₂) vec(R₁₂)ᵀ.
Matrix9d gramFromOrientations(const std::vector<Eigen::Matrix3d>& R12) {
  Matrix9d G = Matrix9d::Zero();
  for (const Eigen::Matrix3d& R : R12) {
    // Row-major vec: entry 3i + j is R(i, j), so ⟨R, X⟩ = vec(R) · vec(X).
    Vector9d row;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) row[3 * i + j] = R(i, j);
    G.selfadjointView<Eigen::Lower>().rankUpdate(row);
  }
  return G.selfadjointView<Eigen::Lower>();
}

/// The axes of a null-vector candidate x = vec(X): X's first singular vectors.
AxisPair axesFromOuterProduct(const Vector9d& x) {
  Eigen::Matrix3d X;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) X(i, j) = x[3 * i + j];
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(X, Eigen::ComputeFullU | Eigen::ComputeFullV);
  return {svd.matrixU().col(0), svd.matrixV().col(0)};
}

}  // namespace

AxisPair universalAxesFromOrientations(const std::vector<Eigen::Matrix3d>& R12) {
  const Eigen::SelfAdjointEigenSolver<Matrix9d> eig(gramFromOrientations(R12));
  return axesFromOuterProduct(eig.eigenvectors().col(0));
}

std::vector<AxisPair> universalStartsFromOrientations(const std::vector<Eigen::Matrix3d>& R12) {
  const auto cost = [&](const AxisPair& axes) {
    double sum = 0.0;
    for (const Eigen::Matrix3d& R : R12) {
      const double r = axes.axis1.dot(R * axes.axis2);
      sum += r * r;
    }
    return sum;
  };
  return nullspaceStarts<9>(gramFromOrientations(R12), axesFromOuterProduct, cost);
}

}  // namespace calibration
}  // namespace lieflow
