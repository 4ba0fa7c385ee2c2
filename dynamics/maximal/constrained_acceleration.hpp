/// \file
/// The constrained acceleration solve of a multibody system in maximal
/// coordinates (index-1 form), linear in the number of bodies along chains:
///
///   M q̈ + Jᵀ λ = F(q, q̇),     J q̈ = −c,
///
/// with q̈ the stacked per-body accelerations (v̇ world, ω̇ body), M block
/// diagonal (m I₃ for v̇, J_i for ω̇), F = (m g + f, τ − ω × J ω) and J, c the
/// stacked constraint blocks and convective terms of dynamics/constraints/
/// (Φ̈ = J q̈ + c). Schur complement (Haug 1989, ch. 11; Baraff 1996,
/// "Linear-time dynamics using Lagrange multipliers"):
///
///   (J M⁻¹ Jᵀ) λ = J M⁻¹ F + c,      q̈ = M⁻¹ (F − Jᵀ λ).
///
/// J M⁻¹ Jᵀ is assembled sparse (two joints couple only if they share a body:
/// block-tridiagonal for a chain) and factored with Eigen::SimplicialLDLT and
/// its default AMD ordering, so the factor's fill and the cost grow linearly
/// along chains and trees. No dense factorization of the whole system.
///
/// Redundant constraints make J M⁻¹ Jᵀ singular: a pivot of the LDLᵀ factor
/// below kPivotTolerance × its diagonal entry (or negative) is reported as a
/// failure naming the joint of that row (status, or InvalidInput from
/// solveConstrainedAccelerationsOrThrow); no multipliers are returned then.
///
/// Reactions: the joint's generalized force on a body is −J_kᵀ λ_k (rows of
/// joint k, block of that body): a force (world) through the CoM and a moment
/// (body frame) about the CoM; they are also given as force and moment about
/// the joint's anchor point in the world frame, and, for a revolute joint, the
/// moment about the axis M_J = M_M · a (M_M the moment on the main body about
/// the hinge point, a = R_a a_a the world axis).
#pragma once

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "dynamics/maximal/multibody_model.hpp"

namespace lieflow {
namespace multibody {

/// Reaction of joint k on one of its bodies.
struct BodyReaction {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();          ///< world, on the body
  Eigen::Vector3d moment_body = Eigen::Vector3d::Zero();    ///< body frame, about the CoM
  Eigen::Vector3d moment_anchor = Eigen::Vector3d::Zero();  ///< world, about the anchor point
};

struct JointReaction {
  BodyReaction main;       ///< zero when main is ground
  BodyReaction secondary;  ///< zero when secondary is ground
  /// On the ground side (world, about the anchor) when that side is ground.
  /// Revolute joints: M_J = M_M · a, the moment on the main body about the
  /// hinge axis (zero for an ideal hinge without applied/prescribed moments;
  /// computed from the secondary side, M_J = −M_S · a, when main is ground).
  std::optional<double> axial_moment;
};

struct AccelerationSolution {
  bool ok = false;
  std::string reason;        ///< why !ok (names the joint)
  int failed_joint = -1;     ///< joint of the first singular pivot, −1 if none
  std::vector<Eigen::Vector3d> vdot;      ///< per body, world (zero for rotation-only)
  std::vector<Eigen::Vector3d> omegadot;  ///< per body, body frame
  Eigen::VectorXd lambda;                 ///< multipliers, rows in joint order
  std::vector<JointReaction> reactions;   ///< per joint
  double constraint_residual = 0.0;       ///< ‖J q̈ + c‖∞
  Eigen::Index factor_nonzeros = 0;       ///< nnz of the strictly lower L factor
};

/// Reusable constrained-acceleration solver for a fixed model topology, on
/// the SchurSolver of schur_solver.hpp (one row group per joint): the
/// pattern of J M⁻¹ Jᵀ is built and analysed once per topology (number of
/// bodies/joints, joint bodies, row counts, rotation_only flags); every
/// solve() refills the values and factorizes. Masses, inertias, gravity,
/// constraint parameters, state and loads may change freely between calls.
///
/// Results are identical to solveConstrainedAccelerations (which runs a
/// temporary solver), including the reporting of redundant constraints.
class ConstrainedAccelerationSolver {
 public:
  ConstrainedAccelerationSolver() = default;
  /// Builds and analyses the pattern for `model` now (otherwise on first
  /// solve). Throws InvalidInput for a malformed model.
  explicit ConstrainedAccelerationSolver(const MultibodyModel& model);

