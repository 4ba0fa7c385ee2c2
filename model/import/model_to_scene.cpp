#include "model/import/model_to_scene.hpp"

#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <sstream>

#include <Eigen/Eigenvalues>

#include "liegroup/input_number.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {
namespace model_import {

namespace {

/// Below this (kg) a group of links has no mass to move.
constexpr double kMassFloor = 1e-12;
/// A merged body's inertia must have λ_min > this × λ_max.
constexpr double kInertiaConditionFloor = 1e-12;
/// A universal joint's second axis passes through its first anchor when
/// they are this close (m); otherwise the joint is an offset universal one.
constexpr double kSamePoint = 1e-12;

constexpr int kGroundGroup = -1;

/// Union of welded links: each link's group root (the link nearest the
/// model's root), or kGroundGroup when welded to the world.
class WeldGroups {
 public:
  explicit WeldGroups(int n) : up_(n) { std::iota(up_.begin(), up_.end(), 0); }
  /// The group root of link i, with path halving (welded chains of 10⁵
  /// links stay linear).
  int find(int i) {
    while (i != kGroundGroup && up_[i] != i) {
      if (up_[i] != kGroundGroup) up_[i] = up_[up_[i]];
      i = up_[i];
    }
    return i;
  }
  /// Welds child's group into parent's (parent −1: the ground).
  void weld(int parent, int child) {
    const int a = parent < 0 ? kGroundGroup : find(parent), b = find(child);
    if (a == b || b == kGroundGroup) return;
    up_[b] = a;
  }

