/// \file
/// The assembled scene behind a Simulation (internal to joints/: the
/// simulation sources share it; the public interface is simulation.hpp).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "dynamics/rigid_body/rigid_body_system.hpp"
#include "dynamics/joint_space/articulated_scene.hpp"
#include "simulation/invariants.hpp"
#include "dynamics/maximal/multibody_scene.hpp"
#include "simulation/simulation.hpp"
#include "simulation/stepper_table.hpp"

namespace lieflow {

struct Simulation::Model {
  /// Rotation-only dynamics (free rotor or about a pivot) vs full free body.
  bool rotor = true;
  /// The body's CSV rows include position and velocity columns.
  bool translational_output = false;
  RigidBodyParameters<double> params;
  RotorState<double> rotor0;
  FreeBodyState<double> free0;
  /// A free rotor's centre of mass stays here.
  Eigen::Vector3d fixed_position = Eigen::Vector3d::Zero();
  /// Scenes with joints (other than one spherical joint to ground): the
  /// constrained multibody system; the fields above are then unused.
  std::unique_ptr<MultibodyScene> multibody;
  /// The same scene in joint coordinates (--formulation joint), when the
  /// joint formulation covers it (else `articulated_why` says why not).
  std::unique_ptr<ArticulatedScene> articulated;
  std::string articulated_why;
  /// What the scene conserves (a fresh copy tracks each run).
  InvariantSet invariants;
  /// Gravity and each body's sensor point (scene order), for --imu rows.
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> sensors;
};

/// Runs a scene in joint coordinates (simulation_articulated.cpp): the
/// stepper the table (stepper_table_rows.hpp) gives o.integrator in column
/// `kind` (kJointTree, kJointCoupled or kJointLoops) on ArticulatedSystem.
SimulationResult runArticulated(const Simulation::Model& model, SystemKind kind, const SimulationOptions& options,
                                const std::vector<std::string>& columns,
                                const std::function<void(const std::vector<double>&)>& row);

}  // namespace lieflow
