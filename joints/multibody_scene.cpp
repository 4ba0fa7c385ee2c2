#include "joints/multibody_scene.hpp"

#include <cmath>
#include <sstream>
#include <tuple>
#include <unordered_map>

#include "liegroup/invalid_input.hpp"

namespace lieflow {

using multibody::kGround;

namespace {

/// Relative tolerance of the assembly checks (anchors coincide).
constexpr double kAssemblyTolerance = 1e-6;
/// The initial projections stop at this max |Φ| (metres, radians).
constexpr double kInitialProjectionTolerance = 1e-13;

constraints::NodeAxes<double> nodeAxes(const NodeAxesDescription& d, const std::string& prefix) {
  return d.has_t ? constraints::makeNodeAxes<double>(d.r, d.s, d.t, prefix)
                 : constraints::makeNodeAxes<double>(d.r, d.s, prefix);
}

std::string fmt(const Eigen::Vector3d& v) {
  std::ostringstream s;
  s.precision(10);
  s << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return s.str();
}

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

multibody::Gear sceneGear(const SceneDescription& scene, std::size_t k,
                          const std::unordered_map<std::string, int>& index) {
  const JointDescription& j = scene.joints[k];
  const std::string label = scene.source + ": joints[" + std::to_string(k) + "] (" + j.name + ")";
  const std::string& prefix = label;
  auto body = [&](const std::string& name) { return name == "ground" ? kGround : index.at(name); };
  multibody::Gear g;
  g.name = label;
  g.bodies = {{body(j.carrier), body(j.main), body(j.secondary), kGround}};
  if (j.type == "coupling") {
    for (const auto& [side, slide, i] : {std::tuple<const char*, bool, int>{"main", j.slide_main, g.bodies[1]},
                                         {"secondary", j.slide_secondary, g.bodies[2]}})
      if (slide && scene.bodies[i].rotation_only)
        throw InvalidInput(prefix + "." + side, "'" + scene.bodies[i].name +
                                                    "' is rotation_only: a sliding node needs translational "
                                                    "coordinates");
    // One slot per body in the roles (carrier 1, node 1, carrier 2, node 2):
    // a body in two roles, the ground included, has one slot.
    const std::array<int, 4> roles = {
        {body(j.carrier), g.bodies[1], body(j.carrier_secondary.empty() ? j.carrier : j.carrier_secondary),
         g.bodies[2]}};
    std::array<std::size_t, 4> slot{};
    std::array<int, 4> slots{{kGround, kGround, kGround, kGround}};
    std::size_t used = 0;
    for (std::size_t r = 0; r < 4; ++r) {
      std::size_t k = 0;
      while (k < used && slots[k] != roles[r]) ++k;
      if (k == used) slots[used++] = roles[r];
      slot[r] = k;
    }
    g.bodies = slots;
    g.constraint = constraints::makeCouplingJoint<double>(j.ratio, j.axes_main.r, j.slide_main, j.axes_secondary.r,
                                                          j.slide_secondary, slot, prefix);
    return g;
  }
  const auto a1 = nodeAxes(j.axes_main, prefix + ".axes_main");
  const auto a2 = nodeAxes(j.axes_secondary, prefix + ".axes_secondary");
  if (j.type == "gear") {
    g.constraint = constraints::makeGearJoint<double>(j.ratio, a1, a2, prefix);
  } else if (j.type == "rack_pinion") {
    g.constraint = constraints::makeRackPinionJoint<double>(j.ratio, a1, a2, prefix);
    if (scene.bodies[g.bodies[2]].rotation_only)
      throw InvalidInput(prefix + ".secondary", "the rack '" + j.secondary +
                                                    "' is rotation_only: it needs translational coordinates");
  } else {
    g.bodies[3] = body(j.tertiary);
    g.constraint = constraints::makeDifferentialJoint<double>(
        j.ratio, a1, a2, nodeAxes(j.axes_tertiary, prefix + ".axes_tertiary"), prefix);
  }
  return g;
}

multibody::JointConstraint sceneJointConstraint(const SceneDescription& scene, std::size_t k,
                                                const std::unordered_map<std::string, int>& index,
                                                const constraints::BodyPose<double>& pa,
                                                const constraints::BodyPose<double>& pb) {
  const JointDescription& j = scene.joints[k];
  const std::string prefix = scene.source + ": joints[" + std::to_string(k) + "] (" + j.name + ")";
  auto body = [&](const std::string& name) { return name == "ground" ? kGround : index.at(name); };
  const int a = body(j.main), b = body(j.secondary);
  multibody::JointConstraint c;
  if (j.type == "spherical") {
    c = constraints::makeSphericalJoint<double>(j.anchor_main, j.anchor_secondary, prefix);
  } else if (j.type == "prismatic") {
    for (const auto& [side, i] : {std::pair<const char*, int>{"main", a}, {"secondary", b}})
      if (i != kGround && scene.bodies[i].rotation_only)
        throw InvalidInput(prefix + "." + side, "'" + scene.bodies[i].name +
                                                   "' is rotation_only: a prismatic joint's bodies need "
                                                   "translational coordinates");
    c = constraints::assemblePrismaticJoint<double>(pa, pb, j.anchor_main, j.anchor_secondary, j.axis_main, prefix);
  } else if (j.type == "fixed") {
    c = constraints::assembleFixedJoint<double>(pa, pb, j.anchor_main, j.anchor_secondary, prefix);
  } else if (j.type == "revolute") {
    const Eigen::Vector3d axis_b =
        j.has_axis_secondary ? j.axis_secondary
                             : Eigen::Vector3d(pb.R.inverse() * (pa.R * j.axis_main.normalized()));
    c = constraints::assembleRevoluteJoint<double>(pa, pb, j.anchor_main, j.anchor_secondary, j.axis_main, axis_b,
                                                   j.initial_angles[0], prefix);
  } else if (j.type == "gimbal") {
    c = constraints::assembleGimbalJoint(pa, pb, j.anchor_main, j.anchor_secondary,
                                         {{j.axis_main, j.axis2_main, j.axis3_main}}, j.initial_angles, prefix);
  } else if (j.offset) {
    c = constraints::assembleOffsetUniversalJoint<double>(pa, pb, j.anchor_main, j.anchor_secondary, j.axis_main,
                                                          j.axis_secondary, j.initial_angles[0], j.initial_angles[1],
                                                          prefix);
  } else {
    c = constraints::assembleUniversalJoint<double>(pa, pb, j.anchor_main, j.anchor_secondary, j.axis_main,
                                                    j.axis_secondary, j.initial_angles[0], j.initial_angles[1],
                                                    prefix);
  }
  // The anchors must coincide at t = 0 (a prismatic joint's lie on its axis).
  const Eigen::Vector3d xa = pa.toWorld(j.anchor_main), xb = pb.toWorld(j.anchor_secondary);
  const double length = std::max({1.0, j.anchor_main.norm(), j.anchor_secondary.norm()});
  if (j.type == "prismatic") {
    const Eigen::Vector3d axis = pa.R * j.axis_main.normalized();
    const Eigen::Vector3d off_axis = (xb - xa) - (xb - xa).dot(axis) * axis;
    if (off_axis.norm() > kAssemblyTolerance * std::max(length, (xb - xa).norm()))
      throw InvalidInput(prefix + ".anchor_secondary",
                         "the anchors are not on the slide axis at t = 0: anchor_secondary at " + fmt(xb) +
                             " is " + fmt(off_axis) + " off the line through anchor_main at " + fmt(xa) +
                             " along axis_main " + fmt(axis) + " (world)");
  } else if (!j.offset && (xa - xb).norm() > kAssemblyTolerance * length)
    throw InvalidInput(prefix + ".anchor_secondary",
                       "the anchors do not coincide at t = 0: anchor_main is at " + fmt(xa) +
                           " and anchor_secondary at " + fmt(xb) +
                           " in the world (the bodies' positions must satisfy the joint)");
  return c;
}

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

  std::vector<multibody::CoordinateDrives> drives;
  std::vector<multibody::Gear> gears;
  for (std::size_t k = 0; k < scene.joints.size(); ++k) {
    const JointDescription& j = scene.joints[k];
    const std::string label = scene.source + ": joints[" + std::to_string(k) + "] (" + j.name + ")";
    if (j.isGear()) {
      gears.push_back(sceneGear(scene, k, index));
      continue;
    }
    const int a = body(j.main), b = body(j.secondary);
    const multibody::JointConstraint c = sceneJointConstraint(scene, k, index, pose(a), pose(b));
    multibody::Joint joint{j.name, a, b, c};
    joint.label = label;
    model.addJoint(joint);
    out->scene_joint.push_back(static_cast<int>(k));
    multibody::CoordinateDrives d;
    const auto user_moment = scene.user_loads.joint_moments.find(j.name);
    for (int i = 0; i < multibody::kMaxJointCoordinates; ++i) {
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
      y.angles[multibody::angleSlot(static_cast<int>(k), i)] = scene.joints[out->scene_joint[k]].initial_angles[i];
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