 private:
  std::vector<int> up_;
};

std::string jointTypeName(ModelJointType t) {
  switch (t) {
    case ModelJointType::kRevolute: return "revolute";
    case ModelJointType::kPrismatic: return "prismatic";
    case ModelJointType::kSpherical: return "spherical";
    case ModelJointType::kUniversal: return "universal";
    case ModelJointType::kGimbal: return "gimbal";
    case ModelJointType::kFixed: return "fixed";
    case ModelJointType::kFree: return "free";
  }
  return "joint";
}

}  // namespace

std::string elementLabel(const std::string& kind, const std::string& name, int line) {
  std::string s = kind + " '" + name + "'";
  if (line > 0) s += " (line " + std::to_string(line) + ")";
  return s;
}

namespace {

/// Throws InvalidInput naming `element` and `what` when a value the reader
/// produced is not a usable number (input_number.hpp): values MuJoCo's
/// compiler derives (a body's mass and inertia from its geoms' density and
/// size, poses composed along the tree) can overflow although each attribute
/// was within bounds.
template <typename Values>
void requireUsable(const ModelDescription& model, const std::string& element, const std::string& what,
                   const Values& values) {
  for (const double v : values) {
    const std::string problem = inputNumberProblem(v);
    if (!problem.empty()) throw InvalidInput(model.source + ": " + element, what + " " + problem);
  }
}

template <int R, int C>
std::vector<double> entries(const Eigen::Matrix<double, R, C>& m) {
  return std::vector<double>(m.data(), m.data() + m.size());
}

void requireUsableNumbers(const ModelDescription& model) {
  if (!validUtf8(model.name)) throw InvalidInput(model.source, "the model's name is not valid UTF-8 text");
  requireUsable(model, "the model", "gravity", entries(model.gravity));
  for (const ModelLink& l : model.links) {
    const std::string element = elementLabel("link", l.name, l.line);
    if (const std::string problem = columnNameProblem(l.name); !problem.empty())
      throw InvalidInput(model.source + ": " + element, "its name " + problem + ": rename it");
    requireUsable(model, element, "mass", std::vector<double>{l.mass});
    if (l.mass < 0.0) throw InvalidInput(model.source + ": " + element, "mass must be >= 0, got " + formatNumber(l.mass));
    requireUsable(model, element, "inertia", entries(l.inertia_world));
    requireUsable(model, element, "centre of mass", entries(l.com_world));
    requireUsable(model, element, "orientation", std::vector<double>(l.orientation.coeffs().data(),
                                                                    l.orientation.coeffs().data() + 4));
    requireUsable(model, element, "angular velocity", entries(l.angular_velocity_world));
    requireUsable(model, element, "velocity", entries(l.velocity_world));
  }
  for (const ModelJoint& j : model.joints) {
    const std::string element = elementLabel("joint", j.name, j.line);
    if (const std::string problem = columnNameProblem(j.name); !problem.empty())
      throw InvalidInput(model.source + ": " + element, "its name " + problem + ": rename it");
    requireUsable(model, element, "anchor", entries(j.anchor_world));
    requireUsable(model, element, "second anchor", entries(j.anchor2_world));
    for (const auto* axis : {&j.axis_world, &j.axis2_world, &j.axis3_world})
      requireUsable(model, element, "axis", entries(*axis));
    requireUsable(model, element, "initial position", j.initial);
    requireUsable(model, element, "stiffness", j.stiffness);
    requireUsable(model, element, "spring reference", j.rest);
    requireUsable(model, element, "damping", j.damping);
    for (int i = 0; i < 3; ++i)
      if (j.stiffness[i] < 0.0 || j.damping[i] < 0.0)
        throw InvalidInput(model.source + ": " + element,
                           "stiffness and damping must be >= 0, got " + formatNumber(j.stiffness[i]) + " and " +
                               formatNumber(j.damping[i]));
  }
  for (const ModelCoupling& c : model.couplings) {
    const std::string element = elementLabel("coupling", c.name, c.line);
    if (const std::string problem = columnNameProblem(c.name); !problem.empty())
      throw InvalidInput(model.source + ": " + element, "its name " + problem + ": rename it");
    requireUsable(model, element, "multiplier and offset", std::vector<double>{c.multiplier, c.offset});
  }
  for (const ModelClosure& c : model.closures) {
    const std::string element = elementLabel("equality", c.name, c.line);
    if (const std::string problem = columnNameProblem(c.name); !problem.empty())
      throw InvalidInput(model.source + ": " + element, "its name " + problem + ": rename it");
    requireUsable(model, element, "anchor", entries(c.anchor_world));
  }
}

/// InvalidInput naming the model file and `element`.
InvalidInput failAt(const ModelDescription& model, const std::string& element, const std::string& reason) {
  return InvalidInput(model.source + ": " + element, reason);
}

/// One scene body per group of welded links with mass, named after its root
/// link: the group's mass, centre of mass and inertia about it (body axes:
/// the root link's), velocities and shapes; body_of_group maps group roots
/// to scene bodies.
void addMergedBodies(const ModelDescription& model, WeldGroups& groups, SceneDescription* out,
                     std::map<int, int>* body_of_group) {
  SceneDescription& scene = *out;
  const auto fail = [&](const std::string& element, const std::string& reason) {
    return failAt(model, element, reason);
  };
  const int nl = static_cast<int>(model.links.size());
  std::vector<std::vector<int>> members_of(nl);  // group root → its links
  for (int i = 0; i < nl; ++i)
    if (const int root = groups.find(i); root != kGroundGroup) members_of[root].push_back(i);
  for (int root = 0; root < nl; ++root) {
    if (groups.find(root) != root) continue;
    double m = 0.0;
    Eigen::Vector3d mc = Eigen::Vector3d::Zero();
    const std::vector<int>& members = members_of[root];
    for (const int i : members) {
      m += model.links[i].mass;
      mc += model.links[i].mass * model.links[i].com_world;
    }
    const ModelLink& r = model.links[root];
    std::string names;
    for (int i : members) names += (names.empty() ? "" : ", ") + model.links[i].name;
    if (!(m > kMassFloor))
      throw fail(elementLabel("link", r.name, r.line),
                 "has no mass (welded links: " + names + ") but moves on a joint: give it an <inertial> mass");
    const Eigen::Vector3d c = mc / m;
    Eigen::Matrix3d I = Eigen::Matrix3d::Zero();
    for (int i : members) {
      const ModelLink& l = model.links[i];
      const Eigen::Vector3d d = l.com_world - c;
      I += l.inertia_world + l.mass * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
    }
    I = 0.5 * (I + I.transpose()).eval();
    const Eigen::Matrix3d R = r.orientation.toRotationMatrix();
    Eigen::Matrix3d I_body = R.transpose() * I * R;
    I_body = 0.5 * (I_body + I_body.transpose()).eval();
    const Eigen::Vector3d ev = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(I_body).eigenvalues();
    if (!(ev.minCoeff() > kInertiaConditionFloor * ev.maxCoeff()) || !(ev.maxCoeff() > 0.0)) {
      std::ostringstream why;
      why << "has a singular inertia (principal moments " << formatNumbers(ev) << " kg m² about its centre of mass"
          << (members.size() > 1 ? ", welded links: " + names : std::string()) << "): give it an <inertia>";
      throw fail(elementLabel("link", r.name, r.line), why.str());
    }
    BodyDescription b;
    b.name = r.name;
    b.mass = m;
    b.inertia = I_body;
    b.orientation = r.orientation.normalized();
    b.position = c;
    b.has_position = true;
    b.angular_velocity = R.transpose() * r.angular_velocity_world;
    // The centre's velocity: v_root + ω × (c − c_root), a rigid group.
    b.velocity = r.velocity_world + r.angular_velocity_world.cross(c - r.com_world);
    b.has_velocity = true;
    for (int i : members)
      for (const VisualShape& v : model.links[i].visuals) b.visuals.push_back(shapeInFrame(v, c, b.orientation));
    (*body_of_group)[root] = static_cast<int>(scene.bodies.size());
    scene.bodies.push_back(b);
  }
}

/// The scene's bodies as the model's links see them: a link's body (−1: the
/// ground), names, rotations and world points in a body's frame.
struct LinkBodies {
  const SceneDescription& scene;
  WeldGroups& groups;
  const std::map<int, int>& body_of_group;

