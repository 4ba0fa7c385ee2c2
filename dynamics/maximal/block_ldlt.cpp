#include "dynamics/maximal/block_ldlt.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCore>

namespace lieflow {
namespace multibody {

void BlockLdlt::analyze(const std::vector<int>& sizes, const std::vector<std::pair<int, int>>& couplings) {
  sizes_ = sizes;
  const int nb = blockCount();
  // Elimination order: AMD on the block graph (natural order for ≤ 2 blocks).
  order_.resize(nb);
  position_.resize(nb);
  for (int g = 0; g < nb; ++g) position_[g] = g;
  if (nb > 2) {
    std::vector<Eigen::Triplet<double, int>> t;
    t.reserve(2 * couplings.size() + nb);
    for (int g = 0; g < nb; ++g) t.emplace_back(g, g, 1.0);
    for (const auto& c : couplings) {
      t.emplace_back(c.first, c.second, 1.0);
      t.emplace_back(c.second, c.first, 1.0);
    }
    Eigen::SparseMatrix<double, Eigen::ColMajor, int> pattern(nb, nb);
    pattern.setFromTriplets(t.begin(), t.end());
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> pinv;
    Eigen::AMDOrdering<int>()(pattern, pinv);
    const Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> p = pinv.inverse();
    for (int g = 0; g < nb; ++g) position_[g] = p.indices()[g];  // block g goes to position p[g]
  }
  for (int g = 0; g < nb; ++g) order_[position_[g]] = g;

  // Symbolic factorization by the elimination tree: the rows below position
  // j are its later neighbours and the rows below its children, minus j.
  std::vector<std::vector<int>> rows(nb), children(nb);
  for (const auto& c : couplings) {
    const int a = position_[c.first], b = position_[c.second];
    if (a == b) continue;
    rows[std::min(a, b)].push_back(std::max(a, b));
  }
  for (int j = 0; j < nb; ++j) {
    std::vector<int>& r = rows[j];
    for (int c : children[j])
      for (int i : rows[c])
        if (i != j) r.push_back(i);
    std::sort(r.begin(), r.end());
    r.erase(std::unique(r.begin(), r.end()), r.end());
    if (!r.empty()) children[r.front()].push_back(j);
  }

  // Slots: the diagonal blocks first (by block index), then column by column.
  diag_slot_.resize(nb);
  for (int g = 0; g < nb; ++g) diag_slot_[g] = g;
  int slots = nb;
  col_begin_.assign(nb + 1, 0);
  below_.clear();
  factor_nonzeros_ = 0;
  std::size_t widest = 0;
  for (int j = 0; j < nb; ++j) {
    col_begin_[j] = static_cast<int>(below_.size());
    const int rj = sizes_[order_[j]];
    factor_nonzeros_ += rj * (rj - 1) / 2;
    for (int i : rows[j]) {
      below_.emplace_back(i, slots++);
      factor_nonzeros_ += static_cast<long long>(sizes_[order_[i]]) * rj;
    }
    widest = std::max(widest, rows[j].size());
  }
  col_begin_[nb] = static_cast<int>(below_.size());
  values_.assign(slots, Block::Zero());
  w_.assign(std::max<std::size_t>(widest, 1), Block::Zero());

  // Updates of column j: every pair of its below rows i ≥ k.
  auto slotOf = [&](int i, int k) {  // positions i > k
    const auto b = below_.begin() + col_begin_[k], e = below_.begin() + col_begin_[k + 1];
    const auto it = std::lower_bound(b, e, std::make_pair(i, -1));
    return it->second;  // present: the fill is closed under the updates
  };
  update_begin_.assign(nb + 1, 0);
  updates_.clear();
  for (int j = 0; j < nb; ++j) {
    update_begin_[j] = static_cast<int>(updates_.size());
    const int b = col_begin_[j], e = col_begin_[j + 1];
    for (int qi = b; qi < e; ++qi)
      for (int qk = b; qk <= qi; ++qk) {
        const int i = below_[qi].first, k = below_[qk].first;
        const int target = i == k ? diag_slot_[order_[i]] : slotOf(i, k);
        updates_.push_back({below_[qi].second, qk - b, target});
      }
  }
  update_begin_[nb] = static_cast<int>(updates_.size());
}

BlockLdlt::Place BlockLdlt::offDiagonalPlace(int k, int l) const {
  const int pk = position_[k], pl = position_[l];
  const int i = std::max(pk, pl), j = std::min(pk, pl);
  const auto b = below_.begin() + col_begin_[j], e = below_.begin() + col_begin_[j + 1];
  const auto it = std::lower_bound(b, e, std::make_pair(i, -1));
  Place p;
  if (it != e && it->first == i) p.slot = it->second;
  p.transposed = pk < pl;
  return p;
}

void BlockLdlt::clear() {
  for (Block& b : values_) b.setZero();
  for (int g = 0; g < blockCount(); ++g)
    for (int r = sizes_[g]; r < kMaxBlockRows; ++r) values_[diag_slot_[g]](r, r) = 1.0;
}

BlockLdlt::Status BlockLdlt::factor(const std::vector<BlockVector>& scale, double tolerance) {
  Status status;
  const int nb = blockCount();
  for (int j = 0; j < nb; ++j) {
    const int g = order_[j];
    Block& A = values_[diag_slot_[g]];
    // Scalar LDLᵀ of the diagonal block in place: strictly lower part ← L,
    // diagonal ← D (upper part unused).
    for (int c = 0; c < kMaxBlockRows; ++c) {
      double d = A(c, c);
      for (int t = 0; t < c; ++t) d -= A(c, t) * A(c, t) * A(t, t);
      if (c < sizes_[g] && !(std::isfinite(d) && d > tolerance * scale[g][c])) {
        status.ok = false;
        status.block = g;
        status.row = c;
        status.pivot = d;
        return status;
      }
      A(c, c) = d;
      for (int r = c + 1; r < kMaxBlockRows; ++r) {
        double s = A(r, c);
        for (int t = 0; t < c; ++t) s -= A(r, t) * A(c, t) * A(t, t);
        A(r, c) = s / d;
      }
    }
    const BlockVector dinv = A.diagonal().cwiseInverse();
    // W_ij = A_ij L_jj⁻ᵀ (rows solve W L_jjᵀ = A_ij), L_ij = W_ij D⁻¹.
    const int b = col_begin_[j], e = col_begin_[j + 1];
    for (int q = b; q < e; ++q) {
      Block& Aij = values_[below_[q].second];
      Block& W = w_[q - b];
      W = Aij;
      for (int c = 0; c < kMaxBlockRows; ++c)
        for (int t = 0; t < c; ++t) W.col(c) -= A(c, t) * W.col(t);
      Aij = W * dinv.asDiagonal();
    }
    for (int u = update_begin_[j]; u < update_begin_[j + 1]; ++u) {
      const Update& up = updates_[u];
      values_[up.target].noalias() -= values_[up.lhs] * w_[up.rhs].transpose();
    }
  }
  return status;
}

void BlockLdlt::solveInPlace(std::vector<BlockVector>& x) const {
  const int nb = blockCount();
  // L z = b (forward, right-looking), then D, then Lᵀ x = y (backward).
  for (int j = 0; j < nb; ++j) {
    const int g = order_[j];
    const Block& A = values_[diag_slot_[g]];
    BlockVector& z = x[g];
    for (int r = 1; r < kMaxBlockRows; ++r)
      for (int t = 0; t < r; ++t) z[r] -= A(r, t) * z[t];
    for (int q = col_begin_[j]; q < col_begin_[j + 1]; ++q)
      x[order_[below_[q].first]].noalias() -= values_[below_[q].second] * z;
  }
  for (int g = 0; g < nb; ++g) x[g].array() /= values_[diag_slot_[g]].diagonal().array();
  for (int j = nb - 1; j >= 0; --j) {
    const int g = order_[j];
    BlockVector& v = x[g];
    for (int q = col_begin_[j]; q < col_begin_[j + 1]; ++q)
      v.noalias() -= values_[below_[q].second].transpose() * x[order_[below_[q].first]];
    const Block& A = values_[diag_slot_[g]];
    for (int r = kMaxBlockRows - 2; r >= 0; --r)
      for (int t = r + 1; t < kMaxBlockRows; ++t) v[r] -= A(t, r) * v[t];
  }
}

}  // namespace multibody
}  // namespace lieflow
