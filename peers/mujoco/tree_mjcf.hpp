/// \file
/// A lieflow tree in joint coordinates (dynamics/joint_space/) written as
/// MJCF, and its initial state given to MuJoCo, so that both engines run the
/// same mechanism from the same state (bench/ and papers/; the MJCF is
/// compiled with model/import/mjcf_model.hpp's compileModelFiles).
///
/// The MJCF of a tree: one nested <body> per lieflow body, its frame the
/// lieflow body frame (origin at the centre of mass, so <inertial pos="0 0 0"
/// fullinertia=...> is lieflow's mass and inertia about the centre of mass),
/// placed in its parent's frame as at zero joint angles. A revolute joint
/// with the parent as its main body is a hinge at anchor_secondary about
/// R_refᵀ a (child frame) and qpos = φ, since R_child = R_p R_ref exp(φ R_refᵀ a)
/// = R_p exp(φ a) R_ref; given child-first it is a hinge about −a with the
/// child frame R_refᵀ. A spherical joint is a ball at the anchor, qpos the
/// relative rotation N, qvel = ω_rel in the child frame (both engines' choice).
/// Spring stiffness, rest angle and damping become the hinge's stiffness,
/// springref and damping. A universal joint is two hinges with a light cross
/// between them (MuJoCo has no universal joint), a rotation-only body a body
/// whose joint passes through its centre, and a joint that closes a loop
/// MuJoCo's soft equality constraints (mjcfFromTree says how). What MJCF
/// cannot say this way (applied or prescribed moments, loads from programs,
/// gear-type joints) is refused with the reason.
#pragma once

#include <string>

#include "dynamics/joint_space/articulated_system.hpp"

struct mjModel_;
struct mjData_;

namespace lieflow {
namespace mujoco_peer {

/// MuJoCo's integrator names in MJCF.
const char* mjIntegratorName(const std::string& name);

/// How the tree is written (mjcfFromTree).
struct MjcfOptions {
  std::string integrator = "RK4";  ///< RK4, Euler or implicit
  double h = 1e-3;                 ///< the time step
  /// The loops' equality constraints: solref's time constant [s] (0: MuJoCo's
  /// default 0.02) with damping ratio 1, and solimp's impedance d (the same
  /// at every violation; MuJoCo clamps it to 0.9999). MuJoCo's constraints
  /// are soft: the closer d is to 1 and the shorter the time constant, the
  /// stiffer (MuJoCo's docs, "Solver parameters").
  double loop_timeconst = 0.0;
  double loop_impedance = 0.9999;
  /// Mass [kg] and inertia [kg m²] of the cross of a universal joint (MuJoCo
  /// refuses a moving body without them; lieflow's cross is massless). Their
  /// effect, measured: a hanging pair of bodies on two universal joints agrees
  /// with lieflow to 6.5e-11 m after 0.5 s (MuJoCo RK4 at h = 1e-5; the same
  /// pair without the crosses' inertia is not writable), two tumbling
  /// rotation-only bodies on a sprung universal joint to 1.8e-11 rad.
  double cross_mass = 1e-9;
  double cross_inertia = 1e-12;
  /// The length [m] along a closing hinge's axis to its second connect point.
  double axis_length = 1.0;
};

/// The names of the MuJoCo joints of tree body i: "<name>:1" (a hinge, a
/// ball, or a universal joint's first hinge, which turns its cross) and
/// "<name>:2" (a universal joint's second hinge).
std::string mjJointName(const articulated::ArticulatedModel& model, int i, int which);

/// The tree as one MJCF document (at most ~90 nested bodies: MuJoCo's XML
/// parser refuses deeper documents); throws std::invalid_argument for what
/// it cannot write (file comment). Bodies keep lieflow's names; a universal
/// joint's cross is a body "<name>:cross" of options.cross_mass between the
/// parent and the child, turned by the first hinge. A rotation-only body
/// must have its joint's anchor at its centre (MuJoCo then holds the
/// centre). A loop-closing joint becomes equality constraints between its
/// two bodies: a ball joint a connect at the anchor (body1 the secondary
/// body, its anchor in that body's frame); a revolute joint one there and
/// one at options.axis_length along the axis; a universal joint the point
/// connect and a spatial tendon of fixed length from a site at
/// options.axis_length along a₁ (main body) to one along a₂ (secondary): the
/// cross's right angle as the distance √2 · axis_length. (A light cross body
/// on the main side would carry the rows instead: tried, it makes MuJoCo's
/// soft rows so soft that the shafts barely feel the loop — R scales with
/// the cross's tiny inverse inertia.) The point connect is left out where
/// both sides hold the anchor (the ground, or a rotation-only body anchored
/// at its centre: the rows would vanish). MuJoCo places body2's anchor and the
/// tendon's length from the configuration qpos0 (all joints at zero):
/// setMujocoState checks that lieflow's initial state is that configuration.
std::string mjcfFromTree(const articulated::ArticulatedModel& model, const MjcfOptions& options);

/// d ← the lieflow state y at t = 0 (qpos: angles and the spherical joints'
/// quaternions, qvel: u; MuJoCo's joints found by name, mjJointName). Throws
/// std::runtime_error when a loop's constraints do not hold at that state
/// (MuJoCo placed their anchors at qpos0, all joints at zero). Defined only
/// in builds with MuJoCo.
void setMujocoState(const articulated::ArticulatedModel& model, const articulated::ArticulatedState& y,
                    const mjModel_* m, mjData_* d);

}  // namespace mujoco_peer
}  // namespace lieflow
