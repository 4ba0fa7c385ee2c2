// MultibodySystem: construction, validation, joint coordinates and angles.
#include "dynamics/maximal/multibody_system.hpp"

#include <cmath>
#include <limits>
#include <sstream>

namespace lieflow {
namespace multibody {

using constraints::BodyPose;
using constraints::BodyVelocity;
using Row6 = Eigen::Matrix<double, 1, 6>;

// --- Construction --------------------------------------------------------------

MultibodySystem::MultibodySystem(MultibodyModel model, std::vector<CoordinateDrives> drives,
                                 std::vector<Gear> gears)
    : model_(std::move(model)), drives_(std::move(drives)), gears_(std::move(gears)) {
  if (drives_.empty()) drives_.resize(model_.joints.size());
  model_.validateModel();
  validate();
  const int nb = bodyCount();
  rot_.resize(nb);
  off_.assign(nb + 1, 0);
  for (int i = 0; i < nb; ++i) {
    rot_[i] = model_.bodies[i].rotation_only ? 1 : 0;
    off_[i + 1] = off_[i] + model_.bodies[i].dofs();
  }
  n_ = off_[nb];
  // Identically satisfied rows (see the header).
  auto fixedPoint = [&](int body, const Eigen::Vector3d& anchor) {
    return body == kGround || (rot_[body] && anchor.norm() <= 1e-12);
  };
  for (std::size_t k = 0; k < model_.joints.size(); ++k) {
    const Joint& j = model_.joints[k];
    const auto anchors = jointAnchors(j.constraint);
    const bool trivial = pointRows(j.constraint) == 3 && fixedPoint(j.main, anchors.first) &&
                         fixedPoint(j.secondary, anchors.second);
    skip_rows_.push_back(trivial ? 3 : 0);
    RowGroup g;
    g.bodies = {{j.main, j.secondary, kGround, kGround}};
    g.rows = constraintRows(j.constraint) - skip_rows_.back();
    pos_groups_.push_back(g);
  }
  // A node is hinged to its carrier when a revolute joint joins them about
  // the node's r axis (parallel to 1e-9 in the node's frame).
  auto hingedToCarrier = [&](int node, int carrier, const Eigen::Vector3d& r_node) {
    for (const Joint& j : model_.joints) {
      const auto* rev = std::get_if<constraints::RevoluteJoint<double>>(&j.constraint);
      if (!rev) continue;
      Eigen::Vector3d axis_node;
      if (j.main == node && j.secondary == carrier)
        axis_node = rev->axis_main;
      else if (j.main == carrier && j.secondary == node)
        axis_node = rev->axis_secondary;
      else
        continue;
      if (std::abs(axis_node.dot(r_node)) >= 1.0 - 1e-9) return true;
    }
    return false;
  };
  for (const Gear& gear : gears_) {
    std::vector<int> rows;
    if (gear.constraint.index() == 0) {  // gear: r row, node 1 s/t, node 2 s/t
      const auto& gj = std::get<constraints::GearJoint<double>>(gear.constraint);
      rows.push_back(0);
      for (int node = 1; node <= 2; ++node)
        if (!hingedToCarrier(gear.bodies[node], gear.bodies[0], node == 1 ? gj.node1.r : gj.node2.r)) {
          rows.push_back(2 * node - 1);
          rows.push_back(2 * node);
        }
    } else if (gear.constraint.index() == 1) {  // rack and pinion: both rows
      rows = {0, 1};
    } else if (std::holds_alternative<constraints::CouplingJoint<double>>(gear.constraint)) {
      rows = {0};  // a coupling: its one row (the nodes' joints hold the rest)
    } else {  // differential: r row; s, t rows unless every node is hinged
      const auto& dj = std::get<constraints::DifferentialJoint<double>>(gear.constraint);
      rows.push_back(0);
      const Eigen::Vector3d r[3] = {dj.node1.r, dj.node2.r, dj.node3.r};
      bool all = true;
      for (int node = 1; node <= 3; ++node)
        all = all && hingedToCarrier(gear.bodies[node], gear.bodies[0], r[node - 1]);
      if (!all) rows.insert(rows.end(), {1, 2});
    }
    gear_rows_.push_back(rows);
  }
  // A fixed joint's slide x is held at 0 (constraints/fixed.hpp): a
  // prescribed row of its own, as its sixth constraint.
  for (std::size_t k = 0; k < model_.joints.size(); ++k)
    if (jointKind(model_.joints[k].constraint) == JointKind::kFixed)
      drives_[k][0].prescribed = TimeFunction::constant(0.0);
  for (std::size_t k = 0; k < model_.joints.size(); ++k)
    for (int i = 0; i < std::max(1, coordinateCount(static_cast<int>(k))); ++i)
      if (drives_[k][i].prescribed) {
        prescribed_.push_back({static_cast<int>(k), i});
        RowGroup g;
        g.bodies = {{model_.joints[k].main, model_.joints[k].secondary, kGround, kGround}};
        g.rows = 1;
        pos_groups_.push_back(g);
      }
  all_groups_ = pos_groups_;
  for (std::size_t i = 0; i < gears_.size(); ++i) {
    RowGroup g;
    g.bodies = gears_[i].bodies;
    g.rows = static_cast<int>(gear_rows_[i].size());
    all_groups_.push_back(g);
  }
  data_.all.setup(rot_, all_groups_);
  if (hasGears()) data_.pos.setup(rot_, pos_groups_);
}

int MultibodySystem::coordinateCount(int k) const {
  switch (jointKind(model_.joints[k].constraint)) {
    case JointKind::kRevolute:
    case JointKind::kPrismatic: return 1;
    case JointKind::kUniversal:
    case JointKind::kOffsetUniversal: return 2;
    case JointKind::kGimbal: return 3;
    default: return 0;  // spherical; fixed (its held slide is a prescribed row, not an output)
  }
}

void MultibodySystem::setUserTorque(int body, UserTorque torque) {
  LIEFLOW_ASSERT(body >= 0 && body < bodyCount(), "setUserTorque: no such body");
  if (user_torques_.empty()) user_torques_.resize(bodyCount());
  user_torques_[body] = std::move(torque);
}

bool MultibodySystem::hasUserTorques() const {
  for (const UserTorque& f : user_torques_)
    if (f) return true;
  return false;
}

bool MultibodySystem::autonomous() const {
  if (hasUserTorques()) return false;
  for (std::size_t k = 0; k < model_.joints.size(); ++k)
    for (int i = 0; i < coordinateCount(static_cast<int>(k)); ++i)
      if (drives_[k][i].dependsOnTime()) return false;
  return true;
}

bool MultibodySystem::hasDampers() const {
  for (std::size_t k = 0; k < model_.joints.size(); ++k)
    for (int i = 0; i < coordinateCount(static_cast<int>(k)); ++i)
      if (drives_[k][i].damping != 0.0) return true;
  return false;
}

int MultibodySystem::positionRowCount() const {
  int m = 0;
  for (const RowGroup& g : pos_groups_) m += g.rows;
  return m;
}

void MultibodySystem::validate() const {
  if (drives_.size() != model_.joints.size())
    throw InvalidInput("joints", "one drive pair per joint expected");
  for (std::size_t k = 0; k < model_.joints.size(); ++k) {
    const std::string label = model_.jointLabel(static_cast<int>(k));
    const int nc = coordinateCount(static_cast<int>(k));
    for (int i = 0; i < kMaxJointCoordinates; ++i) {
      const CoordinateDrive& d = drives_[k][i];
      const bool used = d.hasForce() || d.prescribed.has_value() || d.rest_angle != 0.0;
      if (i >= nc && used)
        throw InvalidInput(label, std::string("a ") + constraintTypeName(model_.joints[k].constraint) +
                                      (nc == 0 ? " joint has no joint coordinate to carry a spring, damper, "
                                                 "moment, force or prescribed motion"
                                               : " joint has " + std::to_string(nc) + " joint coordinate" +
                                                     (nc > 1 ? "s" : "")));
      if (d.prescribed && jointKind(model_.joints[k].constraint) == JointKind::kGimbal)
        throw InvalidInput(label + ".prescribed" + std::to_string(i + 1),
                           "a gimbal's angles carry springs, dampers and moments but are not prescribed");
      if (!(std::isfinite(d.stiffness) && d.stiffness >= 0.0))
        throw InvalidInput(label + ".spring.stiffness", "must be finite and >= 0");
      if (!std::isfinite(d.rest_angle)) throw InvalidInput(label + ".spring.rest_angle", "must be finite");
      if (!(std::isfinite(d.damping) && d.damping >= 0.0))
        throw InvalidInput(label + ".damper.damping", "must be finite and >= 0");
    }
  }
  const int nb = bodyCount();
  for (const Gear& g : gears_) {
    const int nodes =
        std::visit([](const auto& c) { return static_cast<int>(std::decay_t<decltype(c)>::kBodies); }, g.constraint);
    for (int s = 0; s < nodes; ++s) {
      const int b = g.bodies[s];
      const std::string field = g.name + (s == 0 ? ".carrier" : ".node" + std::to_string(s));
      if (b < kGround || b >= nb) throw InvalidInput(field, "unknown body index " + std::to_string(b));
      // A coupling's slots are its bodies in their roles (gear.hpp): the
      // ground may be any of them, and unused ones are the ground.
      if (s > 0 && b == kGround && !std::holds_alternative<constraints::CouplingJoint<double>>(g.constraint))
        throw InvalidInput(field, "a gear node must be a body with rotary inertia, not the ground");
      for (int r = 0; r < s; ++r)
        if (g.bodies[r] == b && b != kGround)
          throw InvalidInput(field, "the same body appears twice in one gear constraint");
    }
    if (g.constraint.index() == 1 && model_.bodies[g.bodies[2]].rotation_only)
      throw InvalidInput(g.name + ".node2", "the rack must have translational coordinates (not rotation_only)");
  }
}

MultibodyGroupState MultibodySystem::makeState(const MultibodyState& bodies) const {
  model_.validateState(bodies);
  State y;
  y.bodies = bodies;
  y.system = this;
  // Principal values: unwrapped around 0.
  y.angles.assign(kMaxJointCoordinates * model_.joints.size(), 0.0);
  rebaseAngles(&y);
  return y;
}

void MultibodySystem::poses(const State& y, int main, int secondary, BodyPose<double>* a, BodyPose<double>* b,
                            BodyVelocity<double>* va, BodyVelocity<double>* vb) const {
  *a = main == kGround ? constraints::groundPose<double>() : y.bodies.poses[main];
  *b = secondary == kGround ? constraints::groundPose<double>() : y.bodies.poses[secondary];
  if (va) *va = main == kGround ? constraints::groundVelocity<double>() : y.bodies.velocities[main];
  if (vb) *vb = secondary == kGround ? constraints::groundVelocity<double>() : y.bodies.velocities[secondary];
}

double MultibodySystem::coordinate(const State& y, int k, int i, Row6* Ja, Row6* Jb) const {
  std::array<double, kMaxJointCoordinates> phi;
  CoordinateRows A, B;
  coordinates(y, k, &phi, Ja ? &A : nullptr, Ja ? &B : nullptr);
  if (Ja) {
    *Ja = A[i];
    *Jb = B[i];
  }
  return phi[i];
}

int MultibodySystem::coordinates(const State& y, int k, std::array<double, kMaxJointCoordinates>* phi,
                                 CoordinateRows* Ja, CoordinateRows* Jb) const {
  const Joint& j = model_.joints[k];
  BodyPose<double> a, b;
  poses(y, j.main, j.secondary, &a, &b, nullptr, nullptr);
  if (const auto* rev = std::get_if<constraints::RevoluteJoint<double>>(&j.constraint)) {
    if (Ja) {
      const auto J = constraints::revoluteAngleJacobians(*rev, a, b);
      (*Ja)[0] = J[0];
      (*Jb)[0] = J[1];
    }
    (*phi)[0] = constraints::revoluteAngle(*rev, a, b, y.angles[angleSlot(k, 0)]);
    return 1;
  }
  const constraints::PrismaticJoint<double>* pri = std::get_if<constraints::PrismaticJoint<double>>(&j.constraint);
  if (!pri) pri = std::get_if<constraints::FixedJoint<double>>(&j.constraint);  // its held slide
  if (pri) {
    const auto x = pri->position();
    if (Ja) {
      const auto J = x.jacobians(a, b);
      (*Ja)[0] = J[0];
      (*Jb)[0] = J[1];
    }
    (*phi)[0] = x.value(a, b);
    return 1;
  }
  if (const auto* gim = std::get_if<constraints::GimbalJoint<double>>(&j.constraint)) {
    const auto ang = constraints::gimbalAngles(*gim, a, b, gimbalPrevious(y, k));
    if (Ja) {
      const auto J = constraints::gimbalAngleJacobians(*gim, a, b, ang.phi);
      for (int i = 0; i < 3; ++i) {
        (*Ja)[i] = J[0].row(i);
        (*Jb)[i] = J[1].row(i);
      }
    }
    for (int i = 0; i < 3; ++i) (*phi)[i] = ang.phi[i];
    return 3;
  }
  const auto& uni = *universalOf(j.constraint);
  if (Ja) {
    const auto J = constraints::universalAngleJacobians(uni, a, b);
    for (int i = 0; i < 2; ++i) {
      (*Ja)[i] = J[0].row(i);
      (*Jb)[i] = J[1].row(i);
    }
  }
  const auto ang = constraints::universalAngles(uni, a, b, y.angles[angleSlot(k, 0)], y.angles[angleSlot(k, 1)]);
  (*phi)[0] = ang.phi1;
  (*phi)[1] = ang.phi2;
  return 2;
}

std::array<double, 3> MultibodySystem::gimbalPrevious(const State& y, int k) const {
  return {{y.angles[angleSlot(k, 0)], y.angles[angleSlot(k, 1)], y.angles[angleSlot(k, 2)]}};
}

double MultibodySystem::coordinateRate(const State& y, int main, int secondary, const Row6& Ja,
                                       const Row6& Jb) const {
  // A rotation-only body's δp columns have no coordinates (its v is 0).
  auto part = [&](int body, const Row6& J) {
    if (body == kGround) return 0.0;
    const BodyVelocity<double>& u = y.bodies.velocities[body];
    return J.tail<3>().dot(u.omega) + (rot_[body] ? 0.0 : J.head<3>().dot(u.v));
  };
  return part(main, Ja) + part(secondary, Jb);
}

void MultibodySystem::addCoordinateForce(int body, const Row6& J, double M, Eigen::VectorXd* F) const {
  if (body == kGround) return;
  if (rot_[body])
    F->segment<3>(off_[body]) += J.tail<3>().transpose() * M;
  else
    F->segment<6>(off_[body]) += J.transpose() * M;
}

double MultibodySystem::coordinateConvective(const State& y, int k, int i) const {
  const Joint& j = model_.joints[k];
  BodyPose<double> a, b;
  BodyVelocity<double> va, vb;
  poses(y, j.main, j.secondary, &a, &b, &va, &vb);
  if (const auto* rev = std::get_if<constraints::RevoluteJoint<double>>(&j.constraint))
    return constraints::revoluteAngleConvective(*rev, a, b, va, vb);
  if (const auto* pri = std::get_if<constraints::PrismaticJoint<double>>(&j.constraint))
    return pri->position().convective(a, b, va, vb);
  if (const auto* fix = std::get_if<constraints::FixedJoint<double>>(&j.constraint))
    return fix->position().convective(a, b, va, vb);
  // Only prescribed coordinates need it; validate() refuses prescribed gimbal angles.
  LIEFLOW_ASSERT(universalOf(j.constraint) != nullptr, "coordinateConvective: a coordinate without a convective term");
  const auto& uni = *universalOf(j.constraint);
  return constraints::universalAngleConvective(uni, a, b, va, vb)[i];
}

void MultibodySystem::rebaseAngles(State* y) const {
  for (std::size_t k = 0; k < model_.joints.size(); ++k) {
    const int nc = coordinateCount(static_cast<int>(k));
    if (nc == 0) continue;
    const Joint& j = model_.joints[k];
    BodyPose<double> a, b;
    poses(*y, j.main, j.secondary, &a, &b, nullptr, nullptr);
    if (const auto* pri = std::get_if<constraints::PrismaticJoint<double>>(&j.constraint)) {
      y->angles[angleSlot(static_cast<int>(k), 0)] = pri->position().value(a, b);  // a length: nothing to unwrap
    } else if (const auto* gim = std::get_if<constraints::GimbalJoint<double>>(&j.constraint)) {
      const auto ang = constraints::gimbalAngles(*gim, a, b, gimbalPrevious(*y, static_cast<int>(k)));
      for (int i = 0; i < 3; ++i) y->angles[angleSlot(static_cast<int>(k), i)] = ang.phi[i];
    } else if (nc == 1) {
      y->angles[angleSlot(static_cast<int>(k), 0)] = constraints::revoluteAngle(std::get<constraints::RevoluteJoint<double>>(j.constraint), a,
                                                    b, y->angles[angleSlot(static_cast<int>(k), 0)]);
    } else {
      const auto ang = constraints::universalAngles(*universalOf(j.constraint), a,
                                                    b, y->angles[angleSlot(static_cast<int>(k), 0)], y->angles[angleSlot(static_cast<int>(k), 1)]);
      y->angles[angleSlot(static_cast<int>(k), 0)] = ang.phi1;
      y->angles[angleSlot(static_cast<int>(k), 1)] = ang.phi2;
    }
  }
}

bool MultibodySystem::samePoses(const State& y) const {
  const auto& P = y.bodies.poses;
  if (P.size() != data_.factor_cache.poses.size()) return false;
  for (std::size_t i = 0; i < P.size(); ++i)
    if (P[i].p != data_.factor_cache.poses[i].p ||
        P[i].R.quaternion().coeffs() != data_.factor_cache.poses[i].R.quaternion().coeffs())
      return false;
  return true;
}

}  // namespace multibody
}  // namespace lieflow
