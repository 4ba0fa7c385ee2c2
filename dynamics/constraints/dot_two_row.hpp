/// \file
/// The "dot-2" constraint row (Haug 1989, "Computer-Aided Kinematics and
/// Dynamics of Mechanical Systems", §9.2; Nikravesh 1988): a direction u fixed
/// in the main body against the vector between the two anchor points,
///
///   Φ = U · D,   U = R_a u,   D = x_b − x_a,   x_a = p_a + R_a s_a,  x_b = p_b + R_b s_b   (1 row).
///
/// It keeps the secondary's anchor on a plane of the main body (two of them
/// make the slot of a prismatic joint) and, with u the slide axis, it is the
/// prismatic joint's coordinate x itself (prismatic.hpp). With right
/// perturbations R ← R exp(δθ), p ← p + δp (README "Conventions"):
///   δU = R_a (δθ_a × u),  δx_a = δp_a + R_a (δθ_a × s_a),
///   δΦ = −U·δp_a + (u × R_aᵀ(x_b − p_a))·δθ_a + U·δp_b + (s_b × R_bᵀ U)·δθ_b,
/// so J_a = [ −Uᵀ   (u × R_aᵀ(x_b − p_a))ᵀ ],  J_b = [ Uᵀ   (s_b × R_bᵀ U)ᵀ ].
/// Velocity form: Φ̇ = U̇·D + U·Ḋ with U̇ = Ω_a × U and
/// Ḋ = v_b + Ω_b × S_b − v_a − Ω_a × S_a (S = R s the world arms, Ω = R ω); the
/// same blocks applied to (v, ω). Convective term (Ω̇ = R ω̇, so every Ω̇ and v̇
/// term is in J q̈):
///   c = (Ω_a × (Ω_a × U))·D + 2 (Ω_a × U)·Ḋ + U·(Ω_b × (Ω_b × S_b) − Ω_a × (Ω_a × S_a)).
#pragma once

#include "dynamics/constraints/body_pose.hpp"

namespace lieflow {
namespace constraints {

template <typename T>
struct DotTwoRow {
  Vector3<T> u_main;            ///< u, main body frame
  Vector3<T> anchor_main;       ///< s_a, main body frame
  Vector3<T> anchor_secondary;  ///< s_b, secondary body frame

  /// D = x_b − x_a (world).
  Vector3<T> separation(const BodyPose<T>& a, const BodyPose<T>& b) const {
    return b.toWorld(anchor_secondary) - a.toWorld(anchor_main);
  }

  T value(const BodyPose<T>& a, const BodyPose<T>& b) const { return (a.R * u_main).dot(separation(a, b)); }

  /// {J_a, J_b} (1 × 6 each: δp columns, then δθ).
  ConstraintBlocks<T, 1, 2> jacobians(const BodyPose<T>& a, const BodyPose<T>& b) const {
    const Vector3<T> U = a.R * u_main;
    const Vector3<T> xb = b.toWorld(anchor_secondary);
    ConstraintBlocks<T, 1, 2> J;
    J[0].template leftCols<3>() = -U.transpose();
    J[0].template rightCols<3>() = u_main.cross(a.R.inverse() * Vector3<T>(xb - a.p)).transpose();
    J[1].template leftCols<3>() = U.transpose();
    J[1].template rightCols<3>() = anchor_secondary.cross(b.R.inverse() * U).transpose();
    return J;
  }

  /// Φ̇ = U̇·D + U·Ḋ.
  T rate(const BodyPose<T>& a, const BodyPose<T>& b, const BodyVelocity<T>& va, const BodyVelocity<T>& vb) const {
    const auto J = jacobians(a, b);
    return (J[0] * va.twist() + J[1] * vb.twist())(0, 0);
  }

  /// c = (Ω_a×(Ω_a×U))·D + 2(Ω_a×U)·Ḋ + U·(Ω_b×(Ω_b×S_b) − Ω_a×(Ω_a×S_a)).
  T convective(const BodyPose<T>& a, const BodyPose<T>& b, const BodyVelocity<T>& va,
               const BodyVelocity<T>& vb) const {
    const Vector3<T> U = a.R * u_main;
    const Vector3<T> Sa = a.R * anchor_main, Sb = b.R * anchor_secondary;
    const Vector3<T> Oa = va.omegaWorld(a), Ob = vb.omegaWorld(b);
    const Vector3<T> D = b.p + Sb - a.p - Sa;
    const Vector3<T> Dd = vb.v + Ob.cross(Sb) - va.v - Oa.cross(Sa);
    const Vector3<T> Ud = Oa.cross(U);
    return Oa.cross(Ud).dot(D) + T(2) * Ud.dot(Dd) + U.dot(Ob.cross(Ob.cross(Sb)) - Oa.cross(Oa.cross(Sa)));
  }
};

}  // namespace constraints
}  // namespace lieflow
