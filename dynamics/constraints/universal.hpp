/// \file
/// The universal (Cardan, Hooke) joint of the Abaqus theory manual
/// ("Universal joint", ../shared/seeds/README.md): two orthogonal hinges, the
/// first axis a₁ fixed in the main body, the second axis a₂ carried by the
/// first hinge and fixed in the secondary body,
///   C(φ_S) = C(φ₂ a₂) C(φ₁ a₁) C(φ_M),  a₁ = C(φ_M) a₁|₀,  a₂ = C(φ₁ a₁) C(φ_M) a₂|₀
/// (spatial form, Abaqus), which in lieflow's body-frame form reads
///   R_b = R_a exp(φ₁ e₁) exp(φ₂ e₂) R_ref                   (body-frame form, used here)
/// with e₁ = a₁ (main frame), e₂ = R_ref a₂ the second axis in the main frame
/// at φ₁ = φ₂ = 0, and R_ref = R_a⁻¹ R_b at φ₁ = φ₂ = 0 (the assembly unless
/// reference angles are given). Substituting a₁ = R_a e₁ and
/// a₂ = R_a exp(φ₁ e₁) e₂ into the spatial form gives exactly the body-frame one.
///
/// Maximal-coordinate constraint (4 rows): a spherical joint at the centre of
/// the cross (spherical.hpp) plus one dot-1 row (dot_row.hpp)
///   Φ = [ p_a + R_a s_a − p_b − R_b s_b ;  (R_a a₁)·(R_b a₂) ],
/// a₁ in the main frame, a₂ in the secondary frame, a₁ ⟂ a₂ at assembly. The
/// dot row's Jacobian has ‖R_a a₁ × R_b a₂‖ = 1 on the manifold: the constraint
/// itself is regular everywhere, including at the 90° configurations (see
/// universal_angles.hpp for what is singular there).
#pragma once

#include <string>

#include "dynamics/constraints/body_pose.hpp"
#include "dynamics/constraints/dot_row.hpp"
#include "dynamics/constraints/spherical.hpp"
#include "dynamics/constraints/validation.hpp"

namespace lieflow {
namespace constraints {

template <typename T>
struct UniversalJoint {
  static constexpr int kRows = 4;
  static constexpr int kPointRows = 3;  ///< the leading spherical rows
  using Residual = Eigen::Matrix<T, 4, 1>;
  using Blocks = ConstraintBlocks<T, 4, 2>;

  SphericalJoint<T> point;     ///< centre of the cross: s_a (main), s_b (secondary)
  Vector3<T> axis1_main;       ///< a₁ = e₁, unit, main frame
  Vector3<T> axis2_secondary;  ///< a₂, unit, secondary frame
  SO3<T> reference;            ///< R_ref = R_a⁻¹ R_b at φ₁ = φ₂ = 0
  // Derived frames of the joint angles (universal_angles.hpp):
  Vector3<T> e2_main;          ///< e₂ = R_ref a₂ (main frame), ⟂ e₁
  Vector3<T> e3_main;          ///< e₃ = e₁ × e₂ (main frame)
  Vector3<T> e1_secondary;     ///< R_ref⁻¹ e₁ (secondary frame)
  Vector3<T> e3_secondary;     ///< R_ref⁻¹ e₃ (secondary frame)

  DotRow<T> row() const { return DotRow<T>{axis1_main, axis2_secondary}; }

  Residual residual(const BodyPose<T>& a, const BodyPose<T>& b) const {
    Residual r;
    r << point.residual(a, b), row().value(a, b);
    return r;
  }

  /// {J_a, J_b}: rows 0–2 spherical, row 3 the dot-1 row.
  Blocks jacobians(const BodyPose<T>& a, const BodyPose<T>& b) const {
    const auto Jp = point.jacobians(a, b);
    const auto Jd = row().jacobians(a, b);
    Blocks J;
    for (int k = 0; k < 2; ++k) J[k] << Jp[k], Jd[k];
    return J;
  }

  /// Φ̇ = J_a (v_a, ω_a) + J_b (v_b, ω_b).
  Residual velocity(const BodyPose<T>& a, const BodyPose<T>& b, const BodyVelocity<T>& va,
                    const BodyVelocity<T>& vb) const {
    return applyBlocks<T, 4, 2>(jacobians(a, b), {va, vb});
  }

