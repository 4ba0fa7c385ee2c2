/// \file
/// The "dot-1" constraint row of two body-fixed directions (Haug 1989,
/// "Computer-Aided Kinematics and Dynamics of Mechanical Systems", ch. 9;
/// Nikravesh 1988, "Computer-Aided Analysis of Mechanical Systems"): u fixed in the main body, w fixed in the secondary body,
///
///   Φ = U · W,   U = R_a u,  W = R_b w            (1 row).
///
/// It is the building block of the revolute (two rows) and universal (one row)
/// joints. With δ(R u) = (R δθ) × (R u) and n = U × W (world):
///   δΦ = n · (R_a δθ_a − R_b δθ_b),
///   J_a = [ 0   (R_aᵀ n)ᵀ ],   J_b = [ 0   −(R_bᵀ n)ᵀ ].
/// Velocity form: Φ̇ = n · (Ω_a − Ω_b), Ω = R ω the world angular velocities
/// (the same blocks applied to (v, ω)).
/// Convective term (U̇ = Ω_a × U, Ü = Ω̇_a × U + Ω_a × (Ω_a × U), Ω̇ = R ω̇):
///   c = (Ω_a × (Ω_a × U))·W + 2 (Ω_a × U)·(Ω_b × W) + U·(Ω_b × (Ω_b × W)).
/// The Jacobian is regular (‖n‖ = 1) wherever U ⟂ W, i.e. on the constraint
/// manifold when u, w are unit.
#pragma once

#include "dynamics/constraints/body_pose.hpp"

namespace lieflow {
namespace constraints {

template <typename T>
struct DotRow {
  Vector3<T> u_main;       ///< u, main body frame
  Vector3<T> w_secondary;  ///< w, secondary body frame

  T value(const BodyPose<T>& a, const BodyPose<T>& b) const {
    return (a.R * u_main).dot(b.R * w_secondary);
  }

  /// {J_a, J_b} (1 × 6 each; translation columns zero).
  ConstraintBlocks<T, 1, 2> jacobians(const BodyPose<T>& a, const BodyPose<T>& b) const {
    const Vector3<T> n = (a.R * u_main).cross(b.R * w_secondary);
    ConstraintBlocks<T, 1, 2> J;
    J[0].setZero();
    J[1].setZero();
    J[0].template rightCols<3>() = (a.R.inverse() * n).transpose();
    J[1].template rightCols<3>() = -(b.R.inverse() * n).transpose();
    return J;
  }

  /// c = (Ω_a×(Ω_a×U))·W + 2(Ω_a×U)·(Ω_b×W) + U·(Ω_b×(Ω_b×W)).
  T convective(const BodyPose<T>& a, const BodyPose<T>& b, const BodyVelocity<T>& va,
               const BodyVelocity<T>& vb) const {
    const Vector3<T> U = a.R * u_main;
    const Vector3<T> W = b.R * w_secondary;
    const Vector3<T> Oa = va.omegaWorld(a);
    const Vector3<T> Ob = vb.omegaWorld(b);
    const Vector3<T> Ud = Oa.cross(U);
    const Vector3<T> Wd = Ob.cross(W);
    return Oa.cross(Ud).dot(W) + T(2) * Ud.dot(Wd) + U.dot(Ob.cross(Wd));
  }
};

}  // namespace constraints
}  // namespace lieflow