  int bodyOf(int link) const {
    if (link < 0) return -1;
    const auto it = body_of_group.find(groups.find(link));
    return it == body_of_group.end() ? -1 : it->second;
  }
  std::string bodyName(int body) const { return body < 0 ? std::string("ground") : scene.bodies[body].name; }
  Eigen::Matrix3d rotation(int body) const {
    return body < 0 ? Eigen::Matrix3d::Identity() : scene.bodies[body].orientation.toRotationMatrix();
  }
  Eigen::Vector3d local(int body, const Eigen::Vector3d& x_world) const {
    if (body < 0) return x_world;
    return rotation(body).transpose() * (x_world - scene.bodies[body].position);
  }
};

/// A joint of `type` between the links' bodies, both anchors at one world
/// point (a joint between links welded together is refused).
JointDescription jointBetween(const ModelDescription& model, const LinkBodies& links, const std::string& name,
                              const std::string& label, ModelJointType type, int link_a, int link_b,
                              const Eigen::Vector3d& anchor_world) {
  const int a = links.bodyOf(link_a), b = links.bodyOf(link_b);
  if (a == b)
    throw failAt(model, label, "joins links that are welded together (into body '" + links.bodyName(a) + "')");
  JointDescription d;
  d.name = name;
  d.type = jointTypeName(type);
  d.main = links.bodyName(a);
  d.secondary = links.bodyName(b);
  d.anchor_main = links.local(a, anchor_world);
  d.anchor_secondary = links.local(b, anchor_world);
  return d;
}

/// Model joint j (not fixed, not free) as a scene joint: its axes in the
/// bodies' frames, initial angles, springs and dashpots.
JointDescription sceneJointOf(const ModelDescription& model, const LinkBodies& links, const ModelJoint& j) {
  JointDescription d = jointBetween(model, links, j.name, elementLabel("joint", j.name, j.line), j.type, j.parent,
                                    j.child, j.anchor_world);
  const int a = links.bodyOf(j.parent), b = links.bodyOf(j.child);
  const Eigen::Vector3d axis = j.axis_world.normalized();
  switch (j.type) {
    case ModelJointType::kRevolute:
      d.axis_main = links.rotation(a).transpose() * axis;
      d.axis_secondary = links.rotation(b).transpose() * axis;
      d.has_axis_secondary = true;
      d.initial_angles[0] = j.initial[0];
      break;
    case ModelJointType::kPrismatic:
      // x = 0 where the anchors coincide: the main anchor sits `initial`
      // back along the axis.
      d.axis_main = links.rotation(a).transpose() * axis;
      d.anchor_main = links.local(a, j.anchor_world - j.initial[0] * axis);
      break;
    case ModelJointType::kUniversal:
      d.axis_main = links.rotation(a).transpose() * axis;
      d.axis_secondary = links.rotation(b).transpose() * j.axis2_world.normalized();
      d.has_axis_secondary = true;
      d.initial_angles = {{j.initial[0], j.initial[1], 0.0}};
      d.offset = (j.anchor2_world - j.anchor_world).norm() > kSamePoint;
      if (d.offset) d.anchor_secondary = links.local(b, j.anchor2_world);
      break;
    case ModelJointType::kGimbal: {
      // The axes at zero angles (main frame), from the hinge lines at the
      // reference configuration, where the angles are `initial`:
      // e₁ = R_aᵀ A₁, e₂ = exp(−φ₁ e₁) R_aᵀ A₂, e₃ = exp(−φ₂ e₂) exp(−φ₁ e₁) R_aᵀ A₃.
      const Eigen::Matrix3d Rt = links.rotation(a).transpose();
      const Eigen::Vector3d e1 = Rt * axis;
      const Eigen::Matrix3d U1 = Eigen::AngleAxisd(-j.initial[0], e1).toRotationMatrix();
      const Eigen::Vector3d e2 = U1 * Rt * j.axis2_world.normalized();
      const Eigen::Matrix3d U2 = Eigen::AngleAxisd(-j.initial[1], e2).toRotationMatrix();
      d.axis_main = e1;
      d.axis2_main = e2;
      d.axis3_main = U2 * U1 * Rt * j.axis3_world.normalized();
      d.initial_angles = j.initial;
      break;
    }
    default: break;
  }
  for (int i = 0; i < 3; ++i) {
    d.coordinates[i].stiffness = j.stiffness[i];
    d.coordinates[i].rest_angle = j.rest[i];
    d.coordinates[i].damping = j.damping[i];
  }
  return d;
}

/// A coupling q_f = m q_l + c of two joints anywhere in the tree: the
/// coupling row −m q̇_l + q̇_f = 0 on their children's rates relative to
/// their parents, each turning or sliding along its axis (held, in its own
/// body's frame, by its joint).
JointDescription couplingOf(const ModelDescription& model, const SceneDescription& scene, const ModelCoupling& g,
                            const std::map<std::string, int>& scene_joint_of,
                            const std::map<std::string, const ModelJoint*>& model_joint) {
  const auto fail = [&](const std::string& element, const std::string& reason) {
    return failAt(model, element, reason);
  };
  const auto body_rotation = [&](const std::string& body) -> Eigen::Matrix3d {
    const int i = scene.bodyIndex(body);
    return i < 0 ? Eigen::Matrix3d::Identity() : Eigen::Matrix3d(scene.bodies[i].orientation.toRotationMatrix());
  };
  const std::string label = elementLabel("coupling", g.name, g.line);
  const auto lead = scene_joint_of.find(g.leader), follow = scene_joint_of.find(g.follower);
  if (lead == scene_joint_of.end() || follow == scene_joint_of.end())
    throw fail(label, "couples '" + g.follower + "' to '" + g.leader +
                          "': both must be revolute or prismatic joints of the model");
  const JointDescription& jl = scene.joints[lead->second];
  const JointDescription& jf = scene.joints[follow->second];
  const auto one_coordinate = [](const JointDescription& j) { return j.type == "revolute" || j.type == "prismatic"; };
  if (!one_coordinate(jl) || !one_coordinate(jf))
    throw fail(label, "couples '" + g.follower + "' to '" + g.leader +
                          "': lieflow couples two revolute or prismatic joints (a coupling row); these are " +
                          jf.type + " and " + jl.type);
  const double q_l = model_joint.at(g.leader)->initial[0], q_f = model_joint.at(g.follower)->initial[0];
  if (std::abs(q_f - (g.multiplier * q_l + g.offset)) > 1e-9)
    throw fail(label, "the reference configuration does not satisfy the coupling (q_follower = " +
                          formatNumber(q_f) + ", multiplier q_leader + offset = " +
                          formatNumber(g.multiplier * q_l + g.offset) + ")");
  if (g.multiplier == 0.0) throw fail(label, "multiplier 0: the follower is held, not coupled");
  // A node's axis in its own body's frame: a revolute joint's
  // axis_secondary; a prismatic joint's axis (main frame) carried into the
  // child's, whose rotation relative to the parent the joint holds.
  const auto node_axis = [&](const JointDescription& j) -> Eigen::Vector3d {
    if (j.type == "revolute") return j.axis_secondary.normalized();
    return (body_rotation(j.secondary).transpose() * body_rotation(j.main) * j.axis_main).normalized();
  };
  JointDescription d;
  d.name = g.name;
  d.type = "coupling";
  d.carrier = jl.main;
  d.carrier_secondary = jf.main;
  d.main = jl.secondary;
  d.secondary = jf.secondary;
  d.ratio = -g.multiplier;
  d.axes_main.r = node_axis(jl);
  d.axes_secondary.r = node_axis(jf);
  d.slide_main = jl.type == "prismatic";
  d.slide_secondary = jf.type == "prismatic";
  return d;
}

/// Models name links and joints apart (a URDF's link 'base' and joint
/// 'base', MJCF's body 's' and slide 's'); a scene's bodies and joints name
/// its CSV columns together (s.x would be the body's and the slide's): a
/// joint named as a body is renamed, with a note.
void separateJointNames(SceneDescription* out) {
  SceneDescription& scene = *out;
  std::set<std::string> taken;
  for (const BodyDescription& b : scene.bodies) taken.insert(b.name);
  for (const JointDescription& j : scene.joints) taken.insert(j.name);
  std::set<std::string> bodies;
  for (const BodyDescription& b : scene.bodies) bodies.insert(b.name);
  for (JointDescription& j : scene.joints) {
    if (!bodies.count(j.name)) continue;
    std::string name = j.name + "_joint";
    for (int k = 2; taken.count(name); ++k) name = j.name + "_joint" + std::to_string(k);
    scene.import_notes.push_back("renamed joint '" + j.name + "' to '" + name +
                                 "' (a body has its name, and they would name the same CSV columns)");
    taken.insert(name);
    j.name = name;
  }
}

}  // namespace

SceneDescription sceneFromModel(const ModelDescription& model) {
  requireUsableNumbers(model);
  const int nl = static_cast<int>(model.links.size());
  WeldGroups groups(nl);
  for (const ModelJoint& j : model.joints)
    if (j.type == ModelJointType::kFixed) groups.weld(j.parent, j.child);

  SceneDescription scene;
  scene.name = model.name;
  scene.source = model.source;
  scene.gravity = model.gravity;
  std::map<int, int> body_of_group;  // group root → scene body
  addMergedBodies(model, groups, &scene, &body_of_group);
  // What is welded to the world stays where it is drawn.
  scene.ground_visuals = model.ground_visuals;
  for (int i = 0; i < nl; ++i)
    if (groups.find(i) == kGroundGroup)
      scene.ground_visuals.insert(scene.ground_visuals.end(), model.links[i].visuals.begin(),
                                  model.links[i].visuals.end());

  const LinkBodies links{scene, groups, body_of_group};
  std::map<std::string, int> scene_joint_of;  // model joint name → scene joint
  for (const ModelJoint& j : model.joints) {
    if (j.type == ModelJointType::kFixed || j.type == ModelJointType::kFree) continue;
    JointDescription d = sceneJointOf(model, links, j);
    scene_joint_of[j.name] = static_cast<int>(scene.joints.size());
    scene.joints.push_back(std::move(d));
  }
  for (const ModelClosure& c : model.closures)
    scene.joints.push_back(jointBetween(model, links, c.name, elementLabel("equality", c.name, c.line), c.type,
                                        c.link1, c.link2, c.anchor_world));
  std::map<std::string, const ModelJoint*> model_joint;
  for (const ModelJoint& j : model.joints) model_joint[j.name] = &j;
  for (const ModelCoupling& g : model.couplings)
    scene.joints.push_back(couplingOf(model, scene, g, scene_joint_of, model_joint));
  separateJointNames(&scene);
  if (model.timestep > 0.0) {
    scene.has_integrator = true;
    scene.integrator.name = "rkmk4";
    scene.integrator.dt = model.timestep;
  }
  std::ostringstream text;
  text << "imported from " << model.source;
  if (!model.ignored.empty()) text << " (ignored: " << model.ignored.size() << " elements)";
  scene.description = text.str();
  scene.import_notes.insert(scene.import_notes.begin(), model.ignored.begin(), model.ignored.end());
  scene.import_notes.insert(scene.import_notes.end(), model.notes.begin(), model.notes.end());
  return scene;
}

}  // namespace model_import
}  // namespace lieflow
