#include "dynamics/maximal/schur_solver.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lieflow {
namespace multibody {

int SchurSolver::translationKind(const Padded& B) {
  const auto T = B.leftCols<3>();
  if (T.isZero(0.0)) return 0;
  if (!T.bottomRows<kMaxGroupRows - 3>().isZero(0.0)) return 2;
  const auto top = T.topRows<3>();
  if (top == Eigen::Matrix3d::Identity()) return 1;
  if (top == -Eigen::Matrix3d::Identity()) return -1;
  return 2;
}

int SchurSolver::groupOfRow(int r) const {
  return static_cast<int>(std::upper_bound(row_.begin(), row_.end(), r) - row_.begin()) - 1;
}

void SchurSolver::clearBlocks(int g) {
  for (auto& b : blocks_[g]) b.setZero(groups_[g].rows, 6);
}

void SchurSolver::setup(const std::vector<char>& rotation_only, const std::vector<RowGroup>& groups) {
  rot_ = rotation_only;
  groups_ = groups;
  const int nb = static_cast<int>(rot_.size());
  const int ng = static_cast<int>(groups_.size());
  off_.assign(nb + 1, 0);
  for (int i = 0; i < nb; ++i) off_[i + 1] = off_[i] + (rot_[i] ? 3 : 6);
  n_ = off_[nb];
  row_.assign(ng + 1, 0);
  for (int g = 0; g < ng; ++g) row_[g + 1] = row_[g] + groups_[g].rows;
  m_ = row_[ng];
  // The groups of each body, (group, slot).
  std::vector<std::vector<std::pair<int, int>>> body_groups(nb);
  for (int g = 0; g < ng; ++g)
    for (int s = 0; s < kMaxGroupBodies; ++s)
      if (groups_[g].bodies[s] != kGround) body_groups[groups_[g].bodies[s]].emplace_back(g, s);
  std::vector<std::pair<int, int>> couplings;
  for (int b = 0; b < nb; ++b)
    for (const auto& k : body_groups[b])
      for (const auto& l : body_groups[b])
        if (k.first < l.first) couplings.emplace_back(k.first, l.first);
  std::sort(couplings.begin(), couplings.end());
  couplings.erase(std::unique(couplings.begin(), couplings.end()), couplings.end());
  std::vector<int> sizes(ng);
  for (int g = 0; g < ng; ++g) sizes[g] = groups_[g].rows;
  ldlt_.analyze(sizes, couplings);
  pattern_nonzeros_ = 0;
  for (int g = 0; g < ng; ++g) pattern_nonzeros_ += static_cast<Eigen::Index>(sizes[g]) * sizes[g];
  for (const auto& c : couplings)
    pattern_nonzeros_ += 2 * static_cast<Eigen::Index>(sizes[c.first]) * sizes[c.second];
  // S_kl = Σ over the bodies b both groups touch of G_kb B_lbᵀ: one
  // contribution per (body, ordered pair of its groups) that lands in the
  // stored (lower) block.
  contributions_.clear();
  for (int b = 0; b < nb; ++b)
    for (const auto& k : body_groups[b])
      for (const auto& l : body_groups[b]) {
        if (k.first == l.first) {
          if (k.second == l.second)
            contributions_.push_back({k.first, k.second, l.first, l.second, ldlt_.diagonalSlot(k.first)});
          continue;  // (a group listing a body twice is not built)
        }
        const BlockLdlt::Place p = ldlt_.offDiagonalPlace(k.first, l.first);
        if (p.transposed) continue;  // the pair (l, k) writes this block
        contributions_.push_back({k.first, k.second, l.first, l.second, p.slot});
      }
  blocks_.assign(ng, {});
  padded_.assign(ng, {});
  gpadded_.assign(ng, {});
  kind_.assign(ng, {});
  for (int g = 0; g < ng; ++g) {
    clearBlocks(g);
    for (int s = 0; s < kMaxGroupBodies; ++s) {
      padded_[g][s].setZero();
      gpadded_[g][s].setZero();
    }
  }
  invm_.assign(nb, 1.0);
  Jinv_.assign(nb, Eigen::Matrix3d::Identity());
  diagA_.resize(m_);
  scale_.assign(ng, BlockLdlt::BlockVector::Zero());
  x_.assign(ng, BlockLdlt::BlockVector::Zero());
  analyzed_ = true;
  ++analyze_count_;
}

FactorStatus SchurSolver::factor(double shift) {
  FactorStatus status;
  if (m_ == 0) return status;
  const int ng = groupCount();
  // B padded to kMaxGroupRows rows and G = B M⁻¹ (δp columns zero for a
  // rotation-only body, so G Bᵀ uses its δθ columns only). The δp columns of
  // point rows are ±I over zeros (spherical.hpp): such blocks are marked
  // (kind ±1) and their translational product ±(1/m) I is added directly;
  // kind 0 marks zero δp columns, kind 2 a general block (G's δp part is
  // formed only then).
  for (int g = 0; g < ng; ++g) {
    const int rows = groups_[g].rows;
    for (int s = 0; s < kMaxGroupBodies; ++s) {
      const int b = groups_[g].bodies[s];
      if (b == kGround) continue;
      Padded& B = padded_[g][s];
      Padded& G = gpadded_[g][s];
      B.topRows(rows) = blocks_[g][s];
      const int kind = rot_[b] ? 0 : translationKind(B);
      kind_[g][s] = static_cast<signed char>(kind);
      if (kind == 2) G.leftCols<3>() = B.leftCols<3>() * invm_[b];
      G.rightCols<3>().noalias() = B.rightCols<3>() * Jinv_[b];
    }
  }
  ldlt_.clear();
  for (const Contribution& c : contributions_) {
    BlockLdlt::Block& V = ldlt_.value(c.slot);
    const Padded& G = gpadded_[c.gk][c.sk];
    const Padded& B = padded_[c.gl][c.sl];
    V.noalias() += G.rightCols<3>() * B.rightCols<3>().transpose();
    const int ka = kind_[c.gk][c.sk], kb = kind_[c.gl][c.sl];
    if (ka == 0 || kb == 0) continue;
    if (ka != 2 && kb != 2)
      V.topLeftCorner<3, 3>().diagonal().array() += ka * kb * invm_[groups_[c.gk].bodies[c.sk]];
    else if (ka == 2)
      V.noalias() += G.leftCols<3>() * B.leftCols<3>().transpose();
    else  // G_k's δp part was not formed: it is B_k's times 1/m
      V.noalias() +=
          (padded_[c.gk][c.sk].leftCols<3>() * invm_[groups_[c.gk].bodies[c.sk]]) * B.leftCols<3>().transpose();
  }
  bool finite = true;
  for (int g = 0; g < ng; ++g) {
    BlockLdlt::Block& D = ldlt_.value(ldlt_.diagonalSlot(g));
    for (int r = 0; r < groups_[g].rows; ++r) {
      const double d = D(r, r);
      diagA_[row_[g] + r] = d;
      scale_[g][r] = d;
      finite = finite && std::isfinite(d);
      if (shift != 0.0) D(r, r) += shift * d;
    }
  }
  if (!finite) {
    status.ok = false;
    status.row = 0;
    status.pivot = std::numeric_limits<double>::quiet_NaN();
    return status;
  }
  const BlockLdlt::Status st = ldlt_.factor(scale_, kPivotTolerance);
  if (!st.ok) {
    status.ok = false;
    status.row = row_[st.block] + st.row;
    status.pivot = st.pivot;
    status.diagonal = diagA_[status.row];
  }
  return status;
}

void SchurSolver::solve(const Eigen::VectorXd& rhs, Eigen::VectorXd& x) {
  x.resize(m_);
  if (m_ == 0) return;
  const int ng = groupCount();
  for (int g = 0; g < ng; ++g) {
    const int rows = groups_[g].rows;
    x_[g].setZero();
    x_[g].head(rows) = rhs.segment(row_[g], rows);
  }
  ldlt_.solveInPlace(x_);
  for (int g = 0; g < ng; ++g) x.segment(row_[g], groups_[g].rows) = x_[g].head(groups_[g].rows);
}

void SchurSolver::multiplyJ(const Eigen::VectorXd& u, Eigen::VectorXd& out) const {
  out.setZero(m_);
  for (int g = 0; g < groupCount(); ++g) {
    auto seg = out.segment(row_[g], groups_[g].rows);
    for (int s = 0; s < kMaxGroupBodies; ++s) {
      const int b = groups_[g].bodies[s];
      if (b == kGround) continue;
      const int c0 = colBegin(b);
      seg.noalias() += blocks_[g][s].rightCols(6 - c0) * u.segment(off_[b], 6 - c0);
    }
  }
}

void SchurSolver::addJTranspose(const Eigen::VectorXd& lambda, double scale, Eigen::VectorXd& y) const {
  for (int g = 0; g < groupCount(); ++g) {
    const auto lg = lambda.segment(row_[g], groups_[g].rows);
    for (int s = 0; s < kMaxGroupBodies; ++s) {
      const int b = groups_[g].bodies[s];
      if (b == kGround) continue;
      const int c0 = colBegin(b);
      y.segment(off_[b], 6 - c0).noalias() += scale * (blocks_[g][s].rightCols(6 - c0).transpose() * lg);
    }
  }
}

void SchurSolver::applyInverseMass(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
  y.resize(n_);
  for (int b = 0; b < bodyCount(); ++b) {
    if (rot_[b]) {
      y.segment<3>(off_[b]).noalias() = Jinv_[b] * x.segment<3>(off_[b]);
    } else {
      y.segment<3>(off_[b]) = x.segment<3>(off_[b]) * invm_[b];
      y.segment<3>(off_[b] + 3).noalias() = Jinv_[b] * x.segment<3>(off_[b] + 3);
    }
  }
}

Eigen::Index SchurSolver::factorNonzeros() const { return m_ == 0 ? 0 : ldlt_.factorNonzeros(); }

}  // namespace multibody
}  // namespace lieflow
