#include "dynamics/joint_space/articulated_scene.hpp"

#include <algorithm>
#include <deque>
#include <optional>
#include <unordered_map>

#include "dynamics/scene_joints.hpp"
#include "model/union_find.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {

using articulated::ArticulatedBody;
using articulated::ArticulatedModel;

namespace {

/// The initial projection onto the loops' rows stops at this max |Φ|
/// (metres, radians), as the maximal assembly's.
constexpr double kInitialProjectionTolerance = 1e-13;
constexpr int kInitialProjectionIterations = 20;

/// exp(φ a) as a matrix, a unit.
Eigen::Matrix3d rotationAbout(const Eigen::Vector3d& a, double phi) {
  return Eigen::AngleAxisd(phi, a).toRotationMatrix();
}

std::string label(const SceneDescription& scene, std::size_t k) {
  return scene.source + ": joints[" + std::to_string(k) + "] (" + scene.joints[k].name + ")";
}

/// A scene joint's force elements or prescribed motion, if any ("" if none).
std::string driveOf(const SceneDescription& scene, const JointDescription& j) {
  if (scene.user_loads.joint_moments.count(j.name)) return "a moment from the program";
  for (const CoordinateDescription& cd : j.coordinates) {
    if (cd.prescribed) return "prescribed motion";
    if (cd.stiffness != 0.0) return "a spring";
    if (cd.damping != 0.0) return "a dashpot";
    if (cd.moment) return "a moment";
  }
  return "";
}

/// The tree: for each body (scene index) the joint to its parent and the
/// parent (scene index, −1 ground), bodies in the order they are reached
/// from the ground (breadth first over the tree's joints); the joints that
/// close loops, and the gear-type joints, in `cuts`. The tree's joints are
/// chosen as a spanning forest (union–find over the bodies and the ground,
/// Kruskal's order): first the joints with force elements or prescribed
/// motion (they need a coordinate of their own), then the others, each in
/// scene order; a joint whose bodies are already connected closes a loop.
/// False with `why` when the joints do not form such a tree or a loop can
/// only be closed by a joint with a force element or prescribed motion.
/// The tree's edges by Kruskal (union–find over the bodies and the ground,
/// node nb): slides, gimbals, offset universal joints and welds first, then
/// driven joints, then plain ones, so that a loop is closed by a plain
/// revolute, universal or spherical joint (*cuts, the gears after them).
/// at[body]: the tree's joints at each body (and at the ground, nb), in
/// scene order. False with *why when a loop cannot be closed that way.
bool spanningTree(const SceneDescription& scene, std::vector<std::vector<int>>* at_out, std::vector<int>* cuts,
                  std::string* why) {
  const int nb = static_cast<int>(scene.bodies.size());
  const std::unordered_map<std::string, int> index = scene.bodyIndices();
  auto body = [&](const std::string& name) { return name == "ground" ? -1 : index.at(name); };
  std::vector<std::vector<int>>& at = *at_out;
  std::vector<int> sliding, driven, plain, gear_cuts;
  for (std::size_t k = 0; k < scene.joints.size(); ++k) {
    const JointDescription& j = scene.joints[k];
    if (j.isGear()) {
      // Rows on the velocities of bodies the tree places: imposed with
      // multipliers (ArticulatedClosure), never a tree edge.
      gear_cuts.push_back(static_cast<int>(k));
      continue;
    }
    // A slide, a gimbal, an offset universal joint and a weld are always tree
    // edges (a loop is closed by a revolute, universal or spherical joint).
    const bool tree_only = j.type == "prismatic" || j.type == "gimbal" || j.type == "fixed" || j.offset;
    (tree_only ? sliding : driveOf(scene, j).empty() ? plain : driven).push_back(static_cast<int>(k));
  }
  // Kruskal: union–find over the bodies and the ground (node nb).
  UnionFind component(nb + 1);
  cuts->clear();
  at.assign(nb + 1, {});
  for (const std::vector<int>* list : {&sliding, &driven, &plain})
    for (int k : *list) {
      const JointDescription& j = scene.joints[k];
      const int a = body(j.main), b = body(j.secondary);
      const int ra = component.find(a < 0 ? nb : a), rb = component.find(b < 0 ? nb : b);
      if (ra == rb) {
        // A loop: this joint is imposed with multipliers on the tree's poses.
        if (list == &sliding) {
          *why = label(scene, k) + " closes a loop of prismatic, gimbal, offset universal or fixed joints: in "
                                   "joint coordinates a loop is closed by a revolute, universal or spherical joint";
          return false;
        }
        if (list == &driven) {
          *why = label(scene, k) + " closes a loop whose every joint carries a force element or prescribed "
                                   "motion (this one " + driveOf(scene, j) +
                 "): a loop-closing joint has no coordinate of its own in joint coordinates";
          return false;
        }
        cuts->push_back(k);
        continue;
      }
      component.join(ra, rb);
      at[a < 0 ? nb : a].push_back(k);
      at[b < 0 ? nb : b].push_back(k);
    }
  for (std::vector<int>& joints : at) std::sort(joints.begin(), joints.end());  // scene order
  cuts->insert(cuts->end(), gear_cuts.begin(), gear_cuts.end());
  return true;
}

/// Why scene joint k cannot carry body c from its parent p (−1: the ground)
/// in joint coordinates (a = the joint's main body), or "" when it can.
std::string treeEdgeProblem(const SceneDescription& scene, int k, int p, int c, int a) {
  const JointDescription& j = scene.joints[k];
  // A rotation-only child turns about its held centre of mass: its joint
  // may constrain only rotations (the maximal formulation's point rows
  // are then identically satisfied: both sides fixed points).
  if (scene.bodies[c].rotation_only && j.type == "fixed")
    return label(scene, k) + " welds the rotation-only body '" + scene.bodies[c].name +
           "' to a body that carries it: a held body turns about its own centre";
  if (scene.bodies[c].rotation_only) {
    const Eigen::Vector3d& own = c == a ? j.anchor_main : j.anchor_secondary;
    const Eigen::Vector3d& other = c == a ? j.anchor_secondary : j.anchor_main;
    const bool parent_fixed = p < 0 || (scene.bodies[p].rotation_only && other.norm() <= 1e-12);
    if (own.norm() > 1e-12 || !parent_fixed) {
      return label(scene, k) + " holds the rotation-only body '" + scene.bodies[c].name +
             "' at a point of a moving body: a constraint on the rotations that needs multipliers";
    }
  }
  // Gimbals and offset universal joints hang from their main body.
  if ((j.type == "gimbal" || j.offset) && c == a)
    return label(scene, k) + " (" + (j.offset ? "an offset universal joint" : "a gimbal") +
           ") would hang its main body '" + j.main + "' from its secondary '" + j.secondary +
           "': joint coordinates take these joints from their main body";
  return "";
}

bool buildTree(const SceneDescription& scene, std::vector<int>* order, std::vector<int>* joint_of,
               std::vector<int>* parent_of, std::vector<int>* cuts, std::string* why) {
  const int nb = static_cast<int>(scene.bodies.size());
  const std::unordered_map<std::string, int> index = scene.bodyIndices();
  auto body = [&](const std::string& name) { return name == "ground" ? -1 : index.at(name); };
  std::vector<std::vector<int>> at;
  if (!spanningTree(scene, &at, cuts, why)) return false;
  order->clear();
  joint_of->assign(nb, -1);
  parent_of->assign(nb, -1);
  std::vector<bool> placed(nb, false), used(scene.joints.size(), false);
  std::deque<int> queue{-1};
  // A rotation-only body no joint reaches from the ground is a root of its
  // own (an implicit spherical joint at its held centre of mass); once the
  // ground's and those trees are placed, a body still unplaced is a root on
  // a free joint (a floating robot's trunk, a free body): in each floating
  // group the first body in scene order that no joint names as its
  // secondary (the model's root link), else the group's first body.
  std::vector<bool> secondary(nb, false);
  for (const JointDescription& j : scene.joints)
    if (!j.isGear() && j.secondary != "ground") secondary[index.at(j.secondary)] = true;
  int next_root = 0;
  auto place_root = [&](int r) {
    placed[r] = true;
    order->push_back(r);
    queue.push_back(r);
    return true;
  };
  auto nextRoot = [&]() {
    for (; next_root < nb; ++next_root)
      if (!placed[next_root] && scene.bodies[next_root].rotation_only) return place_root(next_root++);
    for (int pass = 0; pass < 2; ++pass)
      for (int r = 0; r < nb; ++r)
        if (!placed[r] && (pass == 1 || !secondary[r])) return place_root(r);
    return false;
  };
  while (!queue.empty() || nextRoot()) {
    const int p = queue.front();
    queue.pop_front();
    for (int k : at[p < 0 ? nb : p]) {
      if (used[k]) continue;
      used[k] = true;
      const JointDescription& j = scene.joints[k];
      const int a = body(j.main), b = body(j.secondary);
      const int c = a == p ? b : a;  // a tree joint: c is not placed yet
      if (std::string problem = treeEdgeProblem(scene, k, p, c, a); !problem.empty()) {
        *why = std::move(problem);
        return false;
      }
      placed[c] = true;
      (*joint_of)[c] = k;
      (*parent_of)[c] = p;
      order->push_back(c);
      queue.push_back(c);
    }
  }
  return true;
}

}  // namespace