  /// As solveConstrainedAccelerations, writing into `out` (its storage is
  /// reused). Returns out.ok.
  bool solve(const MultibodyModel& model, const MultibodyState& state,
             const std::vector<BodyLoad>& loads, AccelerationSolution& out);

  AccelerationSolution solve(const MultibodyModel& model, const MultibodyState& state,
                             const std::vector<BodyLoad>& loads = {}) {
    AccelerationSolution out;
    solve(model, state, loads, out);
    return out;
  }

  /// Number of times the pattern was built and analysed (analyzePattern calls).
  int analyzeCount() const { return schur_.analyzeCount(); }
  /// Stored entries (both triangles, explicit zeros included) of J M⁻¹ Jᵀ.
  Eigen::Index patternNonzeros() const { return schur_.patternNonzeros(); }

 private:
  void validate(const MultibodyModel& model, const MultibodyState& state);
  /// solve()'s steps: F = (m g + f, τ − ω × J ω) and M⁻¹ per body; q̈ into
  /// `out`; the joints' blocks J and convective terms c; a failure naming the
  /// joint of row r (returns false); the reactions −J_kᵀ λ_k per body.
  void assembleForces(const MultibodyModel& model, const MultibodyState& state, const std::vector<BodyLoad>& loads);
  void storeAccelerations(AccelerationSolution& out) const;
  void assembleJointRows(const MultibodyModel& model, const MultibodyState& state);
  bool fail(const MultibodyModel& model, int r, const std::string& why, AccelerationSolution& out) const;
  void jointReactions(const MultibodyModel& model, const MultibodyState& state, AccelerationSolution& out) const;
  void setup(const MultibodyModel& model);
  std::vector<RowGroup> topology(const MultibodyModel& model) const;

  SchurSolver schur_;
  std::vector<char> rot_;
  std::vector<double> checked_mass_;
  std::vector<Eigen::Matrix3d> checked_inertia_;
  Eigen::VectorXd F_, y_, qdd_, rhs_, c_, res_;
};

/// Solves the constrained accelerations at `state` under gravity and the
/// optional external loads (one per body, or empty). Never throws on a
/// singular system: returns ok = false with the reason. Throws InvalidInput
/// for malformed model/state (MultibodyModel::validate). Builds a temporary
/// ConstrainedAccelerationSolver: reuse one across steps for a fixed model.
inline AccelerationSolution solveConstrainedAccelerations(const MultibodyModel& model,
                                                          const MultibodyState& state,
                                                          const std::vector<BodyLoad>& loads = {}) {
  ConstrainedAccelerationSolver solver;
  return solver.solve(model, state, loads);
}

/// As solveConstrainedAccelerations, but a singular system throws
/// InvalidInput whose field names the joint ("joints[k] (name)").
inline AccelerationSolution solveConstrainedAccelerationsOrThrow(
    const MultibodyModel& model, const MultibodyState& state, const std::vector<BodyLoad>& loads = {}) {
  AccelerationSolution s = solveConstrainedAccelerations(model, state, loads);
  if (!s.ok) {
    const std::string field =
        s.failed_joint >= 0 ? "joints[" + std::to_string(s.failed_joint) + "]" : "joints";
    throw InvalidInput(field, s.reason);
  }
  return s;
}

}  // namespace multibody
}  // namespace lieflow
