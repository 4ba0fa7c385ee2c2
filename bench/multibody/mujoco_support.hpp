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
/// springref and damping. A universal joint is two hinges with a light cross
/// between them (MuJoCo has no universal joint), a rotation-only body a body
/// whose joint passes through its centre, and a joint that closes a loop
/// MuJoCo's soft equality constraints (mjcfFromTree says how). What MJCF
/// cannot say this way (applied or prescribed moments, loads from programs,
/// gear-type joints) is refused with the reason.
#pragma once

#include <mujoco/mujoco.h>

#include <cstdio>
#include <cmath>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
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

/// How the tree is written (mjcfFromTree).
struct MjcfOptions {
  std::string integrator = "RK4";  ///< RK4, Euler or implicit
  double h = 1e-3;                 ///< the time step
  /// The loops' equality constraints: solref's time constant [s] (0: MuJoCo's
  /// default 0.02) with damping ratio 1, and solimp's impedance d (the same
  /// at every violation; MuJoCo clamps it to 0.9999). MuJoCo's constraints
  /// are soft: the closer d is to 1 and the shorter the time constant, the
  /// stiffer (MuJoCo's docs, "Solver parameters").
  double loop_timeconst = 0.0;
  double loop_impedance = 0.9999;
  /// Mass [kg] and inertia [kg m²] of the cross of a universal joint (MuJoCo
  /// refuses a moving body without them; lieflow's cross is massless). Their
  /// effect, measured: a hanging pair of bodies on two universal joints agrees
  /// with lieflow to 6.5e-11 m after 0.5 s (MuJoCo RK4 at h = 1e-5; the same
  /// pair without the crosses' inertia is not writable), two tumbling
  /// rotation-only bodies on a sprung universal joint to 1.8e-11 rad.
  double cross_mass = 1e-9;
  double cross_inertia = 1e-12;
  /// The length [m] along a closing hinge's axis to its second connect point.
  double axis_length = 1.0;
};

/// The names of the MuJoCo joints of tree body i: "<name>:1" (a hinge, a
/// ball, or a universal joint's first hinge, which turns its cross) and
/// "<name>:2" (a universal joint's second hinge).
inline std::string mjJointName(const articulated::ArticulatedModel& model, int i, int which) {
  return model.names[i] + ":" + std::to_string(which);
}

