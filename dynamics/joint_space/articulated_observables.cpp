// ArticulatedSystem: body poses and velocities, energy, angular momentum and
// the joint outputs.
#include "dynamics/joint_space/articulated_system.hpp"

#include <cmath>
#include <utility>

namespace lieflow {
namespace articulated {

void ArticulatedSystem::kinematics(double t, const State& y) const { forwardPass(t, y, false, true); }

std::pair<double, double> ArticulatedSystem::energyAndTermScale(double t, const State& y) const {
  kinematics(t, y);
  double E = 0.0, S = 0.0;  // the energy and its terms' magnitudes
  for (int i = 0; i < bodyCount(); ++i) {
    const ArticulatedBody& b = model_.bodies[i];
    const Eigen::Vector3d w = angularVelocityBody(i);
    const double rotation = 0.5 * w.dot(b.inertia * w);
    E += rotation;
    S += rotation;
    // A rotation-only body has no translational energy (as in the maximal formulation).
    if (!b.rotation_only) {
      const Eigen::Vector3d& c = data_.bodies[i].c;
      const double translation = 0.5 * b.mass * velocityOfCentre(i).squaredNorm();
      E += translation - b.mass * model_.gravity.dot(c);
      S += translation + b.mass * model_.gravity.norm() * c.norm();
    }
    for (int k = 0; k < b.coordinates(); ++k) {
      const CoordinateDrive& drive = model_.drives[i][k];
      if (drive.stiffness == 0.0) continue;
      const double e = data_.bodies[i].phi[k] - drive.rest_angle;
      E += 0.5 * drive.stiffness * e * e;
      S += 0.5 * drive.stiffness * e * e;
    }
  }
  return {E, S};
}

double ArticulatedSystem::energy(double t, const State& y) const { return energyAndTermScale(t, y).first; }

double ArticulatedSystem::energyTermScale(double t, const State& y) const { return energyAndTermScale(t, y).second; }

Eigen::Vector3d ArticulatedSystem::angularMomentum(double t, const State& y) const {
  kinematics(t, y);
  Eigen::Vector3d L = Eigen::Vector3d::Zero();
  for (int i = 0; i < bodyCount(); ++i) {
    const ArticulatedBody& b = model_.bodies[i];
    L += data_.bodies[i].R * (b.inertia * angularVelocityBody(i));
    if (!b.rotation_only) L += data_.bodies[i].c.cross(b.mass * velocityOfCentre(i));
  }
  return L;
}

Eigen::Vector3d ArticulatedSystem::centreOfMassMomentum(double t, const State& y) const {
  kinematics(t, y);
  double mass = 0.0;
  Eigen::Vector3d mc = Eigen::Vector3d::Zero(), mv = Eigen::Vector3d::Zero();
  for (int i = 0; i < bodyCount(); ++i) {
    const ArticulatedBody& b = model_.bodies[i];
    if (b.rotation_only) continue;
    mass += b.mass;
    mc += b.mass * data_.bodies[i].c;
    mv += b.mass * velocityOfCentre(i);
  }
  const Eigen::Vector3d c = mass > 0.0 ? Eigen::Vector3d(mc / mass) : Eigen::Vector3d::Zero();
  const Eigen::Vector3d vc = mass > 0.0 ? Eigen::Vector3d(mv / mass) : Eigen::Vector3d::Zero();
  Eigen::Vector3d L = Eigen::Vector3d::Zero();
  for (int i = 0; i < bodyCount(); ++i) {
    const ArticulatedBody& b = model_.bodies[i];
    L += data_.bodies[i].R * (b.inertia * angularVelocityBody(i));
    if (!b.rotation_only) L += (data_.bodies[i].c - c).cross(b.mass * (velocityOfCentre(i) - vc));
  }
  return L;
}

double ArticulatedSystem::dissipatedPower(double t, const State& y) const {
  kinematics(t, y);
  double P = 0.0;
  for (int i = 0; i < bodyCount(); ++i)
    for (int k = 0; k < model_.bodies[i].coordinates(); ++k) {
      const double c = model_.drives[i][k].damping;
      P += c * data_.bodies[i].phidot[k] * data_.bodies[i].phidot[k];
    }
  return P;
}

void ArticulatedSystem::jointOutputs(double t, const State& y, std::vector<ArticulatedJointOutput>* out) const {
  accelerations(t, y, &data_.udot);
  if (hasClosures()) {
    // The ABA again with the loops' forces among the external ones: its
    // transmitted forces (below) then include them.
    forwardPass(t, y, true, true);
    applyClosureForces();
    solve(Vector6::Zero(), &data_.udot);
  }
  out->assign(model_.scene_joints, ArticulatedJointOutput());
  for (int i = 0; i < bodyCount(); ++i) {
    const ArticulatedBody& b = model_.bodies[i];
    const BodyData& d = data_.bodies[i];
    if (b.scene_joint < 0) continue;
    ArticulatedJointOutput& o = (*out)[b.scene_joint];
    o.coordinates = b.coordinates();
    if (o.coordinates == 0 && b.kind != JointKind::kFixed) continue;
    // The spatial force the parent passes to the child's subtree,
    // f = I_A a + p_A (Featherstone 2008, §7.3), as a moment about the anchor
    // (about the held centre of mass of a rotation-only child: its support
    // takes the force).
    const Vector6 f = d.IA * d.a + d.pA;
    if (b.kind == JointKind::kFixed) {
      // A weld: the force on the secondary body (the child's, or minus it
      // when the child is the main body) and its moment about the anchor, in
      // the main body's axes, as multibody_observables.cpp reports it.
      const double sign = b.parent_is_main ? 1.0 : -1.0;
      Eigen::Matrix3d R_main = d.R;
      if (b.parent_is_main) R_main = b.parent == kGround ? Eigen::Matrix3d::Identity() : data_.bodies[b.parent].R;
      const Eigen::Vector3d force = sign * (R_main.transpose() * f.tail<3>());
      const Eigen::Vector3d moment = sign * (R_main.transpose() * (f.head<3>() - d.x.cross(f.tail<3>())));
      o.welded = true;
      o.reaction = {{force.x(), force.y(), force.z(), moment.x(), moment.y(), moment.z()}};
      continue;
    }
    const Eigen::Vector3d& point = b.rotation_only ? d.c : d.x;
    const Eigen::Vector3d moment_on_child = f.head<3>() - point.cross(f.tail<3>());
    // On the main body: −(that) when the child is the secondary.
    const Eigen::Vector3d on_main = b.parent_is_main ? Eigen::Vector3d(-moment_on_child) : moment_on_child;
    // A slide's force along its axis on the main body, as the maximal
    // formulation's J.force.
    const Eigen::Vector3d force_on_main = b.parent_is_main ? Eigen::Vector3d(-f.tail<3>()) : Eigen::Vector3d(f.tail<3>());
    for (int k = 0; k < o.coordinates; ++k) {
      o.phi[k] = d.phi[k];
      o.phidot[k] = d.phidot[k];
      o.moment[k] = (b.kind == JointKind::kPrismatic ? force_on_main : on_main).dot(d.axis[k]);
    }
    if (b.offset) {
      // The second hinge passes through the secondary anchor: its moment is
      // about that line.
      const Eigen::Vector3d about_x2 = f.head<3>() - d.x2.cross(f.tail<3>());
      o.moment[1] = -about_x2.dot(d.axis[1]);  // on the main body (the parent)
    }
  }
  if (hasClosures()) closureOutputs(t, out);
}

}  // namespace articulated
}  // namespace lieflow
