/// \file
/// SO(3), the rotation group, stored as a unit Hamilton quaternion.
///
/// Conventions (README "Conventions"): the quaternion is printed (w, x, y, z);
/// R maps body vectors to world vectors; tangent vectors w ∈ ℝ³ are rotation
/// vectors (axis · angle); perturbations are on the right, X ⊕ δ = X exp(δ);
/// Jr is the right Jacobian of exp, exp(w + δ) ≈ exp(w) exp(Jr(w) δ), and
/// Jl(w) = Jr(−w).
///
/// Closed forms (Sola et al. 2018, App. B; Barfoot 2017, §7.1) are written in
/// the half-angle variables h = cos(θ/2), k = sin(θ/2)/θ of
/// detail/so3_kernels.hpp, so none of them cancels near 0 or near π.
#pragma once

#include <cmath>
#include <limits>
#include <random>
#include <utility>
#include <sstream>
#include <string>

#include "liegroup/detail/so3_kernels.hpp"
#include "liegroup/invalid_input.hpp"
#include "liegroup/lie_group_base.hpp"
#include "liegroup/scalar.hpp"

namespace lieflow {

template <typename T>
class SO3;

template <typename T>
struct LieGroupTraits<SO3<T>> {
  using Scalar = T;
  static constexpr int DoF = 3;
  using Tangent = Vector3<T>;
  using Jacobian = Matrix3<T>;
};

template <typename T>
class SO3 : public LieGroupBase<SO3<T>> {
 public:
  using Scalar = T;
  static constexpr int DoF = 3;
  using Tangent = Vector3<T>;
  using Point = Vector3<T>;
  using Jacobian = Matrix3<T>;
  using Matrix = Matrix3<T>;
  using Quaternion = Eigen::Quaternion<T>;

  /// Tolerance of the checked factories: input within it of the group is
  /// projected onto it, input beyond it is rejected.
  static constexpr double kCheckedTolerance = 1e-6;

  /// Debug-build check of the unchecked constructor: |‖q‖² − 1| below
  /// 1e4 ε of the scalar's value type (2e-12 for double, 1e-3 for float), far
  /// above rounding after long chains of products, far below real misuse.
  static constexpr double kUnitAssertTolerance =
      1e4 * std::numeric_limits<ScalarValueTypeT<T>>::epsilon();

  /// The identity rotation.
  SO3() : q_(T(1), T(0), T(0), T(0)) {}

  /// From a unit quaternion, without checks (precondition: |‖q‖ − 1| ≲ 1e-12,
  /// asserted in debug builds). Use fromQuaternionChecked for untrusted input.
  explicit SO3(const Quaternion& q) : q_(q) {
    LIEFLOW_ASSERT(std::abs(scalarValue(q.squaredNorm()) - 1.0) < kUnitAssertTolerance,
                   "SO3(q): quaternion must have unit norm");
  }

  static SO3 identity() { return SO3(); }

  // ---- exp / log -----------------------------------------------------------

  /// exp(w) = (cos(θ/2), sin(θ/2)/θ · w), θ = ‖w‖; any w (angles beyond π wrap).
  static SO3 exp(const Tangent& w) {
    T h, k;
    detail::halfAngle(w.squaredNorm(), &h, &k);
    // Filled through w()/vec(): GCC 12 spills the 4-scalar constructor to the
    // stack and stalls the next vector load (measured 1.38× → 1.08×).
    Quaternion q;
    q.w() = h;
    q.vec() = k * w;
    return SO3(q, NoCheck{});
  }

  /// log(X) ∈ {w : ‖w‖ ≤ π}: 2 atan2(‖v‖, |q_w|)/‖v‖ · sign(q_w) v. Exact to
  /// the last digit near 0 (series of atan x/x) and near π (atan2).
  Tangent log() const {
    T h, scale;
    return logHalfAngle(&h, &scale);
  }

  /// log(X) together with h = cos(θ/2) ≥ 0 and scale = θ/sin(θ/2) = 1/k of the
  /// representative quaternion with w ≥ 0 (what SE3::log needs for V⁻¹).
  Tangent logHalfAngle(T* h, T* scale) const {
    const T n_sq = q_.vec().squaredNorm();
    const T sign = q_.w() < T(0) ? T(-1) : T(1);
    *h = sign * q_.w();
    *scale = detail::logScale(*h, n_sq);
    return (sign * *scale) * q_.vec();
  }

