/// \file
/// SE(3), rigid motions x ↦ R x + t, stored as a unit quaternion and a
/// translation.
///
/// Tangent vectors are ordered ξ = (ρ, ω): translation part first, rotation
/// part second (lieflow convention); exp(ξ) = (exp(ω), V(ω) ρ) with
///   V(ω) = Jl(ω) = I + (1 − cos θ)/θ² W + (θ − sin θ)/θ³ W²,
/// and the 6×6 Jacobians are block upper-triangular,
///   Jl(ξ) = [Jl(ω) Q(ρ, ω); 0 Jl(ω)],  Jr(ξ) = Jl(−ξ),
/// with Q of Barfoot & Furgale 2014 (eq. 102) / Barfoot 2017 (eq. 7.86).
/// All coefficients come from detail/so3_kernels.hpp (no cancellation near 0
/// or π, Jet-safe series at 0).
#pragma once

#include <sstream>
#include <string>

#include "liegroup/so3.hpp"

namespace lieflow {

template <typename T>
class SE3;

template <typename T>
struct LieGroupTraits<SE3<T>> {
  using Scalar = T;
  static constexpr int DoF = 6;
  using Tangent = Vector6<T>;
  using Jacobian = Matrix6<T>;
};

template <typename T>
class SE3 : public LieGroupBase<SE3<T>> {
 public:
  using Scalar = T;
  static constexpr int DoF = 6;
  using Tangent = Vector6<T>;
  using Point = Vector3<T>;
  using Jacobian = Matrix6<T>;
  using Matrix = Matrix4<T>;
  using Rotation = SO3<T>;
  using Quaternion = Eigen::Quaternion<T>;

  /// The identity motion.
  SE3() : t_(Point::Zero()) {}

  /// From a rotation and a translation (both taken as given).
  SE3(const Rotation& R, const Point& t) : R_(R), t_(t) {}

  /// From a unit quaternion and a translation, unchecked (see SO3(q)).
  SE3(const Quaternion& q, const Point& t) : R_(q), t_(t) {}

  static SE3 identity() { return SE3(); }

  // ---- exp / log -----------------------------------------------------------

  /// exp(ρ, ω) = (exp(ω), ρ + (1 − cos θ)/θ² ω×ρ + (θ − sin θ)/θ³ ω×(ω×ρ)).
  static SE3 exp(const Tangent& xi) {
    const Point rho = xi.template head<3>();
    const Point w = xi.template tail<3>();
    const T theta_sq = w.squaredNorm();
    T h, k;
    detail::halfAngle(theta_sq, &h, &k);
    const Point w_x_rho = w.cross(rho);
    const Point t = rho + detail::oneMinusCosCoefficient(k) * w_x_rho +
                    detail::thetaMinusSinCoefficient(theta_sq, h, k) * w.cross(w_x_rho);
    Quaternion q;  // filled through w()/vec(), see SO3::exp
    q.w() = h;
    q.vec() = k * w;
    return SE3(Rotation(q, typename Rotation::NoCheck{}), t);
  }

  /// log(X) = (V⁻¹(ω) t, ω), ω = log(R), ‖ω‖ ≤ π, with
  /// V⁻¹ = I − ½ W + (1 − (θ/2)cot(θ/2))/θ² W², the coefficient formed from
  /// the quaternion itself as (1 − h/(2k))/θ² (exact near π).
  Tangent log() const {
    T h, scale;
    const Point w = R_.logHalfAngle(&h, &scale);
    const T theta_sq = w.squaredNorm();
    // k = sin(θ/2)/θ = 1/scale.
    const T d = theta_sq < T(detail::kHalfCotThetaSq)
                    ? detail::horner(theta_sq, detail::halfCotSeries())
                    : (T(1) - T(0.5) * h * scale) / theta_sq;
    const Point w_x_t = w.cross(t_);
    Tangent xi;
    xi.template head<3>() = t_ - T(0.5) * w_x_t + d * w.cross(w_x_t);
    xi.template tail<3>() = w;
    return xi;
  }

  // ---- group operations ----------------------------------------------------

  /// X⁻¹ = (R⁻¹, −R⁻¹ t).
  SE3 inverse() const {
    const Rotation Rinv = R_.inverse();
    return SE3(Rinv, -(Rinv * t_));
  }

