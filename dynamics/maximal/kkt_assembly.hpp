/// \file
/// The sparse Newton iteration matrix of the index-3 Lie-group generalized-α
/// method (integrators/constrained_generalized_alpha.hpp) for a
/// MultibodySystem: the Assembly of that stepper's System concept.
///
/// Unknowns per body in the system's dof order ((δp world, δθ body) or δθ for
/// a rotation-only body), then the multipliers in the row order of
/// schur(RowSet::kAll) (joints, prescribed coordinates, gears). The scaled
/// matrix (the stepper's file comment, BCA 2012 with the scaling of Bottasso,
/// Bauchau & Cardona 2007)
///   A = [ M + c_C C_t + c_K K_t T    Jᵀ ]     c_C = γ'/β',  c_K = 1/β',
///       [ Φ_q T                      0  ]     T = diag(I₃, Jr(hΔθ_b)) per body,
///       [ B                          0  ]
/// with the tangent terms (g = −F of MultibodySystem::forces, gyroscopic on):
///  * M = diag(m I₃, J_b) per body (constant in maximal coordinates);
///  * C_t: the gyroscopic derivative ∂(ω × Jω)/∂ω = ω^ J − (Jω)^ per body and
///    the dashpots c J_φᵀ J_φ of the joint coordinates;
///  * K_t: the springs k J_φᵀ J_φ and the geometric stiffness of the
///    constraint forces ∂(Jᵀλ)/∂δq, by one-sided differences of the Jacobian
///    blocks (MultibodySystem::constraintJacobians at perturbed poses, bodies
///    coloured so that one evaluation per colour and coordinate suffices: 2
///    colours × 3 rotations along a chain). Holonomic joint and angle blocks
///    depend on the orientations only; with gears the positions are
///    perturbed too (rack-and-pinion slide terms).
///    Left out: the spring's k (φ − φ₀) ∂J_φ/∂δq, ∂(Jᵀλ)/∂δp (zero for these
///    joints) and the velocity rows' ∂(B u)/∂δq — they cost iterations, not
///    accuracy.
/// Pattern: a dense block per body, a dense block for every pair of bodies
/// sharing a row group (joint, prescribed coordinate, gear) and the J and Jᵀ
/// blocks of each group; built once per topology, values refilled in place.
/// Its size and the nonzeros of its LU factors grow linearly along chains
/// and trees (measured on revolute chains: ≈ 265–320 LU nonzeros per body at
/// N = 20…1000).
///
/// Stabilized index 2 (setStabilized(true); the stepper's "Stabilized index
/// 2"): q_{n+1} = q_n exp(hΔq + P ν), P = M⁻¹ J̄ᵀ (J̄ = ½ (J(q_n) + J(q̃_{n+1}))
/// of the position rows: J(q_n) stored by startStep(), q̃_{n+1} the iterate
/// of the step's first matrix(), J̄ held for the step), with the velocity
/// rows J u = b of all m rows and the position rows Φ = 0. Newton runs on
/// (ΔQ, Δλ/β', Δν), ΔQ = ΔΔ + P Δν the correction of the whole position
/// increment: the q-dependent terms see ΔQ, the u- and u̇-dependent ones ΔΔ
/// = ΔQ − P Δν, and M P = J̄ᵀ keeps the ν columns sparse:
///   A = [ M + c_C C_t + c_K K_t T    Jᵀ   −(M + c_C C_g) M⁻¹ J̄ᵀ ]  force (n)
///       [ J + ∂(J u)/∂δq T / γ'      0    −J M⁻¹ J̄ᵀ             ]  velocity (m)
///       [ Φ_q T                      0    0                     ]  position (m_p)
/// (C_g the gyroscopic part of C_t; the dashpots' c_C C P is left out, and
/// ∂(J u)/∂δq comes with the geometric stiffness, from the same differences).
/// The −J M⁻¹ J̄ᵀ blocks couple the groups that share a body (the pattern of
/// J M⁻¹ Jᵀ); the matrix has n + m + m_p rows.
///
/// Joint angles: advance() unwraps them near φ + J_φ(y) dq, the first-order
/// prediction along the increment, so that a Newton iterate that turns a
/// joint by more than π (the predictor of a stiff spring at h ω ≫ 1) keeps
/// the turn instead of wrapping it back (the spring would otherwise pull
/// towards a wrong multiple of 2π).
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "integrators/constrained_generalized_alpha.hpp"
#include "dynamics/maximal/multibody_system.hpp"

