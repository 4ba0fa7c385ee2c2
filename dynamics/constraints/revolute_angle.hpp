/// \file
/// The joint coordinate φ_J of a revolute joint (Abaqus "Revolute joint":
/// the relative rotation about the axis is a degree of freedom), its rate and
/// its Jacobian with respect to the body coordinates.
///
/// Definition. With Q = R_a⁻¹ R_b R_ref⁻¹ (main frame; Q = exp(φ_J a_a) on the
/// constraint manifold, revolute.hpp) and its unit quaternion (q_w, q_v), φ_J
/// is the twist angle of Q about a_a (swing–twist decomposition, Q = swing·twist):
///   φ_J = 2 atan2(q_v·a_a, q_w)      with the sign of q chosen so that q_w ≥ 0,
/// in [−π, π], zero in the reference configuration (the assembly, t = 0, unless
/// a reference angle was given), continuous across ±π through unwrapAngle.
/// Off the manifold it stays defined unless Q is a half-turn about an axis
/// normal to a_a (q_w = q_v·a_a = 0: the constraint violated by 180°).
///
/// Rate (Abaqus: φ̇_S = φ̇_M + φ̇_J a):
///   φ̇_J = (Ω_b − Ω_a)·A,   A = R_a a_a,  Ω = R ω  (world angular velocities).
///
/// Jacobian (exact gradient of the twist angle, valid on and off the
/// manifold). For a left perturbation Q → exp(μ) Q of the main-frame relative
/// rotation, μ = R_a⁻¹ R_b δθ_b − δθ_a, and dq = ½ (0, μ) ⊗ q gives
///   δφ_J = g·μ,  g = [q_w (q_w a + q_v × a) + (q_v·a) q_v] / (q_w² + (q_v·a)²),
///   J_a = [ 0   −gᵀ ],   J_b = [ 0   (R_bᵀ R_a g)ᵀ ].
/// On the manifold q_v = sin(φ_J/2) a, so g = a_a and J q̇ = φ̇_J above.
///
/// Generalized forces: a joint moment M (applied moment, spring −k(φ_J − φ₀),
/// dashpot −c φ̇_J) does virtual work M δφ_J, so it enters the body equations
/// as J_aᵀ M and J_bᵀ M: on the manifold the body-frame moment −M R_aᵀ A on the
/// main body and +M R_bᵀ A on the secondary (Abaqus: M_S = −M_M, M_J = M_M·a).
#pragma once

#include <cmath>

#include "dynamics/constraints/angle_wrap.hpp"
#include "dynamics/constraints/revolute.hpp"

namespace lieflow {
namespace constraints {

namespace detail {

/// The quaternion of Q = R_a⁻¹ R_b R_ref⁻¹ with q_w ≥ 0.
template <typename T>
Eigen::Quaternion<T> revoluteRelativeQuaternion(const RevoluteJoint<T>& j, const BodyPose<T>& a,
                                                const BodyPose<T>& b) {
  Eigen::Quaternion<T> q = (a.R.inverse() * b.R * j.reference.inverse()).quaternion();
  if (q.w() < T(0)) q.coeffs() = -q.coeffs();
  return q;
}

}  // namespace detail

/// The world axis A = R_a a_a.
template <typename T>
Vector3<T> revoluteAxisWorld(const RevoluteJoint<T>& j, const BodyPose<T>& a) {
  return a.R * j.axis_main;
}

/// φ_J in [−π, π] (principal value).
template <typename T>
T revoluteAngle(const RevoluteJoint<T>& j, const BodyPose<T>& a, const BodyPose<T>& b) {
  using std::atan2;
  const Eigen::Quaternion<T> q = detail::revoluteRelativeQuaternion(j, a, b);
  return T(2) * atan2(q.vec().dot(j.axis_main), q.w());
}

/// φ_J unwrapped: the value nearest `previous` (|φ_J − previous| ≤ π).
template <typename T>
T revoluteAngle(const RevoluteJoint<T>& j, const BodyPose<T>& a, const BodyPose<T>& b,
                const T& previous) {
  return unwrapAngle(revoluteAngle(j, a, b), previous);
}

/// φ̇_J = (Ω_b − Ω_a)·A (exact on the constraint manifold; off it the exact
/// rate of revoluteAngle is revoluteAngleJacobians · q̇).
template <typename T>
T revoluteAngleRate(const RevoluteJoint<T>& j, const BodyPose<T>& a, const BodyPose<T>& b,
                    const BodyVelocity<T>& va, const BodyVelocity<T>& vb) {
  return (vb.omegaWorld(b) - va.omegaWorld(a)).dot(revoluteAxisWorld(j, a));
}

/// {J_a, J_b} of φ_J (1 × 6 each, translation columns zero): the exact
/// gradient of revoluteAngle (see the file comment).
template <typename T>
ConstraintBlocks<T, 1, 2> revoluteAngleJacobians(const RevoluteJoint<T>& j, const BodyPose<T>& a,
                                                 const BodyPose<T>& b) {
  const Eigen::Quaternion<T> q = detail::revoluteRelativeQuaternion(j, a, b);
  const Vector3<T>& ax = j.axis_main;
  const Vector3<T> qv = q.vec();
  const T s = qv.dot(ax);
  const Vector3<T> g = (q.w() * (q.w() * ax + qv.cross(ax)) + s * qv) / (q.w() * q.w() + s * s);
  ConstraintBlocks<T, 1, 2> J;
  J[0].setZero();
  J[1].setZero();
  J[0].template rightCols<3>() = -g.transpose();
  J[1].template rightCols<3>() = (b.R.inverse() * (a.R * g)).transpose();
  return J;
}

/// The convective term of φ_J on the constraint manifold:
/// φ̈_J = J_a (v̇_a, ω̇_a) + J_b (v̇_b, ω̇_b) + c with c = (Ω_b − Ω_a)·(Ω_a × A)
/// (from φ̇_J = (Ω_b − Ω_a)·A, Ω̇ = R ω̇, Ȧ = Ω_a × A). Needed for a prescribed
/// φ_J(t) imposed at acceleration level.
template <typename T>
T revoluteAngleConvective(const RevoluteJoint<T>& j, const BodyPose<T>& a, const BodyPose<T>& b,
                          const BodyVelocity<T>& va, const BodyVelocity<T>& vb) {
  const Vector3<T> Oa = va.omegaWorld(a);
  return (vb.omegaWorld(b) - Oa).dot(Oa.cross(revoluteAxisWorld(j, a)));
}

}  // namespace constraints
}  // namespace lieflow
