/// \file
/// States of a single rigid body as elements of product Lie groups, with the
/// operations every Lie-group stepper needs:
///   rplus:  y ⊕ δ = y · exp(δ) blockwise (right action, body-frame increments),
///   dexpInvRight: the right-trivialized inverse derivative of exp, blockwise,
///     exact or truncated after ad^order (see liegroup/dexp.hpp).
///
/// RotorState lives on SO(3) × ℝ³ (R, ω): a rotation-only body (free or about a
/// fixed pivot) pays nothing for translation. FreeBodyState lives on
/// SO(3) × ℝ³ × ℝ³ × ℝ³ (R, p, ω, v): rotation and centre-of-mass translation,
/// which decouple for a rigid body, so SE(3) coupling is not imposed.
/// Vector-space blocks have ad = 0, so dexp⁻¹ is the identity on them.
#pragma once

#include "liegroup/dexp.hpp"
#include "liegroup/so3.hpp"

namespace lieflow {

namespace detail {
/// Right-trivialized dexp⁻¹ on so(3): d/dt exp(Θ) = exp(Θ) (Jr(Θ) Θ')^, so
/// Θ' = Jr⁻¹(Θ) ω = dexp⁻¹_{−Θ}(ω). order < 0: exact; else the series
/// truncated after ad^order.
/// The series is summed with cross products, ad_{−Θ} x = x × Θ, rather than
/// through the matrix of ad (same values as dexpInvTruncated<SO3>).
template <typename T>
Vector3<T> so3DexpInvRight(const Vector3<T>& theta, const Vector3<T>& w, int order) {
  if (order < 0) return SO3<T>::JrInv(theta) * w;
  // B_k / k! for k = 0..8 (B_1 = −1/2, B_odd≥3 = 0), as in liegroup/dexp.hpp.
  static constexpr double kCoeff[9] = {1.0,           -0.5, 1.0 / 12.0, 0.0, -1.0 / 720.0, 0.0,
                                       1.0 / 30240.0, 0.0,  -1.0 / 1209600.0};
  LIEFLOW_ASSERT(order <= 8, "so3DexpInvRight: order must be at most 8");
  Vector3<T> term = w;
  Vector3<T> sum = w;
  for (int k = 1; k <= order; ++k) {
    term = term.cross(theta);
    if (kCoeff[k] != 0.0) sum += T(kCoeff[k]) * term;
  }
  return sum;
}
}  // namespace detail

/// A rotation-only rigid body: orientation R (body → world) and body angular
/// velocity ω (Ṙ = R ω^). Tangent ordering (δθ, δω), δθ a body-frame rotation.
template <typename T>
struct RotorState {
  using Scalar = T;
  static constexpr int kTangentDim = 6;
  using Tangent = Vector6<T>;

  SO3<T> R;
  Vector3<T> omega = Vector3<T>::Zero();

  Tangent zeroTangent() const { return Tangent::Zero(); }

  /// Per-component size for error control: 1 for rotation components
  /// (radians), |ω_i| for velocities.
  Tangent magnitude() const {
    Tangent m;
    m << T(1), T(1), T(1), omega.cwiseAbs();
    return m;
  }

  RotorState rplus(const Tangent& d) const {
    return {R * SO3<T>::exp(d.template head<3>()), omega + d.template tail<3>()};
  }

  static Tangent dexpInvRight(const Tangent& theta, const Tangent& v, int order) {
    Tangent out;
    out.template head<3>() =
        detail::so3DexpInvRight<T>(theta.template head<3>(), v.template head<3>(), order);
    out.template tail<3>() = v.template tail<3>();
    return out;
  }
};

/// A free rigid body: orientation R, centre-of-mass position p (world), body
/// angular velocity ω and centre-of-mass velocity v (world).
/// Tangent ordering (δp, δθ, δv, δω): translation before rotation, as in SE(3).
template <typename T>
struct FreeBodyState {
  using Scalar = T;
  static constexpr int kTangentDim = 12;
  using Tangent = Eigen::Matrix<T, 12, 1>;

  SO3<T> R;
  Vector3<T> p = Vector3<T>::Zero();
  Vector3<T> omega = Vector3<T>::Zero();
  Vector3<T> v = Vector3<T>::Zero();

  Tangent zeroTangent() const { return Tangent::Zero(); }

  /// Per-component size for error control: |p_i|, 1 for rotation components,
  /// |v_i|, |ω_i|.
  Tangent magnitude() const {
    Tangent m;
    m << p.cwiseAbs(), T(1), T(1), T(1), v.cwiseAbs(), omega.cwiseAbs();
    return m;
  }

  FreeBodyState rplus(const Tangent& d) const {
    return {R * SO3<T>::exp(d.template segment<3>(3)), p + d.template segment<3>(0),
            omega + d.template segment<3>(9), v + d.template segment<3>(6)};
  }

  static Tangent dexpInvRight(const Tangent& theta, const Tangent& v, int order) {
    Tangent out = v;
    out.template segment<3>(3) = detail::so3DexpInvRight<T>(theta.template segment<3>(3),
                                                            v.template segment<3>(3), order);
    return out;
  }
};

/// True when every component of the state is finite (blow-up detection).
template <typename T>
bool isFinite(const RotorState<T>& y) {
  using std::isfinite;
  return isfinite(scalarValue(y.R.quaternion().squaredNorm())) &&
         isfinite(scalarValue(y.omega.squaredNorm()));
}

template <typename T>
bool isFinite(const FreeBodyState<T>& y) {
  using std::isfinite;
  return isfinite(scalarValue(y.R.quaternion().squaredNorm())) &&
         isfinite(scalarValue(y.omega.squaredNorm())) && isfinite(scalarValue(y.p.squaredNorm())) &&
         isfinite(scalarValue(y.v.squaredNorm()));
}

}  // namespace lieflow
