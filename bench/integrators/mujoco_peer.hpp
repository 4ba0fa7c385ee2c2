/// \file
/// MuJoCo as an optional peer: the free body of free_body_scene.hpp as a MuJoCo
/// model (one body, one free joint, no geoms, gravity 0, contacts disabled),
/// stepped by mj_step with MuJoCo's semi-implicit Euler or RK4 integrator.
///
/// Built against MuJoCo only when CMake found it (LIEFLOW_HAVE_MUJOCO, see
/// CMakeLists.txt); otherwise mujocoAvailable() is false and constructing a
/// MujocoFreeBody throws. mujoco.h is included only in mujoco_peer.cpp.
///
/// Conventions (MuJoCo XML reference, joint type "free", 2.2): qpos =
/// (position of the body frame in the world, unit quaternion w x y z body →
/// world); qvel = (linear velocity of the body frame origin in the WORLD
/// frame, angular velocity in the LOCAL body frame), i.e. lieflow's (v, ω)
/// when the centre of mass is the body origin (<inertial pos="0 0 0">).
#pragma once

#include <memory>
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "bench/integrators/free_body_scene.hpp"

namespace lieflow {
namespace bench {

/// True when this binary was built with MuJoCo.
bool mujocoAvailable();
/// "MuJoCo 2.2.2" (library version, from mj_versionString()), or why not.
std::string mujocoDescription();

class MujocoFreeBody {
 public:
  enum class Integrator { kEuler, kRk4 };

  /// Builds the model from an XML string (in memory, through an mjVFS) with
  /// timestep h. Throws std::runtime_error with MuJoCo's message on failure
  /// (or when MuJoCo is not available).
  MujocoFreeBody(const FreeBodyScene& scene, Integrator integrator, double h);
  ~MujocoFreeBody();
  MujocoFreeBody(const MujocoFreeBody&) = delete;
  MujocoFreeBody& operator=(const MujocoFreeBody&) = delete;

  /// The model's XML text (for the record).
  const std::string& xml() const;

  /// qpos, qvel from the scene's initial state, time 0.
  void reset();
  /// One mj_step.
  void step();
  /// n mj_steps.
  void steps(long n);

  Eigen::Quaterniond orientation() const;
  Eigen::Vector3d position() const;
  Eigen::Vector3d angularVelocityBody() const;
  Eigen::Vector3d velocityWorld() const;
  double time() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace bench
}  // namespace lieflow
