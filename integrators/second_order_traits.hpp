/// \file
/// What the second-order steppers (integrators/generalized_alpha.hpp) need of
/// a state and a system — SecondOrderStateTraits<State> (the geometry) and
/// SecondOrderSystemTraits<System> (M(q) v̇ + g(q, v, t) = 0 and its tangent
/// matrices); their contract is in generalized_alpha.hpp's file comment — and
/// their specializations for the states of integrators/ and for
/// LinearSecondOrderSystem (the rigid-body systems specialize theirs in
/// dynamics/rigid_body/rigid_body_system.hpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>
#include <utility>

#include <Eigen/Core>
#include <Eigen/LU>

#include "integrators/rigid_body_state.hpp"
#include "integrators/step_report.hpp"
#include "integrators/vector_state.hpp"
#include "liegroup/invalid_input.hpp"
#include "liegroup/scalar.hpp"
#include "liegroup/so3.hpp"

namespace lieflow {

/// The geometry of a state for second-order steppers (see the file comment).
template <class State>
struct SecondOrderStateTraits;

/// The equations of motion M v̇ + g = 0 of a system (see the file comment).
template <class System>
struct SecondOrderSystemTraits;

namespace detail {

/// True for scalars with a value part `.a` and a derivative part `.v`
/// (ceres::Jet), detected without including Ceres.
template <typename T, typename = void>
struct HasDerivativePart : std::false_type {};
template <typename T>
struct HasDerivativePart<T, std::void_t<decltype(std::declval<const T&>().a),
                                        decltype(std::declval<const T&>().v)>>
    : std::true_type {};

/// Exact equality of two scalars, derivative parts included.
template <typename T>
bool identicalScalar(const T& a, const T& b) {
  if constexpr (HasDerivativePart<T>::value) {
    return a.a == b.a && (a.v.array() == b.v.array()).all();
  } else {
    return a == b;
  }
}

/// Exact equality of two coefficient arrays of the same size.
template <typename A, typename B>
bool identicalCoefficients(const Eigen::DenseBase<A>& a, const Eigen::DenseBase<B>& b) {
  if (a.size() != b.size()) return false;
  for (Eigen::Index i = 0; i < a.size(); ++i)
    if (!identicalScalar(a.derived().coeff(i), b.derived().coeff(i))) return false;
  return true;
}

/// max |xᵢ| of the value parts; NaN if any entry is NaN (so that a stopping
/// test `residual <= bound` fails on it).
template <typename Derived>
double maxAbsValue(const Eigen::MatrixBase<Derived>& x) {
  double m = 0.0;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    const double v = std::abs(scalarValue(x.derived().coeff(i)));
    if (std::isnan(v)) return std::numeric_limits<double>::quiet_NaN();
    m = std::max(m, v);
  }
  return m;
}

/// Whether SecondOrderSystemTraits<System> names the independent diagonal
/// blocks of its equations (`static const std::vector<std::vector<int>>&
/// independentBlocks(const System&)`; generalized_alpha.hpp).
template <typename Dynamics, typename System, typename = void>
struct HasIndependentBlocks : std::false_type {};
template <typename Dynamics, typename System>
struct HasIndependentBlocks<Dynamics, System,
                            std::void_t<decltype(Dynamics::independentBlocks(std::declval<const System&>()))>>
    : std::true_type {};

}  // namespace detail

// ---- state geometry ----------------------------------------------------------

/// RotorState: q = R ∈ SO(3), v = ω (body frame).
template <typename T>
struct SecondOrderStateTraits<RotorState<T>> {
  using Scalar = T;
  using State = RotorState<T>;
  static constexpr int kDof = 3;
  using Vector = Vector3<T>;
  using Matrix = Matrix3<T>;

  static Vector velocity(const State& y) { return y.omega; }
  static State advance(const State& y, const Vector& dq, const Vector& v) {
    return {y.R * SO3<T>::exp(dq), v};
  }
  static Matrix tangentOperator(const Vector& dq) { return SO3<T>::Jr(dq); }
  static bool identical(const State& a, const State& b) {
    return detail::identicalCoefficients(a.R.quaternion().coeffs(), b.R.quaternion().coeffs()) &&
           detail::identicalCoefficients(a.omega, b.omega);
  }
};

/// FreeBodyState: q = (p, R) ∈ ℝ³ × SO(3), v = (v_world, ω_body); δq = (δp, δθ).
template <typename T>
struct SecondOrderStateTraits<FreeBodyState<T>> {
  using Scalar = T;
  using State = FreeBodyState<T>;
  static constexpr int kDof = 6;
  using Vector = Vector6<T>;
  using Matrix = Matrix6<T>;

  static Vector velocity(const State& y) {
    Vector v;
    v << y.v, y.omega;
    return v;
  }
  static State advance(const State& y, const Vector& dq, const Vector& v) {
    return {y.R * SO3<T>::exp(dq.template tail<3>()), y.p + dq.template head<3>(),
            v.template tail<3>(), v.template head<3>()};
  }
  static Matrix tangentOperator(const Vector& dq) {
    Matrix Tm = Matrix::Identity();
    Tm.template bottomRightCorner<3, 3>() = SO3<T>::Jr(dq.template tail<3>());
    return Tm;
  }
  static bool identical(const State& a, const State& b) {
    return detail::identicalCoefficients(a.R.quaternion().coeffs(), b.R.quaternion().coeffs()) &&
           detail::identicalCoefficients(a.p, b.p) &&
           detail::identicalCoefficients(a.omega, b.omega) &&
           detail::identicalCoefficients(a.v, b.v);
  }
};

/// VectorState: q = x ∈ ℝᴺ (exp = identity, T = I), v = ẋ.
template <typename T, int N>
struct SecondOrderStateTraits<VectorState<T, N>> {
  using Scalar = T;
  using State = VectorState<T, N>;
  static constexpr int kDof = N;
  using Vector = Eigen::Matrix<T, N, 1>;
  using Matrix = Eigen::Matrix<T, N, N>;

  static Vector velocity(const State& y) { return y.v; }
  static State advance(const State& y, const Vector& dq, const Vector& v) {
    return {y.x + dq, v};
  }
  static Matrix tangentOperator(const Vector& /*dq*/) { return Matrix::Identity(); }
  static bool identical(const State& a, const State& b) {
    return detail::identicalCoefficients(a.x, b.x) && detail::identicalCoefficients(a.v, b.v);
  }
};

// ---- equations of motion -------------------------------------------------------

/// M ẍ + C ẋ + K x − f(t) = 0.
template <typename T, int N>
struct SecondOrderSystemTraits<LinearSecondOrderSystem<T, N>> {
  using Scalar = T;
  using State = VectorState<T, N>;
  using Vector = Eigen::Matrix<T, N, 1>;
  using Matrix = Eigen::Matrix<T, N, N>;

  static void evaluate(const LinearSecondOrderSystem<T, N>& s, const T& t, const State& y,
                       Matrix* M, Vector* g, Matrix* Ct, Matrix* Kt) {
    *M = s.mass();
    *g = s.damping() * y.v + s.stiffness() * y.x - s.load(t);
    if (Ct) *Ct = s.damping();
    if (Kt) *Kt = s.stiffness();
  }
};

}  // namespace lieflow
