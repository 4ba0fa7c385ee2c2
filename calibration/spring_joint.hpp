/// \file
/// The joint `lieflow calibrate spring` fits on its own: one body on a
/// revolute or universal joint to the ground, taken from a scene as the
/// one-body tree of the joint formulation (dynamics/joint_space/
/// articulated_scene.hpp), so that its dynamics are the mechanism fit's
/// (dynamics/joint_space/scalar_dynamics.hpp; a grounded hinge in its closed
/// form) and φ is the `J.phi` (`J.phi1`, `J.phi2`) of `lieflow simulate`.
/// The one-joint fit is the one-body case of the mechanism: what it adds
/// are the options of a single coordinate (starts, held damping, shooting,
/// integrator) and the quantities a single coordinate has (its inertia,
/// gravity stiffness, natural frequency and damping ratio).
#pragma once

#include <array>
#include <memory>
#include <string>

#include <Eigen/Core>

#include "dynamics/joint_types.hpp"
#include "dynamics/joint_space/articulated_model.hpp"
#include "dynamics/joint_space/articulated_scene.hpp"
#include "model/scene.hpp"

namespace lieflow {
namespace calibration {

struct SpringJoint {
  std::string source;          ///< the scene's file or name, for messages
  std::string label;           ///< "SOURCE: joints[k] (name)"
  std::string joint_name;
  std::string type;            ///< "revolute" or "universal"
  std::string body_name;
  bool body_is_main = false;   ///< the body is the joint's main side (ground secondary)
  int coordinates = 1;         ///< 1 (revolute) or 2 (universal)
  /// The scene's springs, dashpots and moments of the coordinates.
  std::array<CoordinateDrive, 2> drives;
  /// φ and φ̇ at t = 0 from the assembled scene.
  Eigen::Vector2d initial_angle = Eigen::Vector2d::Zero();
  Eigen::Vector2d initial_rate = Eigen::Vector2d::Zero();
  /// The one-body tree (shared: a SpringJoint is copied freely).
  std::shared_ptr<const ArticulatedScene> tree;

  const articulated::ArticulatedModel& model() const { return tree->system->model(); }
  /// Whether gravity acts on the coordinate (a body with mass, not
  /// rotation-only, in a scene with gravity).
  bool weighted() const;
  /// The generalized mass M(φ)_ii of coordinate i at φ (kg m²): the inertia
  /// about the joint axis for a revolute joint.
  double inertiaAbout(int i, const Eigen::Vector2d& phi) const;
  /// The generalized gravity moment on coordinate i at φ (N m), at rest.
  double gravityMoment(int i, const Eigen::Vector2d& phi) const;
  /// The gravity stiffness −∂Q_g/∂φ_i at φ (N m/rad), by a central
  /// difference of gravityMoment with step kGravityStiffnessStep.
  double gravityStiffness(int i, const Eigen::Vector2d& phi) const;
  static constexpr double kGravityStiffnessStep = 1e-5;  ///< rad
};

/// The joint `joint_name` (empty: the scene's only revolute or universal
/// joint) and its body. Throws InvalidInput naming the scene, the joint and
/// the reason when the joint is unknown, not revolute/universal, not to
/// ground, its body is in another joint or gear, a coordinate is prescribed,
/// or a rotation-only body is not anchored at its centre of mass.
SpringJoint springJoint(const SceneDescription& scene, const std::string& joint_name);

}  // namespace calibration
}  // namespace lieflow
