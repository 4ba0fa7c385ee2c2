/// \file
/// The revolute joint (hinge) of the Abaqus theory manual ("Revolute joint",
/// ../shared/seeds/README.md): the secondary body turns relative to the main
/// body about an axis a fixed in — and rotating with — the main body,
///   C(φ_S) = C(φ_J a) C(φ_M),   a = C(φ_M) a|₀            (spatial form, Abaqus),
/// which in lieflow's body-frame form (README "Conventions") reads
///   R_b = R_a exp(φ_J a_a) R_ref,                         (body-frame form, used here)
/// a_a the axis in the main frame, R_ref = R_a⁻¹ R_b at φ_J = 0 (the assembly
/// configuration unless a reference angle is given). The two forms are the
/// same rotation: C(φ_J R_a a_a) R_a = R_a exp(φ_J a_a).
///
/// Maximal-coordinate constraint (5 rows): a spherical joint at the hinge
/// point (spherical.hpp) plus two dot-1 rows (dot_row.hpp) keeping the
/// secondary's copy of the axis, A_b = R_b a_b with a_b = R_ref⁻¹ a_a, normal to
/// two main-frame unit vectors u_a, v_a ⟂ a_a ((u, v, a) right-handed):
///   Φ = [ p_a + R_a s_a − p_b − R_b s_b ;  (R_a u_a)·(R_b a_b) ;  (R_a v_a)·(R_b a_b) ].
/// On the manifold A_b = R_a a_a, so R_b a_b stays parallel to the main axis and
/// only the rotation about it is free. Jacobians, velocity form and convective
/// term are those of the two building blocks, stacked.
/// The joint angle φ_J, its rate and Jacobian are in revolute_angle.hpp.
#pragma once

#include <cmath>
#include <sstream>
#include <string>

#include "dynamics/constraints/body_pose.hpp"
#include "dynamics/constraints/dot_row.hpp"
#include "dynamics/constraints/spherical.hpp"
#include "dynamics/constraints/validation.hpp"

namespace lieflow {
namespace constraints {

/// A unit vector u ⟂ a (a unit): the normalized cross product of a with the
/// coordinate axis least aligned with a (‖a × e_k‖² ≥ 2/3, no cancellation).
template <typename T>
Vector3<T> perpendicularUnit(const Vector3<T>& a) {
  int k = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(scalarValue(a[i])) < std::abs(scalarValue(a[k]))) k = i;
  const Vector3<T> u = a.cross(Vector3<T>::Unit(k));
  return u / Eigen::numext::sqrt(u.squaredNorm());
}

template <typename T>
struct RevoluteJoint {
  static constexpr int kRows = 5;
  static constexpr int kPointRows = 3;  ///< the leading spherical rows
  using Residual = Eigen::Matrix<T, 5, 1>;
  using Blocks = ConstraintBlocks<T, 5, 2>;

  SphericalJoint<T> point;   ///< hinge point: anchors s_a (main), s_b (secondary)
  Vector3<T> axis_main;      ///< a_a, unit, main frame
  Vector3<T> axis_secondary; ///< a_b = R_ref⁻¹ a_a, unit, secondary frame
  Vector3<T> u_main;         ///< u_a ⟂ a_a, unit, main frame
  Vector3<T> v_main;         ///< v_a = a_a × u_a, main frame
  SO3<T> reference;          ///< R_ref = R_a⁻¹ R_b at φ_J = 0

  DotRow<T> rowU() const { return DotRow<T>{u_main, axis_secondary}; }
  DotRow<T> rowV() const { return DotRow<T>{v_main, axis_secondary}; }

  Residual residual(const BodyPose<T>& a, const BodyPose<T>& b) const {
    Residual r;
    r << point.residual(a, b), rowU().value(a, b), rowV().value(a, b);
    return r;
  }

  /// {J_a, J_b}: rows 0–2 spherical, rows 3–4 the dot-1 rows.
  Blocks jacobians(const BodyPose<T>& a, const BodyPose<T>& b) const {
    const auto Jp = point.jacobians(a, b);
    const auto Ju = rowU().jacobians(a, b);
    const auto Jv = rowV().jacobians(a, b);
    Blocks J;
    for (int k = 0; k < 2; ++k) J[k] << Jp[k], Ju[k], Jv[k];
    return J;
  }

  /// Φ̇ = J_a (v_a, ω_a) + J_b (v_b, ω_b).
  Residual velocity(const BodyPose<T>& a, const BodyPose<T>& b, const BodyVelocity<T>& va,
                    const BodyVelocity<T>& vb) const {
    return applyBlocks<T, 5, 2>(jacobians(a, b), {va, vb});
  }

  /// c = Φ̈ − J q̈ (spherical.hpp, dot_row.hpp).
  Residual convective(const BodyPose<T>& a, const BodyPose<T>& b, const BodyVelocity<T>& va,
                      const BodyVelocity<T>& vb) const {
    Residual c;
    c << point.convective(a, b, va, vb), rowU().convective(a, b, va, vb),
        rowV().convective(a, b, va, vb);
    return c;
  }