  // ---- group operations ----------------------------------------------------

  /// X⁻¹ = conjugate quaternion.
  SO3 inverse() const { return SO3(q_.conjugate(), NoCheck{}); }

  /// Composition X Y (quaternion product). No renormalization: the product of
  /// unit quaternions is unit to rounding; call normalize() after long chains.
  SO3 operator*(const SO3& other) const { return SO3(q_ * other.q_, NoCheck{}); }
  SO3& operator*=(const SO3& other) {
    q_ = q_ * other.q_;
    return *this;
  }

  /// Rotate a point: R p, as v + 2w (u×v) + 2 u×(u×v) with u = vec(q)
  /// (the form of Eigen's _transformVector, 15 multiplications).
  Point operator*(const Point& p) const {
    const Point t = T(2) * q_.vec().cross(p);
    return p + q_.w() * t + q_.vec().cross(t);
  }

  /// The rotation matrix R (maps body vectors to world vectors).
  Matrix matrix() const { return q_.toRotationMatrix(); }

  /// Adj(X) = R: X exp(δ) X⁻¹ = exp(R δ).
  Jacobian Adj() const { return matrix(); }

  const Quaternion& quaternion() const { return q_; }

  /// Re-project onto the group (q / ‖q‖). Not needed after single operations.
  void normalize() { q_.normalize(); }
  SO3 normalized() const { return SO3(q_.normalized(), NoCheck{}); }

  /// Componentwise closeness of the rotations (q and −q are the same rotation).
  bool isApprox(const SO3& other, double tol) const {
    return (*this * other.inverse()).log().norm() <= T(tol);
  }

  /// The same quaternion in scalar S, converted value by value (so float →
  /// double → float is exact). Casting to a more precise type keeps the
  /// source's precision: a float quaternion is unit only to ~1e-7; call
  /// normalize() on the result to re-project it in the new precision.
  template <typename S>
  SO3<S> cast() const {
    return SO3<S>(q_.template cast<S>(), typename SO3<S>::NoCheck{});
  }

  // ---- Lie algebra ---------------------------------------------------------

  /// w^ = [0 −w3 w2; w3 0 −w1; −w2 w1 0], so w^ v = w × v.
  static Matrix hat(const Tangent& w) {
    Matrix W;
    W << T(0), -w.z(), w.y(), w.z(), T(0), -w.x(), -w.y(), w.x(), T(0);
    return W;
  }

  /// Inverse of hat (reads the lower-left entries; the input must be skew).
  static Tangent vee(const Matrix& W) { return Tangent(W(2, 1), W(0, 2), W(1, 0)); }

  /// ad_w = w^: [w, v] = w × v.
  static Jacobian ad(const Tangent& w) { return hat(w); }

  // ---- Jacobians of exp ----------------------------------------------------

  /// Jr(w) = I − (1 − cos θ)/θ² W + (θ − sin θ)/θ³ W².
  static Jacobian Jr(const Tangent& w) { return expJacobianImpl(w, T(-1)); }

  /// Jl(w) = Jr(−w) = I + (1 − cos θ)/θ² W + (θ − sin θ)/θ³ W².
  static Jacobian Jl(const Tangent& w) { return expJacobianImpl(w, T(1)); }

  /// Jr⁻¹(w) = I + ½ W + (1 − (θ/2)cot(θ/2))/θ² W². Precondition θ < 2π.
  static Jacobian JrInv(const Tangent& w) { return expJacobianInverseImpl(w, T(0.5)); }

  /// Jl⁻¹(w) = Jr⁻¹(−w) = I − ½ W + (1 − (θ/2)cot(θ/2))/θ² W².
  static Jacobian JlInv(const Tangent& w) { return expJacobianInverseImpl(w, T(-0.5)); }

  // ---- Jacobians of the action ----------------------------------------------

  /// d(X p)/dX = −R p^ (right perturbation of X).
  Jacobian actJacobianGroup(const Point& p) const { return -matrix() * hat(p); }

  /// d(X p)/dp = R.
  Jacobian actJacobianPoint(const Point&) const { return matrix(); }

  // ---- random --------------------------------------------------------------

