/// \file
/// Three dot-1 rows (dot_row.hpp) that hold the relative rotation of two
/// bodies fixed, R_a⁻¹ R_b = R_ref: Abaqus' ALIGN connection (all three local
/// directions aligned), the rotational half of the prismatic (TRANSLATOR =
/// SLOT + ALIGN) and fixed (WELD = JOIN + ALIGN) joints.
///
/// With (u, v, a) a right-handed orthonormal triad in the main frame and its
/// copies in the secondary frame a' = R_ref⁻¹ a, v' = R_ref⁻¹ v:
///   Φ = [ (R_a u)·(R_b a') ;  (R_a v)·(R_b a') ;  (R_a u)·(R_b v') ].
/// On the manifold (R_b = R_a R_ref) the rows' directions n = U × W are
/// R_a (u × a, v × a, u × v) = R_a (−v, u, a): orthonormal, so the three rows
/// are independent and as well conditioned as rows can be. Φ = 0 also holds
/// at isolated rotations away from R_ref (the dot products vanish for a
/// half-turn about a, for instance); the position projection starts on the
/// manifold and stays in its neighbourhood, as for the revolute joint's rows.
#pragma once

#include <array>

#include "dynamics/constraints/body_pose.hpp"
#include "dynamics/constraints/dot_row.hpp"

namespace lieflow {
namespace constraints {

template <typename T>
struct AlignRows {
  static constexpr int kRows = 3;
  Vector3<T> u_main, v_main;              ///< u, v (main frame); a = u × v
  Vector3<T> a_secondary, v_secondary;    ///< a' = R_ref⁻¹ a, v' = R_ref⁻¹ v (secondary frame)
  SO3<T> reference;                       ///< R_ref = R_a⁻¹ R_b, held

  std::array<DotRow<T>, 3> rows() const {
    return {{DotRow<T>{u_main, a_secondary}, DotRow<T>{v_main, a_secondary}, DotRow<T>{u_main, v_secondary}}};
  }
};

/// The align rows of the triad (u, v, a) (u, v unit, orthogonal; main frame)
/// at the relative rotation `reference`.
template <typename T>
AlignRows<T> makeAlignRows(const Vector3<T>& u, const Vector3<T>& v, const SO3<T>& reference) {
  AlignRows<T> r;
  r.u_main = u;
  r.v_main = v;
  r.reference = reference;
  r.a_secondary = reference.inverse() * Vector3<T>(u.cross(v));
  r.v_secondary = reference.inverse() * v;
  return r;
}

}  // namespace constraints
}  // namespace lieflow
