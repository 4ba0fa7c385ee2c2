#ifdef LIEFLOW_HAVE_URDFDOM
#include "model/import/urdf_visuals.hpp"

#include <sys/stat.h>

#include <memory>

namespace lieflow {
namespace model_import {

namespace {

/// How many folders up from the URDF a package:// name is looked for.
constexpr int kPackageSearchDepth = 6;

bool isFile(const std::string& path) {
  struct stat st {};
  return !path.empty() && ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

std::string folderOf(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string(".") : slash == 0 ? std::string("/") : path.substr(0, slash);
}

/// One <visual> or <collision> element's shape, or false when its geometry
/// is missing or not finite.
template <class Element>
bool shapeOf(const Element& e, const Eigen::Isometry3d& T, const std::string& urdf_path, VisualShape* s) {
  if (!e.geometry) return false;
  const Eigen::Isometry3d Tw = T * urdfIsometry(e.origin);
  s->position = Tw.translation();
  s->orientation = Eigen::Quaterniond(Tw.linear()).normalized();
  switch (e.geometry->type) {
    case urdf::Geometry::SPHERE: {
      const auto& g = static_cast<const urdf::Sphere&>(*e.geometry);
      s->kind = VisualShape::Kind::kSphere;
      s->size = Eigen::Vector3d(g.radius, 0.0, 0.0);
      break;
    }
    case urdf::Geometry::BOX: {
      const auto& g = static_cast<const urdf::Box&>(*e.geometry);
      s->kind = VisualShape::Kind::kBox;
      s->size = 0.5 * Eigen::Vector3d(g.dim.x, g.dim.y, g.dim.z);  // URDF gives full sizes
      break;
    }
    case urdf::Geometry::CYLINDER: {
      const auto& g = static_cast<const urdf::Cylinder&>(*e.geometry);
      s->kind = VisualShape::Kind::kCylinder;
      s->size = Eigen::Vector3d(g.radius, 0.5 * g.length, 0.0);
      break;
    }
    case urdf::Geometry::MESH: {
      const auto& g = static_cast<const urdf::Mesh&>(*e.geometry);
      s->kind = VisualShape::Kind::kMesh;
      const std::string file = resolveUrdfMesh(g.filename, urdf_path);
      s->mesh_file = file.empty() ? g.filename : file;
      s->mesh_scale = Eigen::Vector3d(g.scale.x, g.scale.y, g.scale.z);
      break;
    }
    default: return false;
  }
  return s->size.allFinite() && s->position.allFinite() && s->mesh_scale.allFinite();
}

}  // namespace

Eigen::Isometry3d urdfIsometry(const urdf::Pose& p) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z).normalized().toRotationMatrix();
  T.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  return T;
}

std::string resolveUrdfMesh(const std::string& filename, const std::string& urdf_path) {
  const std::string package = "package://", file = "file://";
  if (filename.rfind(file, 0) == 0) return isFile(filename.substr(file.size())) ? filename.substr(file.size()) : "";
  if (filename.rfind(package, 0) != 0) {
    const std::string path = filename.front() == '/' ? filename : folderOf(urdf_path) + "/" + filename;
    return isFile(path) ? path : "";
  }
  const std::string rest = filename.substr(package.size());
  const std::size_t slash = rest.find('/');
  if (slash == std::string::npos) return "";
  const std::string name = rest.substr(0, slash), inside = rest.substr(slash + 1);
  std::string folder = folderOf(urdf_path);
  for (int up = 0; up < kPackageSearchDepth; ++up) {
    const std::string base = folder.substr(folder.find_last_of('/') + 1);
    for (const std::string& candidate : {base == name ? folder + "/" + inside : std::string(),
                                         folder + "/" + name + "/" + inside, folder + "/" + inside})
      if (isFile(candidate)) return candidate;
    if (folder == "/" || folder == ".") break;
    folder = folderOf(folder);
  }
  return "";
}

std::vector<VisualShape> urdfLinkShapes(const urdf::Link& link, const Eigen::Isometry3d& T,
                                        const std::string& urdf_path) {
  std::vector<VisualShape> shapes;
  for (const urdf::VisualSharedPtr& v : link.visual_array) {
    VisualShape s;
    if (!v || !shapeOf(*v, T, urdf_path, &s)) continue;
    if (v->material && v->material->color.a > 0.0f)
      s.rgba = {{v->material->color.r, v->material->color.g, v->material->color.b, v->material->color.a}};
    s.origin = "visual of link '" + link.name + "'";
    shapes.push_back(std::move(s));
  }
  if (!shapes.empty()) return shapes;
  for (const urdf::CollisionSharedPtr& c : link.collision_array) {
    VisualShape s;
    if (!c || !shapeOf(*c, T, urdf_path, &s)) continue;
    s.origin = "collision of link '" + link.name + "'";
    shapes.push_back(std::move(s));
  }
  return shapes;
}

}  // namespace model_import
}  // namespace lieflow

#endif  // LIEFLOW_HAVE_URDFDOM
