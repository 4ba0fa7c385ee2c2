/// \file
/// A tree of rigid bodies in joint coordinates (the "joint" formulation of
/// ../shared/DESIGN.md, `--formulation joint`): the model, built once from a
/// scene (articulated_scene.hpp), and the state on the joints' own groups.
///
/// Each body has exactly one joint to its parent (the ground or a body met
/// earlier in the body order), so the joints' coordinates are the whole
/// configuration of the tree: a revolute joint is
/// one angle φ (ℝ, unwrapped), a universal joint two angles (φ₁, φ₂), a
/// spherical joint a rotation N ∈ SO(3) of the child relative to its parent,
/// a prismatic joint one slide x ∈ ℝ along its axis (the relative rotation
/// R_ref held; the secondary anchor at the main one + x R_main a). A body
/// no joint reaches from the ground and that is not rotation-only is a root
/// on a free joint, on SO(3) × ℝ³ as the maximal formulation's bodies are:
/// (R, c) with (ω body axes, v_c world) — the translation stays linear
/// (gravity moves it exactly, the momentum about the centre of mass is kept
/// as in maximal coordinates) where SE(3) would couple it to the rotation.
/// A gimbal is three angles, M = exp(φ₁ e₁) exp(φ₂ e₂) exp(φ₃ e₃) R_ref
/// (e_k in the main frame at zero angles), its hinges through one point; an
/// offset universal joint turns about A₁ through the main anchor and about
/// A₂ through the secondary anchor, which the first hinge carries around
/// (MuJoCo's two hinges of one body at two points). Both hang from their
/// main body (the parent).
///
/// Relative rotation of the secondary body to the main one (R_b = R_a M), the
/// same coordinates as the maximal formulation's joint angles
/// (dynamics/constraints/revolute_angle.hpp, universal_angles.hpp):
///   revolute   M = exp(φ a) R_ref,
///   universal  M = exp(φ₁ a₁) R_ref exp(φ₂ a₂),
/// a, a₁ in the main body's frame, a₂ in the secondary's, R_ref the relative
/// rotation at zero angles. The anchors coincide: c_b + R_b s_b = c_a + R_a s_a.
///
/// A joint that closes a loop (ArticulatedClosure) adds constraint rows on
/// top of the tree, imposed with multipliers: the configuration is then the
/// subset of the coordinates where they hold.
#pragma once

#include <array>
#include <optional>
#include <type_traits>
#include <variant>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "dynamics/joint_types.hpp"

namespace lieflow {
namespace articulated {

/// kFixed: a weld, no coordinate; the child moves with its parent (R_ref and
/// the anchors held), its inertia joins the parent's articulated inertia and
/// the force across the weld is the one the articulated-body algorithm
/// passes (the J.fx … J.mz columns).
enum class JointKind { kRevolute, kUniversal, kSpherical, kPrismatic, kFree, kGimbal, kFixed };

/// The parent of a body attached to the ground (dynamics/body_index.hpp).
using ::lieflow::kGround;

/// One body of the tree with the joint to its parent: what every evaluation
/// reads (names and force elements live beside, in ArticulatedModel, so that
/// a chain of a thousand bodies stays in the cache).
struct ArticulatedBody {
  double mass = 0.0;
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Identity();  ///< about the centre of mass, body axes
  int parent = kGround;                                   ///< tree index, < own index
  int scene_joint = -1;                                   ///< index in SceneDescription::joints; −1: none
  /// A rotation-only body: its centre of mass stays at `fixed_position`
  /// (held by a support, as in the maximal formulation); it turns with its
  /// joint. A rotation-only body no joint reaches from the ground is a root
  /// on an implicit spherical joint at its centre of mass (scene_joint −1).
  bool rotation_only = false;
  Eigen::Vector3d fixed_position = Eigen::Vector3d::Zero();
  /// The scene's orientation at t = 0 (outputs take its quaternion sign).
  Eigen::Quaterniond initial_orientation = Eigen::Quaterniond::Identity();

