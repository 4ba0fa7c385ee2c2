/// \file
/// The two kinds of term of the Radioss gear-type MPC rows (/MPC gear,
/// rack-and-pinion and differential joints; ../shared/seeds/README.md), as
/// blocks per participating body (carrier N0 first, then the nodes), and
/// their convective terms. Each row of gear.hpp is a sum of such terms.
///
/// Notation: carrier 0 with pose (R₀, p₀) and velocity (v₀, ω₀), node i with
/// (R_i, p_i), (v_i, ω_i); Ω = R ω (world); a node axis x_i (one of its local
/// r, s, t) is fixed in the node's body frame, X_i = R_i x_i (world).
///
/// Spin term  c (Δω_i · X_i),  Δω_i = Ω_i − Ω₀:
///   since Ω_i·X_i = ω_i·x_i,  block_i[δθ] += c x_iᵀ,  block_0[δθ] −= c (R₀ᵀ X_i)ᵀ;
///   convective (Δω̇_i = R_i ω̇_i − R₀ ω̇₀ because Ṙω = R ω^ω = 0, Ẋ_i = Ω_i × X_i):
///   c Δω_i · (Ω_i × X_i).
///
/// Slide term  c (ΔV_i · X_i),  ΔV_i = v_i − v₀ − Ω₀ × (p_i − p₀):
///   the velocity of node i relative to the carrier's material point at p_i
///   (for a non-rotating carrier v_i − v₀, for ground v_i); with d = p_i − p₀,
///   block_i[δp] += c X_iᵀ,  block_0[δp] −= c X_iᵀ,  block_0[δθ] −= c (R₀ᵀ (d × X_i))ᵀ;
///   convective (ḋ = v_i − v₀): c [ΔV_i · (Ω_i × X_i) − (Ω₀ × ḋ) · X_i].
///   The transport term makes the row integrable: if X_i is fixed in the
///   carrier, ΔV_i·X_i = d/dt[(p_i − p₀)·X_i].
/// The blocks multiply (v, ω) of each body; d/dt(B q̇) = B q̈ + convective.
/// The carrier is slot 0 unless a term names another (`carrier`: a coupling
/// of two joints with different parents).
#pragma once

#include <array>
#include <cstddef>

#include "dynamics/constraints/body_pose.hpp"

namespace lieflow {
namespace constraints {
namespace detail {

template <typename T, int Rows, std::size_t Bodies>
void addSpinTerm(ConstraintBlocks<T, Rows, Bodies>& B, int row, const T& c, std::size_t node,
                 const std::array<BodyPose<T>, Bodies>& X, const Vector3<T>& x_body, std::size_t carrier = 0) {
  const Vector3<T> Xw = X[node].R * x_body;
  B[node].template rightCols<3>().row(row) += c * x_body.transpose();
  B[carrier].template rightCols<3>().row(row) -= c * (X[carrier].R.inverse() * Xw).transpose();
}

template <typename T, std::size_t Bodies>
T spinTermConvective(const T& c, std::size_t node, const std::array<BodyPose<T>, Bodies>& X,
                     const std::array<BodyVelocity<T>, Bodies>& V, const Vector3<T>& x_body, std::size_t carrier = 0) {
  const Vector3<T> Xw = X[node].R * x_body;
  const Vector3<T> Oi = V[node].omegaWorld(X[node]);
  const Vector3<T> dw = Oi - V[carrier].omegaWorld(X[carrier]);
  return c * dw.dot(Oi.cross(Xw));
}

template <typename T, int Rows, std::size_t Bodies>
void addSlideTerm(ConstraintBlocks<T, Rows, Bodies>& B, int row, const T& c, std::size_t node,
                  const std::array<BodyPose<T>, Bodies>& X, const Vector3<T>& x_body, std::size_t carrier = 0) {
  const Vector3<T> Xw = X[node].R * x_body;
  const Vector3<T> d = X[node].p - X[carrier].p;
  B[node].template leftCols<3>().row(row) += c * Xw.transpose();
  B[carrier].template leftCols<3>().row(row) -= c * Xw.transpose();
  B[carrier].template rightCols<3>().row(row) -= c * (X[carrier].R.inverse() * d.cross(Xw)).transpose();
}

template <typename T, std::size_t Bodies>
T slideTermConvective(const T& c, std::size_t node, const std::array<BodyPose<T>, Bodies>& X,
                      const std::array<BodyVelocity<T>, Bodies>& V, const Vector3<T>& x_body,
                      std::size_t carrier = 0) {
  const Vector3<T> Xw = X[node].R * x_body;
  const Vector3<T> O0 = V[carrier].omegaWorld(X[carrier]);
  const Vector3<T> Oi = V[node].omegaWorld(X[node]);
  const Vector3<T> d = X[node].p - X[carrier].p;
  const Vector3<T> d_dot = V[node].v - V[carrier].v;
  const Vector3<T> dV = d_dot - O0.cross(d);
  return c * (dV.dot(Oi.cross(Xw)) - O0.cross(d_dot).dot(Xw));
}

}  // namespace detail
}  // namespace constraints
}  // namespace lieflow
