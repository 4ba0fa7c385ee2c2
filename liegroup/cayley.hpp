/// \file
/// The Cayley map of so(3) and se(3), cay(ξ) = (I − ξ^/2)⁻¹ (I + ξ^/2), a
/// rational retraction that Cayley-based variational integrators use instead
/// of exp (Kobilarov & Marsden 2011, "Discrete geometric optimal control on
/// Lie groups", §2.3; Lee, Leok, McClamroch 2005 use exp for the same role).
///
/// For so(3), with θ = ‖w‖:
///   cay(w) = I + 4/(4 + θ²) (W + W²/2),  the rotation by 2 atan(θ/2) about w/θ,
///   as a quaternion (1, w/2)/√(1 + θ²/4).
/// Trivialized derivatives, with lieflow's right perturbations:
///   cay(w + δ) ≈ cay(w) exp(dcayRight(w) δ),   dcayRight(w) = 2/(4+θ²) (2I − W),
///   cay(w + δ) ≈ exp(dcayLeft(w) δ) cay(w),    dcayLeft(w)  = 2/(4+θ²) (2I + W),
/// and their inverses I ± W/2 + w wᵀ/4 (no division at all).
#pragma once

#include "liegroup/se3.hpp"
#include "liegroup/so3.hpp"

namespace lieflow {

/// cay(w) ∈ SO(3) for any w ∈ ℝ³ (never reaches a rotation by π).
template <typename T>
SO3<T> cay(const Vector3<T>& w) {
  using std::sqrt;
  const T inv_norm = T(1) / sqrt(T(1) + T(0.25) * w.squaredNorm());
  const T s = T(0.5) * inv_norm;
  return SO3<T>(Eigen::Quaternion<T>(inv_norm, s * w.x(), s * w.y(), s * w.z()));
}

/// cay⁻¹(R) = 2 v / q_w for R = (q_w, v). Precondition: the rotation angle is
/// below π (q_w ≠ 0); the Cayley map does not reach rotations by π.
template <typename T>
Vector3<T> cayInv(const SO3<T>& R) {
  const auto& q = R.quaternion();
  LIEFLOW_ASSERT(scalarValue(q.w()) != 0.0, "cayInv: rotation by pi is outside the Cayley chart");
  return (T(2) / q.w()) * q.vec();
}

/// dcayRight(w) = 2/(4+θ²) (2I − W):  cay(w + δ) ≈ cay(w) exp(dcayRight(w) δ).
template <typename T>
Matrix3<T> dcayRight(const Vector3<T>& w) {
  return (T(2) / (T(4) + w.squaredNorm())) * (T(2) * Matrix3<T>::Identity() - SO3<T>::hat(w));
}

/// dcayRight(w)⁻¹ = I + W/2 + w wᵀ/4.
template <typename T>
Matrix3<T> dcayRightInv(const Vector3<T>& w) {
  return Matrix3<T>::Identity() + T(0.5) * SO3<T>::hat(w) + T(0.25) * w * w.transpose();
}

/// dcayLeft(w) = 2/(4+θ²) (2I + W):  cay(w + δ) ≈ exp(dcayLeft(w) δ) cay(w).
template <typename T>
Matrix3<T> dcayLeft(const Vector3<T>& w) {
  return (T(2) / (T(4) + w.squaredNorm())) * (T(2) * Matrix3<T>::Identity() + SO3<T>::hat(w));
}

/// dcayLeft(w)⁻¹ = I − W/2 + w wᵀ/4.
template <typename T>
Matrix3<T> dcayLeftInv(const Vector3<T>& w) {
  return Matrix3<T>::Identity() - T(0.5) * SO3<T>::hat(w) + T(0.25) * w * w.transpose();
}

/// cay(ρ, ω) ∈ SE(3): rotation cay(ω), translation (I − W/2)⁻¹ ρ
///   = 4/(4+θ²) (ρ + ω×ρ/2 + ω (ω·ρ)/4).
template <typename T>
SE3<T> cay(const Vector6<T>& xi) {
  const Vector3<T> rho = xi.template head<3>();
  const Vector3<T> w = xi.template tail<3>();
  const T scale = T(4) / (T(4) + w.squaredNorm());
  const Vector3<T> t = scale * (rho + T(0.5) * w.cross(rho) + T(0.25) * w.dot(rho) * w);
  return SE3<T>(cay(w), t);
}

/// cay⁻¹(R, t) = ((I − W/2) t, ω) with ω = cay⁻¹(R). Same precondition as SO(3).
template <typename T>
Vector6<T> cayInv(const SE3<T>& X) {
  const Vector3<T> w = cayInv(X.rotation());
  Vector6<T> xi;
  xi.template head<3>() = X.translation() - T(0.5) * w.cross(X.translation());
  xi.template tail<3>() = w;
  return xi;
}

}  // namespace lieflow
