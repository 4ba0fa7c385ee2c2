#include "joints/multibody/schur_solver.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/OrderingMethods>

namespace lieflow {
namespace multibody {

int SchurSolver::groupOfRow(int r) const {
  return static_cast<int>(std::upper_bound(row_.begin(), row_.end(), r) - row_.begin()) - 1;
}

void SchurSolver::clearBlocks(int g) {
  for (auto& b : blocks_[g]) b.setZero(groups_[g].rows, 6);
}

// Position in A_.valuePtr() of entry (row_[k] + r, row_[l] + c).
Eigen::Index SchurSolver::slot(int k, int l, int r, int c) const {
  int offk = 0;
  for (const auto& kv : coupled_[l])
    if (kv.first == k) {
      offk = kv.second;
      break;
    }
  return A_.outerIndexPtr()[row_[l] + c] + offk + r;
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
  body_groups_.assign(nb, {});
  for (int g = 0; g < ng; ++g)
    for (int s = 0; s < kMaxGroupBodies; ++s)
      if (groups_[g].bodies[s] != kGround) body_groups_[groups_[g].bodies[s]].emplace_back(g, s);
  coupled_.assign(ng, {});
  for (int l = 0; l < ng; ++l) {
    std::vector<int> ks{l};
    for (int b : groups_[l].bodies)
      if (b != kGround)
        for (const auto& gs : body_groups_[b]) ks.push_back(gs.first);
    std::sort(ks.begin(), ks.end());
    ks.erase(std::unique(ks.begin(), ks.end()), ks.end());
    int o = 0;
    for (int k : ks) {
      coupled_[l].emplace_back(k, o);
      o += groups_[k].rows;
    }
  }
  blocks_.assign(ng, {});
  gblocks_.assign(ng, {});
  for (int g = 0; g < ng; ++g) clearBlocks(g);
  invm_.assign(nb, 1.0);
  Jinv_.assign(nb, Eigen::Matrix3d::Identity());
  diagA_.resize(m_);
  analyzed_ = true;
  A_.resize(m_, m_);
  if (m_ == 0) return;  // (Eigen's reserve/makeCompressed misbehave on 0 × 0)
  // Compressed column pattern of S (m × m), dense group-by-group blocks.
  std::vector<int> colnnz(m_, 0);
  for (int l = 0; l < ng; ++l) {
    int len = 0;
    for (const auto& kv : coupled_[l]) len += groups_[kv.first].rows;
    for (int c = row_[l]; c < row_[l + 1]; ++c) colnnz[c] = len;
  }
  A_.reserve(colnnz);
  for (int l = 0; l < ng; ++l)
    for (int c = row_[l]; c < row_[l + 1]; ++c)
      for (const auto& kv : coupled_[l])
        for (int r = row_[kv.first]; r < row_[kv.first + 1]; ++r) A_.insert(r, c) = 0.0;
  A_.makeCompressed();
  diag_slot_.resize(m_);
  for (int l = 0; l < ng; ++l)
    for (int c = 0; c < groups_[l].rows; ++c) diag_slot_[row_[l] + c] = slot(l, l, c, c);
  // AMD on the symmetric pattern; the permuted upper triangle Ap = (P S Pᵀ)ᵤ
  // is kept with a value map, so factorize (natural ordering) reads it in
  // place instead of building a permuted copy every time.
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> pinv;
  Eigen::AMDOrdering<int>()(A_, pinv);
  const Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> pm = pinv.inverse();
  perm_ = pm.indices();  // row r goes to position perm_[r]
  orig_.resize(m_);
  for (int r = 0; r < m_; ++r) orig_[perm_[r]] = r;
  std::vector<Eigen::Triplet<double, int>> t;
  for (int c = 0; c < m_; ++c)
    for (SpMat::InnerIterator it(A_, c); it; ++it) {
      const int pr = perm_[it.row()], pc = perm_[c];
      if (pr <= pc) t.emplace_back(pr, pc, 0.0);
    }
  Ap_.resize(m_, m_);
  Ap_.setFromTriplets(t.begin(), t.end());
  Ap_.makeCompressed();
  ap_slot_.assign(A_.nonZeros(), -1);
  for (int c = 0; c < m_; ++c)
    for (Eigen::Index q = A_.outerIndexPtr()[c]; q < A_.outerIndexPtr()[c + 1]; ++q) {
      const int pr = perm_[A_.innerIndexPtr()[q]], pc = perm_[c];
      if (pr > pc) continue;
      const int* b = Ap_.innerIndexPtr() + Ap_.outerIndexPtr()[pc];
      const int* e = Ap_.innerIndexPtr() + Ap_.outerIndexPtr()[pc + 1];
      ap_slot_[q] = std::lower_bound(b, e, pr) - Ap_.innerIndexPtr();
    }
  ap_diag_slot_.resize(m_);
  for (int r = 0; r < m_; ++r) ap_diag_slot_[r] = ap_slot_[diag_slot_[r]];
  rhsp_.resize(m_);
  xp_.resize(m_);
  ldlt_.analyzePattern(Ap_);
  ++analyze_count_;
}

FactorStatus SchurSolver::factor(double shift) {
  FactorStatus status;
  if (m_ == 0) return status;
  const int ng = groupCount();
  // G = B M⁻¹ per block (δp columns zero for rotation-only bodies).
  for (int g = 0; g < ng; ++g)
    for (int s = 0; s < kMaxGroupBodies; ++s) {
      const int b = groups_[g].bodies[s];
      if (b == kGround) continue;
      const GroupBlock& B = blocks_[g][s];
      GroupBlock& G = gblocks_[g][s];
      G.resize(B.rows(), 6);
      if (rot_[b])
        G.leftCols<3>().setZero();
      else
        G.leftCols<3>() = B.leftCols<3>() * invm_[b];
      G.rightCols<3>().noalias() = B.rightCols<3>() * Jinv_[b];
    }
  // S = Σ_b J_b M_b⁻¹ J_bᵀ written into the fixed pattern.
  double* val = A_.valuePtr();
  std::fill(val, val + A_.nonZeros(), 0.0);
  const int nb = bodyCount();
  for (int b = 0; b < nb; ++b) {
    const int c0 = colBegin(b);
    for (const auto& ls : body_groups_[b]) {
      const GroupBlock& Bl = blocks_[ls.first][ls.second];
      for (const auto& ks : body_groups_[b]) {
        const GroupBlock& Gk = gblocks_[ks.first][ks.second];
        const int rk = groups_[ks.first].rows, rl = groups_[ls.first].rows;
        for (int c = 0; c < rl; ++c) {
          double* col = val + slot(ks.first, ls.first, 0, c);
          for (int r = 0; r < rk; ++r) col[r] += Gk.row(r).tail(6 - c0).dot(Bl.row(c).tail(6 - c0));
        }
      }
    }
  }
  for (int r = 0; r < m_; ++r) diagA_[r] = val[diag_slot_[r]];
  double* pval = Ap_.valuePtr();
  for (Eigen::Index q = 0; q < A_.nonZeros(); ++q)
    if (ap_slot_[q] >= 0) pval[ap_slot_[q]] = val[q];
  if (shift != 0.0)
    for (int r = 0; r < m_; ++r) pval[ap_diag_slot_[r]] += shift * diagA_[r];

  auto singularRow = [&](FactorStatus* st) {
    const Eigen::VectorXd D = ldlt_.vectorD();
    for (int p = 0; p < m_; ++p) {
      const int r = orig_[p];
      if (!std::isfinite(D[p]) || !(D[p] > kPivotTolerance * diagA_[r])) {
        st->ok = false;
        st->row = r;
        st->pivot = D[p];
        st->diagonal = diagA_[r];
        return;
      }
    }
  };
  if (!diagA_.allFinite()) {
    status.ok = false;
    status.row = 0;
    status.pivot = std::nan("");
    return status;
  }
  ldlt_.factorize(Ap_);
  if (ldlt_.info() != Eigen::Success) {
    // An exactly zero pivot stops Eigen's factorization: locate the row on
    // S + 1e-12 diag(S) (same pattern), whose redundant rows then have
    // pivots ≈ 1e-12 × their diagonal.
    for (int r = 0; r < m_; ++r) pval[ap_diag_slot_[r]] += 1e-12 * std::max(diagA_[r], 1e-300);
    ldlt_.factorize(Ap_);
    status.ok = false;
    status.row = 0;
    if (ldlt_.info() == Eigen::Success) {
      FactorStatus st;
      singularRow(&st);
      if (!st.ok) status.row = st.row;
      status.diagonal = diagA_[status.row];
    }
    status.pivot = 0.0;
    return status;
  }
  singularRow(&status);
  return status;
}

void SchurSolver::solve(const Eigen::VectorXd& rhs, Eigen::VectorXd& x) {
  x.resize(m_);
  if (m_ == 0) return;
  for (int r = 0; r < m_; ++r) rhsp_[perm_[r]] = rhs[r];
  xp_ = ldlt_.solve(rhsp_);
  for (int r = 0; r < m_; ++r) x[r] = xp_[perm_[r]];
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

Eigen::Index SchurSolver::factorNonzeros() const {
  return m_ == 0 ? 0 : ldlt_.matrixL().nestedExpression().nonZeros();
}

}  // namespace multibody
}  // namespace lieflow