  JointKind kind = JointKind::kRevolute;
  /// Whether the parent is the joint's main body (else its secondary: the
  /// joint's coordinates then turn the parent relative to the child).
  bool parent_is_main = true;
  /// The joint's anchor from the parent's centre of mass, parent axes (world
  /// coordinates of the anchor for the ground), and from the child's.
  Eigen::Vector3d anchor_parent = Eigen::Vector3d::Zero();
  Eigen::Vector3d anchor_child = Eigen::Vector3d::Zero();
  /// Revolute, prismatic: axis a (main frame). Universal: a₁ (main frame), a₂ (secondary frame).
  /// Gimbal: e₁, e₂, e₃ (main frame at zero angles).
  Eigen::Vector3d axis1 = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d axis2 = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d axis3 = Eigen::Vector3d::UnitZ();
  /// An offset universal joint (the second axis through the secondary
  /// anchor, apart from the first): the secondary anchor from the main one in
  /// the main frame at φ₁ = 0; the joint's main body is the parent.
  bool offset = false;
  Eigen::Vector3d offset_ref = Eigen::Vector3d::Zero();
  /// Relative rotation main → secondary at zero angles.
  Eigen::Matrix3d R_ref = Eigen::Matrix3d::Identity();
  /// Whether each coordinate has force elements (ArticulatedModel::drives)
  /// and whether its motion is prescribed.
  std::array<bool, 3> has_force{{false, false, false}};
  std::array<bool, 3> is_prescribed{{false, false, false}};

  /// Offsets into the state: scalar angles (revolute, universal), the
  /// spherical joints' rotations, and the velocity vector u. A free root
  /// keeps its centre of mass c in q at q_begin, v_c (world) in u at
  /// u_begin, its orientation among the rotations and ω (body axes) in u
  /// at u_rotation.
  int q_begin = 0;
  int rotation = -1;
  int u_begin = 0;
  int u_rotation = -1;

  int coordinates() const {
    if (kind == JointKind::kRevolute || kind == JointKind::kPrismatic) return 1;
    return kind == JointKind::kUniversal ? 2 : kind == JointKind::kGimbal ? 3 : 0;
  }
  int dofs() const { return kind == JointKind::kSpherical ? 3 : kind == JointKind::kFree ? 6 : coordinates(); }
  bool prescribed(int i) const { return is_prescribed[i]; }
};

/// A joint that closes a loop of the tree (the tree's joints are the bodies'
/// joints to their parents; every other joint of the scene closes a loop),
/// or the rows of a gear-type joint (they couple other joints' motions):
/// imposed with multipliers, as a constraint of the maximal formulation
/// (dynamics/constraints/) on the poses of its two bodies, which the tree
/// gives as functions of the joint coordinates (articulated_closures.cpp).
/// It carries no force element and no prescribed motion (the assembly puts
/// the joints that do in the tree, and refuses a loop of only such joints:
/// they would act on a coordinate the state does not have).
struct ArticulatedClosure {
  JointConstraint constraint;  ///< a closing joint's rows (if not a gear)
  /// Gear-type rows (gear, rack and pinion, differential; dynamics/constraints/
  /// gear.hpp): imposed on the velocities only, as in maximal coordinates.
  std::optional<GearConstraint> gear;
  /// Tree indices (or kGround) of the joint's main and secondary bodies, or
  /// of the gear's carrier and nodes.
  std::array<int, 4> bodies{{kGround, kGround, kGround, kGround}};
  int scene_joint = -1;     ///< index in SceneDescription::joints
  std::string label;        ///< "SOURCE: joints[k] (name)", for messages
  int row_begin = 0;        ///< its first row among all closure rows
  /// Its angles at t = 0 (the scene's initial_angle(s)): where the outputs'
  /// unwrapping starts.
  std::array<double, 2> initial_angles{{0.0, 0.0}};
  int rows() const {
    if (!gear) return constraintRows(constraint);
    return std::visit([](const auto& g) { return std::decay_t<decltype(g)>::kRows; }, *gear);
  }
};

/// The model: bodies in tree order (every parent before its children).
struct ArticulatedModel {
  std::vector<ArticulatedBody> bodies;
  /// By tree index: the body's name, and the force elements and prescribed
  /// motion of its joint's coordinates.
  std::vector<std::string> names;
  std::vector<std::array<CoordinateDrive, 3>> drives;
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();
  int scalar_coordinates = 0;  ///< nq: angles of revolute and universal joints
  int rotations = 0;           ///< ns: spherical joints
  /// Scene body index → tree index.
  std::vector<int> tree_index;
  /// How many joints the scene has (the joint outputs are by scene joint).
  int scene_joints = 0;
  /// The loop-closing joints and their rows in all (Σ rows()).
  std::vector<ArticulatedClosure> closures;
  int closure_rows = 0;

  int dofs() const { return scalar_coordinates + 3 * rotations; }
  int bodyCount() const { return static_cast<int>(bodies.size()); }
};

}  // namespace articulated
}  // namespace lieflow