  /// c = Φ̈ − J q̈ (spherical.hpp, dot_row.hpp).
  Residual convective(const BodyPose<T>& a, const BodyPose<T>& b, const BodyVelocity<T>& va,
                      const BodyVelocity<T>& vb) const {
    Residual c;
    c << point.convective(a, b, va, vb), row().convective(a, b, va, vb);
    return c;
  }
};

/// A universal joint from its axes and the reference relative rotation R_ref
/// (R_a⁻¹ R_b at φ₁ = φ₂ = 0). Checks (InvalidInput, fields "PREFIX.NAME"):
/// anchors finite; axis1_main, axis2_secondary unit to 1e-6 (normalized);
/// |a₁·R_ref a₂| ≤ 1e-6 ("axis2_secondary": the axes must be orthogonal in the
/// reference configuration); a₂ is then made exactly orthogonal.
template <typename T>
UniversalJoint<T> makeUniversalJoint(const Vector3<T>& anchor_main,
                                     const Vector3<T>& anchor_secondary,
                                     const Vector3<T>& axis1_main,
                                     const Vector3<T>& axis2_secondary, const SO3<T>& reference,
                                     const std::string& prefix = "") {
  UniversalJoint<T> j;
  j.point = makeSphericalJoint(anchor_main, anchor_secondary, prefix);
  j.axis1_main = checkedUnitAxis(axis1_main, fieldName(prefix, "axis1_main"));
  const Vector3<T> a2 = checkedUnitAxis(axis2_secondary, fieldName(prefix, "axis2_secondary"));
  j.reference = reference;
  j.e2_main = checkedOrthogonalAxis(j.axis1_main, Vector3<T>(reference * a2),
                                    fieldName(prefix, "axis2_secondary"), "axis1_main");
  j.e3_main = j.axis1_main.cross(j.e2_main);
  const SO3<T> inv = reference.inverse();
  j.axis2_secondary = inv * j.e2_main;
  j.e1_secondary = inv * j.axis1_main;
  j.e3_secondary = inv * j.e3_main;
  return j;
}

/// A universal joint assembled at the poses main0, secondary0 where the joint
/// angles are (φ₁₀, φ₂₀) (zero unless a reference says otherwise). With
/// Q₀ = R_a0⁻¹ R_b0: e₂ = exp(−φ₁₀ e₁) Q₀ a₂ and R_ref = exp(−φ₂₀ e₂) exp(−φ₁₀ e₁) Q₀.
/// Same checks as makeUniversalJoint (a₁ ⟂ a₂ at assembly: |R_a0 a₁ · R_b0 a₂| ≤ 1e-6).
template <typename T>
UniversalJoint<T> assembleUniversalJoint(const BodyPose<T>& main0, const BodyPose<T>& secondary0,
                                         const Vector3<T>& anchor_main,
                                         const Vector3<T>& anchor_secondary,
                                         const Vector3<T>& axis1_main,
                                         const Vector3<T>& axis2_secondary,
                                         const T& phi1_initial = T(0), const T& phi2_initial = T(0),
                                         const std::string& prefix = "") {
  const Vector3<T> e1 = checkedUnitAxis(axis1_main, fieldName(prefix, "axis1_main"));
  const Vector3<T> a2 = checkedUnitAxis(axis2_secondary, fieldName(prefix, "axis2_secondary"));
  const SO3<T> Q0 = main0.R.inverse() * secondary0.R;
  const SO3<T> undo1 = SO3<T>::exp(-phi1_initial * e1);
  const Vector3<T> e2 = checkedOrthogonalAxis(e1, Vector3<T>(undo1 * (Q0 * a2)),
                                              fieldName(prefix, "axis2_secondary"), "axis1_main");
  const SO3<T> reference = SO3<T>::exp(-phi2_initial * e2) * undo1 * Q0;
  // a₂ made exactly orthogonal (reference a₂ = e₂ then holds exactly).
  const Vector3<T> a2_orthogonal = reference.inverse() * e2;
  return makeUniversalJoint(anchor_main, anchor_secondary, e1, a2_orthogonal, reference, prefix);
}

}  // namespace constraints
}  // namespace lieflow
