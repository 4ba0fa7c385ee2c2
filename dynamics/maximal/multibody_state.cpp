// The group state of a MultibodySystem: ⊕, dexp⁻¹, velocities in and out.
#include "dynamics/maximal/multibody_system.hpp"

#include <cmath>
#include <limits>
#include <sstream>

#include "integrators/rigid_body_state.hpp"

namespace lieflow {
namespace multibody {

using constraints::BodyPose;
using constraints::BodyVelocity;
using Row6 = Eigen::Matrix<double, 1, 6>;

// --- State -------------------------------------------------------------------

MultibodyGroupState::Tangent MultibodyGroupState::zeroTangent() const {
  return Tangent::Zero(2 * system->dofs());
}

int MultibodyGroupState::tangentSize() const { return 2 * system->dofs(); }

MultibodyGroupState MultibodyGroupState::rplus(const Tangent& d) const {
  MultibodyGroupState out = *this;
  out.rplusInPlace(d);
  return out;
}

void MultibodyGroupState::rplusInPlace(const Tangent& d) {
  const int n = system->dofs();
  for (int i = 0; i < system->bodyCount(); ++i) {
    const int o = system->dofBegin(i);
    BodyPose<double>& P = bodies.poses[i];
    BodyVelocity<double>& V = bodies.velocities[i];
    if (system->rotationOnly(i)) {
      P.R = P.R * SO3d::exp(d.segment<3>(o));
      V.omega += d.segment<3>(n + o);
    } else {
      P.p += d.segment<3>(o);
      P.R = P.R * SO3d::exp(d.segment<3>(o + 3));
      V.v += d.segment<3>(n + o);
      V.omega += d.segment<3>(n + o + 3);
    }
  }
  system->rebaseAngles(this);
}

MultibodyGroupState::Tangent MultibodyGroupState::dexpInvRight(const Tangent& theta, const Tangent& v,
                                                               int order) const {
  Tangent out;
  dexpInvRightInto(theta, v, order, &out);
  return out;
}

void MultibodyGroupState::dexpInvRightInto(const Tangent& theta, const Tangent& v, int order, Tangent* out) const {
  *out = v;
  for (int i = 0; i < system->bodyCount(); ++i) {
    const int o = system->dofBegin(i) + (system->rotationOnly(i) ? 0 : 3);
    out->segment<3>(o) = detail::so3DexpInvRight<double>(theta.segment<3>(o), v.segment<3>(o), order);
  }
}

MultibodyGroupState::Tangent MultibodyGroupState::magnitude() const {
  const int n = system->dofs();
  Tangent m(2 * n);
  m.head(n).setOnes();
  m.tail(n) = velocities().cwiseAbs();
  return m;
}

Eigen::VectorXd MultibodyGroupState::velocities() const {
  Eigen::VectorXd u;
  velocitiesInto(&u);
  return u;
}

void MultibodyGroupState::velocitiesInto(Eigen::VectorXd* out) const {
  Eigen::VectorXd& u = *out;
  u.resize(system->dofs());
  for (int i = 0; i < system->bodyCount(); ++i) {
    const int o = system->dofBegin(i);
    if (system->rotationOnly(i)) {
      u.segment<3>(o) = bodies.velocities[i].omega;
    } else {
      u.segment<3>(o) = bodies.velocities[i].v;
      u.segment<3>(o + 3) = bodies.velocities[i].omega;
    }
  }
}

void MultibodyGroupState::setVelocities(const Eigen::VectorXd& u) {
  for (int i = 0; i < system->bodyCount(); ++i) {
    const int o = system->dofBegin(i);
    if (system->rotationOnly(i)) {
      bodies.velocities[i].omega = u.segment<3>(o);
    } else {
      bodies.velocities[i].v = u.segment<3>(o);
      bodies.velocities[i].omega = u.segment<3>(o + 3);
    }
  }
}

bool isFinite(const MultibodyGroupState& y) {
  for (std::size_t i = 0; i < y.bodies.poses.size(); ++i) {
    if (!y.bodies.poses[i].p.allFinite() || !y.bodies.poses[i].R.quaternion().coeffs().allFinite() ||
        !y.bodies.velocities[i].v.allFinite() || !y.bodies.velocities[i].omega.allFinite())
      return false;
  }
  return true;
}

}  // namespace multibody
}  // namespace lieflow
