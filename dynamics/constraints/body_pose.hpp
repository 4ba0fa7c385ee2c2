/// \file
/// Body coordinates of the maximal-coordinate constraint library: a body's
/// pose (R, p), its velocity (v, ω), the ground, and the per-body Jacobian
/// blocks every constraint of dynamics/constraints/ returns.
///
/// Conventions (README "Conventions"):
///  * R ∈ SO(3) maps body vectors to the world (x_world = R x_body + p), p is
///    the centre of mass in the world frame;
///  * perturbations are on the right for the rotation and additive for the
///    position: (R, p) ⊕ (δp, δθ) = (R exp(δθ), p + δp), δθ in the BODY frame;
///  * velocities are the matching tangent vectors: v = ṗ (world) and the body
///    angular velocity ω (Ṙ = R ω^); accelerations are (v̇, ω̇);
///  * per body the tangent ordering is (δp, δθ) — translation first, as SE(3)
///    in lieflow — so a constraint block per body is rows × 6.
///
/// Ground is the fixed identity pose (R = I, p = 0, v = ω = 0). It has no
/// coordinates: a constraint to ground is evaluated with groundPose() and
/// groundVelocity() and its ground block is simply dropped.
///
/// Rotation-only bodies (no translational state, p constant) drop the δp
/// columns of their blocks: use rotationColumns(block) (the right 3 columns).
#pragma once

#include <array>
#include <cstddef>

#include <Eigen/Core>

#include "liegroup/scalar.hpp"
#include "liegroup/so3.hpp"

namespace lieflow {
namespace constraints {

/// A body's pose: orientation R (body → world) and centre of mass p (world).
template <typename T>
struct BodyPose {
  SO3<T> R;
  Vector3<T> p = Vector3<T>::Zero();

  /// x_world = R x_body + p.
  Vector3<T> toWorld(const Vector3<T>& x_body) const { return R * x_body + p; }

  /// (R, p) ⊕ (δp, δθ) = (R exp(δθ), p + δp): the perturbation every Jacobian
  /// of dynamics/constraints/ is taken with respect to.
  BodyPose rplus(const Vector6<T>& delta) const {
    return BodyPose{R * SO3<T>::exp(delta.template tail<3>()), p + delta.template head<3>()};
  }
};

/// A body's velocity: v = ṗ (centre of mass, world frame) and ω (body frame,
/// Ṙ = R ω^). The tangent vector is (v, ω), translation first.
template <typename T>
struct BodyVelocity {
  Vector3<T> v = Vector3<T>::Zero();
  Vector3<T> omega = Vector3<T>::Zero();

  /// (v, ω) stacked, translation first.
  Vector6<T> twist() const {
    Vector6<T> out;
    out << v, omega;
    return out;
  }
  static BodyVelocity fromTwist(const Vector6<T>& twist) {
    return BodyVelocity{twist.template head<3>(), twist.template tail<3>()};
  }
  /// The world-frame angular velocity Ω = R ω.
  Vector3<T> omegaWorld(const BodyPose<T>& pose) const { return pose.R * omega; }
};

/// The ground: identity pose, at rest, no coordinates.
template <typename T>
BodyPose<T> groundPose() {
  return BodyPose<T>{SO3<T>::identity(), Vector3<T>::Zero()};
}
template <typename T>
BodyVelocity<T> groundVelocity() {
  return BodyVelocity<T>{};
}

/// The Jacobian blocks of a constraint, one rows × 6 block per participating
/// body, columns (δp, δθ). Body order: (main, secondary) for the holonomic
/// joints, (carrier, node 1, node 2[, node 3]) for the gear rows.
template <typename T, int Rows, std::size_t Bodies>
using ConstraintBlocks = std::array<Eigen::Matrix<T, Rows, 6>, Bodies>;

/// Σ_k B_k (v_k, ω_k): the velocity form of a constraint with blocks B_k.
template <typename T, int Rows, std::size_t Bodies>
Eigen::Matrix<T, Rows, 1> applyBlocks(const ConstraintBlocks<T, Rows, Bodies>& blocks,
                                      const std::array<BodyVelocity<T>, Bodies>& velocities) {
  Eigen::Matrix<T, Rows, 1> out = Eigen::Matrix<T, Rows, 1>::Zero();
  for (std::size_t k = 0; k < Bodies; ++k)
    out += blocks[k].template leftCols<3>() * velocities[k].v +
           blocks[k].template rightCols<3>() * velocities[k].omega;
  return out;
}

/// The δθ columns of a block: the whole block of a rotation-only body (whose
/// p is constant, so its δp columns are dropped). A view into `block`: keep
/// the block alive while the view is used (or assign it to a Matrix).
template <typename Derived>
auto rotationColumns(const Eigen::MatrixBase<Derived>& block) {
  return block.template rightCols<3>();
}

/// The δp columns of a block (a view, as rotationColumns).
template <typename Derived>
auto translationColumns(const Eigen::MatrixBase<Derived>& block) {
  return block.template leftCols<3>();
}

}  // namespace constraints
}  // namespace lieflow
