#include "calibration/axis_problem.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <ceres/crs_matrix.h>
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "calibration/unit_axis.hpp"

namespace lieflow {
namespace calibration {
namespace {

/// Row r of a Jacobian over the axes' 4 tangent coordinates and the n − 4
/// estimated nuisance coordinates; the axes' columns multiplied by `axis_scale`.
Eigen::VectorXd jacobianRow(const ceres::CRSMatrix& J, int r, double axis_scale) {
  Eigen::VectorXd j = Eigen::VectorXd::Zero(J.num_cols);
  for (int e = J.rows[r]; e < J.rows[r + 1]; ++e) j[J.cols[e]] = (J.cols[e] < 4 ? axis_scale : 1.0) * J.values[e];
  return j;
}

/// The Jacobian of every block over p.blocks() (with or without the loss).
void evaluateJacobian(AxisProblem& p, bool apply_loss, double* cost, std::vector<double>* r, ceres::CRSMatrix* J) {
  ceres::Problem::EvaluateOptions eval;
  eval.parameter_blocks = p.blocks();
  eval.residual_blocks = p.allBlocks();
  eval.apply_loss_function = apply_loss;
  p.problem().Evaluate(eval, cost, r, nullptr, J);
  if (J->num_cols != 4 + p.nuisanceCount())
    throw std::logic_error("two-axis fit: expected a Jacobian in the 4 tangent coordinates and the nuisance");
}

}  // namespace

/// H = JᵀJ of the whitened residuals per rad² of axis rotation — marginal
/// over the estimated nuisance (the Schur complement H_aa − H_an H_nn⁻¹ H_na)
/// — the noise's share H_noise = ⅙ Σ Δ²Jₖᵀ Δ²Jₖ of the axes' columns (second
/// differences over consecutive samples of one kind; identifiability.hpp),
/// the cost, and the nuisance's linear regression on the axes' tangent
/// coordinates, δν = −H_nn⁻¹ H_na δ (empty without nuisance).
void informationAtAxes(AxisProblem& p, Eigen::Matrix4d* H, Eigen::Matrix4d* H_noise, double* cost,
                       Eigen::MatrixXd* profile, Eigen::MatrixXd* whole) {
  ceres::CRSMatrix J;
  evaluateJacobian(p, true, cost, nullptr, &J);
  const int n = J.num_cols;
  // Tangent coordinates δ turn an axis by ‖δ‖/2: ∂r/∂θ = 2 ∂r/∂δ.
  const auto row = [&](int r) { return jacobianRow(J, r, kSphereTangentPerRadian); };
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(n, n), hn = Eigen::MatrixXd::Zero(n, n);
  for (int r = 0; r < J.num_rows; ++r) h.selfadjointView<Eigen::Lower>().rankUpdate(row(r));
  int begin = 0;
  for (std::size_t k = 0; k < p.kindCount(); ++k) {
    const int per_block = p.residualsPerBlock(k);
    const int end = begin + p.kind(k).blockCount() * per_block;
    for (int r = begin + per_block; r + per_block < end; ++r)
      hn.selfadjointView<Eigen::Lower>().rankUpdate(row(r + per_block) - 2.0 * row(r) + row(r - per_block), 1.0 / 6.0);
    begin = end;
  }
  h = Eigen::MatrixXd(h.selfadjointView<Eigen::Lower>());
  if (whole) *whole = h;
  *H_noise = Eigen::MatrixXd(hn.selfadjointView<Eigen::Lower>()).topLeftCorner<4, 4>();
  *H = h.topLeftCorner<4, 4>();
  profile->resize(n - 4, 4);
  if (n > 4) {
    const Eigen::LDLT<Eigen::MatrixXd> nn(h.bottomRightCorner(n - 4, n - 4));
    const Eigen::MatrixXd regression = nn.solve(h.bottomLeftCorner(n - 4, 4));
    *H -= h.topRightCorner(4, n - 4) * regression;
    *profile = -regression / kSphereTangentPerRadian;  // per tangent coordinate δ = kSphereTangentPerRadian θ
  }
}

bool gaussNewtonStep(AxisProblem& p, GaussNewtonStep* out) {
  std::vector<double> r;
  ceres::CRSMatrix J;
  evaluateJacobian(p, false, nullptr, &r, &J);
  const int n = J.num_cols;
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(n);
  for (int row = 0; row < J.num_rows; ++row) {
    const Eigen::VectorXd j = jacobianRow(J, row, 1.0);
    H.selfadjointView<Eigen::Lower>().rankUpdate(j);
    g += r[row] * j;
  }
  H = Eigen::MatrixXd(H.selfadjointView<Eigen::Lower>());
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(H);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 1e-12 * ldlt.vectorD().maxCoeff())) return false;
  out->step = -ldlt.solve(g);
  out->decrease = -0.5 * g.dot(out->step);
  return std::isfinite(out->decrease);
}

/// Step 8: the sandwich covariance of the axes in tangent coordinates
/// (marginal: the axes' block of the whole H⁻¹MH⁻¹; file comment of
/// two_axis_solver.hpp); `batches` receives B. Returns false when it cannot
/// be formed (too few samples, H singular).
bool sandwichCovariance(AxisProblem& p, Eigen::Matrix4d* tangent, int* batches) {
  std::vector<double> r;
  ceres::CRSMatrix J;
  evaluateJacobian(p, true, nullptr, &r, &J);
  const int n = J.num_cols;
  int fewest = std::numeric_limits<int>::max();
  for (std::size_t k = 0; k < p.kindCount(); ++k) fewest = std::min(fewest, p.kind(k).blockCount());
  const int B = std::min(kSandwichBatches, fewest / kSandwichMinBatchSamples);
  if (B < 4) return false;
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(n, n);
  std::vector<Eigen::VectorXd> S(B, Eigen::VectorXd::Zero(n));
  int row = 0;
  for (std::size_t k = 0; k < p.kindCount(); ++k) {
    const int per_block = p.residualsPerBlock(k), blocks = p.kind(k).blockCount();
    for (int b = 0; b < blocks; ++b) {
      Eigen::VectorXd score = Eigen::VectorXd::Zero(n);
      for (int i = 0; i < per_block; ++i, ++row) {
        const Eigen::VectorXd j = jacobianRow(J, row, 1.0);
        H.selfadjointView<Eigen::Lower>().rankUpdate(j);
        score += r[row] * j;
      }
      S[static_cast<std::size_t>(b) * B / blocks] += score;
    }
  }
  H = Eigen::MatrixXd(H.selfadjointView<Eigen::Lower>());
  Eigen::VectorXd mean = Eigen::VectorXd::Zero(n);
  for (const Eigen::VectorXd& s : S) mean += s / B;
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n, n);
  for (const Eigen::VectorXd& s : S) M += (s - mean) * (s - mean).transpose();
  M *= static_cast<double>(B) / (B - 1);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(H);
  if (!(eig.eigenvalues().minCoeff() > 1e-12 * eig.eigenvalues().maxCoeff())) return false;
  const Eigen::MatrixXd Hinv =
      eig.eigenvectors() * eig.eigenvalues().cwiseInverse().asDiagonal() * eig.eigenvectors().transpose();
  *tangent = (Hinv * M * Hinv).topLeftCorner<4, 4>();
  *batches = B;
  return true;
}

}  // namespace calibration
}  // namespace lieflow
