/// \file
/// The spherical joint (ball joint): the anchor s_a fixed in the main body and
/// the anchor s_b fixed in the secondary body coincide,
///
///   Φ(a, b) = p_a + R_a s_a − p_b − R_b s_b = 0          (3 rows).
///
/// With the perturbations of body_pose.hpp, δ(R s) = R (δθ × s) = −R ŝ δθ, so
///   J_a = [ I   −R_a ŝ_a ],    J_b = [ −I   R_b ŝ_b ]
/// (the spherical joint of Haug 1989, "Computer-Aided Kinematics and Dynamics
/// of Mechanical Systems", ch. 9, written for body-frame rotation perturbations).
/// Velocity form: Φ̇ = v_a + R_a(ω_a × s_a) − v_b − R_b(ω_b × s_b) = J_a (v_a, ω_a) + J_b (v_b, ω_b).
/// Acceleration form: Φ̈ = J_a (v̇_a, ω̇_a) + J_b (v̇_b, ω̇_b) + c with the convective term
///   c = d/dt(J) q̇ = R_a (ω_a × (ω_a × s_a)) − R_b (ω_b × (ω_b × s_b))
/// (the centripetal accelerations of the two anchors).
///
/// Convention of every convective term in dynamics/constraints/: c is the part
/// of Φ̈ (or of d/dt of a velocity-level row B q̇) that does not depend on the
/// accelerations, so the acceleration-level constraint reads J q̈ = −c.
#pragma once

#include <string>

#include "dynamics/constraints/body_pose.hpp"
#include "dynamics/constraints/validation.hpp"

namespace lieflow {
namespace constraints {

template <typename T>
struct SphericalJoint {
  static constexpr int kRows = 3;
  static constexpr int kPointRows = 3;  ///< all its rows are the point rows
  using Residual = Eigen::Matrix<T, 3, 1>;
  using Blocks = ConstraintBlocks<T, 3, 2>;

  Vector3<T> anchor_main = Vector3<T>::Zero();       ///< s_a, main body frame
  Vector3<T> anchor_secondary = Vector3<T>::Zero();  ///< s_b, secondary body frame

  /// Φ = p_a + R_a s_a − p_b − R_b s_b.
  Residual residual(const BodyPose<T>& a, const BodyPose<T>& b) const {
    return a.toWorld(anchor_main) - b.toWorld(anchor_secondary);
  }

  /// {J_a, J_b} = {[I, −R_a ŝ_a], [−I, R_b ŝ_b]}.
  Blocks jacobians(const BodyPose<T>& a, const BodyPose<T>& b) const {
    Blocks J;
    J[0].template leftCols<3>().setIdentity();
    J[0].template rightCols<3>() = -(a.R.matrix() * SO3<T>::hat(anchor_main));
    J[1].template leftCols<3>() = -Matrix3<T>::Identity();
    J[1].template rightCols<3>() = b.R.matrix() * SO3<T>::hat(anchor_secondary);
    return J;
  }

  /// Φ̇ = J_a (v_a, ω_a) + J_b (v_b, ω_b).
  Residual velocity(const BodyPose<T>& a, const BodyPose<T>& b, const BodyVelocity<T>& va,
                    const BodyVelocity<T>& vb) const {
    return applyBlocks<T, 3, 2>(jacobians(a, b), {va, vb});
  }

  /// c = R_a (ω_a × (ω_a × s_a)) − R_b (ω_b × (ω_b × s_b)).
  Residual convective(const BodyPose<T>& a, const BodyPose<T>& b, const BodyVelocity<T>& va,
                      const BodyVelocity<T>& vb) const {
    const Vector3<T> ca = va.omega.cross(va.omega.cross(anchor_main));
    const Vector3<T> cb = vb.omega.cross(vb.omega.cross(anchor_secondary));
    return a.R * ca - b.R * cb;
  }
};

/// A spherical joint with anchors checked finite; fields "PREFIX.anchor_main",
/// "PREFIX.anchor_secondary".
template <typename T>
SphericalJoint<T> makeSphericalJoint(const Vector3<T>& anchor_main, const Vector3<T>& anchor_secondary,
                                     const std::string& prefix = "") {
  checkFinite(anchor_main, fieldName(prefix, "anchor_main"));
  checkFinite(anchor_secondary, fieldName(prefix, "anchor_secondary"));
  return SphericalJoint<T>{anchor_main, anchor_secondary};
}

}  // namespace constraints
}  // namespace lieflow