  /// X Y = (R_X R_Y, R_X t_Y + t_X).
  SE3 operator*(const SE3& other) const { return SE3(R_ * other.R_, R_ * other.t_ + t_); }
  SE3& operator*=(const SE3& other) {
    t_ += R_ * other.t_;
    R_ *= other.R_;
    return *this;
  }

  /// X p = R p + t.
  Point operator*(const Point& p) const { return R_ * p + t_; }

  /// The 4×4 homogeneous matrix [R t; 0 1].
  Matrix matrix() const {
    Matrix M = Matrix::Identity();
    M.template topLeftCorner<3, 3>() = R_.matrix();
    M.template topRightCorner<3, 1>() = t_;
    return M;
  }

  /// Adj(X) = [R t^R; 0 R] in (ρ, ω) order: X exp(ξ) X⁻¹ = exp(Adj ξ).
  Jacobian Adj() const {
    const Matrix3<T> R = R_.matrix();
    Jacobian A;
    A.template topLeftCorner<3, 3>() = R;
    A.template topRightCorner<3, 3>() = Rotation::hat(t_) * R;
    A.template bottomLeftCorner<3, 3>().setZero();
    A.template bottomRightCorner<3, 3>() = R;
    return A;
  }

  const Rotation& rotation() const { return R_; }
  const Point& translation() const { return t_; }
  Rotation& rotation() { return R_; }
  Point& translation() { return t_; }
  const Quaternion& quaternion() const { return R_.quaternion(); }

  void normalize() { R_.normalize(); }
  SE3 normalized() const { return SE3(R_.normalized(), t_); }

  bool isApprox(const SE3& other, double tol) const {
    return (*this * other.inverse()).log().norm() <= T(tol);
  }

  template <typename S>
  SE3<S> cast() const {
    return SE3<S>(R_.template cast<S>(), t_.template cast<S>());
  }

  // ---- Lie algebra ---------------------------------------------------------

  /// ξ^ = [ω^ ρ; 0 0].
  static Matrix hat(const Tangent& xi) {
    Matrix M = Matrix::Zero();
    M.template topLeftCorner<3, 3>() = Rotation::hat(xi.template tail<3>());
    M.template topRightCorner<3, 1>() = xi.template head<3>();
    return M;
  }

  /// Inverse of hat.
  static Tangent vee(const Matrix& M) {
    Tangent xi;
    xi.template head<3>() = M.template topRightCorner<3, 1>();
    xi.template tail<3>() = Rotation::vee(M.template topLeftCorner<3, 3>());
    return xi;
  }

  /// ad_ξ = [ω^ ρ^; 0 ω^]: [ξ, η] = ad_ξ η.
  static Jacobian ad(const Tangent& xi) {
    const Matrix3<T> W = Rotation::hat(xi.template tail<3>());
    Jacobian A;
    A.template topLeftCorner<3, 3>() = W;
    A.template topRightCorner<3, 3>() = Rotation::hat(xi.template head<3>());
    A.template bottomLeftCorner<3, 3>().setZero();
    A.template bottomRightCorner<3, 3>() = W;
    return A;
  }

  // ---- Jacobians of exp ----------------------------------------------------

  /// Q(ρ, ω) of Barfoot 2017 eq. (7.86), the off-diagonal block of Jl(ξ):
  ///   Q = ½P + a (WP + PW + WPW) + b (W²P + PW² − 3WPW) + c (WPW² + W²PW),
  /// P = ρ^, W = ω^, a = (θ − sin θ)/θ³, b = (θ²/2 + cos θ − 1)/θ⁴,
  /// c = (2θ − 3 sin θ + θ cos θ)/(2θ⁵).
  static Matrix3<T> Q(const Point& rho, const Point& w) {
    const T theta_sq = w.squaredNorm();
    T h, k;
    detail::halfAngle(theta_sq, &h, &k);
    const T a = detail::thetaMinusSinCoefficient(theta_sq, h, k);
    const T b = detail::cosRemainderCoefficient(theta_sq, k);
    const T c = detail::sinCosMixCoefficient(theta_sq, h, k);
    const Matrix3<T> P = Rotation::hat(rho);
    const Matrix3<T> W = Rotation::hat(w);
    const Matrix3<T> WP = W * P;
    const Matrix3<T> PW = P * W;
    const Matrix3<T> WPW = WP * W;
    return T(0.5) * P + a * (WP + PW + WPW) + b * (W * WP + PW * W - T(3) * WPW) +
           c * (WPW * W + W * WPW);
  }