bool articulatedCovers(const SceneDescription& scene, std::string* why) {
  std::vector<int> order, joint_of, parent_of, cuts;
  if (scene.joints.empty()) {
    *why = scene.source + " has no joints";
    return false;
  }
  return buildTree(scene, &order, &joint_of, &parent_of, &cuts, why);
}

namespace {

/// A scene body's rotation at t = 0 (the identity for the ground, −1).
Eigen::Matrix3d sceneRotation(const SceneDescription& scene, int scene_body) {
  return scene_body < 0 ? Eigen::Matrix3d::Identity()
                        : Eigen::Matrix3d(scene.bodies[scene_body].orientation.normalized().toRotationMatrix());
}

/// The tree's scalar coordinates nq (angles, slides, a free root's centre
/// of mass) and rotations ns (spherical joints, free roots' orientations).
void countCoordinates(const SceneDescription& scene, const std::vector<int>& order, const std::vector<int>& joint_of,
                      int* nq, int* ns) {
  for (int c : order) {
    const std::string& type = joint_of[c] >= 0 ? scene.joints[joint_of[c]].type
                              : scene.bodies[c].rotation_only ? std::string("spherical") : std::string("free");
    if (type == "spherical") {
      ++*ns;
    } else if (type == "free") {
      ++*ns;     // its orientation
      *nq += 3;  // its centre of mass
    } else {
      *nq += type == "universal" ? 2 : type == "gimbal" ? 3 : type == "fixed" ? 0 : 1;  // revolute, prismatic: 1
    }
  }
}

/// The drives of joint j's coordinates (its springs, dashpots, moments,
/// prescribed motions and the program's moment `user_moment`, if any) on
/// body b, and their values at t = 0 in y0: the prescribed value, else a
/// slide's x0, else the initial angle.
void setDrives(const JointDescription& j, const UserLoads::JointMoment* user_moment, std::optional<double> x0,
               ArticulatedBody* b, std::array<CoordinateDrive, 3>* drives, articulated::ArticulatedState* y0) {
  for (int i = 0; i < b->coordinates(); ++i) {
    const CoordinateDescription& cd = j.coordinates[i];
    CoordinateDrive& d = (*drives)[i];
    d.stiffness = cd.stiffness;
    d.rest_angle = cd.rest_angle;
    d.damping = cd.damping;
    d.moment = cd.moment;
    d.prescribed = cd.prescribed;
    if (user_moment) {
      const UserLoads::JointMoment f = *user_moment;
      d.user_moment = [f, i](double time, double phi, double phidot) { return f(time, i, phi, phidot); };
    }
    y0->q[b->q_begin + i] = d.prescribed ? (*d.prescribed)(0.0) : x0 ? *x0 : j.initial_angles[i];
    b->has_force[i] = d.hasForce();
    b->is_prescribed[i] = d.prescribed.has_value();
  }
}

/// The loop-closing joints `cuts`: the maximal formulation's constraints,
/// assembled at the scene's poses (the tree reproduces them at y0), and the
/// gear rows, appended to model->closures.
void addClosures(const SceneDescription& scene, const std::vector<int>& cuts, ArticulatedModel* model) {
  auto tree = [&](int scene_body) { return scene_body < 0 ? articulated::kGround : model->tree_index[scene_body]; };
  auto pose = [&](int i) {
    if (i < 0) return constraints::groundPose<double>();
    return constraints::BodyPose<double>{SO3d(scene.bodies[i].orientation.normalized()), scene.bodies[i].position};
  };
  const std::unordered_map<std::string, int> index = scene.bodyIndices();
  for (int k : cuts) {
    const JointDescription& j = scene.joints[k];
    articulated::ArticulatedClosure c;
    if (j.isGear()) {
      const Gear g = sceneGear(scene, static_cast<std::size_t>(k), index);
      c.gear = g.constraint;
      for (int s = 0; s < 4; ++s) c.bodies[s] = tree(g.bodies[s]);
    } else {
      const int a = j.main == "ground" ? -1 : scene.bodyIndex(j.main);
      const int b = j.secondary == "ground" ? -1 : scene.bodyIndex(j.secondary);
      c.constraint = sceneJointConstraint(scene, static_cast<std::size_t>(k), index, pose(a), pose(b));
      c.bodies[0] = tree(a);
      c.bodies[1] = tree(b);
      c.initial_angles = {{j.initial_angles[0], j.initial_angles[1]}};
    }
    c.scene_joint = k;
    c.label = label(scene, static_cast<std::size_t>(k));
    c.row_begin = model->closure_rows;
    model->closure_rows += c.rows();
    model->closures.push_back(std::move(c));
  }
}

/// The program's body torques on the system (its joint moments went to the
/// drives); names that match no body or joint are InvalidInput.
void attachUserLoads(const SceneDescription& scene, articulated::ArticulatedSystem* system) {
  articulated::ArticulatedSystem& sys = *system;
  for (const auto& [name, f] : scene.user_loads.body_torques) {
    const int i = scene.bodyIndex(name);
    if (i < 0) throw InvalidInput("torques", "the scene has no body '" + name + "'");
    sys.setUserTorque(sys.model().tree_index[i], f);
  }
  for (const auto& [name, f] : scene.user_loads.joint_moments) {
    (void)f;
    bool found = false;
    for (const JointDescription& j : scene.joints) found = found || j.name == name;
    if (!found) throw InvalidInput("moments", "the scene has no joint '" + name + "'");
  }
}

/// Child c of the tree on scene joint k = its parent `parent` (a scene body,
/// or −1 for the ground): the joint's kind, anchors, axes, reference
/// rotation and drives on body b (b->parent set), its coordinates' or
/// rotation's slots (from *q_next, *r_next; rotations after the nq scalar
/// coordinates in u) and values at t = 0 in y0.
void setTreeJoint(const SceneDescription& scene, int c, int parent, int nq, int* r_next, int* q_next,
                  ArticulatedBody* b, std::array<CoordinateDrive, 3>* drives, articulated::ArticulatedState* y0) {
  const int k = b->scene_joint;
  const JointDescription& j = scene.joints[k];
  const std::string& parent_name = parent < 0 ? std::string("ground") : scene.bodies[parent].name;
  b->parent_is_main = j.main == parent_name;
  b->anchor_parent = b->parent_is_main ? j.anchor_main : j.anchor_secondary;
  b->anchor_child = b->parent_is_main ? j.anchor_secondary : j.anchor_main;
  const int main = b->parent_is_main ? parent : c, sec = b->parent_is_main ? c : parent;
  const Eigen::Matrix3d M0 = sceneRotation(scene, main).transpose() * sceneRotation(scene, sec);
  const auto user_moment = scene.user_loads.joint_moments.find(j.name);
  if (j.type == "spherical") {
    b->kind = articulated::JointKind::kSpherical;
    b->rotation = (*r_next)++;
    b->u_begin = nq + 3 * b->rotation;
    const Eigen::Matrix3d N0 = sceneRotation(scene, parent).transpose() * sceneRotation(scene, c);
    y0->N.push_back(SO3d(Eigen::Quaterniond(N0).normalized()));
    if (user_moment != scene.user_loads.joint_moments.end())
      throw InvalidInput("moments", "joint '" + j.name +
                                        "' is spherical: a moment acts on the coordinate of a revolute or "
                                        "universal joint");
  } else {
    // An anchor in the world at t = 0 (`local` in the frame of `body`, or
    // of the world).
    const auto anchor = [&](int body, const Eigen::Vector3d& local) -> Eigen::Vector3d {
      return body < 0 ? local : Eigen::Vector3d(scene.bodies[body].position + sceneRotation(scene, body) * local);
    };
    const bool slides = j.type == "prismatic";
    b->kind = slides                  ? articulated::JointKind::kPrismatic
              : j.type == "universal" ? articulated::JointKind::kUniversal
              : j.type == "gimbal"    ? articulated::JointKind::kGimbal
              : j.type == "fixed"     ? articulated::JointKind::kFixed
                                      : articulated::JointKind::kRevolute;
    b->q_begin = b->u_begin = *q_next;
    *q_next += b->coordinates();
    b->axis1 = j.axis_main.normalized();
    b->axis2 = j.axis_secondary.normalized();
    b->R_ref = slides || b->kind == articulated::JointKind::kFixed
                   ? M0
                   : Eigen::Matrix3d(rotationAbout(b->axis1, -j.initial_angles[0]) * M0);
    if (b->kind == articulated::JointKind::kUniversal)
      b->R_ref = b->R_ref * rotationAbout(b->axis2, -j.initial_angles[1]);
    if (b->kind == articulated::JointKind::kGimbal) {
      // M0 = exp(φ₁e₁) exp(φ₂e₂) exp(φ₃e₃) R_ref at the initial angles.
      b->axis2 = j.axis2_main.normalized();
      b->axis3 = j.axis3_main.normalized();
      b->R_ref = rotationAbout(b->axis3, -j.initial_angles[2]) * rotationAbout(b->axis2, -j.initial_angles[1]) *
                 rotationAbout(b->axis1, -j.initial_angles[0]) * M0;
    }
    if (j.offset) {
      // δ: the secondary anchor from the main one, main frame, at φ₁ = 0.
      b->offset = true;
      b->offset_ref = rotationAbout(b->axis1, -j.initial_angles[0]) * sceneRotation(scene, main).transpose() *
                      (anchor(sec, j.anchor_secondary) - anchor(main, j.anchor_main));
    }
    // A slide's x at t = 0, as the maximal formulation reads it from the
    // poses: x = (R_main a)·(anchor_secondary − anchor_main), world.
    double x0 = 0.0;
    if (slides) {
      x0 = (sceneRotation(scene, main) * b->axis1).dot(anchor(sec, j.anchor_secondary) - anchor(main, j.anchor_main));
    }
    const UserLoads::JointMoment* f =
        user_moment != scene.user_loads.joint_moments.end() ? &user_moment->second : nullptr;
    setDrives(j, f, slides ? std::optional<double>(x0) : std::nullopt, b, drives, y0);
  }
}

}  // namespace

