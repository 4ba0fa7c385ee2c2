/// \file
/// Three hinges through one point with orthogonal axes (a gimbal; MuJoCo's
/// hip: three hinge joints of one body at one point): a spherical joint
/// (spherical.hpp, 3 rows) whose relative rotation is read as three angles
/// about body-fixed axes in sequence,
///   R_b = R_a exp(φ₁ e₁) exp(φ₂ e₂) exp(φ₃ e₃) R_ref,
/// e₁, e₂, e₃ the hinge axes in the main frame at φ = 0 (orthonormal, either
/// handedness) and R_ref = R_a⁻¹ R_b at φ = 0 — the universal joint's form
/// (universal.hpp) with a third hinge. The angles carry springs, dashpots and
/// moments; they are not prescribed (no convective term here).
///
/// Angles: with E = [e₁ e₂ s e₃] right-handed (s = ±1) and
/// M = Eᵀ R_a⁻¹ R_b R_ref⁻¹ E = R_x(φ₁) R_y(φ₂) R_z(s φ₃) (Tait–Bryan x-y-z),
///   φ₂ = atan2(M₀₂, √(M₀₀² + M₀₁²)),  φ₁ = atan2(−M₁₂, M₂₂),  s φ₃ = atan2(−M₀₁, M₀₀),
/// and the same rotation is (φ₁ + π, π − φ₂, φ₃ + π): of the two, the one
/// nearest the previous angles (each unwrapped), so that φ₂ may pass ±90°.
/// Rates: the relative angular velocity in the main frame,
/// ω_rel = R_aᵀ(Ω_b − Ω_a) = R_aᵀ R_b ω_b − ω_a, is B φ̇ with
/// B = [e₁, R₁ e₂, R₁ R₂ e₃] (R_i = exp(φ_i e_i)), det B = ±cos φ₂, so
///   ∂φ/∂θ_a = −B⁻¹,   ∂φ/∂θ_b = B⁻¹ R_aᵀ R_b   (no translation columns).
/// At φ₂ = ±90° (gimbal lock) B is singular; `condition` = 1/|cos φ₂| says so.
#pragma once

#include <array>
#include <cmath>
#include <string>

#include "dynamics/constraints/angle_wrap.hpp"
#include "dynamics/constraints/body_pose.hpp"
#include "dynamics/constraints/spherical.hpp"
#include "dynamics/constraints/validation.hpp"

namespace lieflow {
namespace constraints {

template <typename T>
struct GimbalJoint {
  static constexpr int kRows = 3;
  static constexpr int kPointRows = 3;
  using Residual = Eigen::Matrix<T, 3, 1>;
  using Blocks = ConstraintBlocks<T, 3, 2>;

  SphericalJoint<T> point;           ///< the hinges' common point: s_a, s_b
  std::array<Vector3<T>, 3> axes;    ///< e₁, e₂, e₃ (main frame, at φ = 0), orthonormal
  T handedness = T(1);               ///< s = det[e₁ e₂ e₃] = ±1
  SO3<T> reference;                  ///< R_ref = R_a⁻¹ R_b at φ = 0

