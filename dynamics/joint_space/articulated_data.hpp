/// \file
/// The workspace of an ArticulatedSystem: the "Data" of the model/data split
/// of Pinocchio and MuJoCo. The system's model (ArticulatedModel, with what
/// is derived from it once: each joint's Rodrigues basis) does not change
/// after construction; everything an evaluation writes lives here — per body
/// the kinematics and the articulated-body algorithm's quantities, the mass
/// matrix's composite inertias, the variational passes' scratch and the
/// loops' matrices. Sized once from the model (the system's constructor;
/// the composite inertias at their first use) and reused by every
/// evaluation, so that no step allocates; a system's const functions write
/// it, so one system serves one thread at a time (a copy has its own data).
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>
#include <Eigen/StdVector>

#include "dynamics/joint_space/spatial_algebra.hpp"
#include "dynamics/joint_space/tree_passes.hpp"

namespace lieflow {
namespace articulated {

struct ArticulatedData {
  /// One body's kinematics and articulated-body quantities (the ABA's passes).
  using Body = TreeBody<double>;

  std::vector<Body> bodies;
  /// A floating root's spatial momentum h in I_A a + p_A = h: zero for the
  /// dynamics, the given velocities' momentum while projecting them.
  std::vector<Vector6, Eigen::aligned_allocator<Vector6>> root_momentum;
  bool projecting = false;
  /// Composite inertias of the mass matrix (sized at its first use).
  std::vector<Matrix6, Eigen::aligned_allocator<Matrix6>> composite;
  Eigen::VectorXd udot;
  /// Scratch of the variational passes (kinetic, solveMass, forces, frames).
  std::vector<Vector6> twist, accumulated, before;
  /// The variational passes' free trees (by root rotation index): the
  /// centre-of-mass velocity v_z and the uniform motion that stops the tree.
  std::vector<Eigen::Vector3d> tree_vz, tree_shift;
  /// The variational passes' coupling rows: scratch of Y's columns, G Y,
  /// G v and the multipliers.
  Eigen::VectorXd coupling_rhs, coupling_x, coupling_g, coupling_lambda;
  Eigen::MatrixXd coupling_GY;
  /// With loops or gear rows: the multipliers of the iteration's last pass
  /// (projectIncrement), which constraintImpulse applies.
  Eigen::VectorXd loop_lambda;
  std::vector<Matrix6> articulated;

  /// Loop workspace, sized at construction (m closure rows, n dofs): G (m × n),
  /// Y = M⁻¹ Gᵀ (n × m), G Y and its factorization, Φ or its
  /// derivatives (m), λ (m), a scratch m-vector, solve scratch (n).
  Eigen::MatrixXd closure_G, closure_Y, closure_A;
  Eigen::VectorXd closure_r, closure_lambda, closure_s, closure_x, closure_rhs;
  /// closureInverseMass's workspace for C = m columns: per body the 6 × m
  /// forces, then accelerations, its 3 × m scratch rows and a floating
  /// root's generalized forces as a spatial force (6 × m). One row (a
  /// gripper's one mimic) has its own fixed-size copy: Eigen's dynamic
  /// 6 × 1 products cost the Panda's step 15 % (perf).
  template <int C>
  struct ClosureColumns {
    std::vector<Eigen::Matrix<double, 6, C>, Eigen::aligned_allocator<Eigen::Matrix<double, 6, C>>> pA;
    Eigen::Matrix<double, 3, C> rows3;
    Eigen::Matrix<double, 6, C> root_force;
    void resize(std::size_t bodies, int m) {
      pA.assign(bodies, Eigen::Matrix<double, 6, C>::Zero(6, m));
      rows3.setZero(3, m);
      root_force.setZero(6, m);
    }
  };
  ClosureColumns<Eigen::Dynamic> closure_columns;
  ClosureColumns<1> closure_column;
  std::vector<int> closure_perm;  ///< the pivoted Cholesky's row order
  /// The closing joints' last output angles (unwrapping; reset at t = 0).
  std::vector<std::array<double, 2>> closure_phi;
};

}  // namespace articulated
}  // namespace lieflow
