/// \file
/// The fixed joint (weld): all relative motion held, Abaqus' WELD connection
/// (JOIN + ALIGN). A scene keeps a fixed joint as a constraint when its
/// reaction is wanted (columns J.fx … J.mz); a model importer merges welded
/// bodies instead, which costs nothing at run time.
///
/// It is a prismatic joint (prismatic.hpp) whose slide is held: the five rows
/// of the slot (two dot-2 rows) and the align rows (three dot-1 rows), with
/// the slide axis a = e_z of the main frame, and the sixth condition
///   x = (R_a a)·(x_b − x_a) = 0,
/// the coordinate row position(), which the multibody system imposes as a
/// held coordinate (a one-row group of its own, like a prescribed
/// coordinate: the Schur solver's blocks have at most five rows, and six-row
/// blocks would cost every chain of revolute joints 5–10 % per step,
/// measured). Together: x_b = x_a and R_a⁻¹ R_b = R_ref, six independent rows
/// whose directions on the manifold are orthonormal.
///
/// The reaction on the secondary body is −J_bᵀ λ over the six rows: a force f
/// (world) and a moment (body frame, about its centre of mass), reported about
/// the anchor point in the main body's frame (multibody_observables.cpp).
#pragma once

#include <string>

#include "dynamics/constraints/prismatic.hpp"

namespace lieflow {
namespace constraints {

template <typename T>
struct FixedJoint : PrismaticJoint<T> {};

/// A fixed joint holding the relative rotation `reference` (R_a⁻¹ R_b) and
/// the anchors together; anchors checked finite (fields "PREFIX.anchor_*").
template <typename T>
FixedJoint<T> makeFixedJoint(const Vector3<T>& anchor_main, const Vector3<T>& anchor_secondary,
                             const SO3<T>& reference, const std::string& prefix = "") {
  FixedJoint<T> j;
  static_cast<PrismaticJoint<T>&>(j) =
      makePrismaticJoint<T>(anchor_main, anchor_secondary, Vector3<T>::UnitZ(), reference, prefix);
  return j;
}

/// A fixed joint assembled at the poses main0, secondary0 (R_ref their
/// relative rotation; the anchors must coincide, checked by the caller).
template <typename T>
FixedJoint<T> assembleFixedJoint(const BodyPose<T>& main0, const BodyPose<T>& secondary0,
                                 const Vector3<T>& anchor_main, const Vector3<T>& anchor_secondary,
                                 const std::string& prefix = "") {
  return makeFixedJoint<T>(anchor_main, anchor_secondary, SO3<T>(main0.R.inverse() * secondary0.R), prefix);
}

}  // namespace constraints
}  // namespace lieflow
