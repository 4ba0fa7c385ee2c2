/// \file
/// The reduced model of calibration/grounded_joint_system.hpp taken from a scene:
/// the body on joint `name` (a revolute or universal joint between one body
/// and `ground`, that body in no other joint), with its inertia about the
/// pivot, the joint geometry of the assembled scene (axes and the reference
/// rotation R_ref, so that φ here is the `J.phi` of `lieflow simulate`), the
/// scene's springs, dashpots and applied moments, and the initial state.
#pragma once

#include <array>
#include <string>

#include <Eigen/Core>

#include "calibration/grounded_joint_system.hpp"
#include "dynamics/maximal/multibody_system.hpp"
#include "model/scene.hpp"

namespace lieflow {

struct GroundedJointScene {
  std::string source;          ///< the scene's file or name, for messages
  std::string label;           ///< "SOURCE: joints[k] (name)"
  std::string joint_name;
  std::string type;            ///< "revolute" or "universal"
  std::string body_name;
  bool body_is_main = false;   ///< the body is the joint's main side (ground secondary)
  int coordinates = 1;         ///< 1 (revolute) or 2 (universal)
  GroundedJointModel<1> revolute;   ///< used when coordinates == 1
  GroundedJointModel<2> universal;  ///< used when coordinates == 2
  /// The scene's springs, dashpots and moments of the coordinates (the
  /// moments are also in the models above).
  std::array<CoordinateDrive, 2> drives;
  /// φ and φ̇ at t = 0 from the assembled scene.
  Eigen::Vector2d initial_angle = Eigen::Vector2d::Zero();
  Eigen::Vector2d initial_rate = Eigen::Vector2d::Zero();

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

/// Builds the reduced model of joint `joint_name` (empty: the scene's only
/// revolute or universal joint). Throws InvalidInput naming the scene, the
/// joint and the reason when the joint is unknown, not revolute/universal,
/// not to ground, its body is in another joint or gear, a coordinate is
/// prescribed, or a rotation-only body is not anchored at its centre of mass.
GroundedJointScene groundedJointScene(const SceneDescription& scene, const std::string& joint_name);

}  // namespace lieflow
