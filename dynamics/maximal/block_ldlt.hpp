/// \file
/// LDLᵀ of a symmetric block-sparse matrix whose blocks are at most
/// kMaxBlockRows square (the Schur complement J M⁻¹ Jᵀ of schur_solver.hpp,
/// one block row per constraint group), with the structure analysed once and
/// fixed-size 5 × 5 arithmetic in the numeric factorization and solves.
///
/// Storage: every block row is padded to kMaxBlockRows. A padded row has 1 on
/// the diagonal and 0 elsewhere, so its pivot is exactly 1, its unknown stays
/// 0 for a zero right-hand side, and it never couples to a real row. The
/// fixed size lets Eigen unroll the 5 × 5 products (no loops over dynamic
/// sizes, no index indirection per scalar entry), which is what makes a
/// block solve several times cheaper than a scalar sparse LDLᵀ on the same
/// pattern (the profile of bench_multibody before this file: 55 % of a
/// projected RKMK4 step in the scalar assembly and Eigen's SimplicialLDLT).
///
/// Factorization (block right-looking LDLᵀ; Golub & Van Loan, §4.1 and
/// §4.5, blockwise; Davis 2006, "Direct Methods for Sparse Linear Systems",
/// ch. 4 for the elimination tree and the symbolic fill): with the blocks in
/// elimination order j = 0, 1, …,
///   A_jj = L_jj D_j L_jjᵀ        (scalar LDLᵀ of the diagonal block, no pivoting),
///   W_ij = A_ij L_jj⁻ᵀ,  L_ij = W_ij D_j⁻¹        for every i > j in column j,
///   A_ik ← A_ik − L_ij W_kjᵀ                       for every pair i ≥ k in column j,
/// which is exactly the scalar LDLᵀ of the permuted matrix (same pivots,
/// same rounding order per entry up to the grouping of the sums). The
/// elimination order is AMD on the block graph; the fill (the blocks the
/// updates create) is found once by the elimination tree.
///
/// A pivot d of a real row with d ≤ tolerance · scale (or non-finite) stops
/// the factorization and is reported (the caller names the row).
#pragma once

#include <utility>
#include <vector>

#include <Eigen/Core>

namespace lieflow {
namespace multibody {

constexpr int kMaxBlockRows = 5;

class BlockLdlt {
 public:
  using Block = Eigen::Matrix<double, kMaxBlockRows, kMaxBlockRows>;
  using BlockVector = Eigen::Matrix<double, kMaxBlockRows, 1>;

  /// Where an off-diagonal block (k, l) lives: slot in the value array and
  /// whether it is stored as (k, l) (rows of k) or as its transpose (l, k).
  struct Place {
    int slot = -1;
    bool transposed = false;
  };

  /// Outcome of factor().
  struct Status {
    bool ok = true;
    int block = -1;       ///< block row of the first bad pivot (−1 if none)
    int row = -1;         ///< its row inside the block
    double pivot = 0.0;   ///< the pivot d
  };

  /// Analyses the pattern: block row g has sizes[g] ≤ kMaxBlockRows real
  /// rows; `couplings` lists the off-diagonal blocks (k, l), k ≠ l, in either
  /// order and possibly repeated. Orders the blocks (AMD), computes the fill
  /// and the update lists.
  void analyze(const std::vector<int>& sizes, const std::vector<std::pair<int, int>>& couplings);

  int blockCount() const { return static_cast<int>(sizes_.size()); }
  /// Stored blocks, fill included (diagonal ones too).
  int storedBlocks() const { return static_cast<int>(values_.size()); }
  /// Slot of diagonal block g.
  int diagonalSlot(int g) const { return diag_slot_[g]; }
  /// Place of the off-diagonal block (k, l); it must be in the pattern.
  Place offDiagonalPlace(int k, int l) const;

  /// Sets every stored value to 0 and the padded diagonal entries to 1.
  void clear();
  Block& value(int slot) { return values_[slot]; }
  const Block& value(int slot) const { return values_[slot]; }

  /// Factors in place. scale[g](r) is the size a pivot of block g, row r is
  /// measured against (the caller's unshifted diagonal).
  Status factor(const std::vector<BlockVector>& scale, double tolerance);

  /// x ← A⁻¹ x, x[g] the (padded) block of block row g. After a successful
  /// factor() only.
  void solveInPlace(std::vector<BlockVector>& x) const;

  /// Nonzeros of the strictly lower scalar factor (real rows only).
  long long factorNonzeros() const { return factor_nonzeros_; }

 private:
  struct Update {
    int lhs;     ///< slot of L_ij
    int rhs;     ///< index of W_kj in the column's list (w_)
    int target;  ///< slot of A_ik: value(target) −= L_ij · W_kjᵀ
  };
  std::vector<int> sizes_;
  std::vector<int> order_;                 ///< block at elimination position j
  std::vector<int> position_;              ///< elimination position of block g
  std::vector<int> diag_slot_;             ///< per block
  std::vector<int> col_begin_;             ///< per position: its below blocks in below_
  std::vector<std::pair<int, int>> below_;  ///< (row position i, slot), sorted by i
  std::vector<int> update_begin_;          ///< per position: its updates in updates_
  std::vector<Update> updates_;
  std::vector<Block> values_;
  mutable std::vector<Block> w_;           ///< W_ij of the current column
  long long factor_nonzeros_ = 0;
};

}  // namespace multibody
}  // namespace lieflow