namespace lieflow {
namespace multibody {

struct KktAssemblyOptions {
  /// Include the geometric stiffness ∂(Jᵀλ)/∂δq of the constraint forces in
  /// K_t (one-sided differences: 6 evaluations of all Jacobian blocks per
  /// Newton iteration along a chain, ~1/3 of an iteration's time at 1000
  /// bodies). Without it Newton converges linearly at a rate ~ β h² |λ| ℓ / I
  /// (large reactions: fast spin, heavy loads; measured on the 1000 rad/s
  /// rotor with a blade: 3–4 instead of 2 iterations per step).
  bool geometric_stiffness = true;
};

class KktAssembly {
 public:
  using State = MultibodyGroupState;

  explicit KktAssembly(KktAssemblyOptions options = {}) : options_(options) {}
  const KktAssemblyOptions& options() const { return options_; }
  void setOptions(const KktAssemblyOptions& options) { options_ = options; }

  /// Binds to `system` (kept by reference) and builds the pattern when its
  /// topology differs from the bound one; true when the pattern is new.
  bool bind(const MultibodySystem& system);
  /// Bound to `system` (same object, same topology).
  bool boundTo(const MultibodySystem& system) const;

  int dofs() const { return n_; }
  int positionRows() const { return mp_; }
  int velocityRows() const { return m_ - mp_; }

  /// The stabilized index-2 formulation (file comment) or index 3; a change
  /// unbinds (the next bind() builds the pattern).
  void setStabilized(bool stabilized) {
    if (stabilized != stabilized_) system_ = nullptr;
    stabilized_ = stabilized;
  }
  bool stabilized() const { return stabilized_; }
  /// Stabilized: stores J(q_n) of the position rows at the step's start.
  void startStep(double t, const State& y);
  /// Stabilized: dq += M⁻¹ J̄ᵀ ν (ν of size positionRows(); J̄ = J(q_n) until
  /// the step's first matrix()).
  void addStartCorrection(const Eigen::VectorXd& nu, Eigen::VectorXd* dq) const;
  static void velocityInto(const State& y, Eigen::VectorXd* u) { y.velocitiesInto(u); }
  /// out = (q exp(dq), u): positions moved by dq (δp world, δθ body),
  /// velocities replaced, joint angles unwrapped near y's plus J_φ(y) dq.
  /// out's storage is reused (no allocation once it has y's sizes); out may
  /// not be y.
  static void advanceInto(const State& y, const Eigen::VectorXd& dq, const Eigen::VectorXd& u, State* out);
  static bool identical(const State& a, const State& b);

  /// u̇, λ of the index-1 equations (MultibodySystem::accelerations).
  bool accelerations(double t, const State& y, Eigen::VectorXd* udot, Eigen::VectorXd* lambda,
                     std::string* why) const;

  /// r = M u̇ − F(t, y) + Jᵀλ and c = [Φ(q, t); B u − b] (stabilized: c =
  /// [Φ(q, t); J u − b] over all m rows, size m_p + m); returns
  /// max(‖M u̇‖∞, ‖F‖∞, ‖Jᵀλ‖∞). Leaves J(y) in schur(RowSet::kAll) for
  /// matrix().
  double residual(double t, const State& y, const Eigen::VectorXd& udot, const Eigen::VectorXd& lambda,
                  Eigen::VectorXd* r, Eigen::VectorXd* c);

  /// The scaled iteration matrix (file comment) at the y of the last
  /// residual() call; dq = hΔq.
  const Eigen::SparseMatrix<double>& matrix(const State& y, const Eigen::VectorXd& dq, double damping_factor,
                                            double stiffness_factor, const Eigen::VectorXd& lambda);

