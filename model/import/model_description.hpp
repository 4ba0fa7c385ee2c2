/// \file
/// A mechanism as a model file describes it (MJCF, URDF), before it becomes a
/// lieflow scene: links with their mass properties and poses in the world at
/// the model's reference configuration, and the joints between them with
/// world anchors and axes. The readers (urdf_import.cpp, mjcf_import.cpp)
/// fill it; model_to_scene.hpp merges welded links and writes the scene.
///
/// Every element keeps where it came from (`line`, 0 when the reader cannot
/// tell) so that errors and the list of ignored features name it.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "model/time_function.hpp"
#include "model/visual_shape.hpp"

namespace lieflow {
namespace model_import {

/// One rigid link. The link frame is the model's body frame; the lieflow
/// body keeps its orientation and has its centre of mass as origin.
struct ModelLink {
  std::string name;
  int line = 0;
  double mass = 0.0;
  /// Inertia about the centre of mass, world axes, at the reference configuration.
  Eigen::Matrix3d inertia_world = Eigen::Matrix3d::Zero();
  Eigen::Vector3d com_world = Eigen::Vector3d::Zero();
  /// The link frame's orientation (link → world) at the reference configuration.
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  /// Initial velocities (world; ω in world axes); zero unless the model sets them.
  Eigen::Vector3d angular_velocity_world = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_world = Eigen::Vector3d::Zero();
  /// Its shapes, placed in the world at the reference configuration.
  std::vector<VisualShape> visuals;
};

/// The joint types a model file maps to (DESIGN.md Additions; issue 15).
enum class ModelJointType { kRevolute, kPrismatic, kSpherical, kUniversal, kGimbal, kFixed, kFree };

/// A joint between `parent` and `child` (link indices; −1 is the world).
/// The child moves relative to the parent; the scene's joint has the parent
/// as `main` and the child as `secondary`.
struct ModelJoint {
  std::string name;
  int line = 0;
  ModelJointType type = ModelJointType::kFixed;
  int parent = -1;
  int child = -1;
  Eigen::Vector3d anchor_world = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis_world = Eigen::Vector3d::UnitZ();   ///< revolute, prismatic; universal: the first axis
  Eigen::Vector3d axis2_world = Eigen::Vector3d::UnitY();  ///< universal: the second axis
  /// universal: a point of the second axis (apart from anchor_world: an
  /// offset universal joint, MuJoCo's two hinges of one body at two points).
  Eigen::Vector3d anchor2_world = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis3_world = Eigen::Vector3d::UnitX();  ///< gimbal: the third axis
  /// Per coordinate (a universal joint has two, about axis then axis2; a
  /// gimbal three, then axis3; the axes as they are at the reference
  /// configuration):
  /// q at the reference configuration (the scene's initial angle or slide;
  /// 0 when the reference configuration is the model's zero), the spring
  /// (N m/rad or N/m) with its rest value (rad or m), and the dashpot
  /// (N m s/rad or N s/m).
  std::array<double, 3> initial{{0.0, 0.0, 0.0}};
  std::array<double, 3> stiffness{{0.0, 0.0, 0.0}};
  std::array<double, 3> rest{{0.0, 0.0, 0.0}};
  std::array<double, 3> damping{{0.0, 0.0, 0.0}};
};

/// A coupling q_follower = multiplier q_leader + offset of two joints (URDF
/// <mimic>, MJCF equality joint with a linear polycoef): a coupling row in
/// the scene when both are revolute or prismatic joints of one parent.
struct ModelCoupling {
  std::string name;
  int line = 0;
  std::string leader, follower;  ///< joint names
  double multiplier = 1.0;
  double offset = 0.0;
};

/// A loop closure (MJCF equality connect / weld between two links).
struct ModelClosure {
  std::string name;
  int line = 0;
  ModelJointType type = ModelJointType::kSpherical;  ///< spherical (connect) or fixed (weld)
  int link1 = -1, link2 = -1;                          ///< −1: the world
  Eigen::Vector3d anchor_world = Eigen::Vector3d::Zero();
};

struct ModelDescription {
  std::string name;
  std::string source;  ///< the file, for messages
  Eigen::Vector3d gravity = Eigen::Vector3d(0.0, 0.0, -9.81);
  double timestep = 0.0;  ///< the model's step, 0 if none
  std::vector<ModelLink> links;
  std::vector<ModelJoint> joints;
  std::vector<ModelCoupling> couplings;
  std::vector<ModelClosure> closures;
  /// Shapes fixed to the world (a URDF's fixed root, MJCF world geoms), world frame.
  std::vector<VisualShape> ground_visuals;
  /// What the reader left out because the user allowed it (--ignore), one
  /// line each ("ignored contacts: geom 'floor' (line 12)").
  std::vector<std::string> ignored;
  /// What the reader says of the model beyond that, one sentence each (a
  /// URDF's root fixed to the world).
  std::vector<std::string> notes;
};

}  // namespace model_import
}  // namespace lieflow
