#include "calibration/hinge_initial.hpp"

#include "calibration/hinge_residuals.hpp"
#include "calibration/hinge_search.hpp"
#include "calibration/nullspace_starts.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

namespace lieflow {
namespace calibration {
namespace {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Vector12d = Eigen::Matrix<double, 12, 1>;
using Matrix12d = Eigen::Matrix<double, 12, 12>;

/// ωᵀSω = q(ω) · s(S) for symmetric S with s = (S₀₀, S₁₁, S₂₂, S₀₁, S₀₂, S₁₂).
Vector6d quadraticRow(const Eigen::Vector3d& w) {
  Vector6d q;
  q << w.x() * w.x(), w.y() * w.y(), w.z() * w.z(), 2.0 * w.x() * w.y(), 2.0 * w.x() * w.z(),
      2.0 * w.y() * w.z();
  return q;
}

Eigen::Matrix3d symmetricFrom(const Vector6d& s) {
  Eigen::Matrix3d S;
  S << s[0], s[3], s[4], s[3], s[1], s[5], s[4], s[5], s[2];
  return S;
}

/// The eigenvector of S's smallest eigenvalue (Eigen's closed form for 3 × 3:
/// the axes it gives are starts, refined afterwards; ranking up to 144
/// candidates took 288 iterative solves).
Eigen::Vector3d smallestEigenvector(const Eigen::Matrix3d& S) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.computeDirect(S);
  return eig.eigenvectors().col(0).normalized();
}

/// G = Σ rowᵀrow of the relaxation's rows [q(ω₁), −q(ω₂)] / (‖ω₁‖² + ‖ω₂‖²)^½.
Matrix12d gramFromRates(const std::vector<Eigen::Vector3d>& w1, const std::vector<Eigen::Vector3d>& w2) {
  Matrix12d G = Matrix12d::Zero();
  for (std::size_t k = 0; k < w1.size(); ++k) {
    const double scale_sq = w1[k].squaredNorm() + w2[k].squaredNorm();
    if (!(scale_sq > 0.0)) continue;
    Vector12d row;
    row << quadraticRow(w1[k]), -quadraticRow(w2[k]);
    G.selfadjointView<Eigen::Lower>().rankUpdate(row, 1.0 / scale_sq);
  }
  return G.selfadjointView<Eigen::Lower>();
}

/// The axes of a null-vector candidate x = (s(A), s(B)).
AxisPair axesFromQuadrics(const Vector12d& x) {
  Eigen::Matrix3d A = symmetricFrom(x.head<6>()), B = symmetricFrom(x.tail<6>());
  if (A.trace() + B.trace() < 0.0) {
    A = -A;
    B = -B;
  }
  return {smallestEigenvector(A), smallestEigenvector(B)};
}

}  // namespace

AxisPair hingeAxesFromRates(const std::vector<Eigen::Vector3d>& w1, const std::vector<Eigen::Vector3d>& w2) {
  const Eigen::SelfAdjointEigenSolver<Matrix12d> eig(gramFromRates(w1, w2));
  return axesFromQuadrics(eig.eigenvectors().col(0));
}

std::vector<AxisPair> hingeStartsFromRates(const std::vector<Eigen::Vector3d>& w1,
                                           const std::vector<Eigen::Vector3d>& w2) {
  // Candidates are ranked on the samples the search's starts run on (every
  // ⌈N/kSearchSamples⌉-th, hinge_search.hpp): the ranking only orders starts
  // that the search descends and polishes on all samples (on 1000 samples
  // with three near-null directions, 144 candidates cost 144 000 residuals
  // on all of them, 14 400 on these).
  const std::size_t stride = std::max<std::size_t>(1, (w1.size() + kSearchSamples - 1) / kSearchSamples);
  std::vector<GyroHingeResidual> residuals;
  residuals.reserve(w1.size() / stride + 1);
  for (std::size_t k = 0; k < w1.size(); k += stride) residuals.emplace_back(w1[k], w2[k]);
  const double one = 1.0;
  for (GyroHingeResidual& r : residuals) r.weight = &one;
  const auto cost = [&](const AxisPair& axes) {
    double sum = 0.0, r = 0.0;
    for (const GyroHingeResidual& residual : residuals) {
      residual(axes.axis1.data(), axes.axis2.data(), &r);
      sum += r * r;
    }
    return sum;
  };
  return nullspaceStarts<12>(gramFromRates(w1, w2), axesFromQuadrics, cost);
}

AxisPair hingeAxesFromOrientations(const std::vector<Eigen::Matrix3d>& R12) {
  Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
  for (const Eigen::Matrix3d& R : R12) M += R;
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  return {svd.matrixU().col(0), svd.matrixV().col(0)};
}

std::vector<AxisPair> hingeStartsFromCentreForces(const std::vector<Eigen::Vector3d>& c1,
                                                  const std::vector<Eigen::Vector3d>& c2) {
  Eigen::Matrix<double, 6, 6> G = Eigen::Matrix<double, 6, 6>::Zero();
  for (std::size_t k = 0; k < c1.size(); ++k) {
    Eigen::Matrix<double, 6, 1> row;
    row << c1[k], -c2[k];
    const double n2 = row.squaredNorm();
    if (n2 > 0.0) G.selfadjointView<Eigen::Lower>().rankUpdate(row, 1.0 / n2);
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eig(
      Eigen::Matrix<double, 6, 6>(G.selfadjointView<Eigen::Lower>()));
  const Eigen::Matrix<double, 6, 1> e0 = eig.eigenvectors().col(0), e1 = eig.eigenvectors().col(1);
  const Eigen::Vector3d j1 = e0.head<3>().norm() >= e1.head<3>().norm() ? e0.head<3>() : e1.head<3>();
  const Eigen::Vector3d j2 = e0.tail<3>().norm() >= e1.tail<3>().norm() ? e0.tail<3>() : e1.tail<3>();
  const Eigen::Vector3d a1 = j1.norm() > 0.0 ? Eigen::Vector3d(j1.normalized()) : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d a2 = j2.norm() > 0.0 ? Eigen::Vector3d(j2.normalized()) : Eigen::Vector3d::UnitX();
  // The sign the smallest eigenvector gives first (its halves are consistent there).
  const double s = e0.head<3>().dot(a1) * e0.tail<3>().dot(a2) >= 0.0 ? 1.0 : -1.0;
  return {AxisPair{a1, s * a2}, AxisPair{a1, -s * a2}};
}

}  // namespace calibration
}  // namespace lieflow