 private:
  /// A dense block of A: entry (r, c) at values[slots_[slot0 + c·rows + r]].
  struct Block {
    int rows = 0, cols = 0;
    std::size_t slot0 = 0;
  };
  /// A block of the pattern: rows × cols from (row0, col0).
  struct Place {
    int row0, col0, rows, cols;
  };
  /// bind()'s steps: the blocks of M, J and Jᵀ (body_block_, j_block_,
  /// jt_block_, pair_block_); with stabilized_, those of the position rows
  /// and ν columns (pj_block_, fnu_block_, vnu_contributions_); A_'s pattern
  /// of N columns and each block's slots in it; the bodies' colours.
  void placeIndexOneBlocks(const MultibodySystem& system, std::vector<Place>* places);
  void placeStabilizedBlocks(const MultibodySystem& system, std::vector<Place>* places);
  void buildPattern(const std::vector<Place>& places, int N);
  void colourBodies();
  template <typename Derived>
  void addBlock(int k, const Eigen::MatrixBase<Derived>& value, int r0 = 0, int c0 = 0);
  int rotationBegin(int b) const { return rot_[b] ? 0 : 3; }
  int dofsOf(int b) const { return rot_[b] ? 3 : 6; }  ///< body b's coordinates (a rotation-only body 3)
  /// K_λ T (times `factor`) into the body-pair blocks and, with a nonzero
  /// velocity_factor, ∂(J u)/∂δq T (times it) into the velocity rows.
  void geometricStiffness(const State& y, const Eigen::VectorXd& lambda, double factor, double velocity_factor,
                          const std::vector<Eigen::Matrix3d>& Jr);

  KktAssemblyOptions options_;
  bool stabilized_ = false;
  const MultibodySystem* system_ = nullptr;
  std::vector<char> rot_;
  std::vector<RowGroup> groups_;
  int n_ = 0, m_ = 0, mp_ = 0;
  Eigen::SparseMatrix<double> A_;
  std::vector<Eigen::Index> slots_;
  std::vector<Block> blocks_;
  std::vector<int> body_block_;                                   ///< per body
  std::vector<std::array<std::array<int, kMaxGroupBodies>, kMaxGroupBodies>> pair_block_;  ///< per group
  std::vector<std::array<int, kMaxGroupBodies>> j_block_, jt_block_;  ///< per group
  /// Stabilized: per position group, the blocks Φ_q T (position rows) and
  /// −(M + c_C C) M⁻¹ J̄ᵀ (force rows, ν columns); the −J_g M⁻¹ J̄_g2ᵀ
  /// contributions (block, g, slot in g, g2, slot in g2).
  std::vector<std::array<int, kMaxGroupBodies>> pj_block_, fnu_block_;
  struct NuContribution {
    int block, g, s, g2, s2;
  };
  std::vector<NuContribution> vnu_contributions_;
  std::vector<std::array<GroupBlock, kMaxGroupBodies>> start_;  ///< J(q_n), position groups
  std::vector<std::array<GroupBlock, kMaxGroupBodies>> mid_;    ///< J̄ of this step
  bool mid_fixed_ = false;  ///< J̄ set by this step's first matrix()
  Eigen::VectorXd F_, phi_, b_, Mu_, JTl_, Ju_, u_, w_;
  std::vector<Eigen::Matrix3d> Jr_;
  double t_ = 0.0;                                   ///< t of the last residual()
  std::vector<int> colour_;                          ///< per body (geometricStiffness)
  State perturbed_;                                  ///< geometricStiffness' q ⊕ ε e_j
  std::vector<CoordinateElement> elements_;          ///< matrix()'s springs and dashpots
  int colours_ = 0;
  std::vector<std::array<GroupBlock, kMaxGroupBodies>> base_;  ///< J(y) saved
};

}  // namespace multibody

template <>
struct ConstrainedSystemTraits<multibody::MultibodySystem> {
  using Assembly = multibody::KktAssembly;
};

}  // namespace lieflow