std::unique_ptr<ArticulatedScene> assembleArticulated(const SceneDescription& scene) {
  std::vector<int> order, joint_of, parent_of, cuts;
  std::string why;
  if (!articulatedCovers(scene, &why) || !buildTree(scene, &order, &joint_of, &parent_of, &cuts, &why))
    throw InvalidInput("`formulation`", "joint coordinates cannot represent this scene: " + why +
                                            " (run it with `formulation` maximal)");
  ArticulatedModel model;
  model.gravity = scene.gravity;
  const int nb = static_cast<int>(scene.bodies.size());
  model.tree_index.assign(nb, -1);
  model.scene_joints = static_cast<int>(scene.joints.size());
  for (int t = 0; t < nb; ++t) model.tree_index[order[t]] = t;
  // Angles first, then spherical rotations in u (articulated_state.hpp).
  int nq = 0, ns = 0;
  countCoordinates(scene, order, joint_of, &nq, &ns);
  articulated::ArticulatedState y0;
  y0.q.setZero(nq);
  y0.u.setZero(nq + 3 * ns);
  int q_next = 0, r_next = 0;
  for (int t = 0; t < nb; ++t) {
    const int c = order[t];
    const int k = joint_of[c];
    const BodyDescription& bd = scene.bodies[c];
    ArticulatedBody b;
    b.mass = bd.mass;
    b.inertia = bd.inertia;
    b.scene_joint = k;
    b.rotation_only = bd.rotation_only;
    b.initial_orientation = bd.orientation.normalized();
    b.fixed_position = bd.position;
    if (k < 0 && !bd.rotation_only) {
      // A floating root: (R, c) on SO(3) × ℝ³; its velocities come from the
      // scene's by the projection below (its own are free: (ω, v_c) as given).
      b.kind = articulated::JointKind::kFree;
      b.rotation = r_next++;
      b.q_begin = b.u_begin = q_next;
      q_next += 3;
      b.u_rotation = nq + 3 * b.rotation;
      y0.q.segment<3>(b.q_begin) = bd.position;
      y0.N.push_back(SO3d(Eigen::Quaterniond(sceneRotation(scene, c)).normalized()));
      model.bodies.push_back(b);
      model.names.push_back(bd.name);
      model.drives.emplace_back();
      continue;
    }
    if (k < 0) {
      // A root rotation-only body: spherical about its centre of mass.
      b.kind = articulated::JointKind::kSpherical;
      b.anchor_parent = bd.position;
      b.rotation = r_next++;
      b.u_begin = nq + 3 * b.rotation;
      y0.N.push_back(SO3d(Eigen::Quaterniond(sceneRotation(scene, c)).normalized()));
      model.bodies.push_back(b);
      model.names.push_back(bd.name);
      model.drives.emplace_back();
      continue;
    }
    std::array<CoordinateDrive, 3> drives;
    b.parent = parent_of[c] < 0 ? articulated::kGround : model.tree_index[parent_of[c]];
    setTreeJoint(scene, c, parent_of[c], nq, &r_next, &q_next, &b, &drives, &y0);
    model.bodies.push_back(b);
    model.names.push_back(bd.name);
    model.drives.push_back(std::move(drives));
  }
  model.scalar_coordinates = nq;
  model.rotations = ns;
  addClosures(scene, cuts, &model);
  auto out = std::make_unique<ArticulatedScene>();
  out->system = std::make_unique<articulated::ArticulatedSystem>(std::move(model));
  articulated::ArticulatedSystem& sys = *out->system;
  attachUserLoads(scene, &sys);
  std::vector<Eigen::Vector3d> omega(nb), v(nb);
  for (int t = 0; t < nb; ++t) {
    const BodyDescription& bd = scene.bodies[order[t]];
    omega[t] = bd.angular_velocity;
    v[t] = bd.velocity;
  }
  if (sys.hasClosures()) {
    // As the maximal assembly: onto the loops' position rows, then (below)
    // the velocities onto their velocity rows in the mass metric.
    int iterations = 0;
    if (!sys.projectPositions(0.0, &y0, kInitialProjectionTolerance, kInitialProjectionIterations, &iterations, &why))
      throw InvalidInput("`formulation`", scene.source + ": the loops do not close at t = 0: " + why);
  }
  sys.projectVelocities(0.0, omega, v, &y0);
  sys.projectVelocities(0.0, &y0, &why);
  if (sys.hasClosures())
    sys.setClosureRowsIndependent(static_cast<int>(sys.independentClosureRows(0.0, y0).size()) ==
                                  sys.model().closure_rows);
  out->y0 = std::move(y0);
  return out;
}

}  // namespace lieflow
