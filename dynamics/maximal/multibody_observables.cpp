// MultibodySystem: energy, angular momentum and the joint outputs.
#include "dynamics/maximal/multibody_system.hpp"

#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

namespace lieflow {
namespace multibody {

using constraints::BodyPose;
using constraints::BodyVelocity;
using Row6 = Eigen::Matrix<double, 1, 6>;

// --- Observables ---------------------------------------------------------------

std::pair<double, double> MultibodySystem::energyAndTermScale(const State& y) const {
  double E = 0.0, S = 0.0;  // the energy and its terms' magnitudes
  for (int i = 0; i < bodyCount(); ++i) {
    const RigidBody& b = model_.bodies[i];
    const Eigen::Vector3d& w = y.bodies.velocities[i].omega;
    const double rotation = 0.5 * w.dot(b.inertia * w);
    E += rotation;
    S += rotation;
    if (!rot_[i]) {
      const Eigen::Vector3d& p = y.bodies.poses[i].p;
      const double translation = 0.5 * b.mass * y.bodies.velocities[i].v.squaredNorm();
      E += translation - b.mass * model_.gravity.dot(p);
      S += translation + b.mass * model_.gravity.norm() * p.norm();
    }
  }
  for (std::size_t k = 0; k < model_.joints.size(); ++k)
    for (int i = 0; i < coordinateCount(static_cast<int>(k)); ++i) {
      const CoordinateDrive& d = drives_[k][i];
      if (d.stiffness == 0.0) continue;
      const double e = y.angles[angleSlot(static_cast<int>(k), i)] - d.rest_angle;
      E += 0.5 * d.stiffness * e * e;
      S += 0.5 * d.stiffness * e * e;
    }
  return {E, S};
}

double MultibodySystem::energy(const State& y) const { return energyAndTermScale(y).first; }

double MultibodySystem::energyTermScale(const State& y) const { return energyAndTermScale(y).second; }

Eigen::Vector3d MultibodySystem::angularMomentum(const State& y) const {
  return momentumAbout(y, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
}

Eigen::Vector3d MultibodySystem::momentumAbout(const State& y, const Eigen::Vector3d& point,
                                               const Eigen::Vector3d& velocity) const {
  Eigen::Vector3d L = Eigen::Vector3d::Zero();
  for (int i = 0; i < bodyCount(); ++i) {
    const RigidBody& b = model_.bodies[i];
    const auto& P = y.bodies.poses[i];
    const auto& V = y.bodies.velocities[i];
    L += P.R * (b.inertia * V.omega);
    if (!rot_[i]) L += (P.p - point).cross(b.mass * (V.v - velocity));
  }
  return L;
}

bool MultibodySystem::conservesAngularMomentum() const {
  // External moments about the origin come from gravity (unless every body
  // is rotation-only, held at its centre of mass), from the ground side of
  // joints and gears, and from the supports of rotation-only bodies whenever
  // a joint passes a force to them (its point rows are imposed). Joint
  // springs, dashpots, applied moments and prescribed motion between two
  // bodies act in equal and opposite pairs.
  if (hasUserTorques()) return false;  // a program's torques on bodies are external
  bool all_rotation_only = true;
  for (int i = 0; i < bodyCount(); ++i) all_rotation_only = all_rotation_only && rot_[i];
  if (model_.gravity.squaredNorm() != 0.0 && !all_rotation_only) return false;
  for (std::size_t k = 0; k < model_.joints.size(); ++k) {
    const Joint& j = model_.joints[k];
    if (j.main == kGround || j.secondary == kGround) return false;
    if ((rot_[j.main] || rot_[j.secondary]) && skip_rows_[k] != 3) return false;
  }
  for (const Gear& g : gears_)
    for (int b : g.bodies)
      if (b == kGround || rot_[b]) return false;
  return true;
}

Eigen::Vector3d MultibodySystem::centreOfMassMomentum(const State& y) const {
  double mass = 0.0;
  Eigen::Vector3d mc = Eigen::Vector3d::Zero(), mv = Eigen::Vector3d::Zero();
  for (int i = 0; i < bodyCount(); ++i) {
    if (rot_[i]) continue;
    const double m = model_.bodies[i].mass;
    mass += m;
    mc += m * y.bodies.poses[i].p;
    mv += m * y.bodies.velocities[i].v;
  }
  if (!(mass > 0.0)) return angularMomentum(y);
  return momentumAbout(y, mc / mass, mv / mass);
}

bool MultibodySystem::conservesCentreOfMassMomentum() const {
  if (hasUserTorques()) return false;
  for (int i = 0; i < bodyCount(); ++i)
    if (rot_[i]) return false;  // held at its centre: the support is an external force
  for (const Joint& j : model_.joints)
    if (j.main == kGround || j.secondary == kGround) return false;
  for (const Gear& g : gears_)
    for (int b : g.bodies)
      if (b == kGround) return false;
  return true;
}

double MultibodySystem::dissipatedPower(const State& y) const {
  double P = 0.0;
  for (std::size_t k = 0; k < model_.joints.size(); ++k) {
    const Joint& j = model_.joints[k];
    const int nc = coordinateCount(static_cast<int>(k));
    bool any = false;
    for (int i = 0; i < nc; ++i) any = any || drives_[k][i].damping != 0.0;
    if (!any) continue;
    std::array<double, kMaxJointCoordinates> phi;
    CoordinateRows Ja, Jb;
    coordinates(y, static_cast<int>(k), &phi, &Ja, &Jb);
    for (int i = 0; i < nc; ++i) {
      const double phidot = coordinateRate(y, j.main, j.secondary, Ja[i], Jb[i]);
      P += drives_[k][i].damping * phidot * phidot;
    }
  }
  return P;
}

bool MultibodySystem::conservesEnergyBalance() const { return hasDampers() && autonomous(); }

std::vector<JointOutput> MultibodySystem::jointOutputs(double t, const State& y) const {
  const int nj = static_cast<int>(model_.joints.size());
  std::vector<JointOutput> out(nj);
  bool any = false;
  for (int k = 0; k < nj; ++k) {
    out[k].kind = jointKind(model_.joints[k].constraint);
    out[k].coordinates = coordinateCount(k);
    any = any || out[k].coordinates > 0 || out[k].kind == JointKind::kFixed;
  }
  if (!any) return out;
  Eigen::VectorXd udot, lambda;
  std::string why;
  const bool solved = hasConstraints() && accelerations(t, y, &udot, &lambda, &why);
  SchurSolver& S = data_.all;
  // Prescribed row of (k, i), or −1.
  auto prescribedRow = [&](int k, int i) {
    int g = nj;
    for (const CoordinateRef& p : prescribed_) {
      if (p.joint == k && p.coordinate == i) return S.rowBegin(g);
      ++g;
    }
    return -1;
  };
  for (int k = 0; k < nj; ++k) {
    JointOutput& o = out[k];
    const Joint& j = model_.joints[k];
    BodyPose<double> pa, pb;
    BodyVelocity<double> va, vb;
    poses(y, j.main, j.secondary, &pa, &pb, &va, &vb);
    if (o.kind == JointKind::kFixed) {
      // The reaction on the secondary body (or minus that on the main body
      // when the secondary is ground): −J_sᵀ λ, a force (world) and a moment
      // (body frame, about its centre of mass), moved to the anchor and
      // turned into the main body's frame.
      if (!solved) continue;
      const bool on_secondary = j.secondary != kGround;
      const BodyPose<double>& P = on_secondary ? pb : pa;
      Eigen::Matrix<double, 6, 1> g =
          -S.block(k, on_secondary ? 1 : 0).transpose() * lambda.segment(S.rowBegin(k), S.groupRows(k));
      // The held slide's row (constraints/fixed.hpp), as a prescribed one.
      Row6 Ja, Jb;
      coordinate(y, k, 0, &Ja, &Jb);
      g -= (on_secondary ? Jb : Ja).transpose() * lambda[prescribedRow(k, 0)];
      const Eigen::Vector3d anchor = pa.toWorld(jointAnchors(j.constraint).first);
      const Eigen::Vector3d moment = P.R * g.tail<3>() - (anchor - P.p).cross(g.head<3>());
      const double sign = on_secondary ? 1.0 : -1.0;
      o.reaction << sign * (pa.R.inverse() * g.head<3>()), sign * (pa.R.inverse() * moment);
      continue;
    }
    if (o.coordinates == 0) continue;
    // Generalized force (f world, τ body) of the joint on the main body (or on
    // the secondary when main is ground, negated at the end).
    const bool use_main = j.main != kGround;
    const BodyPose<double>& P = use_main ? pa : pb;
    Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
    if (solved) g -= S.block(k, use_main ? 0 : 1).transpose() * lambda.segment(S.rowBegin(k), S.groupRows(k));
    // Each axis as a line: its direction and a point (a universal joint's
    // second axis passes through the secondary anchor, apart from the first
    // for an offset universal joint).
    std::array<Eigen::Vector3d, kMaxJointCoordinates> axes, anchors;
    if (const auto* rev = std::get_if<constraints::RevoluteJoint<double>>(&j.constraint)) {
      axes[0] = pa.R * rev->axis_main;
      anchors[0] = pa.toWorld(rev->point.anchor_main);
    } else if (const auto* pri = std::get_if<constraints::PrismaticJoint<double>>(&j.constraint)) {
      axes[0] = pa.R * pri->axis_main;
      anchors[0] = pa.toWorld(pri->anchor_main);
    } else if (const auto* gim = std::get_if<constraints::GimbalJoint<double>>(&j.constraint)) {
      // The hinge lines now: e₁, R₁ e₂, R₁ R₂ e₃ (main frame), through the point.
      const auto ang = constraints::gimbalAngles(*gim, pa, pb, gimbalPrevious(y, k));
      const SO3d R1 = SO3d::exp(ang.phi[0] * gim->axes[0]), R2 = SO3d::exp(ang.phi[1] * gim->axes[1]);
      axes = {{pa.R * gim->axes[0], pa.R * (R1 * gim->axes[1]), pa.R * (R1 * (R2 * gim->axes[2]))}};
      anchors.fill(pa.toWorld(gim->point.anchor_main));
      o.condition = ang.condition;
    } else {
      const auto& uni = *universalOf(j.constraint);
      axes[0] = pa.R * uni.axis1_main;
      axes[1] = pb.R * uni.axis2_secondary;
      anchors[0] = pa.toWorld(uni.point.anchor_main);
      anchors[1] = pb.toWorld(uni.point.anchor_secondary);
      o.condition = constraints::universalAngles(uni, pa, pb).condition;
    }
    std::array<double, kMaxJointCoordinates> phis;
    CoordinateRows Jas, Jbs;
    coordinates(y, k, &phis, &Jas, &Jbs);
    for (int i = 0; i < o.coordinates; ++i) {
      const Row6& Ja = Jas[i];
      const Row6& Jb = Jbs[i];
      o.phi[i] = phis[i];
      o.phidot[i] = coordinateRate(y, j.main, j.secondary, Ja, Jb);
      const Row6& Jside = use_main ? Ja : Jb;
      const CoordinateDrive& d = drives_[k][i];
      double M = 0.0;
      if (d.hasForce()) M = d.momentAt(t, o.phi[i], o.phidot[i]);
      const int pr = prescribedRow(k, i);
      if (solved && pr >= 0) M -= lambda[pr];
      g += Jside.transpose() * M;
    }
    const double sign = use_main ? 1.0 : -1.0;
    if (o.kind == JointKind::kPrismatic) {
      o.moment[0] = sign * g.head<3>().dot(axes[0]);  // the force along the axis
      continue;
    }
    for (int i = 0; i < o.coordinates; ++i) {
      const Eigen::Vector3d moment = P.R * g.tail<3>() - (anchors[i] - P.p).cross(g.head<3>());
      o.moment[i] = sign * moment.dot(axes[i]);
    }
  }
  return out;
}

}  // namespace multibody
}  // namespace lieflow