  /// residual(), jacobians() and convective() at once, each where asked
  /// (null: not computed; c needs va, vb), with R_a and R_b formed once as
  /// matrices: the same formulas (spherical.hpp, dot_row.hpp) with the
  /// rotations of the anchors and axes shared, a third of the work of the
  /// three calls on the multibody hot path.
  void evaluate(const BodyPose<T>& a, const BodyPose<T>& b, const BodyVelocity<T>* va, const BodyVelocity<T>* vb,
                Residual* phi, Blocks* J, Residual* c) const {
    const Matrix3<T> Ra = a.R.matrix(), Rb = b.R.matrix();
    const Vector3<T> sa = Ra * point.anchor_main, sb = Rb * point.anchor_secondary;  // world arms
    const Vector3<T> U = Ra * u_main, V = Ra * v_main, W = Rb * axis_secondary;
    if (phi) *phi << a.p + sa - b.p - sb, U.dot(W), V.dot(W);
    if (J) {
      // [I, −R_a ŝ_a] = [I, −(R_a s_a)^ R_a]; dot rows: ±(Rᵀ (U × W))ᵀ.
      const Vector3<T> nU = U.cross(W), nV = V.cross(W);
      (*J)[0].template topLeftCorner<3, 3>().setIdentity();
      (*J)[0].template topRightCorner<3, 3>() = -(SO3<T>::hat(sa) * Ra);
      (*J)[1].template topLeftCorner<3, 3>() = -Matrix3<T>::Identity();
      (*J)[1].template topRightCorner<3, 3>() = SO3<T>::hat(sb) * Rb;
      (*J)[0].template bottomLeftCorner<2, 3>().setZero();
      (*J)[1].template bottomLeftCorner<2, 3>().setZero();
      (*J)[0].template block<1, 3>(3, 3) = (Ra.transpose() * nU).transpose();
      (*J)[0].template block<1, 3>(4, 3) = (Ra.transpose() * nV).transpose();
      (*J)[1].template block<1, 3>(3, 3) = -(Rb.transpose() * nU).transpose();
      (*J)[1].template block<1, 3>(4, 3) = -(Rb.transpose() * nV).transpose();
    }
    if (c) {
      const Vector3<T> Oa = Ra * va->omega, Ob = Rb * vb->omega;  // world angular velocities
      // Point rows: Ω_a × (Ω_a × R_a s_a) − Ω_b × (Ω_b × R_b s_b) (= R (ω × (ω × s))).
      const Vector3<T> Wd = Ob.cross(W);
      const Vector3<T> Ud = Oa.cross(U), Vd = Oa.cross(V);
      const Vector3<T> Wdd = Ob.cross(Wd);
      *c << Oa.cross(Oa.cross(sa)) - Ob.cross(Ob.cross(sb)),
          Oa.cross(Ud).dot(W) + T(2) * Ud.dot(Wd) + U.dot(Wdd),
          Oa.cross(Vd).dot(W) + T(2) * Vd.dot(Wd) + V.dot(Wdd);
    }
  }
};

/// A revolute joint from its axes and reference relative rotation R_ref
/// (R_a⁻¹ R_b at φ_J = 0). Checks (InvalidInput, fields "PREFIX.NAME"):
/// anchors finite; axis_main, axis_secondary unit to 1e-6 (normalized) and
/// aligned in the reference configuration, ‖R_ref a_b − a_a‖ ≤ 1e-6
/// ("axis_secondary"). a_b is then set to exactly R_ref⁻¹ a_a.
template <typename T>
RevoluteJoint<T> makeRevoluteJoint(const Vector3<T>& anchor_main, const Vector3<T>& anchor_secondary,
                                   const Vector3<T>& axis_main, const Vector3<T>& axis_secondary,
                                   const SO3<T>& reference, const std::string& prefix = "") {
  RevoluteJoint<T> j;
  j.point = makeSphericalJoint(anchor_main, anchor_secondary, prefix);
  j.axis_main = checkedUnitAxis(axis_main, fieldName(prefix, "axis_main"));
  const Vector3<T> ab = checkedUnitAxis(axis_secondary, fieldName(prefix, "axis_secondary"));
  const double misalignment = std::sqrt(scalarValue((reference * ab - j.axis_main).squaredNorm()));
  if (!(misalignment <= kAxisAlignmentTolerance)) {
    std::ostringstream reason;
    reason << "axis is not aligned with axis_main in the reference configuration (‖R_ref a_b − a_a‖ = "
           << misalignment << " > " << kAxisAlignmentTolerance << ")";
    throw InvalidInput(fieldName(prefix, "axis_secondary"), reason.str());
  }
  j.reference = reference;
  j.axis_secondary = reference.inverse() * j.axis_main;
  j.u_main = perpendicularUnit(j.axis_main);
  j.v_main = j.axis_main.cross(j.u_main);
  return j;
}

/// A revolute joint assembled at the poses main0, secondary0 where the joint
/// angle is `initial_angle` (0 unless a reference says otherwise):
/// R_ref = exp(−φ₀ a_a) R_a0⁻¹ R_b0. Same checks as makeRevoluteJoint (the
/// axes must be aligned at assembly: R_b0 a_b ∥ R_a0 a_a).
template <typename T>
RevoluteJoint<T> assembleRevoluteJoint(const BodyPose<T>& main0, const BodyPose<T>& secondary0,
                                       const Vector3<T>& anchor_main,
                                       const Vector3<T>& anchor_secondary,
                                       const Vector3<T>& axis_main, const Vector3<T>& axis_secondary,
                                       const T& initial_angle = T(0),
                                       const std::string& prefix = "") {
  const Vector3<T> aa = checkedUnitAxis(axis_main, fieldName(prefix, "axis_main"));
  const SO3<T> reference = SO3<T>::exp(-initial_angle * aa) * main0.R.inverse() * secondary0.R;
  return makeRevoluteJoint(anchor_main, anchor_secondary, aa, axis_secondary, reference, prefix);
}

}  // namespace constraints
}  // namespace lieflow
