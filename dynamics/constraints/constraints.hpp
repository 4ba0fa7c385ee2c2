/// \file
/// The kinematic constraint library of the joints issue, in maximal
/// coordinates (each body its own pose (R, p), joints as constraints imposed
/// with Lagrange multipliers; joint angles as functions of the body poses).
/// Header-only, templated on the scalar (double, ceres::Jet).
///
///   body_pose.hpp        BodyPose, BodyVelocity, ground, ConstraintBlocks
///   validation.hpp       bad-input checks (InvalidInput naming the field)
///   angle_wrap.hpp       principal and unwrapped angles
///   spherical.hpp        spherical joint (3 rows)
///   dot_row.hpp          dot-1 row of two body-fixed directions
///   dot_two_row.hpp      dot-2 row: a body-fixed direction against the anchors' separation
///   align.hpp            three dot-1 rows holding the relative rotation
///   prismatic.hpp        prismatic joint (5 rows) and its coordinate x
///   fixed.hpp            fixed joint: a prismatic joint with its slide held
///   revolute.hpp         revolute joint (5 rows)
///   revolute_angle.hpp   φ_J, its rate, Jacobian and convective term
///   universal.hpp        universal joint (4 rows)
///   universal_angles.hpp φ₁, φ₂, rates, Jacobians, the 90° singularity
///   offset_universal.hpp a universal joint whose hinges do not meet (4 rows)
///   gimbal.hpp           three hinges through one point (3 rows) and their angles
///   gear_terms.hpp       spin and slide terms of the gear rows
///   gear.hpp             gear, rack and pinion, differential (velocity rows)
#pragma once

#include "dynamics/constraints/angle_wrap.hpp"
#include "dynamics/constraints/body_pose.hpp"
#include "dynamics/constraints/align.hpp"
#include "dynamics/constraints/dot_row.hpp"
#include "dynamics/constraints/dot_two_row.hpp"
#include "dynamics/constraints/fixed.hpp"
#include "dynamics/constraints/gear.hpp"
#include "dynamics/constraints/gear_terms.hpp"
#include "dynamics/constraints/gimbal.hpp"
#include "dynamics/constraints/offset_universal.hpp"
#include "dynamics/constraints/prismatic.hpp"
#include "dynamics/constraints/revolute.hpp"
#include "dynamics/constraints/revolute_angle.hpp"
#include "dynamics/constraints/spherical.hpp"
#include "dynamics/constraints/universal.hpp"
#include "dynamics/constraints/universal_angles.hpp"
#include "dynamics/constraints/validation.hpp"
