/// \file
/// What both formulations of dynamics/ say of a joint: its constraint (the
/// joint types of dynamics/constraints/ as one variant, JointKind its index),
/// the gear-type rows, the force elements and drive of each joint coordinate
/// (spring −k (φ − φ₀), dashpot −c φ̇, applied moment M(t), prescribed φ(t))
/// and what a run writes of a joint (README "Trajectory and recording CSV").
/// The maximal-coordinate system (dynamics/maximal/) imposes the constraint
/// with multipliers; the joint-coordinate one (dynamics/joint_space/) moves
/// on the joint's own group and imposes only loop-closing joints.
#pragma once

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>

#include <Eigen/Core>

#include "dynamics/body_index.hpp"
#include "dynamics/constraints/constraints.hpp"
#include "model/time_function.hpp"

namespace lieflow {

/// The constraint types the acceleration solve handles.
/// The index of each type is its JointKind.
using JointConstraint = std::variant<constraints::SphericalJoint<double>,
                                     constraints::RevoluteJoint<double>,
                                     constraints::UniversalJoint<double>,
                                     constraints::PrismaticJoint<double>,
                                     constraints::FixedJoint<double>,
                                     constraints::OffsetUniversalJoint<double>,
                                     constraints::GimbalJoint<double>>;

/// The kind of a joint: the index of its constraint in JointConstraint.
enum class JointKind {
  kSpherical = 0,
  kRevolute = 1,
  kUniversal = 2,
  kPrismatic = 3,
  kFixed = 4,
  kOffsetUniversal = 5,
  kGimbal = 6
};

/// The universal joint whose angles a universal or offset universal joint
/// has (universal_angles.hpp), or null for the other kinds.
inline const constraints::UniversalJoint<double>* universalOf(const JointConstraint& c) {
  if (const auto* u = std::get_if<constraints::UniversalJoint<double>>(&c)) return u;
  if (const auto* o = std::get_if<constraints::OffsetUniversalJoint<double>>(&c)) return &o->cross;
  return nullptr;
}

inline JointKind jointKind(const JointConstraint& c) { return static_cast<JointKind>(c.index()); }

inline int constraintRows(const JointConstraint& c) {
  return std::visit([](const auto& j) { return std::decay_t<decltype(j)>::kRows; }, c);
}

/// The number of leading rows that are a spherical joint's at the anchors
/// (3, or 0 for the prismatic and fixed joints, whose rows are a slot's).
inline int pointRows(const JointConstraint& c) {
  return std::visit([](const auto& j) { return std::decay_t<decltype(j)>::kPointRows; }, c);
}

/// The joint's anchors s_a (main frame) and s_b (secondary frame).
inline std::pair<Eigen::Vector3d, Eigen::Vector3d> jointAnchors(const JointConstraint& c) {
  return std::visit(
      [](const auto& j) -> std::pair<Eigen::Vector3d, Eigen::Vector3d> {
        using C = std::decay_t<decltype(j)>;
        if constexpr (std::is_same_v<C, constraints::SphericalJoint<double>>)
          return {j.anchor_main, j.anchor_secondary};
        else if constexpr (std::is_base_of_v<constraints::PrismaticJoint<double>, C>)  // prismatic, fixed
          return {j.anchor_main, j.anchor_secondary};
        else if constexpr (std::is_same_v<C, constraints::OffsetUniversalJoint<double>>)
          return {j.cross.point.anchor_main, j.cross.point.anchor_secondary};
        else
          return {j.point.anchor_main, j.point.anchor_secondary};
      },
      c);
}

inline const char* constraintTypeName(const JointConstraint& c) {
  switch (jointKind(c)) {
    case JointKind::kSpherical: return "spherical";
    case JointKind::kRevolute: return "revolute";
    case JointKind::kUniversal: return "universal";
    case JointKind::kPrismatic: return "prismatic";
    case JointKind::kFixed: return "fixed";
    case JointKind::kOffsetUniversal: return "universal (offset)";
    case JointKind::kGimbal: return "gimbal";
  }
  return "joint";
}

/// The most coordinates one joint has (a gimbal: three angles).
constexpr int kMaxJointCoordinates = 3;
/// The slot of coordinate i of joint k in MultibodyGroupState::angles.
constexpr int angleSlot(int k, int i) { return kMaxJointCoordinates * k + i; }

/// Force elements and drive of one joint coordinate.
struct CoordinateDrive {
  double stiffness = 0.0;   ///< k ≥ 0: spring moment −k (φ − rest_angle)
  double rest_angle = 0.0;  ///< φ₀
  double damping = 0.0;     ///< c ≥ 0: dashpot moment −c φ̇
  std::optional<TimeFunction> moment;      ///< applied moment M(t)
  std::optional<TimeFunction> prescribed;  ///< imposed φ(t)
  /// A program's moment M(t, φ, φ̇) (UserLoads::JointMoment), added to the above.
  std::function<double(double t, double phi, double phidot)> user_moment;
  /// Whether the coordinate's motion or force is a function of time: an
  /// applied moment M(t), prescribed motion φ(t) or a program's moment.
  bool dependsOnTime() const { return moment.has_value() || prescribed.has_value() || static_cast<bool>(user_moment); }
  bool hasForce() const {
    return stiffness != 0.0 || damping != 0.0 || moment.has_value() || static_cast<bool>(user_moment);
  }
  /// The applied moment M(t) (0 without one).
  double appliedMoment(double t) const { return moment ? (*moment)(t) : 0.0; }
  /// The moment of the force elements at (t, φ, φ̇).
  double momentAt(double t, double phi, double phidot) const {
    double M = -stiffness * (phi - rest_angle) - damping * phidot + appliedMoment(t);
    if (user_moment) M += user_moment(t, phi, phidot);
    return M;
  }
};

/// The drives of one joint's coordinates (unused slots stay empty).
using CoordinateDrives = std::array<CoordinateDrive, kMaxJointCoordinates>;

using GearConstraint = std::variant<constraints::GearJoint<double>, constraints::RackPinionJoint<double>,
                                    constraints::DifferentialJoint<double>, constraints::CouplingJoint<double>>;

/// A gear-type constraint: bodies (carrier N0, node 1, node 2[, node 3]),
/// kGround allowed for the carrier.
struct Gear {
  std::string name;
  std::array<int, 4> bodies{{kGround, kGround, kGround, kGround}};
  GearConstraint constraint;
};


/// Joint outputs for the trajectory CSV (README "Trajectory and recording CSV").
struct JointOutput {
  JointKind kind = JointKind::kSpherical;
  int coordinates = 0;               ///< 0 (spherical, fixed), 1 (revolute, prismatic), 2 (universal)
  /// Per coordinate: φ, φ̇ and the moment on the main body about the axis
  /// (prismatic: x, ẋ and the force on the main body along the axis).
  std::array<double, kMaxJointCoordinates> phi{}, phidot{}, moment{};
  /// Fixed joint: the reaction on the secondary body, force (fx, fy, fz) and
  /// moment about the anchor (mx, my, mz), in the main body's frame.
  Eigen::Matrix<double, 6, 1> reaction = Eigen::Matrix<double, 6, 1>::Zero();
  double condition = 1.0;            ///< universal: κ = 1/min|cos φᵢ| (universal_angles.hpp)
};

}  // namespace lieflow
