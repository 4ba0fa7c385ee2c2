/// \file
/// The gear-type joints of Radioss (/MPC: rotational gear, rack and pinion,
/// differential gear; ../shared/seeds/README.md), imposed on velocities with
/// Lagrange multipliers: each is a row set B(q) with B q̇ = 0, one rows × 6
/// block per participating body, body order (carrier N0, node 1, node 2[, 3]).
/// The carrier may be the ground (groundPose(), groundVelocity(); drop its
/// block). Each node i has local axes (r_i, s_i, t_i) fixed in its body frame
/// (NodeAxes), r_i = R_i r_i|body in the world, Δω_i = Ω_i − Ω₀ (world angular
/// velocities Ω = R ω), ΔV_i the node's velocity relative to the carrier
/// (gear_terms.hpp). Rows (Radioss):
///   gear (5 rows):          α(Δω₁·r₁) + (Δω₂·r₂) = 0,  Δω₁·s₁ = Δω₁·t₁ = 0,  Δω₂·s₂ = Δω₂·t₂ = 0;
///   rack and pinion (2):    α(Δω₁·s₁) + (ΔV₂·s₂) = 0,  α(Δω₁·t₁) + (ΔV₂·t₂) = 0;
///   differential (3):       α(Δω₁·x₁) + (Δω₂·x₂) + (Δω₃·x₃) = 0,  x = r, s, t.
/// Blocks and convective terms (d/dt(B q̇) = B q̈ + c) in gear_terms.hpp.
///
/// Position-level meaning (the rows are integrable where the axes stay fixed
/// relative to the carrier, which the rows themselves enforce for the gear):
///  * gear: the s, t rows make each gear turn relative to the carrier only
///    about its r axis, R₀⁻¹ R_i = (R₀⁻¹ R_i)|₀ exp(φ_i r_i) (a revolute joint
///    to the carrier at velocity level), and the r row is then
///    d/dt(α φ₁ + φ₂) = 0, i.e. α φ₁ + φ₂ = const, φ_i the rotation of gear i
///    relative to the carrier about its axis. Radioss's rigid-link relation on
///    the translations of N1, N2 is a spherical joint (carrier, node) at the
///    node's centre (spherical.hpp) — not repeated here. A gear node must not
///    also be hinged to the carrier (the rows would be redundant).
///  * rack and pinion: with x₂ = (p₂ − p₀)·S₂ and S₂ fixed in the carrier,
///    ΔV₂·S₂ = ẋ₂, so α θ₁ + x₂ = const: the rack travels −α × the pinion's
///    rotation θ₁ about s₁ relative to the carrier (likewise along t).
///  * differential: α φ₁ + φ₂ + φ₃ = const for rotations about the r axes.
///    If every node is also held to spin about its r axis relative to the
///    carrier (e.g. by revolute joints), the s and t rows vanish identically
///    and are redundant: the dynamics layer must not impose both.
/// Rows are imposed on velocities, so their position-level drift is not
/// corrected by these rows (as in Radioss).
#pragma once

#include <array>
#include <cmath>
#include <sstream>
#include <string>

#include "dynamics/constraints/body_pose.hpp"
#include "dynamics/constraints/gear_terms.hpp"
#include "dynamics/constraints/validation.hpp"

