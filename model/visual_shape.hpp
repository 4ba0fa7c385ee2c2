/// \file
/// What a body looks like, for the replay (replay/): the shapes a model file
/// gives it (MJCF geoms as MuJoCo's compiler gives them, URDF <visual>
/// primitives and meshes). Nothing in the dynamics reads them; a body without
/// shapes is drawn as the box with its inertia (replay/replay_scene.hpp).
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace lieflow {

/// One shape, placed by `position` and `orientation` (shape frame → the
/// frame it is given in: a body's axes from its centre of mass in a scene,
/// the world in a model file at its reference configuration).
struct VisualShape {
  /// Cylinders and capsules lie along the shape frame's z axis (as in MJCF
  /// and URDF).
  enum class Kind { kBox, kSphere, kCylinder, kCapsule, kEllipsoid, kMesh };
  Kind kind = Kind::kBox;
  /// box: half extents; sphere: (radius, -, -); cylinder and capsule:
  /// (radius, half length, -); ellipsoid: the three radii.
  Eigen::Vector3d size = Eigen::Vector3d::Zero();
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  std::array<double, 4> rgba{{0.7, 0.7, 0.7, 1.0}};
  /// kMesh: either triangles (`vertices` x,y,z…, `faces` i,j,k…, shape
  /// frame, as MuJoCo's compiler leaves a mesh), or a file the replay page
  /// parses (`mesh_file`, STL, COLLADA or OBJ) scaled by `mesh_scale`.
  std::vector<float> vertices;
  std::vector<int> faces;
  std::string mesh_file;
  Eigen::Vector3d mesh_scale = Eigen::Vector3d::Ones();
  /// Where it came from ("geom 'torso' (line 12)"), for notes.
  std::string origin;
};

/// `shape` (given in the world) in the frame whose origin is `origin` and
/// whose axes are `axes` (frame → world), both in the world.
inline VisualShape shapeInFrame(VisualShape shape, const Eigen::Vector3d& origin, const Eigen::Quaterniond& axes) {
  shape.position = axes.conjugate() * (shape.position - origin);
  shape.orientation = (axes.conjugate() * shape.orientation).normalized();
  return shape;
}

}  // namespace lieflow