/// The tree as one MJCF document (at most ~90 nested bodies: MuJoCo's XML
/// parser refuses deeper documents); throws std::invalid_argument for what
/// it cannot write (file comment). Bodies keep lieflow's names; a universal
/// joint's cross is a body "<name>:cross" of options.cross_mass between the
/// parent and the child, turned by the first hinge. A rotation-only body
/// must have its joint's anchor at its centre (MuJoCo then holds the
/// centre). A loop-closing joint becomes equality constraints between its
/// two bodies: a ball joint a connect at the anchor (body1 the secondary
/// body, its anchor in that body's frame); a revolute joint one there and
/// one at options.axis_length along the axis; a universal joint the point
/// connect and a spatial tendon of fixed length from a site at
/// options.axis_length along a₁ (main body) to one along a₂ (secondary): the
/// cross's right angle as the distance √2 · axis_length. (A light cross body
/// on the main side would carry the rows instead: tried, it makes MuJoCo's
/// soft rows so soft that the shafts barely feel the loop — R scales with
/// the cross's tiny inverse inertia.) The point connect is left out where
/// both sides hold the anchor (the ground, or a rotation-only body anchored
/// at its centre: the rows would vanish). MuJoCo places body2's anchor and the
/// tendon's length from the configuration qpos0 (all joints at zero):
/// setMjState checks that lieflow's initial state is that configuration.
inline std::string mjcfFromTree(const articulated::ArticulatedModel& model, const MjcfOptions& options) {
  using articulated::JointKind;
  constexpr int kMaxDepth = 90;
  const int n = model.bodyCount();
  std::vector<std::vector<int>> children(n + 1);  // n: the world
  std::vector<int> depth(n, 1);
  auto anchored = [](const Eigen::Vector3d& a) { return a.norm() <= 1e-12; };
  for (int i = 0; i < n; ++i) {
    const articulated::ArticulatedBody& b = model.bodies[i];
    const std::string& name = model.names[i];
    if (b.rotation_only && !anchored(b.anchor_child))
      throw std::invalid_argument("rotation-only body '" + name + "' has its joint away from its centre");
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
                "  <option timestep=\"%.17g\" gravity=\"%.17g %.17g %.17g\" integrator=\"%s\" solver=\"Newton\" "
                "tolerance=\"1e-15\" iterations=\"100\">\n"
                "    <flag contact=\"disable\"/>\n"
                "  </option>\n"
                "  <worldbody>\n",
                options.h, model.gravity.x(), model.gravity.y(), model.gravity.z(),
                mjIntegratorName(options.integrator));
  xml += buf;
  auto body = [&](const std::string& name, const Eigen::Vector3d& pos, const Eigen::Matrix3d& R) {
    const Eigen::Quaterniond q(R);
    std::snprintf(buf, sizeof buf, "<body name=\"%s\" pos=\"%.17g %.17g %.17g\" quat=\"%.17g %.17g %.17g %.17g\">\n",
                  name.c_str(), pos.x(), pos.y(), pos.z(), q.w(), q.x(), q.y(), q.z());
    xml += buf;
  };
  auto hinge = [&](const std::string& name, const Eigen::Vector3d& pos, const Eigen::Vector3d& axis,
                   const multibody::CoordinateDrive* d) {
    std::snprintf(buf, sizeof buf,
                  "<joint name=\"%s\" type=\"hinge\" pos=\"%.17g %.17g %.17g\" axis=\"%.17g %.17g %.17g\" "
                  "stiffness=\"%.17g\" springref=\"%.17g\" damping=\"%.17g\"/>\n",
                  name.c_str(), pos.x(), pos.y(), pos.z(), axis.x(), axis.y(), axis.z(), d ? d->stiffness : 0.0,
                  d ? d->rest_angle : 0.0, d ? d->damping : 0.0);
    xml += buf;
  };
  auto cross = [&]() {
    std::snprintf(buf, sizeof buf,
                  "<inertial pos=\"0 0 0\" mass=\"%.17g\" diaginertia=\"%.17g %.17g %.17g\"/>\n",
                  options.cross_mass, options.cross_inertia, options.cross_inertia, options.cross_inertia);
    xml += buf;
  };
  // The loops' sites (a universal loop's distance tendon ends), by body (n: the world).
  std::vector<std::string> sites(n + 1);
  auto side = [&](int body_index) { return body_index == articulated::kGround ? n : body_index; };
  for (std::size_t c = 0; c < model.closures.size(); ++c) {
    const articulated::ArticulatedClosure& closure = model.closures[c];
    if (closure.gear) throw std::invalid_argument("loop '" + closure.label + "' is a gear-type joint");
    if (const auto* u = std::get_if<constraints::UniversalJoint<double>>(&closure.constraint)) {
      const Eigen::Vector3d a = u->point.anchor_main + options.axis_length * u->axis1_main;
      const Eigen::Vector3d b = u->point.anchor_secondary + options.axis_length * u->axis2_secondary;
      std::snprintf(buf, sizeof buf, "<site name=\"loop%zu:a\" pos=\"%.17g %.17g %.17g\"/>\n", c, a.x(), a.y(), a.z());
      sites[side(closure.bodies[0])] += buf;
      std::snprintf(buf, sizeof buf, "<site name=\"loop%zu:b\" pos=\"%.17g %.17g %.17g\"/>\n", c, b.x(), b.y(), b.z());
      sites[side(closure.bodies[1])] += buf;
    } else if (!std::holds_alternative<constraints::SphericalJoint<double>>(closure.constraint) &&
               !std::holds_alternative<constraints::RevoluteJoint<double>>(closure.constraint)) {
      throw std::invalid_argument("loop '" + closure.label + "' is closed by a joint MJCF cannot write here");
    }
  }
  // Depth-first, children in tree order.
  auto write = [&](auto&& self, int i) -> void {
    const articulated::ArticulatedBody& b = model.bodies[i];
    const multibody::CoordinateDrive* d = &model.drives[i][0];
    if (b.kind == JointKind::kUniversal) {
      // main first: M = exp(φ₁ a₁) R_ref exp(φ₂ a₂) is the child in the parent;
      // child first it is the parent in the child: Mᵀ = exp(−φ₂ a₂) R_refᵀ exp(−φ₁ a₁).
      const Eigen::Vector3d first = b.parent_is_main ? b.axis1 : Eigen::Vector3d(-b.axis2);
      const Eigen::Vector3d second = b.parent_is_main ? b.axis2 : Eigen::Vector3d(-b.axis1);
      const Eigen::Matrix3d R_rel = b.parent_is_main ? b.R_ref : Eigen::Matrix3d(b.R_ref.transpose());
      body(model.names[i] + ":cross", b.anchor_parent, Eigen::Matrix3d::Identity());
      hinge(mjJointName(model, i, 1), Eigen::Vector3d::Zero(), first, b.parent_is_main ? &model.drives[i][0] : &model.drives[i][1]);
      cross();
      body(model.names[i], -(R_rel * b.anchor_child), R_rel);
      hinge(mjJointName(model, i, 2), b.anchor_child, second, b.parent_is_main ? &model.drives[i][1] : &model.drives[i][0]);
    } else {
      Eigen::Matrix3d R_rel = Eigen::Matrix3d::Identity();  // child frame in the parent's, zero angles
      if (b.kind == JointKind::kRevolute) R_rel = b.parent_is_main ? b.R_ref : Eigen::Matrix3d(b.R_ref.transpose());
      body(model.names[i], b.anchor_parent - R_rel * b.anchor_child, R_rel);
      if (b.kind == JointKind::kRevolute) {
        const Eigen::Vector3d axis =
            b.parent_is_main ? Eigen::Vector3d(b.R_ref.transpose() * b.axis1) : Eigen::Vector3d(-b.axis1);
        hinge(mjJointName(model, i, 1), b.anchor_child, axis, d);
      } else {
        std::snprintf(buf, sizeof buf, "<joint name=\"%s\" type=\"ball\" pos=\"%.17g %.17g %.17g\"/>\n",
                      mjJointName(model, i, 1).c_str(), b.anchor_child.x(), b.anchor_child.y(), b.anchor_child.z());
        xml += buf;
      }
    }
    const Eigen::Matrix3d& I = b.inertia;
    std::snprintf(buf, sizeof buf,
                  "<inertial pos=\"0 0 0\" mass=\"%.17g\" fullinertia=\"%.17g %.17g %.17g %.17g %.17g %.17g\"/>\n",
                  b.mass, I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2));
    xml += buf;
    xml += sites[i];
    for (int c : children[i]) self(self, c);
    xml += "</body>\n";
    if (b.kind == JointKind::kUniversal) xml += "</body>\n";
  };
  xml += sites[n];
  for (int r : children[n]) write(write, r);
  xml += "  </worldbody>\n";
  // The loops' rows.
  std::string equality;
  auto holds = [&](int body_index, const Eigen::Vector3d& anchor) {
    return body_index == articulated::kGround || (model.bodies[body_index].rotation_only && anchored(anchor));
  };
  auto bodyName = [&](int body_index) {
    return body_index == articulated::kGround ? std::string("world") : model.names[body_index];
  };
  std::string tendons;
  auto solref = [&]() {
    char text[64] = "";
    if (options.loop_timeconst > 0.0) std::snprintf(text, sizeof text, " solref=\"%.17g 1\"", options.loop_timeconst);
    return std::string(text);
  };
  auto connect = [&](const std::string& body1, const std::string& body2, const Eigen::Vector3d& anchor) {
    std::snprintf(buf, sizeof buf,
                  "<connect body1=\"%s\" body2=\"%s\" anchor=\"%.17g %.17g %.17g\"%s solimp=\"%.17g %.17g 0.001\"/>\n",
                  body1.c_str(), body2.c_str(), anchor.x(), anchor.y(), anchor.z(), solref().c_str(),
                  options.loop_impedance, options.loop_impedance);
    equality += buf;
  };
  for (std::size_t c = 0; c < model.closures.size(); ++c) {
    const articulated::ArticulatedClosure& closure = model.closures[c];
    const int main = closure.bodies[0], secondary = closure.bodies[1];
    std::visit(
        [&](const auto& joint) {
          using J = std::decay_t<decltype(joint)>;
          if constexpr (std::is_same_v<J, constraints::SphericalJoint<double>>) {
            if (!(holds(main, joint.anchor_main) && holds(secondary, joint.anchor_secondary)))
              connect(bodyName(secondary), bodyName(main), joint.anchor_secondary);
          } else if constexpr (std::is_same_v<J, constraints::RevoluteJoint<double>>) {
            const auto& s = joint.point;
            if (!(holds(main, s.anchor_main) && holds(secondary, s.anchor_secondary)))
              connect(bodyName(secondary), bodyName(main), s.anchor_secondary);
            connect(bodyName(secondary), bodyName(main),
                    s.anchor_secondary + options.axis_length * joint.axis_secondary);
          } else if constexpr (std::is_same_v<J, constraints::UniversalJoint<double>>) {
            // The point, and the cross's right angle: the ends of a₁ (main)
            // and a₂ (secondary) at axis_length from the anchor keep their
            // distance √2 · axis_length (a tendon of fixed length).
            const auto& s = joint.point;
            if (!(holds(main, s.anchor_main) && holds(secondary, s.anchor_secondary)))
              connect(bodyName(secondary), bodyName(main), s.anchor_secondary);
            std::snprintf(buf, sizeof buf, "<tendon tendon1=\"loop%zu\"%s solimp=\"%.17g %.17g 0.001\"/>\n", c,
                          solref().c_str(), options.loop_impedance, options.loop_impedance);
            equality += buf;
            std::snprintf(buf, sizeof buf,
                          "<spatial name=\"loop%zu\"><site site=\"loop%zu:a\"/><site site=\"loop%zu:b\"/></spatial>\n",
                          c, c, c);
            tendons += buf;
          }
        },
        closure.constraint);
  }
  if (!tendons.empty()) xml += "  <tendon>\n" + tendons + "  </tendon>\n";
  if (!equality.empty()) xml += "  <equality>\n" + equality + "  </equality>\n";
  xml += "</mujoco>\n";
  return xml;
}

