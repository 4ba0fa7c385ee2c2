/// \file
/// MuJoCo beside lieflow (bench/ and papers/ only; built where CMake found
/// libmujoco-dev): loading MJCF held in memory, and a lieflow tree in joint
/// coordinates (joints/articulated/) written as MJCF with its initial state,
/// so that both engines run the same mechanism from the same state.
///
/// The MJCF of a tree: one nested <body> per lieflow body, its frame the
/// lieflow body frame (origin at the centre of mass, so <inertial pos="0 0 0"
/// fullinertia=...> is lieflow's mass and inertia about the centre of mass),
/// placed in its parent's frame as at zero joint angles. A revolute joint
/// with the parent as its main body is a hinge at anchor_secondary about
/// R_refᵀ a (child frame) and qpos = φ, since R_child = R_p R_ref exp(φ R_refᵀ a)
/// = R_p exp(φ a) R_ref; given child-first it is a hinge about −a with the
/// child frame R_refᵀ. A spherical joint is a ball at the anchor, qpos the
/// relative rotation N, qvel = ω_rel in the child frame (both engines' choice).
/// Spring stiffness, rest angle and damping become the hinge's stiffness,
/// springref and damping. What MJCF cannot say this way (universal joints,
/// rotation-only bodies, applied or prescribed moments, loads from programs)
/// is refused with the reason.
#pragma once

#include <mujoco/mujoco.h>

#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "joints/articulated/articulated_system.hpp"

