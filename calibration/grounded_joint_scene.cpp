#include "calibration/grounded_joint_scene.hpp"

#include <variant>

#include "dynamics/maximal/multibody_scene.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {
namespace {

/// J_o = J_c + m (‖c‖² I − c cᵀ) (parallel-axis theorem).
Eigen::Matrix3d aboutPivot(const Eigen::Matrix3d& J_c, double m, const Eigen::Vector3d& c) {
  return J_c + m * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
}

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

template <int N>
double generalized(const GroundedJointModel<N>& model, int i, const Eigen::Vector2d& phi, bool mass) {
  const GroundedJointForces<double, N> none{};
  const GroundedJointSystem<double, N> system(model, none);
  const Eigen::Matrix<double, N, 1> q = phi.head<N>();
  return mass ? system.massMatrix(q)(i, i) : system.gravityForce(q)[i];
}

}  // namespace

double GroundedJointScene::inertiaAbout(int i, const Eigen::Vector2d& phi) const {
  return coordinates == 1 ? generalized(revolute, i, phi, true) : generalized(universal, i, phi, true);
}

double GroundedJointScene::gravityMoment(int i, const Eigen::Vector2d& phi) const {
  return coordinates == 1 ? generalized(revolute, i, phi, false) : generalized(universal, i, phi, false);
}

double GroundedJointScene::gravityStiffness(int i, const Eigen::Vector2d& phi) const {
  Eigen::Vector2d plus = phi, minus = phi;
  plus[i] += kGravityStiffnessStep;
  minus[i] -= kGravityStiffnessStep;
  return -(gravityMoment(i, plus) - gravityMoment(i, minus)) / (2.0 * kGravityStiffnessStep);
}

GroundedJointScene groundedJointScene(const SceneDescription& scene, const std::string& joint_name) {
  const int k = findJoint(scene, joint_name);
  const JointDescription& j = scene.joints[k];
  GroundedJointScene out;
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
    if (j.coordinates[i].prescribed)
      throw InvalidInput(out.label + ".prescribed", "the coordinate is prescribed: there is no free motion to fit");

  // Assemble the scene for the joint's geometry (R_ref, unit axes) and the
  // consistent initial state, exactly as `lieflow simulate` does.
  const std::unique_ptr<MultibodyScene> assembled = assembleMultibody(scene);
  const multibody::MultibodySystem& system = *assembled->system;
  int model_joint = -1;
  for (std::size_t m = 0; m < assembled->scene_joint.size(); ++m)
    if (assembled->scene_joint[m] == k) model_joint = static_cast<int>(m);
  const multibody::Joint& joint = system.model().joints[model_joint];
  const int body = out.body_is_main ? joint.main : joint.secondary;
  const BodyDescription& b = scene.bodies[body];

  Eigen::Vector3d anchor;
  if (const auto* r = std::get_if<constraints::RevoluteJoint<double>>(&joint.constraint)) {
    const Eigen::Matrix3d R_ref = r->reference.matrix();
    GroundedJointModel<1>& g = out.revolute;
    g.coordinate = {{0}};
    if (out.body_is_main) {  // I = R_a exp(φ a) R_ref  ⇒  R_a = R_ref⁻¹ exp(−φ a)
      g.P = {{R_ref.transpose(), Eigen::Matrix3d::Identity()}};
      g.axis = {{-r->axis_main}};
    } else {                  // R_b = exp(φ a) R_ref
      g.P = {{Eigen::Matrix3d::Identity(), R_ref}};
      g.axis = {{r->axis_main}};
    }
    anchor = out.body_is_main ? r->point.anchor_main : r->point.anchor_secondary;
  } else {
    const auto& u = std::get<constraints::UniversalJoint<double>>(joint.constraint);
    const Eigen::Matrix3d R_ref = u.reference.matrix();
    GroundedJointModel<2>& g = out.universal;
    const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
    if (out.body_is_main) {  // R_a = R_ref⁻¹ exp(−φ₂ e₂) exp(−φ₁ e₁)
      g.P = {{R_ref.transpose(), I, I}};
      g.axis = {{-u.e2_main, -u.axis1_main}};
      g.coordinate = {{1, 0}};
    } else {                  // R_b = exp(φ₁ e₁) exp(φ₂ e₂) R_ref
      g.P = {{I, I, R_ref}};
      g.axis = {{u.axis1_main, u.e2_main}};
      g.coordinate = {{0, 1}};
    }
    anchor = out.body_is_main ? u.point.anchor_main : u.point.anchor_secondary;
  }

  // Inertia about the pivot; a rotation-only body turns about its centre of
  // mass and its weight is carried by its support.
  const Eigen::Vector3d c = -anchor;
  if (b.rotation_only && c.norm() > 1e-9 * std::max(1.0, anchor.norm()))
    throw InvalidInput(out.label + (out.body_is_main ? ".anchor_main" : ".anchor_secondary"),
                       "body '" + b.name + "' is rotation_only: it must be anchored at its centre of mass");
  auto fill = [&](auto& g) {
    g.mass = b.rotation_only ? 0.0 : b.mass;
    g.com_from_pivot = b.rotation_only ? Eigen::Vector3d::Zero() : c;
    g.inertia_pivot = b.rotation_only ? b.inertia : aboutPivot(b.inertia, b.mass, c);
    g.gravity = b.rotation_only ? Eigen::Vector3d::Zero() : scene.gravity;
    for (int i = 0; i < out.coordinates; ++i)
      if (j.coordinates[i].moment) {
        const TimeFunction f = *j.coordinates[i].moment;
        g.moment[i] = [f](double t) { return f.evaluate(t, 0); };
      }
  };
  if (out.coordinates == 1)
    fill(out.revolute);
  else
    fill(out.universal);
  for (int i = 0; i < 2; ++i) out.drives[i] = system.drives()[model_joint][i];

  const std::vector<JointOutput> joints0 = system.jointOutputs(0.0, assembled->y0);
  for (int i = 0; i < out.coordinates; ++i) {
    out.initial_angle[i] = joints0[model_joint].phi[i];
    out.initial_rate[i] = joints0[model_joint].phidot[i];
  }
  return out;
}

}  // namespace lieflow