namespace lieflow {
namespace constraints {

/// A node's local axes (r, s, t), a right-handed orthonormal triad in the
/// node's body frame.
template <typename T>
struct NodeAxes {
  Vector3<T> r, s, t;
};

/// Node axes from r and s (t = r × s). Fields "PREFIX.r", "PREFIX.s": unit to
/// 1e-6 (normalized), orthogonal to 1e-6 (s made exactly orthogonal).
template <typename T>
NodeAxes<T> makeNodeAxes(const Vector3<T>& r, const Vector3<T>& s, const std::string& prefix = "") {
  NodeAxes<T> n;
  n.r = checkedUnitAxis(r, fieldName(prefix, "r"));
  n.s = checkedOrthogonalAxis(n.r, checkedUnitAxis(s, fieldName(prefix, "s")), fieldName(prefix, "s"),
                              "r");
  n.t = n.r.cross(n.s);
  return n;
}

/// Node axes from r, s and t; additionally t must be r × s to 1e-6 ("PREFIX.t").
template <typename T>
NodeAxes<T> makeNodeAxes(const Vector3<T>& r, const Vector3<T>& s, const Vector3<T>& t,
                         const std::string& prefix = "") {
  NodeAxes<T> n = makeNodeAxes(r, s, prefix);
  const Vector3<T> tt = checkedUnitAxis(t, fieldName(prefix, "t"));
  const double err = std::sqrt(scalarValue((tt - n.t).squaredNorm()));
  if (!(err <= kAxisOrthogonalityTolerance)) {
    std::ostringstream reason;
    reason << "axis is not r × s (‖t − r × s‖ = " << err
           << "; a right-handed orthonormal frame is required)";
    throw InvalidInput(fieldName(prefix, "t"), reason.str());
  }
  return n;
}

/// Rotational gear: bodies (carrier, gear 1, gear 2), 5 rows.
template <typename T>
struct GearJoint {
  static constexpr int kRows = 5;
  static constexpr std::size_t kBodies = 3;
  using Poses = std::array<BodyPose<T>, kBodies>;
  using Velocities = std::array<BodyVelocity<T>, kBodies>;
  using Blocks = ConstraintBlocks<T, kRows, kBodies>;
  using Rows = Eigen::Matrix<T, kRows, 1>;

  T ratio;  ///< α
  NodeAxes<T> node1, node2;

  /// B(q): row 0 α(Δω₁·r₁) + Δω₂·r₂; rows 1, 2 Δω₁·s₁, Δω₁·t₁; rows 3, 4 Δω₂·s₂, Δω₂·t₂.
  Blocks rows(const Poses& X) const {
    Blocks B;
    for (auto& b : B) b.setZero();
    detail::addSpinTerm(B, 0, ratio, 1, X, node1.r);
    detail::addSpinTerm(B, 0, T(1), 2, X, node2.r);
    detail::addSpinTerm(B, 1, T(1), 1, X, node1.s);
    detail::addSpinTerm(B, 2, T(1), 1, X, node1.t);
    detail::addSpinTerm(B, 3, T(1), 2, X, node2.s);
    detail::addSpinTerm(B, 4, T(1), 2, X, node2.t);
    return B;
  }

  /// B q̇.
  Rows velocity(const Poses& X, const Velocities& V) const { return applyBlocks(rows(X), V); }

  /// c = d/dt(B q̇) − B q̈.
  Rows convective(const Poses& X, const Velocities& V) const {
    Rows c;
    c << detail::spinTermConvective(ratio, 1, X, V, node1.r) +
             detail::spinTermConvective(T(1), 2, X, V, node2.r),
        detail::spinTermConvective(T(1), 1, X, V, node1.s),
        detail::spinTermConvective(T(1), 1, X, V, node1.t),
        detail::spinTermConvective(T(1), 2, X, V, node2.s),
        detail::spinTermConvective(T(1), 2, X, V, node2.t);
    return c;
  }
};

/// Rack and pinion: bodies (carrier, pinion N1, rack N2), 2 rows.
template <typename T>
struct RackPinionJoint {
  static constexpr int kRows = 2;
  static constexpr std::size_t kBodies = 3;
  using Poses = std::array<BodyPose<T>, kBodies>;
  using Velocities = std::array<BodyVelocity<T>, kBodies>;
  using Blocks = ConstraintBlocks<T, kRows, kBodies>;
  using Rows = Eigen::Matrix<T, kRows, 1>;

  T ratio;  ///< α (length per radian: rack travel per pinion rotation)
  NodeAxes<T> pinion, rack;

