/// \file
/// A universal joint whose two hinges do not meet: the first axis a₁ fixed
/// in the main body through its anchor s_a, the second a₂ fixed in the
/// secondary body through its anchor s_b, the axes orthogonal (MuJoCo's two
/// hinges of one body at two points, e.g. an ankle). The relative rotation
/// is the universal joint's, R_b = R_a exp(φ₁ e₁) exp(φ₂ e₂) R_ref
/// (universal.hpp), and since the second hinge turns about a line through
/// x_b and the first about a line through x_a, the separation
/// D = x_b − x_a = R_a exp(φ₁ e₁) D₀ turns with the first hinge only. In the
/// frame (A₁, A₂, A₁ × A₂), A₁ = R_a a₁, A₂ = R_b a₂, which turns the same way,
/// D keeps its coordinates c at assembly:
///   Φ = [ x_a − x_b + c₁ A₁ + c₂ A₂ + c₃ A₁ × A₂ ;  A₁·A₂ ]      (4 rows).
/// With c = 0 it is the universal joint. Jacobians (right perturbations,
/// δA₁ = −R_a â₁ δθ_a, δA₂ = −R_b â₂ δθ_b, δ(A₁ × A₂) = Â₂ R_a â₁ δθ_a − Â₁ R_b â₂ δθ_b):
///   J_a = [ I   −R_a ŝ_a − c₁ R_a â₁ + c₃ Â₂ R_a â₁ ],
///   J_b = [ −I   R_b ŝ_b − c₂ R_b â₂ − c₃ Â₁ R_b â₂ ]   (point rows; the dot row as in dot_row.hpp).
/// Convective term (Ω = R ω world, Ä = Ω̇ × A + Ω × (Ω × A), the Ω̇ terms in J q̈):
///   c = Ω_a × (Ω_a × S_a) − Ω_b × (Ω_b × S_b) + c₁ Ω_a × (Ω_a × A₁) + c₂ Ω_b × (Ω_b × A₂)
///       + c₃ [ (Ω_a × (Ω_a × A₁)) × A₂ + 2 (Ω_a × A₁) × (Ω_b × A₂) + A₁ × (Ω_b × (Ω_b × A₂)) ],
/// S = R s the world arms. The joint angles are the universal joint's
/// (universal_angles.hpp, on `cross`).
#pragma once

#include <string>

#include "dynamics/constraints/body_pose.hpp"
#include "dynamics/constraints/universal.hpp"

namespace lieflow {
namespace constraints {

template <typename T>
struct OffsetUniversalJoint {
  static constexpr int kRows = 4;
  static constexpr int kPointRows = 0;  ///< the anchors are apart
  using Residual = Eigen::Matrix<T, 4, 1>;
  using Blocks = ConstraintBlocks<T, 4, 2>;

  UniversalJoint<T> cross;  ///< axes, R_ref, anchors (s_a on axis 1, s_b on axis 2), the angles
  Vector3<T> offset;        ///< c: x_b − x_a = c₁ A₁ + c₂ A₂ + c₃ A₁ × A₂

  Residual residual(const BodyPose<T>& a, const BodyPose<T>& b) const {
    const Vector3<T> A1 = a.R * cross.axis1_main, A2 = b.R * cross.axis2_secondary;
    Residual r;
    r << a.toWorld(cross.point.anchor_main) - b.toWorld(cross.point.anchor_secondary) + offset[0] * A1 +
             offset[1] * A2 + offset[2] * A1.cross(A2),
        A1.dot(A2);
    return r;
  }

  Blocks jacobians(const BodyPose<T>& a, const BodyPose<T>& b) const {
    const Matrix3<T> Ra = a.R.matrix(), Rb = b.R.matrix();
    const Vector3<T> A1 = Ra * cross.axis1_main, A2 = Rb * cross.axis2_secondary;
    const Matrix3<T> dA1 = -(Ra * SO3<T>::hat(cross.axis1_main));       // ∂A₁/∂θ_a
    const Matrix3<T> dA2 = -(Rb * SO3<T>::hat(cross.axis2_secondary));  // ∂A₂/∂θ_b
    Blocks J;
    J[0].template topLeftCorner<3, 3>().setIdentity();
    J[0].template topRightCorner<3, 3>() =
        -(Ra * SO3<T>::hat(cross.point.anchor_main)) + offset[0] * dA1 - offset[2] * (SO3<T>::hat(A2) * dA1);
    J[1].template topLeftCorner<3, 3>() = -Matrix3<T>::Identity();
    J[1].template topRightCorner<3, 3>() =
        Rb * SO3<T>::hat(cross.point.anchor_secondary) + offset[1] * dA2 + offset[2] * (SO3<T>::hat(A1) * dA2);
    const auto Jd = cross.row().jacobians(a, b);
    J[0].template bottomRows<1>() = Jd[0];
    J[1].template bottomRows<1>() = Jd[1];
    return J;
  }

  Residual velocity(const BodyPose<T>& a, const BodyPose<T>& b, const BodyVelocity<T>& va,
                    const BodyVelocity<T>& vb) const {
    return applyBlocks<T, 4, 2>(jacobians(a, b), {va, vb});
  }

  Residual convective(const BodyPose<T>& a, const BodyPose<T>& b, const BodyVelocity<T>& va,
                      const BodyVelocity<T>& vb) const {
    const Vector3<T> A1 = a.R * cross.axis1_main, A2 = b.R * cross.axis2_secondary;
    const Vector3<T> Sa = a.R * cross.point.anchor_main, Sb = b.R * cross.point.anchor_secondary;
    const Vector3<T> Oa = va.omegaWorld(a), Ob = vb.omegaWorld(b);
    const Vector3<T> A1d = Oa.cross(A1), A2d = Ob.cross(A2);
    const Vector3<T> A1dd = Oa.cross(A1d), A2dd = Ob.cross(A2d);
    Residual c;
    c << Oa.cross(Oa.cross(Sa)) - Ob.cross(Ob.cross(Sb)) + offset[0] * A1dd + offset[1] * A2dd +
             offset[2] * (A1dd.cross(A2) + T(2) * A1d.cross(A2d) + A1.cross(A2dd)),
        cross.row().convective(a, b, va, vb);
    return c;
  }
};

/// An offset universal joint assembled at the poses main0, secondary0 (as
/// assembleUniversalJoint; the anchors may be apart): c is the anchors'
/// separation in the frame (A₁, A₂, A₁ × A₂) at assembly.
template <typename T>
OffsetUniversalJoint<T> assembleOffsetUniversalJoint(const BodyPose<T>& main0, const BodyPose<T>& secondary0,
                                                     const Vector3<T>& anchor_main, const Vector3<T>& anchor_secondary,
                                                     const Vector3<T>& axis1_main, const Vector3<T>& axis2_secondary,
                                                     const T& phi1_initial = T(0), const T& phi2_initial = T(0),
                                                     const std::string& prefix = "") {
  OffsetUniversalJoint<T> j;
  j.cross = assembleUniversalJoint<T>(main0, secondary0, anchor_main, anchor_secondary, axis1_main, axis2_secondary,
                                      phi1_initial, phi2_initial, prefix);
  const Vector3<T> A1 = main0.R * j.cross.axis1_main, A2 = secondary0.R * j.cross.axis2_secondary;
  const Vector3<T> D = secondary0.toWorld(anchor_secondary) - main0.toWorld(anchor_main);
  j.offset = Vector3<T>(D.dot(A1), D.dot(A2), D.dot(A1.cross(A2)));
  return j;
}

}  // namespace constraints
}  // namespace lieflow
