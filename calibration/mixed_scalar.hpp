/// \file
/// Products of recorded data (double) with parameters (double or ceres::Jet)
/// inside residual functors, without casting the data to Jets first (a cast
/// Matrix3 of Jet<double, 6> multiplies 7× the numbers for nothing).
#pragma once

#include <Eigen/Core>

#include "liegroup/scalar.hpp"

namespace lieflow {
namespace calibration {
namespace mixed {

/// R v for a data matrix R and a parameter vector v.
template <typename T>
Vector3<T> mul(const Eigen::Matrix3d& R, const Vector3<T>& v) {
  return Vector3<T>(R(0, 0) * v[0] + R(0, 1) * v[1] + R(0, 2) * v[2],
                    R(1, 0) * v[0] + R(1, 1) * v[1] + R(1, 2) * v[2],
                    R(2, 0) * v[0] + R(2, 1) * v[1] + R(2, 2) * v[2]);
}

/// a × v for a data vector a and a parameter vector v.
template <typename T>
Vector3<T> cross(const Eigen::Vector3d& a, const Vector3<T>& v) {
  return Vector3<T>(a[1] * v[2] - a[2] * v[1], a[2] * v[0] - a[0] * v[2], a[0] * v[1] - a[1] * v[0]);
}

/// a · v for a data vector a and a parameter vector v.
template <typename T>
T dot(const Eigen::Vector3d& a, const Vector3<T>& v) {
  return a[0] * v[0] + a[1] * v[1] + a[2] * v[2];
}

}  // namespace mixed
}  // namespace calibration
}  // namespace lieflow