  /// B(q): row 0 α(Δω₁·s₁) + ΔV₂·s₂; row 1 α(Δω₁·t₁) + ΔV₂·t₂.
  Blocks rows(const Poses& X) const {
    Blocks B;
    for (auto& b : B) b.setZero();
    detail::addSpinTerm(B, 0, ratio, 1, X, pinion.s);
    detail::addSlideTerm(B, 0, T(1), 2, X, rack.s);
    detail::addSpinTerm(B, 1, ratio, 1, X, pinion.t);
    detail::addSlideTerm(B, 1, T(1), 2, X, rack.t);
    return B;
  }

  Rows velocity(const Poses& X, const Velocities& V) const { return applyBlocks(rows(X), V); }

  Rows convective(const Poses& X, const Velocities& V) const {
    Rows c;
    c << detail::spinTermConvective(ratio, 1, X, V, pinion.s) +
             detail::slideTermConvective(T(1), 2, X, V, rack.s),
        detail::spinTermConvective(ratio, 1, X, V, pinion.t) +
            detail::slideTermConvective(T(1), 2, X, V, rack.t);
    return c;
  }
};

/// A coupling of two one-coordinate joints: node i turns (revolute) or
/// slides (prismatic) along its axis x_i (its body frame) relative to its
/// joint's other body, carrier i, and its rate q̇_i = Δω_i·x_i or ΔV_i·x_i
/// (gear_terms.hpp, relative to carrier i; the node's own joint holds its
/// other relative motions, so these are the joint's φ̇ or ẋ). One row:
/// α q̇₁ + q̇₂ = 0, i.e. q₂ = −α q₁ + const — a URDF <mimic> with multiplier
/// −α, or an MJCF joint equality of first order. Unlike the gear's, the row
/// does not hold the nodes' other motions: their joints do.
/// Four body slots; each role (carrier 1, node 1, carrier 2, node 2) names
/// one, so that a body in two roles (the two joints' common parent; a
/// follower hung from the leader's child) has one slot, and unused slots
/// are the ground (kGround in the system's body list).
template <typename T>
struct CouplingJoint {
  static constexpr int kRows = 1;
  static constexpr std::size_t kBodies = 4;
  using Poses = std::array<BodyPose<T>, kBodies>;
  using Velocities = std::array<BodyVelocity<T>, kBodies>;
  using Blocks = ConstraintBlocks<T, kRows, kBodies>;
  using Rows = Eigen::Matrix<T, kRows, 1>;

  T ratio;  ///< α
  Vector3<T> axis1, axis2;
  bool slide1 = false, slide2 = false;  ///< prismatic nodes (else revolute)
  /// Slots of carrier 1, node 1, carrier 2, node 2 (distinct nodes).
  std::array<std::size_t, 4> slot{{0, 1, 0, 2}};

  /// B(q): α q̇₁ + q̇₂ with q̇_i = Δω_i·x_i or ΔV_i·x_i.
  Blocks rows(const Poses& X) const {
    Blocks B;
    for (auto& b : B) b.setZero();
    addTerm(B, ratio, slot[1], slot[0], X, axis1, slide1);
    addTerm(B, T(1), slot[3], slot[2], X, axis2, slide2);
    return B;
  }

  Rows velocity(const Poses& X, const Velocities& V) const { return applyBlocks(rows(X), V); }

  Rows convective(const Poses& X, const Velocities& V) const {
    Rows c;
    c << term(ratio, slot[1], slot[0], X, V, axis1, slide1) + term(T(1), slot[3], slot[2], X, V, axis2, slide2);
    return c;
  }

 private:
  static void addTerm(Blocks& B, const T& c, std::size_t node, std::size_t carrier, const Poses& X,
                      const Vector3<T>& x, bool slide) {
    if (slide)
      detail::addSlideTerm(B, 0, c, node, X, x, carrier);
    else
      detail::addSpinTerm(B, 0, c, node, X, x, carrier);
  }
  static T term(const T& c, std::size_t node, std::size_t carrier, const Poses& X, const Velocities& V,
                const Vector3<T>& x, bool slide) {
    return slide ? detail::slideTermConvective(c, node, X, V, x, carrier)
                 : detail::spinTermConvective(c, node, X, V, x, carrier);
  }
};

/// Differential gear: bodies (carrier, input N1, outputs N2, N3), 3 rows.
template <typename T>
struct DifferentialJoint {
  static constexpr int kRows = 3;
  static constexpr std::size_t kBodies = 4;
  using Poses = std::array<BodyPose<T>, kBodies>;
  using Velocities = std::array<BodyVelocity<T>, kBodies>;
  using Blocks = ConstraintBlocks<T, kRows, kBodies>;
  using Rows = Eigen::Matrix<T, kRows, 1>;

