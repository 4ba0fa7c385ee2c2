#include "dynamics/scene_joints.hpp"

#include <array>
#include <cmath>
#include <sstream>
#include <string>
#include <tuple>

#include "liegroup/invalid_input.hpp"

namespace lieflow {

namespace {

/// Relative tolerance of the assembly checks (anchors coincide).
constexpr double kAssemblyTolerance = 1e-6;

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

Gear sceneGear(const SceneDescription& scene, std::size_t k,
               const std::unordered_map<std::string, int>& index) {
  const JointDescription& j = scene.joints[k];
  const std::string label = scene.source + ": joints[" + std::to_string(k) + "] (" + j.name + ")";
  const std::string& prefix = label;
  auto body = [&](const std::string& name) { return name == "ground" ? kGround : index.at(name); };
  Gear g;
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

JointConstraint sceneJointConstraint(const SceneDescription& scene, std::size_t k,
                                     const std::unordered_map<std::string, int>& index,
                                     const constraints::BodyPose<double>& pa,
                                     const constraints::BodyPose<double>& pb) {
  const JointDescription& j = scene.joints[k];
  const std::string prefix = scene.source + ": joints[" + std::to_string(k) + "] (" + j.name + ")";
  auto body = [&](const std::string& name) { return name == "ground" ? kGround : index.at(name); };
  const int a = body(j.main), b = body(j.secondary);
  JointConstraint c;
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

}  // namespace lieflow