/// d ← the lieflow state y at t = 0 (qpos: angles and the spherical joints'
/// quaternions, qvel: u; MuJoCo's joints found by name, mjJointName). Throws
/// std::runtime_error when a loop's constraints do not hold at that state
/// (MuJoCo placed their anchors at qpos0, all joints at zero).
inline void setMjState(const articulated::ArticulatedModel& model, const articulated::ArticulatedState& y,
                       const mjModel* m, mjData* d) {
  mj_resetData(m, d);
  auto joint = [&](const std::string& name) {
    const int j = mj_name2id(m, mjOBJ_JOINT, name.c_str());
    if (j < 0) throw std::runtime_error("MuJoCo model has no joint " + name);
    return std::pair<int, int>(m->jnt_qposadr[j], m->jnt_dofadr[j]);
  };
  for (int i = 0; i < model.bodyCount(); ++i) {
    const articulated::ArticulatedBody& b = model.bodies[i];
    const auto [qa, va] = joint(mjJointName(model, i, 1));
    if (b.kind == articulated::JointKind::kSpherical) {
      const Eigen::Quaterniond& q = y.N[b.rotation].quaternion();
      d->qpos[qa] = q.w();
      d->qpos[qa + 1] = q.x();
      d->qpos[qa + 2] = q.y();
      d->qpos[qa + 3] = q.z();
      for (int k = 0; k < 3; ++k) d->qvel[va + k] = y.u[b.u_begin + k];
    } else if (b.kind == articulated::JointKind::kUniversal) {
      // The MuJoCo hinges' order: (φ₁, φ₂), child first (φ₂, φ₁) about −a₂, −a₁.
      const int first = b.parent_is_main ? 0 : 1;
      const auto [qb, vb] = joint(mjJointName(model, i, 2));
      d->qpos[qa] = y.q[b.q_begin + first];
      d->qvel[va] = y.u[b.u_begin + first];
      d->qpos[qb] = y.q[b.q_begin + 1 - first];
      d->qvel[vb] = y.u[b.u_begin + 1 - first];
    } else {
      d->qpos[qa] = y.q[b.q_begin];
      d->qvel[va] = y.u[b.u_begin];
    }
  }
  d->time = 0.0;
  if (m->neq > 0) {
    mj_forward(m, d);
    double worst = 0.0;
    for (int r = 0; r < d->nefc; ++r)
      if (d->efc_type[r] == mjCNSTR_EQUALITY) worst = std::max(worst, std::abs(d->efc_pos[r]));
    if (worst > 1e-9)
      throw std::runtime_error("the loops are not closed at MuJoCo's qpos0 (lieflow's initial state misses them by " +
                               std::to_string(worst) + " m)");
  }
}

}  // namespace bench
}  // namespace lieflow
