// The shapes of an MJCF model's bodies as MuJoCo's compiler leaves them:
// each visible geom (groups 0-2, the ones MuJoCo's viewer shows by default)
// at its pose in the world, meshes as the compiler's triangles (already in
// the geom's frame: MuJoCo centres and aligns a mesh on its inertia and
// moves the geom to match).
#ifdef LIEFLOW_HAVE_MUJOCO

#include <mujoco/mujoco.h>

#include <string>
#include <vector>

#include "model/import/mjcf_model.hpp"
#include "model/visual_shape.hpp"

namespace lieflow {
namespace model_import {

namespace {
/// MuJoCo's viewer shows geom groups 0, 1 and 2 unless asked otherwise.
constexpr int kVisibleGroups = 3;
}  // namespace

std::vector<VisualShape> mjcfBodyShapes(const mjModel_* m, const mjData_* d, int body) {
  std::vector<VisualShape> shapes;
  const int first = m->body_geomadr[body];
  for (int g = first; first >= 0 && g < first + m->body_geomnum[body]; ++g) {
    if (m->geom_group[g] < 0 || m->geom_group[g] >= kVisibleGroups) continue;
    const float* rgba = m->geom_matid[g] >= 0 ? m->mat_rgba + 4 * m->geom_matid[g] : m->geom_rgba + 4 * g;
    if (!(rgba[3] > 0.0f)) continue;
    VisualShape s;
    const mjtNum* size = m->geom_size + 3 * g;
    switch (m->geom_type[g]) {
      case mjGEOM_SPHERE: s.kind = VisualShape::Kind::kSphere; break;
      case mjGEOM_CAPSULE: s.kind = VisualShape::Kind::kCapsule; break;
      case mjGEOM_ELLIPSOID: s.kind = VisualShape::Kind::kEllipsoid; break;
      case mjGEOM_CYLINDER: s.kind = VisualShape::Kind::kCylinder; break;
      case mjGEOM_BOX: s.kind = VisualShape::Kind::kBox; break;
      case mjGEOM_MESH: {
        const int mesh = m->geom_dataid[g];
        if (mesh < 0) continue;
        s.kind = VisualShape::Kind::kMesh;
        const float* v = m->mesh_vert + 3 * m->mesh_vertadr[mesh];
        s.vertices.assign(v, v + 3 * m->mesh_vertnum[mesh]);
        const int* f = m->mesh_face + 3 * m->mesh_faceadr[mesh];
        s.faces.assign(f, f + 3 * m->mesh_facenum[mesh]);
        break;
      }
      default: continue;  // planes, height fields: the page draws its own ground
    }
    s.size = mjVec3(size);
    s.position = mjVec3(d->geom_xpos + 3 * g);
    s.orientation = Eigen::Quaterniond(mjMat3(d->geom_xmat + 9 * g)).normalized();
    for (int k = 0; k < 4; ++k) s.rgba[k] = rgba[k];
    const char* name = mj_id2name(m, mjOBJ_GEOM, g);
    s.origin = name && *name ? "geom '" + std::string(name) + "'" : "geom " + std::to_string(g);
    shapes.push_back(std::move(s));
  }
  return shapes;
}

}  // namespace model_import
}  // namespace lieflow

#endif  // LIEFLOW_HAVE_MUJOCO
