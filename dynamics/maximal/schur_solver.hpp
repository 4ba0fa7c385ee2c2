/// \file
/// The one sparse linear-algebra kernel of the multibody layer: the Schur
/// complement S = J M⁻¹ Jᵀ of a set of constraint rows in maximal
/// coordinates, its LDLᵀ factorization, and the products with J, Jᵀ and M⁻¹
/// that the acceleration solve, the projections and the RATTLE iteration are
/// built from (Haug 1989, ch. 11; Baraff 1996, "Linear-time dynamics using
/// Lagrange multipliers").
///
/// Rows come in groups (a joint's rows, a prescribed joint coordinate, a gear
/// constraint); a group touches at most kMaxGroupBodies bodies and holds at
/// most kMaxGroupRows rows, with one rows × 6 block per body, columns (δp, δθ)
/// as in dynamics/constraints/body_pose.hpp. A rotation-only body has only the
/// δθ columns (the right three of its blocks).
///
/// Sparsity: two groups couple in S only when they share a body, so S is
/// block-tridiagonal along a chain. Its block pattern is built once per
/// topology (block_ldlt.hpp: AMD on the block graph, elimination tree, fill)
/// together with the list of body contributions G_k B_lᵀ (G = B M⁻¹) each
/// block receives; factor() zeroes the blocks, adds the contributions with
/// fixed 5 × 6 products and factors blockwise. Fill and cost grow linearly
/// along chains and trees; nothing dense of the whole system is ever formed,
/// and nothing is allocated after setup().
///
/// Redundant rows make S singular: a pivot d of the factor with
/// d ≤ kPivotTolerance · S_rr (or non-finite) is reported with its row.
#pragma once

#include <array>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "dynamics/body_index.hpp"
#include "dynamics/maximal/block_ldlt.hpp"

namespace lieflow {
namespace multibody {

/// Index of the ground in body lists (the ground has no coordinates).
using ::lieflow::kGround;

/// A pivot d_r ≤ kPivotTolerance · S_rr marks a row that depends on earlier
/// rows (redundant or conflicting constraints).
constexpr double kPivotTolerance = 1e-10;

constexpr int kMaxGroupBodies = 4;
constexpr int kMaxGroupRows = kMaxBlockRows;

/// A group's block for one body: rows × 6 without heap allocation.
using GroupBlock = Eigen::Matrix<double, Eigen::Dynamic, 6, 0, kMaxGroupRows, 6>;
using GroupRows = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxGroupRows, 1>;

/// Which bodies a row group touches (kGround entries have no block) and how
/// many rows it has.
struct RowGroup {
  std::array<int, kMaxGroupBodies> bodies{{kGround, kGround, kGround, kGround}};
  int rows = 0;
  bool operator==(const RowGroup& o) const { return bodies == o.bodies && rows == o.rows; }
};

/// Outcome of SchurSolver::factor.
struct FactorStatus {
  bool ok = true;
  int row = -1;         ///< first singular row (original order), −1 if none
  double pivot = 0.0;   ///< its pivot
  double diagonal = 0.0;  ///< its diagonal entry S_rr
};

class SchurSolver {
 public:
  /// Builds the pattern for bodies with the given rotation-only flags and the
  /// row groups (in row order), orders it (AMD) and analyses it.
  void setup(const std::vector<char>& rotation_only, const std::vector<RowGroup>& groups);
  bool matches(const std::vector<char>& rotation_only, const std::vector<RowGroup>& groups) const {
    return analyzed_ && rotation_only == rot_ && groups == groups_;
  }

  int bodyCount() const { return static_cast<int>(rot_.size()); }
  int groupCount() const { return static_cast<int>(groups_.size()); }
  int rows() const { return m_; }
  int dofs() const { return n_; }
  int rowBegin(int g) const { return row_[g]; }
  int groupRows(int g) const { return groups_[g].rows; }
  const RowGroup& group(int g) const { return groups_[g]; }
  int dofBegin(int b) const { return off_[b]; }
  bool rotationOnly(int b) const { return rot_[b] != 0; }
  /// The group holding row r.
  int groupOfRow(int r) const;

  /// The block of group g for its body slot s (rows × 6); fill it before
  /// factor()/multiply*.
  GroupBlock& block(int g, int s) { return blocks_[g][s]; }
  const GroupBlock& block(int g, int s) const { return blocks_[g][s]; }
  /// Sets every block of group g to zero (rows × 6).
  void clearBlocks(int g);

  /// M⁻¹ of body b: 1/m (unused for rotation-only bodies) and J⁻¹.
  void setInverseMass(int b, double inverse_mass, const Eigen::Matrix3d& inverse_inertia) {
    invm_[b] = inverse_mass;
    Jinv_[b] = inverse_inertia;
  }

  /// Assembles S = J M⁻¹ Jᵀ (+ shift·diag(S) on the diagonal) from the
  /// current blocks and factors it. On a singular pivot returns !ok with the
  /// row; solve() must not be called then.
  FactorStatus factor(double shift = 0.0);

  /// x = S⁻¹ rhs (after a successful factor()). x may alias nothing.
  void solve(const Eigen::VectorXd& rhs, Eigen::VectorXd& x);

  /// out = J u (u of size dofs(), out of size rows()).
  void multiplyJ(const Eigen::VectorXd& u, Eigen::VectorXd& out) const;
  /// y += scale · Jᵀ λ.
  void addJTranspose(const Eigen::VectorXd& lambda, double scale, Eigen::VectorXd& y) const;
  /// y = M⁻¹ x (per body).
  void applyInverseMass(const Eigen::VectorXd& x, Eigen::VectorXd& y) const;

  /// Entries (both triangles) of the block pattern of S.
  Eigen::Index patternNonzeros() const { return pattern_nonzeros_; }
  /// Nonzeros of the strictly lower factor L.
  Eigen::Index factorNonzeros() const;
  /// Number of symbolic analyses (setup calls with rows) so far.
  int analyzeCount() const { return analyze_count_; }
  /// Diagonal of S from the last factor() (original row order).
  const Eigen::VectorXd& diagonal() const { return diagA_; }

 private:
  using Padded = Eigen::Matrix<double, kMaxGroupRows, 6>;
  /// ldlt_.value(slot) += G[gk][sk] · B[gl][sl]ᵀ (the stored block has the rows of gk).
  struct Contribution {
    int gk, sk, gl, sl, slot;
  };
  int colBegin(int b) const { return rot_[b] ? 3 : 0; }
  /// The δp columns of a padded block: 0 all zero, ±1 ±I over zero rows
  /// (point rows), 2 anything else.
  static int translationKind(const Padded& B);

  bool analyzed_ = false;
  int analyze_count_ = 0;
  int n_ = 0, m_ = 0;
  Eigen::Index pattern_nonzeros_ = 0;
  std::vector<char> rot_;
  std::vector<RowGroup> groups_;
  std::vector<int> off_, row_;
  std::vector<std::array<GroupBlock, kMaxGroupBodies>> blocks_;
  std::vector<std::array<Padded, kMaxGroupBodies>> padded_, gpadded_;  // B and B M⁻¹, padded
  std::vector<std::array<signed char, kMaxGroupBodies>> kind_;          // translationKind per block
  std::vector<Contribution> contributions_;
  std::vector<double> invm_;
  std::vector<Eigen::Matrix3d> Jinv_;
  BlockLdlt ldlt_;
  std::vector<BlockLdlt::BlockVector> scale_, x_;
  Eigen::VectorXd diagA_;
};

}  // namespace multibody
}  // namespace lieflow
