#include "dynamics/maximal/multibody_scene.hpp"

#include <cmath>
#include <sstream>
#include <tuple>
#include <unordered_map>

#include "dynamics/scene_joints.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {


namespace {

/// The initial projections stop at this max |Φ| (metres, radians).
constexpr double kInitialProjectionTolerance = 1e-13;

}  // namespace

bool needsMultibody(const SceneDescription& scene) {
  if (scene.bodies.size() != 1 || scene.joints.size() > 1 || !scene.user_loads.empty()) return true;
  if (scene.joints.empty()) return false;
  const JointDescription& j = scene.joints[0];
  return j.type != "spherical" || (j.main != "ground" && j.secondary != "ground");
}

namespace {

/// The program's body torques on the system; its joint moments were given to
/// the drives. Names that match no body, or no joint with coordinates, are
/// InvalidInput ("torques" / "moments").
void attachUserLoads(const SceneDescription& scene, MultibodyScene* out) {
  const UserLoads& loads = scene.user_loads;
  out->has_user_loads = !loads.empty();
  const std::unordered_map<std::string, int> index = scene.bodyIndices();
  for (const auto& [name, f] : loads.body_torques) {
    const auto it = index.find(name);
    if (it == index.end()) throw InvalidInput("torques", "the scene has no body '" + name + "'");
    const UserLoads::BodyTorque torque = f;
    out->system->setUserTorque(it->second, [torque](double t, const constraints::BodyPose<double>& pose,
                                                     const constraints::BodyVelocity<double>& velocity) {
      return torque(t, pose.R.quaternion(), pose.p, velocity.omega, velocity.v);
    });
  }
  for (const auto& [name, f] : loads.joint_moments) {
    (void)f;
    int k = -1;
    for (std::size_t j = 0; j < scene.joints.size(); ++j)
      if (scene.joints[j].name == name) k = static_cast<int>(j);
    if (k < 0) throw InvalidInput("moments", "the scene has no joint '" + name + "'");
    const std::string& type = scene.joints[k].type;
    if (type != "revolute" && type != "universal" && type != "prismatic" && type != "gimbal")
      throw InvalidInput("moments", "joint '" + name + "' is " + type +
                                        ": a moment (or a prismatic joint's force) acts on the coordinate of a "
                                        "revolute, universal or prismatic joint");
  }
}

}  // namespace

std::unique_ptr<MultibodyScene> assembleMultibody(const SceneDescription& scene) {
  auto out = std::make_unique<MultibodyScene>();
  multibody::MultibodyModel model;
  model.gravity = scene.gravity;
  multibody::MultibodyState s;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const BodyDescription& b = scene.bodies[i];
    const std::string field = scene.source + ": bodies[" + std::to_string(i) + "]";
    if (b.spring_stiffness > 0.0)
      throw InvalidInput(field + ".torsional_spring",
                         "a torsional spring to ground is for single-body scenes; in a scene with joints use a "
                         "joint spring");
    if (b.rotation_only && b.has_velocity && b.velocity.norm() > 0.0)
      throw InvalidInput(field + ".velocity", "a rotation-only body has no translational state");
    model.addBody(multibody::RigidBody{b.name, b.mass, b.inertia, b.rotation_only});
    s.poses.push_back(constraints::BodyPose<double>{SO3d(b.orientation), b.position});
    s.velocities.push_back(constraints::BodyVelocity<double>{b.rotation_only ? Eigen::Vector3d::Zero() : b.velocity,
                                                             b.angular_velocity});
  }
  const std::unordered_map<std::string, int> index = scene.bodyIndices();
  auto body = [&](const std::string& name) { return name == "ground" ? kGround : index.at(name); };
  auto pose = [&](int i) { return i == kGround ? constraints::groundPose<double>() : s.poses[i]; };

  std::vector<CoordinateDrives> drives;
  std::vector<Gear> gears;
  for (std::size_t k = 0; k < scene.joints.size(); ++k) {
    const JointDescription& j = scene.joints[k];
    const std::string label = scene.source + ": joints[" + std::to_string(k) + "] (" + j.name + ")";
    if (j.isGear()) {
      gears.push_back(sceneGear(scene, k, index));
      continue;
    }
    const int a = body(j.main), b = body(j.secondary);
    const JointConstraint c = sceneJointConstraint(scene, k, index, pose(a), pose(b));
    multibody::Joint joint{j.name, a, b, c};
    joint.label = label;
    model.addJoint(joint);
    out->scene_joint.push_back(static_cast<int>(k));
    CoordinateDrives d;
    const auto user_moment = scene.user_loads.joint_moments.find(j.name);
    for (int i = 0; i < kMaxJointCoordinates; ++i) {
      const CoordinateDescription& cd = j.coordinates[i];
      d[i].stiffness = cd.stiffness;
      d[i].rest_angle = cd.rest_angle;
      d[i].damping = cd.damping;
      d[i].moment = cd.moment;
      d[i].prescribed = cd.prescribed;
      const int coordinates = j.type == "gimbal"      ? 3
                              : j.type == "universal" ? 2
                              : (j.type == "revolute" || j.type == "prismatic") ? 1
                                                                                : 0;
      if (user_moment != scene.user_loads.joint_moments.end() && i < coordinates) {
        const UserLoads::JointMoment f = user_moment->second;
        d[i].user_moment = [f, i](double t, double phi, double phidot) { return f(t, i, phi, phidot); };
      }
    }
    drives.push_back(d);
  }
  out->system = std::make_unique<multibody::MultibodySystem>(std::move(model), std::move(drives), std::move(gears));
  attachUserLoads(scene, out.get());
  const multibody::MultibodySystem& sys = *out->system;
  multibody::MultibodyGroupState y = sys.makeState(s);
  // The joint angles at t = 0 are the given initial angles (the principal
  // values could differ by 2π, a gimbal's by its other branch): read again
  // near them (a prismatic joint's x is a length, read as it is).
  for (std::size_t k = 0; k < sys.model().joints.size(); ++k)
    for (int i = 0; i < sys.coordinateCount(static_cast<int>(k)); ++i)
      y.angles[angleSlot(static_cast<int>(k), i)] = scene.joints[out->scene_joint[k]].initial_angles[i];
  sys.rebaseAngles(&y);
  std::string why;
  // The system's messages start with the joint's label ("SOURCE: joints[k]
  // (name): reason"); split it off as the field.
  auto fail = [&](const std::string& text, const std::string& context) -> InvalidInput {
    const auto cut = text.find("): ");
    if (cut == std::string::npos) return InvalidInput(scene.source + ": joints", context + text);
    return InvalidInput(text.substr(0, cut + 1), context + text.substr(cut + 3));
  };
  if (sys.hasConstraints() && !sys.factorConstraints(0.0, y, multibody::RowSet::kAll, &why)) throw fail(why, "");
  const double phi0 = sys.constraintError(0.0, y);
  int iterations = 0;
  if (!sys.projectPositions(0.0, &y, kInitialProjectionTolerance, 50, &iterations, &why))
    throw fail(why, "the initial state cannot be brought onto the joints' constraints: ");
  out->initial_position_correction = phi0;
  const Eigen::VectorXd u0 = y.velocities();
  if (!sys.projectVelocities(0.0, &y, &why)) throw fail(why, "");
  out->initial_velocity_correction = (y.velocities() - u0).lpNorm<Eigen::Infinity>();
  out->y0 = y;
  return out;
}

}  // namespace lieflow
