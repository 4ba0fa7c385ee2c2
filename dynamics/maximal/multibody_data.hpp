/// \file
/// The workspace of a MultibodySystem: the "Data" of the model/data split of
/// Pinocchio and MuJoCo. The system's model — bodies, joints, drives, gears
/// and what is derived from them once (row groups, dof offsets) — does not
/// change after construction; everything an evaluation writes lives here:
/// the Schur complement solvers (their Jacobian blocks, S = J M⁻¹ Jᵀ and its
/// factorization), which poses the held factorization belongs to, and the
/// vectors of the acceleration solve and the projections. It is sized once
/// from the model (MultibodySystem's constructor) and reused by every
/// evaluation, so that no step allocates; a system's const functions write
/// it, so one system serves one thread at a time (copy the system for
/// another thread: the copy has its own data).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "dynamics/constraints/constraints.hpp"
#include "dynamics/maximal/multibody_group_state.hpp"
#include "dynamics/maximal/schur_solver.hpp"

namespace lieflow {
namespace multibody {

struct MultibodyData {
  /// The Schur complement solvers of all rows (holonomic, prescribed and
  /// gear) and, when there are gears, of the position rows alone.
  SchurSolver all, pos;

  /// The last successful factorization (MultibodySystem::factorConstraints):
  /// which solver holds it and at which poses (J and S depend on q only). Any
  /// rewrite of the blocks invalidates it.
  struct FactorCache {
    bool valid = false;
    const SchurSolver* solver = nullptr;
    std::vector<constraints::BodyPose<double>> poses;
  };
  FactorCache factor_cache;

  /// The position projection's start (restored when it fails).
  MultibodyGroupState projection_backup;
  /// Vectors of the acceleration solve, the projections and the residuals.
  Eigen::VectorXd phi, projection_step, udot, residual, b, u;
  Eigen::VectorXd F, y, rhs, c, lam, tmp;
};

}  // namespace multibody
}  // namespace lieflow