namespace lieflow {
namespace bench {

struct MjModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct MjDataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
using MjModelPtr = std::unique_ptr<mjModel, MjModelDeleter>;
using MjDataPtr = std::unique_ptr<mjData, MjDataDeleter>;

/// mj_loadXML of files[0] with every (name, text) file in memory (an mjVFS,
/// on the heap: it is large); null with *error set on failure.
inline MjModelPtr loadMjcf(const std::vector<std::pair<std::string, std::string>>& files, std::string* error) {
  if (files.size() > mjMAXVFS) {
    *error = "too many MJCF files for an mjVFS";
    return nullptr;
  }
  std::unique_ptr<mjVFS> vfs(new mjVFS);
  mj_defaultVFS(vfs.get());
  for (const auto& f : files) {
    if (mj_makeEmptyFileVFS(vfs.get(), f.first.c_str(), static_cast<int>(f.second.size())) != 0) {
      mj_deleteVFS(vfs.get());
      *error = "mj_makeEmptyFileVFS failed";
      return nullptr;
    }
    const int index = mj_findFileVFS(vfs.get(), f.first.c_str());
    std::memcpy(vfs->filedata[index], f.second.data(), f.second.size());
  }
  char err[1000] = "";
  MjModelPtr m(mj_loadXML(files[0].first.c_str(), vfs.get(), err, sizeof err));
  mj_deleteVFS(vfs.get());
  if (!m) *error = err;
  return m;
}

/// MuJoCo's integrator names in MJCF.
inline const char* mjIntegratorName(const std::string& name) {
  if (name == "RK4" || name == "Euler" || name == "implicit") return name.c_str();
  throw std::invalid_argument("MuJoCo integrator '" + name + "' (RK4, Euler or implicit)");
}

/// The tree as one MJCF document (at most ~90 nested bodies: MuJoCo's XML
/// parser refuses deeper documents); throws std::invalid_argument for what
/// it cannot write (file comment). *document_order receives the tree index of
/// each MuJoCo body 1, 2, … (MuJoCo numbers bodies, and their joints, in
/// document order: depth first).
inline std::string mjcfFromTree(const articulated::ArticulatedModel& model, const std::string& integrator,
                                double h, std::vector<int>* document_order) {
  document_order->clear();
  using articulated::JointKind;
  constexpr int kMaxDepth = 90;
  const int n = model.bodyCount();
  std::vector<std::vector<int>> children(n + 1);  // n: the world
  std::vector<int> depth(n, 1);
  for (int i = 0; i < n; ++i) {
    const articulated::ArticulatedBody& b = model.bodies[i];
    const std::string& name = model.names[i];
    if (b.rotation_only) throw std::invalid_argument("body '" + name + "' is rotation-only");
    if (b.kind == JointKind::kUniversal) throw std::invalid_argument("body '" + name + "' is on a universal joint");
    for (int k = 0; k < b.coordinates(); ++k) {
      const multibody::CoordinateDrive& d = model.drives[i][k];
      if (d.moment || d.prescribed || d.user_moment)
        throw std::invalid_argument("joint of body '" + name + "' has an applied or prescribed moment");
    }
    if (b.parent != articulated::kGround) depth[i] = depth[b.parent] + 1;
    if (depth[i] > kMaxDepth) throw std::invalid_argument("the tree is deeper than " + std::to_string(kMaxDepth));
    children[b.parent == articulated::kGround ? n : b.parent].push_back(i);
  }
  char buf[1024];
  std::string xml;
  std::snprintf(buf, sizeof buf,
                "<mujoco model=\"lieflow-tree\">\n"
                "  <compiler angle=\"radian\"/>\n"
                "  <option timestep=\"%.17g\" gravity=\"%.17g %.17g %.17g\" integrator=\"%s\">\n"
                "    <flag contact=\"disable\"/>\n"
                "  </option>\n"
                "  <worldbody>\n",
                h, model.gravity.x(), model.gravity.y(), model.gravity.z(), mjIntegratorName(integrator));
  xml += buf;
  // Depth-first, children in tree order (MuJoCo numbers bodies in document
  // order: with a chain or any tree built parent-first that is the tree order).
  auto write = [&](auto&& self, int i) -> void {
    const articulated::ArticulatedBody& b = model.bodies[i];
    document_order->push_back(i);
    Eigen::Matrix3d R_rel = Eigen::Matrix3d::Identity();  // child frame in the parent's, zero angles
    Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
    if (b.kind == JointKind::kRevolute) {
      R_rel = b.parent_is_main ? b.R_ref : Eigen::Matrix3d(b.R_ref.transpose());
      axis = b.parent_is_main ? Eigen::Vector3d(b.R_ref.transpose() * b.axis1) : Eigen::Vector3d(-b.axis1);
    }
    const Eigen::Vector3d pos = b.anchor_parent - R_rel * b.anchor_child;
    const Eigen::Quaterniond q(R_rel);
    std::snprintf(buf, sizeof buf, "<body name=\"%s\" pos=\"%.17g %.17g %.17g\" quat=\"%.17g %.17g %.17g %.17g\">\n",
                  model.names[i].c_str(), pos.x(), pos.y(), pos.z(), q.w(), q.x(), q.y(), q.z());
    xml += buf;
    if (b.kind == JointKind::kRevolute) {
      const multibody::CoordinateDrive& d = model.drives[i][0];
      std::snprintf(buf, sizeof buf,
                    "<joint type=\"hinge\" pos=\"%.17g %.17g %.17g\" axis=\"%.17g %.17g %.17g\" stiffness=\"%.17g\" "
                    "springref=\"%.17g\" damping=\"%.17g\"/>\n",
                    b.anchor_child.x(), b.anchor_child.y(), b.anchor_child.z(), axis.x(), axis.y(), axis.z(),
                    d.stiffness, d.rest_angle, d.damping);
    } else {
      std::snprintf(buf, sizeof buf, "<joint type=\"ball\" pos=\"%.17g %.17g %.17g\"/>\n", b.anchor_child.x(),
                    b.anchor_child.y(), b.anchor_child.z());
    }
    xml += buf;
    const Eigen::Matrix3d& I = b.inertia;
    std::snprintf(buf, sizeof buf,
                  "<inertial pos=\"0 0 0\" mass=\"%.17g\" fullinertia=\"%.17g %.17g %.17g %.17g %.17g %.17g\"/>\n",
                  b.mass, I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2));
    xml += buf;
    for (int c : children[i]) self(self, c);
    xml += "</body>\n";
  };
  for (int r : children[n]) write(write, r);
  xml += "  </worldbody>\n</mujoco>\n";
  return xml;
}

/// d ← the lieflow state y at t = 0 (qpos: angles and the spherical joints'
/// quaternions, qvel: u; MuJoCo's joint j is that of tree body order[j]).
inline void setMjState(const articulated::ArticulatedModel& model, const std::vector<int>& order,
                       const articulated::ArticulatedState& y, const mjModel* m, mjData* d) {
  mj_resetData(m, d);
  for (int j = 0; j < model.bodyCount(); ++j) {
    const articulated::ArticulatedBody& b = model.bodies[order[j]];
    const int qa = m->jnt_qposadr[j], va = m->jnt_dofadr[j];
    if (b.kind == articulated::JointKind::kSpherical) {
      const Eigen::Quaterniond& q = y.N[b.rotation].quaternion();
      d->qpos[qa] = q.w();
      d->qpos[qa + 1] = q.x();
      d->qpos[qa + 2] = q.y();
      d->qpos[qa + 3] = q.z();
      for (int k = 0; k < 3; ++k) d->qvel[va + k] = y.u[b.u_begin + k];
    } else {
      d->qpos[qa] = y.q[b.q_begin];
      d->qvel[va] = y.u[b.u_begin];
    }
  }
  d->time = 0.0;
}

}  // namespace bench
}  // namespace lieflow
