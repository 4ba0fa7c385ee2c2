// A lieflow tree as MJCF (tree_mjcf.hpp).
#include "peers/mujoco/tree_mjcf.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#ifdef LIEFLOW_HAVE_MUJOCO
#include <mujoco/mujoco.h>
#endif

namespace lieflow {
namespace mujoco_peer {

const char* mjIntegratorName(const std::string& name) {
  if (name == "RK4" || name == "Euler" || name == "implicit") return name.c_str();
  throw std::invalid_argument("MuJoCo integrator '" + name + "' (RK4, Euler or implicit)");
}

std::string mjJointName(const articulated::ArticulatedModel& model, int i, int which) {
  return model.names[i] + ":" + std::to_string(which);
}

namespace {

/// Whether an anchor is at the body's centre (to round-off).
bool anchored(const Eigen::Vector3d& a) { return a.norm() <= 1e-12; }

/// The children of each tree body and of the world (index n), after the
/// checks of what MJCF can say (file comment).
std::vector<std::vector<int>> writableChildren(const articulated::ArticulatedModel& model) {
  constexpr int kMaxDepth = 90;
  const int n = model.bodyCount();
  std::vector<std::vector<int>> children(n + 1);  // n: the world
  std::vector<int> depth(n, 1);
  for (int i = 0; i < n; ++i) {
    const articulated::ArticulatedBody& b = model.bodies[i];
    const std::string& name = model.names[i];
    if (b.rotation_only && !anchored(b.anchor_child))
      throw std::invalid_argument("rotation-only body '" + name + "' has its joint away from its centre");
    for (int k = 0; k < b.coordinates(); ++k) {
      const CoordinateDrive& d = model.drives[i][k];
      if (d.moment || d.prescribed || d.user_moment)
        throw std::invalid_argument("joint of body '" + name + "' has an applied or prescribed moment");
    }
    if (b.parent != articulated::kGround) depth[i] = depth[b.parent] + 1;
    if (depth[i] > kMaxDepth) throw std::invalid_argument("the tree is deeper than " + std::to_string(kMaxDepth));
    children[b.parent == articulated::kGround ? n : b.parent].push_back(i);
  }
  return children;
}

/// The loops' sites (a universal loop's distance tendon ends), by body (n:
/// the world); a loop MJCF cannot close here is refused.
std::vector<std::string> loopSites(const articulated::ArticulatedModel& model, const MjcfOptions& options) {
  const int n = model.bodyCount();
  char buf[1024];
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
  return sites;
}

/// The bodies, depth-first and children in tree order, with their joints,
/// inertias and sites, appended to *out.
void writeBodies(const articulated::ArticulatedModel& model, const MjcfOptions& options,
                 const std::vector<std::vector<int>>& children, const std::vector<std::string>& sites,
                 std::string* out) {
  using articulated::JointKind;
  const int n = model.bodyCount();
  std::string& xml = *out;
  char buf[1024];
  auto body = [&](const std::string& name, const Eigen::Vector3d& pos, const Eigen::Matrix3d& R) {
    const Eigen::Quaterniond q(R);
    std::snprintf(buf, sizeof buf, "<body name=\"%s\" pos=\"%.17g %.17g %.17g\" quat=\"%.17g %.17g %.17g %.17g\">\n",
                  name.c_str(), pos.x(), pos.y(), pos.z(), q.w(), q.x(), q.y(), q.z());
    xml += buf;
  };
  auto hinge = [&](const std::string& name, const Eigen::Vector3d& pos, const Eigen::Vector3d& axis,
                   const CoordinateDrive* d) {
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
  auto write = [&](auto&& self, int i) -> void {
    const articulated::ArticulatedBody& b = model.bodies[i];
    const CoordinateDrive* d = &model.drives[i][0];
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
}

/// The loops' rows: MuJoCo's equality constraints (connects, and a fixed-
/// length tendon for a universal joint's right angle), appended to *out.
void writeLoops(const articulated::ArticulatedModel& model, const MjcfOptions& options, std::string* out) {
  std::string& xml = *out;
  char buf[1024];
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
}

}  // namespace

std::string mjcfFromTree(const articulated::ArticulatedModel& model, const MjcfOptions& options) {
  const std::vector<std::vector<int>> children = writableChildren(model);
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
  const std::vector<std::string> sites = loopSites(model, options);
  writeBodies(model, options, children, sites, &xml);
  xml += "  </worldbody>\n";
  writeLoops(model, options, &xml);
  return xml;
}

#ifdef LIEFLOW_HAVE_MUJOCO
void setMujocoState(const articulated::ArticulatedModel& model, const articulated::ArticulatedState& y,
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
#endif

}  // namespace mujoco_peer
}  // namespace lieflow
