// The scene half of a replay page: each body's shapes (or its inertia's
// box), the joints' markers, the ground's shapes, as the JSON the player
// (player.js) reads.
#include "replay/replay_scene.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <sstream>

#include <Eigen/Eigenvalues>

#include <sys/stat.h>

namespace lieflow {
namespace replay {

namespace {

/// A principal moment's share of the largest below which the box is given
/// this thickness instead (a rod's or a disc's zero moment).
constexpr double kThinShare = 0.02;

const char* kindName(VisualShape::Kind k) {
  switch (k) {
    case VisualShape::Kind::kBox: return "box";
    case VisualShape::Kind::kSphere: return "sphere";
    case VisualShape::Kind::kCylinder: return "cylinder";
    case VisualShape::Kind::kCapsule: return "capsule";
    case VisualShape::Kind::kEllipsoid: return "ellipsoid";
    case VisualShape::Kind::kMesh: return "mesh";
  }
  return "box";
}

nlohmann::json vec(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

std::string lowerExtension(const std::string& path) {
  const std::size_t dot = path.find_last_of('.');
  std::string e = dot == std::string::npos ? "" : path.substr(dot + 1);
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return e;
}

/// A shape's farthest point from its own origin (meshes from a file: 0, unknown).
double shapeRadius(const VisualShape& s) {
  switch (s.kind) {
    case VisualShape::Kind::kBox: return s.size.norm();
    case VisualShape::Kind::kSphere: return s.size.x();
    case VisualShape::Kind::kCylinder:
    case VisualShape::Kind::kCapsule: return std::hypot(s.size.x(), s.size.y()) + s.size.x();
    case VisualShape::Kind::kEllipsoid: return s.size.maxCoeff();
    case VisualShape::Kind::kMesh: {
      double r = 0.0;
      for (std::size_t i = 0; i + 2 < s.vertices.size(); i += 3)
        r = std::max(r, std::sqrt(double(s.vertices[i]) * s.vertices[i] + double(s.vertices[i + 1]) * s.vertices[i + 1] +
                                  double(s.vertices[i + 2]) * s.vertices[i + 2]));
      return r;
    }
  }
  return 0.0;
}

}  // namespace

std::string base64(const void* data, std::size_t size) {
  static const char* kDigits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* p = static_cast<const unsigned char*>(data);
  std::string out;
  out.reserve((size + 2) / 3 * 4);
  for (std::size_t i = 0; i < size; i += 3) {
    const unsigned v = (unsigned(p[i]) << 16) | (i + 1 < size ? unsigned(p[i + 1]) << 8 : 0u) |
                       (i + 2 < size ? unsigned(p[i + 2]) : 0u);
    out += kDigits[(v >> 18) & 63];
    out += kDigits[(v >> 12) & 63];
    out += i + 1 < size ? kDigits[(v >> 6) & 63] : '=';
    out += i + 2 < size ? kDigits[v & 63] : '=';
  }
  return out;
}

VisualShape inertiaBox(const BodyDescription& body) {
  // A solid box of half extents (a, b, c) and mass m has principal moments
  // I₁ = m(b² + c²)/3, ... so a² = 3(I₂ + I₃ − I₁)/(2m), and cyclically.
  VisualShape box;
  box.kind = VisualShape::Kind::kBox;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(0.5 * (body.inertia + body.inertia.transpose()));
  const Eigen::Vector3d I = eig.eigenvalues().cwiseMax(0.0);
  Eigen::Vector3d h2;
  const double m = body.mass > 0.0 ? body.mass : 1.0;
  for (int k = 0; k < 3; ++k) h2[k] = 1.5 * (I[(k + 1) % 3] + I[(k + 2) % 3] - I[k]) / m;
  const double largest = std::max(h2.maxCoeff(), 1e-12);
  for (int k = 0; k < 3; ++k) box.size[k] = std::sqrt(std::max(h2[k], kThinShare * kThinShare * largest));
  Eigen::Matrix3d axes = eig.eigenvectors();
  if (axes.determinant() < 0.0) axes.col(2) *= -1.0;
  box.orientation = Eigen::Quaterniond(axes).normalized();
  box.origin = "the box with the inertia of body '" + body.name + "'";
  return box;
}

nlohmann::json shapeData(const VisualShape& s, MeshBudget* budget, std::vector<std::string>* notes) {
  nlohmann::json j = {{"kind", kindName(s.kind)},
                      {"size", vec(s.size)},
                      {"pos", vec(s.position)},
                      {"quat", {s.orientation.w(), s.orientation.x(), s.orientation.y(), s.orientation.z()}},
                      {"rgba", {s.rgba[0], s.rgba[1], s.rgba[2], s.rgba[3]}},
                      {"scale", vec(s.mesh_scale)}};
  if (s.kind != VisualShape::Kind::kMesh) return j;
  if (!s.vertices.empty()) {
    const std::size_t bytes = (s.vertices.size() + s.faces.size()) * 4;
    if (bytes > budget->left) {
      notes->push_back(s.origin + ": its mesh is past the page's mesh budget; drawn as a box");
      return nullptr;
    }
    budget->left -= bytes;
    std::vector<std::uint32_t> faces(s.faces.begin(), s.faces.end());
    j["format"] = "triangles";
    j["vertices"] = base64(s.vertices.data(), s.vertices.size() * sizeof(float));
    j["faces"] = base64(faces.data(), faces.size() * sizeof(std::uint32_t));
    return j;
  }
  const std::string format = lowerExtension(s.mesh_file);
  if (format != "stl" && format != "dae" && format != "obj") {
    notes->push_back(s.origin + ": mesh '" + s.mesh_file + "' is not STL, COLLADA or OBJ; not drawn");
    return nullptr;
  }
  struct stat st {};
  if (::stat(s.mesh_file.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) {
    notes->push_back(s.origin + ": mesh '" + s.mesh_file + "' not found; not drawn");
    return nullptr;
  }
  // Its size first: a file past the budget is not read at all.
  if (static_cast<std::uint64_t>(st.st_size) > budget->left) {
    notes->push_back(s.origin + ": mesh '" + s.mesh_file + "' is past the page's mesh budget; not drawn");
    return nullptr;
  }
  std::ifstream in(s.mesh_file, std::ios::binary);
  std::string data(static_cast<std::size_t>(st.st_size), '\0');
  if (!in.read(&data[0], st.st_size)) {
    notes->push_back(s.origin + ": mesh '" + s.mesh_file + "' could not be read; not drawn");
    return nullptr;
  }
  budget->left -= data.size();
  budget->formats.insert(format);
  j["format"] = format;
  j["data"] = base64(data.data(), data.size());
  return j;
}

SceneData sceneData(const SceneDescription& scene, MeshBudget* budget, std::vector<std::string>* notes) {
  SceneData out;
  out.bodies = nlohmann::json::array();
  std::vector<std::string> boxed;
  for (const BodyDescription& b : scene.bodies) {
    nlohmann::json shapes = nlohmann::json::array();
    double reach = 0.0;
    for (const VisualShape& s : b.visuals) {
      nlohmann::json j = shapeData(s, budget, notes);
      if (j.is_null()) continue;
      shapes.push_back(std::move(j));
      reach = std::max(reach, s.position.norm() + shapeRadius(s));
    }
    if (shapes.empty()) {
      VisualShape box = inertiaBox(b);
      box.rgba = {{0.35 + 0.5 * std::fmod(0.618 * double(out.bodies.size()), 1.0), 0.55, 0.75, 1.0}};
      shapes.push_back(shapeData(box, budget, notes));
      reach = shapeRadius(box);
      boxed.push_back(b.name);
    }
    out.reach.push_back(reach);
    out.bodies.push_back({{"name", b.name}, {"shapes", std::move(shapes)}});
  }
  out.boxes = boxed.size();
  if (!boxed.empty() && boxed.size() < scene.bodies.size()) {
    std::string names;
    for (std::size_t i = 0; i < boxed.size() && i < 5; ++i) names += (i ? ", " : "") + boxed[i];
    notes->push_back(std::to_string(boxed.size()) + " of " + std::to_string(scene.bodies.size()) +
                     " bodies have no shapes in the scene and are drawn as the box with their inertia (" + names +
                     (boxed.size() > 5 ? ", ..." : "") + ")");
  } else if (!boxed.empty()) {
    notes->push_back("every body is drawn as the solid box with its mass and principal moments (the scene gives no shapes)");
  }
  out.ground = nlohmann::json::array();
  for (const VisualShape& s : scene.ground_visuals)
    if (nlohmann::json j = shapeData(s, budget, notes); !j.is_null()) out.ground.push_back(std::move(j));

  // Markers: each joint's anchor (and axes) on the body it is given in.
  const auto index = scene.bodyIndices();
  auto bodyOf = [&](const std::string& name) { return name == "ground" || !index.count(name) ? -1 : index.at(name); };
  out.joints = nlohmann::json::array();
  for (const JointDescription& j : scene.joints) {
    if (j.isGear()) continue;
    nlohmann::json axes = nlohmann::json::array();
    if (j.type == "revolute" || j.type == "prismatic" || j.type == "universal") axes.push_back(vec(j.axis_main.normalized()));
    if (j.type == "gimbal") {
      for (const Eigen::Vector3d& a : {j.axis_main, j.axis2_main, j.axis3_main}) axes.push_back(vec(a.normalized()));
    }
    out.joints.push_back({{"name", j.name}, {"body", bodyOf(j.main)}, {"anchor", vec(j.anchor_main)}, {"axes", axes}});
    if (j.type == "universal")
      out.joints.push_back({{"name", j.name + " (second axis)"},
                            {"body", bodyOf(j.secondary)},
                            {"anchor", vec(j.anchor_secondary)},
                            {"axes", {vec(j.axis_secondary.normalized())}}});
  }
  return out;
}

}  // namespace replay
}  // namespace lieflow