  T ratio;  ///< α
  NodeAxes<T> node1, node2, node3;

  /// B(q): row k = α(Δω₁·x₁) + Δω₂·x₂ + Δω₃·x₃ with x = r, s, t for k = 0, 1, 2.
  Blocks rows(const Poses& X) const {
    Blocks B;
    for (auto& b : B) b.setZero();
    for (int k = 0; k < 3; ++k) {
      detail::addSpinTerm(B, k, ratio, 1, X, axis(node1, k));
      detail::addSpinTerm(B, k, T(1), 2, X, axis(node2, k));
      detail::addSpinTerm(B, k, T(1), 3, X, axis(node3, k));
    }
    return B;
  }

  Rows velocity(const Poses& X, const Velocities& V) const { return applyBlocks(rows(X), V); }

  Rows convective(const Poses& X, const Velocities& V) const {
    Rows c;
    for (int k = 0; k < 3; ++k)
      c[k] = detail::spinTermConvective(ratio, 1, X, V, axis(node1, k)) +
             detail::spinTermConvective(T(1), 2, X, V, axis(node2, k)) +
             detail::spinTermConvective(T(1), 3, X, V, axis(node3, k));
    return c;
  }

  static const Vector3<T>& axis(const NodeAxes<T>& n, int k) {
    return k == 0 ? n.r : (k == 1 ? n.s : n.t);
  }
};

/// Checked constructors: the ratio must be finite and non-zero ("PREFIX.ratio");
/// the node axes are checked by makeNodeAxes.
template <typename T>
GearJoint<T> makeGearJoint(const T& ratio, const NodeAxes<T>& node1, const NodeAxes<T>& node2,
                           const std::string& prefix = "") {
  return GearJoint<T>{checkedGearRatio(ratio, fieldName(prefix, "ratio")), node1, node2};
}
template <typename T>
RackPinionJoint<T> makeRackPinionJoint(const T& ratio, const NodeAxes<T>& pinion,
                                       const NodeAxes<T>& rack, const std::string& prefix = "") {
  return RackPinionJoint<T>{checkedGearRatio(ratio, fieldName(prefix, "ratio")), pinion, rack};
}
/// A coupling; the axes must be unit to 1e-6 ("PREFIX.axis_main",
/// "PREFIX.axis_secondary"; normalized).
/// `slot`: carrier 1, node 1, carrier 2, node 2 (CouplingJoint::slot).
template <typename T>
CouplingJoint<T> makeCouplingJoint(const T& ratio, const Vector3<T>& axis1, bool slide1, const Vector3<T>& axis2,
                                   bool slide2, const std::array<std::size_t, 4>& slot = {{0, 1, 0, 2}},
                                   const std::string& prefix = "") {
  return CouplingJoint<T>{checkedGearRatio(ratio, fieldName(prefix, "ratio")),
                          checkedUnitAxis(axis1, fieldName(prefix, "axis_main")),
                          checkedUnitAxis(axis2, fieldName(prefix, "axis_secondary")),
                          slide1,
                          slide2,
                          slot};
}
template <typename T>
DifferentialJoint<T> makeDifferentialJoint(const T& ratio, const NodeAxes<T>& node1,
                                           const NodeAxes<T>& node2, const NodeAxes<T>& node3,
                                           const std::string& prefix = "") {
  return DifferentialJoint<T>{checkedGearRatio(ratio, fieldName(prefix, "ratio")), node1, node2,
                              node3};
}

}  // namespace constraints
}  // namespace lieflow
