#include "calibration/spring_joint.hpp"

#include <algorithm>

#include "dynamics/joint_space/scalar_dynamics.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {
namespace calibration {
namespace {

/// The scene joint to fit: by name, or the only revolute/universal joint.
int findJoint(const SceneDescription& scene, const std::string& name) {
  std::string available;
  int only = -1, candidates = 0;
  for (std::size_t k = 0; k < scene.joints.size(); ++k) {
    const JointDescription& j = scene.joints[k];
    if (!name.empty() && j.name == name) return static_cast<int>(k);
    available += (available.empty() ? "" : ", ") + j.name;
    if (j.type == "revolute" || j.type == "universal") {
      only = static_cast<int>(k);
      ++candidates;
    }
  }
  if (!name.empty())
    throw InvalidInput(scene.source + ": `joint`",
                       "no joint '" + name + "' in the scene (joints: " + (available.empty() ? "none" : available) +
                           ")");
  if (candidates != 1)
    throw InvalidInput(scene.source + ": `joint`",
                       "the scene has " + std::to_string(candidates) +
                           " revolute or universal joints: name the one to fit with `joint` (joints: " +
                           (available.empty() ? "none" : available) + ")");
  return only;
}

/// τ(φ, 0, u̇) of the one-body tree (u̇ = e_i, or 0).
Eigen::VectorXd transmitted(const articulated::ArticulatedModel& model, const Eigen::Vector2d& phi, int unit) {
  const articulated::ScalarDynamics<double> dynamics(model);
  const int n = model.dofs();
  Eigen::VectorXd udot = Eigen::VectorXd::Zero(n);
  if (unit >= 0) udot[unit] = 1.0;
  return dynamics.inverseDynamics(phi.head(n), Eigen::VectorXd::Zero(n), udot);
}

}  // namespace

bool SpringJoint::weighted() const {
  const articulated::ArticulatedBody& b = model().bodies[0];
  return !b.rotation_only && b.mass > 0.0 && model().gravity.squaredNorm() > 0.0;
}

double SpringJoint::inertiaAbout(int i, const Eigen::Vector2d& phi) const {
  return transmitted(model(), phi, i)[i] - transmitted(model(), phi, -1)[i];
}

double SpringJoint::gravityMoment(int i, const Eigen::Vector2d& phi) const {
  return -transmitted(model(), phi, -1)[i];  // M q̈ = Q − h: gravity's share of −h at rest
}

double SpringJoint::gravityStiffness(int i, const Eigen::Vector2d& phi) const {
  Eigen::Vector2d plus = phi, minus = phi;
  plus[i] += kGravityStiffnessStep;
  minus[i] -= kGravityStiffnessStep;
  return -(gravityMoment(i, plus) - gravityMoment(i, minus)) / (2.0 * kGravityStiffnessStep);
}

SpringJoint springJoint(const SceneDescription& scene, const std::string& joint_name) {
  const int k = findJoint(scene, joint_name);
  const JointDescription& j = scene.joints[static_cast<std::size_t>(k)];
  SpringJoint out;
  out.source = scene.source;
  out.label = scene.source + ": joints[" + std::to_string(k) + "] (" + j.name + ")";
  out.joint_name = j.name;
  out.type = j.type;
  if (j.type != "revolute" && j.type != "universal")
    throw InvalidInput(out.label + ".type", "calibrate spring fits a revolute or universal joint coordinate; this "
                                            "joint is '" + j.type + "'");
  out.coordinates = j.type == "revolute" ? 1 : 2;
  if (j.offset)
    throw InvalidInput(out.label + ".offset", "calibrate spring models a universal joint whose axes meet");
  if ((j.main == "ground") == (j.secondary == "ground"))
    throw InvalidInput(out.label + ".main",
                       "calibrate spring models one body on a joint to ground; this joint joins '" + j.main +
                           "' and '" + j.secondary + "'");
  out.body_is_main = j.secondary == "ground";
  out.body_name = out.body_is_main ? j.main : j.secondary;
  for (std::size_t m = 0; m < scene.joints.size(); ++m) {
    const JointDescription& o = scene.joints[m];
    if (static_cast<int>(m) == k) continue;
    if (o.main == out.body_name || o.secondary == out.body_name || o.carrier == out.body_name ||
        (o.isGear() && o.tertiary == out.body_name))
      throw InvalidInput(out.label, "body '" + out.body_name + "' is also in joints[" + std::to_string(m) + "] (" +
                                        o.name + "): calibrate spring models one body on one joint to ground");
  }
  for (int i = 0; i < out.coordinates; ++i)
    if (j.coordinates[static_cast<std::size_t>(i)].prescribed)
      throw InvalidInput(out.label + ".prescribed", "the coordinate is prescribed: there is no free motion to fit");
  const int body = scene.bodyIndex(out.body_name);
  if (body < 0) throw InvalidInput(out.label, "no body '" + out.body_name + "' in the scene");
  const BodyDescription& b = scene.bodies[static_cast<std::size_t>(body)];
  const Eigen::Vector3d& anchor = out.body_is_main ? j.anchor_main : j.anchor_secondary;
  if (b.rotation_only && anchor.norm() > 1e-9)
    throw InvalidInput(out.label + (out.body_is_main ? ".anchor_main" : ".anchor_secondary"),
                       "body '" + b.name + "' is rotation_only: it must be anchored at its centre of mass");

  // The body and its joint alone, assembled as `lieflow simulate
  // --formulation joint` assembles them (axes, R_ref and the consistent
  // initial state).
  SceneDescription one;
  one.name = scene.name;
  one.source = scene.source;
  one.gravity = scene.gravity;
  one.bodies = {b};
  one.joints = {j};
  std::string why;
  if (!articulatedCovers(one, &why)) throw InvalidInput(out.label, why);
  std::shared_ptr<ArticulatedScene> tree = assembleArticulated(one);
  out.tree = tree;
  const articulated::ArticulatedModel& model = tree->system->model();
  for (int i = 0; i < out.coordinates; ++i) {
    out.drives[static_cast<std::size_t>(i)] = model.drives[0][static_cast<std::size_t>(i)];
    out.initial_angle[i] = tree->y0.q[i];
    out.initial_rate[i] = tree->y0.u[i];
  }
  return out;
}

}  // namespace calibration
}  // namespace lieflow
