/// \file
/// The joint coordinates φ₁, φ₂ of a universal joint (Abaqus "Universal
/// joint": the two relative rotations are degrees of freedom), their rates,
/// Jacobians and the 90° singularity.
///
/// Definition (body-frame form of universal.hpp). With M = R_a⁻¹ R_b and
/// Q = M R_ref⁻¹ = exp(φ₁ e₁) exp(φ₂ e₂) on the manifold, (e₁, e₂, e₃) the
/// orthonormal main-frame triad of the joint:
///   Q e₂ = cos φ₁ e₂ + sin φ₁ e₃        ⇒  φ₁ = atan2(e₃·w, e₂·w),   w = Q e₂ = M a₂,
///   Qᵀ e₁ = cos φ₂ e₁ + sin φ₂ e₃       ⇒  φ₂ = atan2(e₁·Q e₃, e₁·Q e₁),
/// with Q e_k = M (R_ref⁻¹ e_k). Both in [−π, π], zero in the reference
/// configuration, continuous across ±π through unwrapAngle; (φ₁, φ₂) ↦ Q is
/// one-to-one (mod 2π), so both are defined on the whole constraint manifold.
/// Off the manifold they stay defined unless the cross arms become parallel
/// (e₁·w = ±1, the dot constraint violated by 90°).
///
/// Rates (Abaqus: φ̇_S = φ̇_M + φ̇₁ a₁ + φ̇₂ a₂, a₁ ⟂ a₂):
///   φ̇₁ = (Ω_b − Ω_a)·A₁,  φ̇₂ = (Ω_b − Ω_a)·A₂,   A₁ = R_a a₁,  A₂ = R_b a₂ (world).
///
/// Jacobians (exact gradients of the atan2 forms, on and off the manifold).
/// For a left perturbation Q → exp(μ) Q, μ = M δθ_b − δθ_a (main frame),
/// δw = μ × w and δ(e₁·Q e_k) = μ·(Q e_k × e₁), so with x = e₂·w, y = e₃·w,
/// r₁ = e₁·Q e₁, r₃ = e₁·Q e₃:
///   g₁ = w × (x e₃ − y e₂) / (x² + y²),   g₂ = (r₁ Q e₃ − r₃ Q e₁) × e₁ / (r₁² + r₃²),
///   J_a = [ 0  −g_kᵀ ],   J_b = [ 0  (Mᵀ g_k)ᵀ ].
/// On the manifold g₁ = e₁ and g₂ = exp(φ₁ e₁) e₂ (the two hinge axes in the
/// main frame), so J q̇ equals the rates above and a hinge moment M_k acts as
/// +M_k A_k on the secondary body and −M_k A_k on the main body.
///
/// The 90° singularity. The angles above are smooth on the manifold and the
/// constraint row of universal.hpp stays regular; what degenerates is the
/// transmission through the cross. The joint's only rotational reaction is a
/// moment λ n, n = A₁ × A₂, whose lever arms about the two shaft axes — the
/// directions normal to both hinges in the reference configuration, e₃ fixed
/// in the main body and R_ref⁻¹ e₃ fixed in the secondary — are cos φ₁ and
/// cos φ₂ (n = R_a exp(φ₁ e₁) e₃ on the manifold). So for a Cardan shaft
/// (each shaft turning about its e₃ axis, joint referenced to straight shafts)
///   ω_b / ω_a = cos φ₁ / cos φ₂,    cos β = cos φ₁ cos φ₂   (β the bend angle).
/// When a hinge angle reaches ±90° (β = 90°) one lever arm vanishes: that
/// shaft can no longer be driven, the driven shaft's angle is no longer
/// determined by the driving one (∂Φ/∂θ_b ∝ cos φ₂ in a Newton solve), and the
/// reaction moments grow like 1/cos. (In the Cardan-angle x-y-z description of
/// the relative rotation the same place is the gimbal lock at φ₂ = ±90°, where φ₁
/// and the constrained twist about e₃ can no longer be told apart.)
/// It is reported by the condition number of the lever-arm matrix
/// D = diag(cos φ₁, cos φ₂) relative to the straight joint (D = I, and every
/// entry |cos φ_k| ≤ 1):
///   κ = ‖D⁻¹‖₂ = 1 / min(|cos φ₁|, |cos φ₂|)  ≥ max(ω_b/ω_a, ω_a/ω_b),
/// |cos φ_k| being the sine of the angle between shaft k and the plane of the
/// cross. κ = 1 for straight shafts, 1/cos β at the extremes of a Cardan
/// revolution, +∞ at the singularity (also where both hinges reach 90° at
/// once, the fully locked cross, where the ratio cos φ₁/cos φ₂ is 0/0).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "dynamics/constraints/angle_wrap.hpp"
#include "dynamics/constraints/universal.hpp"

