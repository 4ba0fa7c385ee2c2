/// \file
/// The state a MultibodySystem is stepped on (multibody_system.hpp): the
/// bodies' poses and velocities on the product of their groups, with the
/// unwrapped joint coordinates. Implemented in multibody_state.cpp.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "dynamics/maximal/multibody_model.hpp"

namespace lieflow {
namespace multibody {

class MultibodySystem;

/// The state on Π_i (SO(3) × ℝ³ × ℝ³ × ℝ³ or SO(3) × ℝ³): body poses and
/// velocities, plus the unwrapped joint coordinates (kMaxJointCoordinates
/// slots per joint).
/// Tangent (size 2n, n = Σ dofs): first the position increments per body in
/// body order ((δp world, δθ body) or δθ), then the velocity increments
/// ((δv, δω) or δω). ⊕ is right multiplication by exp on each SO(3) and
/// addition elsewhere; dexp⁻¹ acts blockwise on the δθ blocks.
struct MultibodyGroupState {
  using Scalar = double;
  using Tangent = Eigen::VectorXd;

  MultibodyState bodies;
  std::vector<double> angles;  ///< unwrapped φ (angleSlot(k, i) for coordinate i of joint k)
  const MultibodySystem* system = nullptr;

  Tangent zeroTangent() const;
  /// 2 · dofs (δq then δu).
  int tangentSize() const;
  MultibodyGroupState rplus(const Tangent& d) const;
  /// *this = rplus(d) without allocating (integrators/state_workspace.hpp).
  void rplusInPlace(const Tangent& d);
  /// Right-trivialized dexp⁻¹ blockwise (so(3) series on the δθ blocks).
  Tangent dexpInvRight(const Tangent& theta, const Tangent& v, int order) const;
  /// *out = dexpInvRight(theta, v, order); out must not alias theta or v.
  void dexpInvRightInto(const Tangent& theta, const Tangent& v, int order, Tangent* out) const;
  /// Per-component size for error control: 1 for positions, |u| for velocities.
  Tangent magnitude() const;
  /// The stacked body velocities u (size n).
  Eigen::VectorXd velocities() const;
  /// The same into *out (resized; no allocation when it has the size).
  void velocitiesInto(Eigen::VectorXd* out) const;
  void setVelocities(const Eigen::VectorXd& u);
};

bool isFinite(const MultibodyGroupState& y);

}  // namespace multibody
}  // namespace lieflow