  /// A rotation uniformly distributed on SO(3) (Haar measure): a normalized
  /// 4-D standard normal sample (Shoemake 1992; Muller 1959).
  template <typename Generator>
  static SO3 random(Generator& gen) {
    std::normal_distribution<double> normal;
    Eigen::Quaterniond q;
    do {
      q = Eigen::Quaterniond(normal(gen), normal(gen), normal(gen), normal(gen));
    } while (q.squaredNorm() < 1e-12);
    q.normalize();
    return SO3(q.cast<T>());
  }

  // ---- checked factories (for untrusted input) -------------------------------

  /// From a quaternion given as (w, x, y, z). Rejects non-finite entries and a
  /// norm farther than kCheckedTolerance from 1; normalizes otherwise.
  /// `field` names the input in the error message.
  static SO3 fromQuaternionChecked(const Quaternion& q, const std::string& field = "quaternion") {
    const double c[4] = {scalarValue(q.w()), scalarValue(q.x()), scalarValue(q.y()),
                         scalarValue(q.z())};
    for (int i = 0; i < 4; ++i)
      if (!std::isfinite(c[i])) throw InvalidInput(field, "quaternion has a non-finite component");
    const double norm = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2] + c[3] * c[3]);
    if (!(std::abs(norm - 1.0) <= kCheckedTolerance)) {
      std::ostringstream reason;
      reason << "quaternion norm " << norm << " is not within " << kCheckedTolerance
             << " of 1 (a unit quaternion (w, x, y, z) is required)";
      throw InvalidInput(field, reason.str());
    }
    return SO3(q.normalized(), NoCheck{});
  }

  /// From (w, x, y, z) in any indexable container of size 4 (JSON arrays).
  template <typename Array>
  static SO3 fromArrayChecked(const Array& a, const std::string& field = "quaternion") {
    if (a.size() != 4) {
      std::ostringstream reason;
      reason << "expected 4 numbers (w, x, y, z), got " << a.size();
      throw InvalidInput(field, reason.str());
    }
    return fromQuaternionChecked(Quaternion(T(a[0]), T(a[1]), T(a[2]), T(a[3])), field);
  }

  /// From a rotation matrix. Rejects non-finite entries, ‖RᵀR − I‖_max beyond
  /// kCheckedTolerance and det R < 0 (a reflection); projects onto SO(3)
  /// otherwise.
  static SO3 fromRotationMatrixChecked(const Matrix& R, const std::string& field = "rotation") {
    Eigen::Matrix3d Rd;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        Rd(i, j) = scalarValue(R(i, j));
        if (!std::isfinite(Rd(i, j))) throw InvalidInput(field, "rotation matrix has a non-finite entry");
      }
    const double orth = (Rd.transpose() * Rd - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
    if (!(orth <= kCheckedTolerance)) {
      std::ostringstream reason;
      reason << "matrix is not orthonormal (max |RᵀR − I| = " << orth << " > " << kCheckedTolerance
             << ")";
      throw InvalidInput(field, reason.str());
    }
    if (Rd.determinant() < 0.0)
      throw InvalidInput(field, "matrix has determinant −1 (a reflection, not a rotation)");
    return SO3(Quaternion(R).normalized(), NoCheck{});
  }

 private:
  template <typename S>
  friend class SO3;
  template <typename S>
  friend class SE3;

  struct NoCheck {};
  SO3(const Quaternion& q, NoCheck) : q_(q) {}

  /// I + s (1 − cos θ)/θ² W + (θ − sin θ)/θ³ W², s = ±1.
  static Jacobian expJacobianImpl(const Tangent& w, const T& s) {
    const T theta_sq = w.squaredNorm();
    T h, k;
    detail::halfAngle(theta_sq, &h, &k);
    const Matrix W = hat(w);
    return Jacobian::Identity() + (s * detail::oneMinusCosCoefficient(k)) * W +
           detail::thetaMinusSinCoefficient(theta_sq, h, k) * (W * W);
  }

  /// I + s W + (1 − (θ/2)cot(θ/2))/θ² W², s = ±½.
  static Jacobian expJacobianInverseImpl(const Tangent& w, const T& s) {
    const T theta_sq = w.squaredNorm();
    T h, k;
    detail::halfAngle(theta_sq, &h, &k);
    const Matrix W = hat(w);
    return Jacobian::Identity() + s * W + detail::halfCotCoefficient(theta_sq, h, k) * (W * W);
  }

  Quaternion q_;
};

using SO3d = SO3<double>;
using SO3f = SO3<float>;

}  // namespace lieflow