  /// Jl(ξ) = [Jl(ω) Q(ρ, ω); 0 Jl(ω)].
  static Jacobian Jl(const Tangent& xi) {
    const Point rho = xi.template head<3>();
    const Point w = xi.template tail<3>();
    const Matrix3<T> J = Rotation::Jl(w);
    Jacobian A;
    A.template topLeftCorner<3, 3>() = J;
    A.template topRightCorner<3, 3>() = Q(rho, w);
    A.template bottomLeftCorner<3, 3>().setZero();
    A.template bottomRightCorner<3, 3>() = J;
    return A;
  }

  /// Jr(ξ) = Jl(−ξ).
  static Jacobian Jr(const Tangent& xi) { return Jl(-xi); }

  /// Jl⁻¹(ξ) = [Jl⁻¹(ω) −Jl⁻¹ Q Jl⁻¹; 0 Jl⁻¹(ω)]. Precondition ‖ω‖ < 2π.
  static Jacobian JlInv(const Tangent& xi) {
    const Point rho = xi.template head<3>();
    const Point w = xi.template tail<3>();
    const Matrix3<T> Jinv = Rotation::JlInv(w);
    Jacobian A;
    A.template topLeftCorner<3, 3>() = Jinv;
    A.template topRightCorner<3, 3>() = -Jinv * Q(rho, w) * Jinv;
    A.template bottomLeftCorner<3, 3>().setZero();
    A.template bottomRightCorner<3, 3>() = Jinv;
    return A;
  }

  /// Jr⁻¹(ξ) = Jl⁻¹(−ξ).
  static Jacobian JrInv(const Tangent& xi) { return JlInv(-xi); }

  // ---- Jacobians of the action ----------------------------------------------

  /// d(X p)/dX = [R  −R p^] (right perturbation, (ρ, ω) order).
  Eigen::Matrix<T, 3, 6> actJacobianGroup(const Point& p) const {
    const Matrix3<T> R = R_.matrix();
    Eigen::Matrix<T, 3, 6> J;
    J.template leftCols<3>() = R;
    J.template rightCols<3>() = -R * Rotation::hat(p);
    return J;
  }

  /// d(X p)/dp = R.
  Matrix3<T> actJacobianPoint(const Point&) const { return R_.matrix(); }

  // ---- random --------------------------------------------------------------

  /// Uniform rotation, translation uniform in the cube [−scale, scale]³.
  template <typename Generator>
  static SE3 random(Generator& gen, double scale = 1.0) {
    std::uniform_real_distribution<double> uniform(-scale, scale);
    const Rotation R = Rotation::random(gen);
    const Point t(T(uniform(gen)), T(uniform(gen)), T(uniform(gen)));
    return SE3(R, t);
  }

  // ---- checked factories ---------------------------------------------------

  /// From a quaternion (w, x, y, z) and a translation; see
  /// SO3::fromQuaternionChecked. Rejects a non-finite translation.
  static SE3 fromQuaternionTranslationChecked(const Quaternion& q, const Point& t,
                                              const std::string& field = "pose") {
    const Rotation R = Rotation::fromQuaternionChecked(q, field + ".orientation");
    checkFinite(t, field + ".position");
    return SE3(R, t);
  }

  /// From a 4×4 homogeneous matrix: the rotation block is checked as in
  /// SO3::fromRotationMatrixChecked and the last row must be (0, 0, 0, 1).
  static SE3 fromMatrixChecked(const Matrix& M, const std::string& field = "pose") {
    for (int j = 0; j < 4; ++j) {
      const double expected = j == 3 ? 1.0 : 0.0;
      if (!(std::abs(scalarValue(M(3, j)) - expected) <= Rotation::kCheckedTolerance))
        throw InvalidInput(field, "last row of a homogeneous matrix must be (0, 0, 0, 1)");
    }
    const Rotation R =
        Rotation::fromRotationMatrixChecked(M.template topLeftCorner<3, 3>(), field + ".rotation");
    const Point t = M.template topRightCorner<3, 1>();
    checkFinite(t, field + ".translation");
    return SE3(R, t);
  }

 private:
  static void checkFinite(const Point& t, const std::string& field) {
    for (int i = 0; i < 3; ++i)
      if (!std::isfinite(scalarValue(t[i]))) throw InvalidInput(field, "non-finite component");
  }

  Rotation R_;
  Point t_;
};

using SE3d = SE3<double>;
using SE3f = SE3<float>;

}  // namespace lieflow