namespace lieflow {
namespace constraints {

/// κ above which universalAngles(...).nearSingular() reports the 90°
/// singularity: a hinge angle within 1e-3 rad (0.06°) of ±90°. The dynamics layer decides what to do (stop with a
/// message, or warn).
constexpr double kUniversalNearSingularCondition = 1e3;

template <typename T>
struct UniversalAngles {
  T phi1;               ///< rotation about the first axis a₁ (main body)
  T phi2;               ///< rotation about the second axis a₂ (carried by hinge 1)
  double cos_bend;      ///< cos φ₁ cos φ₂ (cos of the shaft bend angle β)
  double condition;     ///< κ ≥ 1 (file comment); +∞ at the 90° singularity
  bool nearSingular(double limit = kUniversalNearSingularCondition) const {
    return !(condition < limit);
  }
};

namespace detail {

/// The atan2 arguments of φ₁ (x, y) and φ₂ (r₁, r₃) and the vectors their
/// gradients need (main frame).
template <typename T>
struct UniversalFrame {
  SO3<T> M;                ///< R_a⁻¹ R_b
  Vector3<T> w, qe1, qe3;  ///< Q e₂ = M a₂, Q e₁, Q e₃
  T x, y, r1, r3;
};

template <typename T>
UniversalFrame<T> universalFrame(const UniversalJoint<T>& j, const BodyPose<T>& a,
                                 const BodyPose<T>& b) {
  UniversalFrame<T> f;
  f.M = a.R.inverse() * b.R;
  f.w = f.M * j.axis2_secondary;
  f.qe1 = f.M * j.e1_secondary;
  f.qe3 = f.M * j.e3_secondary;
  f.x = j.e2_main.dot(f.w);
  f.y = j.e3_main.dot(f.w);
  f.r1 = j.axis1_main.dot(f.qe1);
  f.r3 = j.axis1_main.dot(f.qe3);
  return f;
}

}  // namespace detail

/// φ₁, φ₂ in [−π, π] with the singularity report.
template <typename T>
UniversalAngles<T> universalAngles(const UniversalJoint<T>& j, const BodyPose<T>& a,
                                   const BodyPose<T>& b) {
  using std::atan2;
  const detail::UniversalFrame<T> f = detail::universalFrame(j, a, b);
  UniversalAngles<T> out;
  out.phi1 = atan2(f.y, f.x);
  out.phi2 = atan2(f.r3, f.r1);
  const double x = scalarValue(f.x), y = scalarValue(f.y);
  const double r1 = scalarValue(f.r1), r3 = scalarValue(f.r3);
  const double c1 = std::abs(x) / std::hypot(x, y);
  const double c2 = std::abs(r1) / std::hypot(r1, r3);
  out.cos_bend = (x / std::hypot(x, y)) * (r1 / std::hypot(r1, r3));
  const double lo = std::min(c1, c2);
  out.condition = lo > 0.0 ? 1.0 / lo : std::numeric_limits<double>::infinity();
  return out;
}

/// φ₁, φ₂ unwrapped: each the value nearest its previous value.
template <typename T>
UniversalAngles<T> universalAngles(const UniversalJoint<T>& j, const BodyPose<T>& a,
                                   const BodyPose<T>& b, const T& previous_phi1,
                                   const T& previous_phi2) {
  UniversalAngles<T> out = universalAngles(j, a, b);
  out.phi1 = unwrapAngle(out.phi1, previous_phi1);
  out.phi2 = unwrapAngle(out.phi2, previous_phi2);
  return out;
}

/// (φ̇₁, φ̇₂) = ((Ω_b − Ω_a)·A₁, (Ω_b − Ω_a)·A₂) (exact on the manifold; off
/// it the exact rates of universalAngles are universalAngleJacobians · q̇).
template <typename T>
Eigen::Matrix<T, 2, 1> universalAngleRates(const UniversalJoint<T>& j, const BodyPose<T>& a,
                                           const BodyPose<T>& b, const BodyVelocity<T>& va,
                                           const BodyVelocity<T>& vb) {
  const Vector3<T> dw = vb.omegaWorld(b) - va.omegaWorld(a);
  return Eigen::Matrix<T, 2, 1>(dw.dot(a.R * j.axis1_main), dw.dot(b.R * j.axis2_secondary));
}

/// {J_a, J_b} of (φ₁, φ₂) (2 × 6 each, translation columns zero): the exact
/// gradients of universalAngles (file comment).
template <typename T>
ConstraintBlocks<T, 2, 2> universalAngleJacobians(const UniversalJoint<T>& j, const BodyPose<T>& a,
                                                  const BodyPose<T>& b) {
  const detail::UniversalFrame<T> f = detail::universalFrame(j, a, b);
  const Vector3<T> g1 =
      f.w.cross(f.x * j.e3_main - f.y * j.e2_main) / (f.x * f.x + f.y * f.y);
  const Vector3<T> g2 =
      (f.r1 * f.qe3 - f.r3 * f.qe1).cross(j.axis1_main) / (f.r1 * f.r1 + f.r3 * f.r3);
  const SO3<T> Minv = f.M.inverse();
  ConstraintBlocks<T, 2, 2> J;
  J[0].setZero();
  J[1].setZero();
  J[0].template rightCols<3>().row(0) = -g1.transpose();
  J[0].template rightCols<3>().row(1) = -g2.transpose();
  J[1].template rightCols<3>().row(0) = (Minv * g1).transpose();
  J[1].template rightCols<3>().row(1) = (Minv * g2).transpose();
  return J;
}

/// The convective terms of (φ₁, φ₂) on the constraint manifold:
/// c = (Δω·(Ω_a × A₁), Δω·(Ω_b × A₂)), Δω = Ω_b − Ω_a (A₁ turns with the main
/// body, A₂ = R_b a₂ with the secondary). Needed for prescribed φ₁(t), φ₂(t)
/// imposed at acceleration level.
template <typename T>
Eigen::Matrix<T, 2, 1> universalAngleConvective(const UniversalJoint<T>& j, const BodyPose<T>& a,
                                                const BodyPose<T>& b, const BodyVelocity<T>& va,
                                                const BodyVelocity<T>& vb) {
  const Vector3<T> Oa = va.omegaWorld(a);
  const Vector3<T> Ob = vb.omegaWorld(b);
  const Vector3<T> dw = Ob - Oa;
  return Eigen::Matrix<T, 2, 1>(dw.dot(Oa.cross(a.R * j.axis1_main)),
                                dw.dot(Ob.cross(b.R * j.axis2_secondary)));
}

}  // namespace constraints
}  // namespace lieflow
