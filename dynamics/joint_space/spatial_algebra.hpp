/// \file
/// Spatial vector algebra of the joint formulation (Featherstone, "Rigid Body
/// Dynamics Algorithms", 2008, ch. 2), in world axes about the world origin:
/// a motion V = (ω, v_O), a force (n_O, f). The small inline operations
/// every pass of the articulated-body code uses, in one place.
#pragma once

#include <cmath>

#include <Eigen/Core>

namespace lieflow {
namespace articulated {

using Vector6 = Eigen::Matrix<double, 6, 1>;
using Matrix6 = Eigen::Matrix<double, 6, 6>;

/// a × b written out: Eigen's cross on 3-blocks of 6-vectors is left out of
/// line by GCC inside the large passes (12 % of the ABA's time in calls).
EIGEN_ALWAYS_INLINE Eigen::Vector3d cross3(const Eigen::Ref<const Eigen::Vector3d>& a,
                                           const Eigen::Ref<const Eigen::Vector3d>& b) {
  return Eigen::Vector3d(a.y() * b.z() - a.z() * b.y(), a.z() * b.x() - a.x() * b.z(), a.x() * b.y() - a.y() * b.x());
}

/// cos φ and sin φ from one call (adjacent, so that GCC makes them one sincos).
EIGEN_ALWAYS_INLINE void sinCos(double phi, double* c, double* s) {
  const double cc = std::cos(phi), ss = std::sin(phi);
  *c = cc;
  *s = ss;
}

/// [v]×, the cross-product matrix.
EIGEN_ALWAYS_INLINE Eigen::Matrix3d hat(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

/// exp(φ a) for a unit axis a (Rodrigues): cos φ I + sin φ [a]× + (1 − cos φ) a aᵀ,
/// from c = cos φ and s = sin φ.
EIGEN_ALWAYS_INLINE Eigen::Matrix3d rotationAbout(const Eigen::Vector3d& a, double c, double s) {
  Eigen::Matrix3d m = (1.0 - c) * (a * a.transpose());
  m.diagonal().array() += c;
  m(0, 1) -= s * a.z();
  m(1, 0) += s * a.z();
  m(0, 2) += s * a.y();
  m(2, 0) -= s * a.y();
  m(1, 2) -= s * a.x();
  m(2, 1) += s * a.x();
  return m;
}
EIGEN_ALWAYS_INLINE Eigen::Matrix3d rotationAbout(const Eigen::Vector3d& a, double phi) {
  return rotationAbout(a, std::cos(phi), std::sin(phi));
}

/// Below this |φ − φ₀| sinCosNear uses the addition formulas.
constexpr double kNearAngle = 0.05;

/// cos φ and sin φ from those of a nearby φ₀ (c₀, s₀): the addition formulas
/// with the Taylor series of δ = φ − φ₀ to δ⁹ and δ¹⁰, whose first terms left
/// out are below 1e-21 for |δ| < kNearAngle (the libm call costs as much as
/// the rest of a joint's pose); std::cos and std::sin beyond.
EIGEN_ALWAYS_INLINE void sinCosNear(double phi, double phi0, double c0, double s0, double* c, double* s) {
  const double d = phi - phi0;
  if (!(std::abs(d) < kNearAngle)) {
    sinCos(phi, c, s);
    return;
  }
  const double d2 = d * d;
  const double sd = d * (1.0 - d2 / 6.0 * (1.0 - d2 / 20.0 * (1.0 - d2 / 42.0 * (1.0 - d2 / 72.0))));
  const double cd = 1.0 - d2 / 2.0 * (1.0 - d2 / 12.0 * (1.0 - d2 / 30.0 * (1.0 - d2 / 56.0 * (1.0 - d2 / 90.0))));
  *c = c0 * cd - s0 * sd;
  *s = s0 * cd + c0 * sd;
}

/// The unit rotation twist about the line through x with direction A: (A, x × A).
EIGEN_ALWAYS_INLINE Vector6 lineTwist(const Eigen::Vector3d& A, const Eigen::Vector3d& x) {
  Vector6 s;
  s.head<3>() = A;
  s.tail<3>() = cross3(x, A);
  return s;
}

/// V ×ₘ m (motion cross product).
EIGEN_ALWAYS_INLINE Vector6 crossMotion(const Vector6& V, const Vector6& m) {
  Vector6 r;
  r.head<3>() = cross3(V.head<3>(), m.head<3>());
  r.tail<3>() = cross3(V.head<3>(), m.tail<3>()) + cross3(V.tail<3>(), m.head<3>());
  return r;
}

/// V ×_f h (force cross product).
EIGEN_ALWAYS_INLINE Vector6 crossForce(const Vector6& V, const Vector6& h) {
  Vector6 r;
  r.head<3>() = cross3(V.head<3>(), h.head<3>()) + cross3(V.tail<3>(), h.tail<3>());
  r.tail<3>() = cross3(V.head<3>(), h.tail<3>());
  return r;
}

/// A rotation-only body held at c moves as P (ω, v) = (ω, c × ω): P as a
/// 6 × 6 matrix [I 0; [c]× 0].
inline Matrix6 rotationOnlyMap(const Eigen::Vector3d& c) {
  Matrix6 P = Matrix6::Zero();
  P.topLeftCorner<3, 3>().setIdentity();
  P.bottomLeftCorner<3, 3>() = hat(c);
  return P;
}

/// P V without the matrix: (ω, c × ω).
/// A free root's columns S = [R 0; [c]× R I] (u = (ω body, v_c world) to
/// its motion (ω, v_O) about the origin, v_O = v_c + c × ω).
inline Matrix6 freeColumns(const Eigen::Matrix3d& R, const Eigen::Vector3d& c) {
  Matrix6 S;
  S << R, Eigen::Matrix3d::Zero(), hat(c) * R, Eigen::Matrix3d::Identity();
  return S;
}

EIGEN_ALWAYS_INLINE Vector6 heldMotion(const Eigen::Vector3d& c, const Vector6& V) {
  Vector6 r;
  r.head<3>() = V.head<3>();
  r.tail<3>() = cross3(c, V.head<3>());
  return r;
}

/// Pᵀ F: the force (n, f) on a body held at c as its moment about c, (n − c × f, 0).
EIGEN_ALWAYS_INLINE Vector6 heldForce(const Eigen::Vector3d& c, const Vector6& F) {
  Vector6 r;
  r.head<3>() = F.head<3>() - cross3(c, F.tail<3>());
  r.tail<3>().setZero();
  return r;
}

}  // namespace articulated
}  // namespace lieflow
