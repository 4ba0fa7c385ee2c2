/// \file
/// Scalar-generic helpers for liegroup/: fixed-size Eigen aliases, the debug
/// precondition macro, and the hook that lets `ceres::Jet` (or any scalar with
/// ADL overloads of sqrt, sin, cos, atan2) flow through every formula.
#pragma once

#include <cassert>
#include <cmath>
#include <type_traits>
#include <utility>

#include <Eigen/Core>
#include <Eigen/Geometry>

/// Debug-build precondition check of the unchecked fast paths. Release builds
/// compile it away; the checked factories (`fromQuaternionChecked`, ...) are the
/// way to validate untrusted input.
#ifndef LIEFLOW_ASSERT
#define LIEFLOW_ASSERT(condition, message) assert((condition) && (message))
#endif

namespace lieflow {

/// π, the double nearest it: the one constant of the project (no M_PI, which
/// the C++ standard does not promise).
inline constexpr double kPi = 3.141592653589793238462643383279502884;

template <typename T>
using Vector3 = Eigen::Matrix<T, 3, 1>;
template <typename T>
using Vector6 = Eigen::Matrix<T, 6, 1>;
template <typename T>
using Matrix3 = Eigen::Matrix<T, 3, 3>;
template <typename T>
using Matrix4 = Eigen::Matrix<T, 4, 4>;
template <typename T>
using Matrix6 = Eigen::Matrix<T, 6, 6>;

/// The plain floating-point value of a scalar: itself for float/double, the
/// value part `.a` for `ceres::Jet`. Used only for diagnostics and debug asserts,
/// never to choose a formula (branches compare the scalar itself, which for Jets
/// compares the value part, so the derivative follows the chosen branch).
inline double scalarValue(double x) { return x; }
inline double scalarValue(float x) { return static_cast<double>(x); }
template <typename J>
auto scalarValue(const J& x) -> decltype(scalarValue(x.a)) {
  return scalarValue(x.a);
}

/// The floating-point type underneath a scalar: float → float, double →
/// double, ceres::Jet<double, N> → double (recursively through `.a`).
template <typename T, typename = void>
struct ScalarValueType {
  using type = T;
};
template <typename J>
struct ScalarValueType<J, std::void_t<decltype(std::declval<J>().a)>> {
  using type = typename ScalarValueType<std::decay_t<decltype(std::declval<J>().a)>>::type;
};
template <typename T>
using ScalarValueTypeT = typename ScalarValueType<T>::type;

}  // namespace lieflow
