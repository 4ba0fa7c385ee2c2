/// \file
/// The prismatic joint (slider): Abaqus' TRANSLATOR connection, SLOT + ALIGN
/// (Abaqus theory manual, "Connection types"; ../shared/DESIGN.md Additions).
/// The secondary body slides relative to the main body along an axis a fixed
/// in the main body, without relative rotation:
///   x_b − x_a = x R_a a_a,   R_a⁻¹ R_b = R_ref,
/// x_a = p_a + R_a s_a, x_b = p_b + R_b s_b the anchors, x the joint
/// coordinate (J.x; 0 where the anchors coincide).
///
/// Maximal-coordinate constraint (5 rows): two dot-2 rows (dot_two_row.hpp)
/// keep x_b on the main body's line through x_a along a, and the three align
/// rows (align.hpp) hold the relative rotation:
///   Φ = [ U·D ;  V·D ;  align(R_a, R_b) ],   U = R_a u_a, V = R_a v_a, D = x_b − x_a,
/// (u_a, v_a, a_a) right-handed and orthonormal. The coordinate is the third
/// dot-2 row, x = (R_a a_a)·D, whose Jacobian, rate and convective term are
/// those of dot_two_row.hpp.
#pragma once

#include <sstream>
#include <string>

#include "dynamics/constraints/align.hpp"
#include "dynamics/constraints/body_pose.hpp"
#include "dynamics/constraints/dot_two_row.hpp"
#include "dynamics/constraints/revolute.hpp"
#include "dynamics/constraints/validation.hpp"

namespace lieflow {
namespace constraints {

template <typename T>
struct PrismaticJoint {
  static constexpr int kRows = 5;
  /// No leading spherical rows (the anchors are apart by x).
  static constexpr int kPointRows = 0;
  using Residual = Eigen::Matrix<T, 5, 1>;
  using Blocks = ConstraintBlocks<T, 5, 2>;

  Vector3<T> anchor_main;       ///< s_a, main frame
  Vector3<T> anchor_secondary;  ///< s_b, secondary frame
  Vector3<T> axis_main;         ///< a_a, unit, main frame
  AlignRows<T> align;           ///< u_a, v_a and R_ref

  DotTwoRow<T> slotU() const { return DotTwoRow<T>{align.u_main, anchor_main, anchor_secondary}; }
  DotTwoRow<T> slotV() const { return DotTwoRow<T>{align.v_main, anchor_main, anchor_secondary}; }
  /// x = (R_a a_a)·(x_b − x_a) as a row: its value, Jacobian, rate and
  /// convective term are the joint coordinate's.
  DotTwoRow<T> position() const { return DotTwoRow<T>{axis_main, anchor_main, anchor_secondary}; }

  Residual residual(const BodyPose<T>& a, const BodyPose<T>& b) const {
    const auto R = align.rows();
    Residual r;
    r << slotU().value(a, b), slotV().value(a, b), R[0].value(a, b), R[1].value(a, b), R[2].value(a, b);
    return r;
  }

  Blocks jacobians(const BodyPose<T>& a, const BodyPose<T>& b) const {
    const auto R = align.rows();
    const auto Ju = slotU().jacobians(a, b), Jv = slotV().jacobians(a, b);
    const auto J0 = R[0].jacobians(a, b), J1 = R[1].jacobians(a, b), J2 = R[2].jacobians(a, b);
    Blocks J;
    for (int k = 0; k < 2; ++k) J[k] << Ju[k], Jv[k], J0[k], J1[k], J2[k];
    return J;
  }

  Residual velocity(const BodyPose<T>& a, const BodyPose<T>& b, const BodyVelocity<T>& va,
                    const BodyVelocity<T>& vb) const {
    return applyBlocks<T, 5, 2>(jacobians(a, b), {va, vb});
  }

  Residual convective(const BodyPose<T>& a, const BodyPose<T>& b, const BodyVelocity<T>& va,
                      const BodyVelocity<T>& vb) const {
    const auto R = align.rows();
    Residual c;
    c << slotU().convective(a, b, va, vb), slotV().convective(a, b, va, vb), R[0].convective(a, b, va, vb),
        R[1].convective(a, b, va, vb), R[2].convective(a, b, va, vb);
    return c;
  }
};

/// A prismatic joint from its anchors, axis (unit to 1e-6, normalized) and
/// the relative rotation it holds, R_ref = R_a⁻¹ R_b. Checks (InvalidInput,
/// fields "PREFIX.NAME"): anchors finite, axis_main a unit vector.
template <typename T>
PrismaticJoint<T> makePrismaticJoint(const Vector3<T>& anchor_main, const Vector3<T>& anchor_secondary,
                                     const Vector3<T>& axis_main, const SO3<T>& reference,
                                     const std::string& prefix = "") {
  checkFinite(anchor_main, fieldName(prefix, "anchor_main"));
  checkFinite(anchor_secondary, fieldName(prefix, "anchor_secondary"));
  PrismaticJoint<T> j;
  j.anchor_main = anchor_main;
  j.anchor_secondary = anchor_secondary;
  j.axis_main = checkedUnitAxis(axis_main, fieldName(prefix, "axis_main"));
  const Vector3<T> u = perpendicularUnit(j.axis_main);
  j.align = makeAlignRows<T>(u, j.axis_main.cross(u), reference);
  return j;
}

/// A prismatic joint assembled at the poses main0, secondary0: R_ref is their
/// relative rotation, and the secondary anchor must lie on the slide line of
/// the main anchor (checked by the caller with the scene's tolerance).
template <typename T>
PrismaticJoint<T> assemblePrismaticJoint(const BodyPose<T>& main0, const BodyPose<T>& secondary0,
                                         const Vector3<T>& anchor_main, const Vector3<T>& anchor_secondary,
                                         const Vector3<T>& axis_main, const std::string& prefix = "") {
  return makePrismaticJoint<T>(anchor_main, anchor_secondary, axis_main, SO3<T>(main0.R.inverse() * secondary0.R),
                               prefix);
}

}  // namespace constraints
}  // namespace lieflow
