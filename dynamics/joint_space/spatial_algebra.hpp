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
/// (These operations are templates on the scalar, for the passes of
/// tree_passes.hpp on ceres::Jet; on double they are the same arithmetic.)
/// (A double vector with a Jet one gives Jets: a constant stays in double.)
template <class A, class B>
using CrossScalar =
    typename Eigen::ScalarBinaryOpTraits<typename A::Scalar, typename B::Scalar>::ReturnType;
template <class A, class B>
EIGEN_ALWAYS_INLINE Eigen::Matrix<CrossScalar<A, B>, 3, 1> cross3(const Eigen::MatrixBase<A>& a_in,
                                                                  const Eigen::MatrixBase<B>& b_in) {
  // Each coefficient is read twice: an expression is evaluated once first
  // (as Eigen's own cross does), a vector or block is read in place.
  const typename Eigen::internal::nested_eval<A, 2>::type a(a_in.derived());
  const typename Eigen::internal::nested_eval<B, 2>::type b(b_in.derived());
  return Eigen::Matrix<CrossScalar<A, B>, 3, 1>(a.y() * b.z() - a.z() * b.y(), a.z() * b.x() - a.x() * b.z(),
                                                a.x() * b.y() - a.y() * b.x());
}

/// cos φ and sin φ from one call (adjacent, so that GCC makes them one sincos).
template <typename T>
EIGEN_ALWAYS_INLINE void sinCos(T phi, T* c, T* s) {
  using std::cos;
  using std::sin;
  const T cc = cos(phi), ss = sin(phi);
  *c = cc;
  *s = ss;
}

/// [v]×, the cross-product matrix.
template <class D>
EIGEN_ALWAYS_INLINE Eigen::Matrix<typename D::Scalar, 3, 3> hat(const Eigen::MatrixBase<D>& v) {
  using T = typename D::Scalar;
  Eigen::Matrix<T, 3, 3> m;
  m << T(0.0), -v.z(), v.y(), v.z(), T(0.0), -v.x(), -v.y(), v.x(), T(0.0);
  return m;
}

/// exp(φ a) for a unit axis a (Rodrigues): cos φ I + sin φ [a]× + (1 − cos φ) a aᵀ,
/// from c = cos φ and s = sin φ.
template <typename T, typename A = T>
EIGEN_ALWAYS_INLINE Eigen::Matrix<T, 3, 3> rotationAbout(const Eigen::Matrix<A, 3, 1>& a, const T& c, const T& s) {
  // Written out (no Eigen product of a aᵀ: inside the passes GCC left that
  // out of line, 2.7 times the cost of the gimbal's rotations); the axis may
  // be a double constant where c and s are Jets.
  const T v = T(1.0) - c;
  const A xx = a.x() * a.x(), yy = a.y() * a.y(), zz = a.z() * a.z();
  const A xy = a.x() * a.y(), xz = a.x() * a.z(), yz = a.y() * a.z();
  Eigen::Matrix<T, 3, 3> m;
  m(0, 0) = v * xx + c;
  m(1, 1) = v * yy + c;
  m(2, 2) = v * zz + c;
  m(0, 1) = v * xy - s * a.z();
  m(1, 0) = v * xy + s * a.z();
  m(0, 2) = v * xz + s * a.y();
  m(2, 0) = v * xz - s * a.y();
  m(1, 2) = v * yz - s * a.x();
  m(2, 1) = v * yz + s * a.x();
  return m;
}
EIGEN_ALWAYS_INLINE Eigen::Matrix3d rotationAbout(const Eigen::Vector3d& a, double phi) {
  return rotationAbout<double>(a, std::cos(phi), std::sin(phi));
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
template <class A, class X>
EIGEN_ALWAYS_INLINE Eigen::Matrix<typename A::Scalar, 6, 1> lineTwist(const Eigen::MatrixBase<A>& axis,
                                                                      const Eigen::MatrixBase<X>& x) {
  Eigen::Matrix<typename A::Scalar, 6, 1> s;
  s.template head<3>() = axis;
  s.template tail<3>() = cross3(x, axis);
  return s;
}

/// V ×ₘ m (motion cross product).
template <class A, class B>
EIGEN_ALWAYS_INLINE Eigen::Matrix<typename A::Scalar, 6, 1> crossMotion(const Eigen::MatrixBase<A>& V,
                                                                        const Eigen::MatrixBase<B>& m) {
  Eigen::Matrix<typename A::Scalar, 6, 1> r;
  r.template head<3>() = cross3(V.template head<3>(), m.template head<3>());
  r.template tail<3>() =
      cross3(V.template head<3>(), m.template tail<3>()) + cross3(V.template tail<3>(), m.template head<3>());
  return r;
}

/// V ×_f h (force cross product).
template <class A, class B>
EIGEN_ALWAYS_INLINE Eigen::Matrix<typename A::Scalar, 6, 1> crossForce(const Eigen::MatrixBase<A>& V,
                                                                       const Eigen::MatrixBase<B>& h) {
  Eigen::Matrix<typename A::Scalar, 6, 1> r;
  r.template head<3>() =
      cross3(V.template head<3>(), h.template head<3>()) + cross3(V.template tail<3>(), h.template tail<3>());
  r.template tail<3>() = cross3(V.template head<3>(), h.template tail<3>());
  return r;
}

/// A rotation-only body held at c moves as P (ω, v) = (ω, c × ω): P as a
/// 6 × 6 matrix [I 0; [c]× 0].
template <class D>
inline Eigen::Matrix<typename D::Scalar, 6, 6> rotationOnlyMap(const Eigen::MatrixBase<D>& c) {
  using T = typename D::Scalar;
  Eigen::Matrix<T, 6, 6> P = Eigen::Matrix<T, 6, 6>::Zero();
  P.template topLeftCorner<3, 3>().setIdentity();
  P.template bottomLeftCorner<3, 3>() = hat(c);
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

template <class C, class D>
EIGEN_ALWAYS_INLINE Eigen::Matrix<typename D::Scalar, 6, 1> heldMotion(const Eigen::MatrixBase<C>& c,
                                                                       const Eigen::MatrixBase<D>& V) {
  Eigen::Matrix<typename D::Scalar, 6, 1> r;
  r.template head<3>() = V.template head<3>();
  r.template tail<3>() = cross3(c, V.template head<3>());
  return r;
}

/// Pᵀ F: the force (n, f) on a body held at c as its moment about c, (n − c × f, 0).
template <class C, class D>
EIGEN_ALWAYS_INLINE Eigen::Matrix<typename D::Scalar, 6, 1> heldForce(const Eigen::MatrixBase<C>& c,
                                                                      const Eigen::MatrixBase<D>& F) {
  Eigen::Matrix<typename D::Scalar, 6, 1> r;
  r.template head<3>() = F.template head<3>() - cross3(c, F.template tail<3>());
  r.template tail<3>().setZero();
  return r;
}

}  // namespace articulated
}  // namespace lieflow