  Residual residual(const BodyPose<T>& a, const BodyPose<T>& b) const { return point.residual(a, b); }
  Blocks jacobians(const BodyPose<T>& a, const BodyPose<T>& b) const { return point.jacobians(a, b); }
  Residual velocity(const BodyPose<T>& a, const BodyPose<T>& b, const BodyVelocity<T>& va,
                    const BodyVelocity<T>& vb) const {
    return point.velocity(a, b, va, vb);
  }
  Residual convective(const BodyPose<T>& a, const BodyPose<T>& b, const BodyVelocity<T>& va,
                      const BodyVelocity<T>& vb) const {
    return point.convective(a, b, va, vb);
  }
};

struct GimbalAngles {
  std::array<double, 3> phi;
  double condition;  ///< 1/|cos φ₂| (∞ at gimbal lock)
};

/// The angles at (a, b), each within π of `previous`, on the branch nearest it.
inline GimbalAngles gimbalAngles(const GimbalJoint<double>& j, const BodyPose<double>& a, const BodyPose<double>& b,
                                 const std::array<double, 3>& previous = {{0.0, 0.0, 0.0}}) {
  Eigen::Matrix3d E;
  E << j.axes[0], j.axes[1], j.handedness * j.axes[2];
  const Eigen::Matrix3d M = E.transpose() * (a.R.inverse() * b.R * j.reference.inverse()).matrix() * E;
  const double pi = 3.14159265358979323846;
  const double p2 = std::atan2(M(0, 2), std::hypot(M(0, 0), M(0, 1)));
  const double p1 = std::atan2(-M(1, 2), M(2, 2));
  const double p3 = j.handedness * std::atan2(-M(0, 1), M(0, 0));
  const std::array<std::array<double, 3>, 2> branches{{{{p1, p2, p3}}, {{p1 + pi, pi - p2, p3 + pi}}}};
  GimbalAngles out{};
  double best = -1.0;
  for (const auto& branch : branches) {
    std::array<double, 3> phi;
    double distance = 0.0;
    for (int i = 0; i < 3; ++i) {
      phi[i] = unwrapAngle(branch[i], previous[i]);
      distance += (phi[i] - previous[i]) * (phi[i] - previous[i]);
    }
    if (best < 0.0 || distance < best) {
      best = distance;
      out.phi = phi;
    }
  }
  out.condition = 1.0 / std::abs(std::cos(out.phi[1]));
  return out;
}

/// {∂φ/∂(δp_a, δθ_a), ∂φ/∂(δp_b, δθ_b)} (3 × 6 each) at angles φ.
inline ConstraintBlocks<double, 3, 2> gimbalAngleJacobians(const GimbalJoint<double>& j, const BodyPose<double>& a,
                                                          const BodyPose<double>& b, const std::array<double, 3>& phi) {
  const SO3d R1 = SO3d::exp(phi[0] * j.axes[0]), R2 = SO3d::exp(phi[1] * j.axes[1]);
  Eigen::Matrix3d B;
  B << j.axes[0], R1 * j.axes[1], R1 * (R2 * j.axes[2]);
  const Eigen::Matrix3d Binv = B.inverse();
  ConstraintBlocks<double, 3, 2> J;
  J[0].setZero();
  J[1].setZero();
  J[0].rightCols<3>() = -Binv;
  J[1].rightCols<3>() = Binv * (a.R.inverse() * b.R).matrix();
  return J;
}

/// A gimbal from its point's anchors, its axes (main frame at φ = 0; unit to
/// 1e-6, orthogonal to 1e-6) and the relative rotation R_a⁻¹ R_b at the
/// assembly, where the angles are `initial`: R_ref = exp(−φ₃ e₃) exp(−φ₂ e₂)
/// exp(−φ₁ e₁) Q₀. Fields "PREFIX.axis1_main" … "PREFIX.axis3_main".
inline GimbalJoint<double> assembleGimbalJoint(const BodyPose<double>& main0, const BodyPose<double>& secondary0,
                                               const Eigen::Vector3d& anchor_main,
                                               const Eigen::Vector3d& anchor_secondary,
                                               const std::array<Eigen::Vector3d, 3>& axes_main,
                                               const std::array<double, 3>& initial, const std::string& prefix = "") {
  GimbalJoint<double> j;
  j.point = makeSphericalJoint<double>(anchor_main, anchor_secondary, prefix);
  for (int i = 0; i < 3; ++i)
    j.axes[i] = checkedUnitAxis(axes_main[i], fieldName(prefix, "axis" + std::to_string(i + 1) + "_main"));
  j.axes[1] = checkedOrthogonalAxis(j.axes[0], j.axes[1], fieldName(prefix, "axis2_main"), "axis1_main");
  j.axes[2] = checkedOrthogonalAxis(j.axes[0], j.axes[2], fieldName(prefix, "axis3_main"), "axis1_main");
  j.axes[2] = checkedOrthogonalAxis(j.axes[1], j.axes[2], fieldName(prefix, "axis3_main"), "axis2_main");
  j.handedness = j.axes[0].cross(j.axes[1]).dot(j.axes[2]) >= 0.0 ? 1.0 : -1.0;
  // Exactly orthonormal: e₃ = s e₁ × e₂.
  j.axes[2] = j.handedness * j.axes[0].cross(j.axes[1]);
  const SO3d Q0 = main0.R.inverse() * secondary0.R;
  j.reference = SO3d::exp(-initial[2] * j.axes[2]) * SO3d::exp(-initial[1] * j.axes[1]) *
                SO3d::exp(-initial[0] * j.axes[0]) * Q0;
  return j;
}

}  // namespace constraints
}  // namespace lieflow
