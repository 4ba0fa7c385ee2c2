/// \file
/// A URDF link's shapes (<visual>, or <collision> when it has no visual):
/// boxes, cylinders, spheres and meshes, placed in the world at the link's
/// frame T. A mesh's `filename` is resolved to a file: `package://PKG/rest`
/// as PKG's folder among the URDF's folder, its ancestors and their
/// children (a ROS workspace's layout), `file://` as a path, anything else
/// relative to the URDF's folder; one that does not resolve keeps its name
/// (the replay draws the link's inertia box instead and says so).
#pragma once
#ifdef LIEFLOW_HAVE_URDFDOM

#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <urdf_model/link.h>

#include "model/visual_shape.hpp"

namespace lieflow {
namespace model_import {

std::vector<VisualShape> urdfLinkShapes(const urdf::Link& link, const Eigen::Isometry3d& T,
                                        const std::string& urdf_path);

/// A URDF <origin> (or urdfdom pose) as an isometry, its quaternion normalized.
Eigen::Isometry3d urdfIsometry(const urdf::Pose& p);

/// The file a URDF mesh name refers to, or "" when none exists.
std::string resolveUrdfMesh(const std::string& filename, const std::string& urdf_path);

}  // namespace model_import
}  // namespace lieflow

#endif  // LIEFLOW_HAVE_URDFDOM
