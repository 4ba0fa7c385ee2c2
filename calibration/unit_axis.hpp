/// \file
/// Unit axes on ceres::SphereManifold<3>: the scale of its tangent space, the
/// sign convention of reported axes, and angles between axes.
///
/// Ceres 2.1's SphereManifold (sphere_manifold.h, after Hertzberg et al. 2013,
/// §B.2) moves x by Plus(x, δ) = H(x)ᵀ [sin(‖δ‖/2) δ/‖δ‖, cos(‖δ‖/2)] ‖x‖, with
/// H(x) the Householder reflection taking x to the last basis vector: a unit
/// axis turns by the angle ‖δ‖/2, and PlusJacobian = ½ H(x)[:, 0:2]. Tangent
/// covariances from ceres::Covariance are therefore in units of (2 rad)²; an
/// axis-angle covariance is the tangent one divided by
/// kSphereTangentPerRadian² = 4 (checked in tests/calibration/unit_axis_test.cpp).
#pragma once

#include <algorithm>
#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace lieflow {
namespace calibration {

/// Tangent-space units of ceres::SphereManifold<3> per radian of axis rotation.
constexpr double kSphereTangentPerRadian = 2.0;

constexpr double kRadToDeg = 57.295779513082320876798154814105;

/// +1 or −1 such that sign · v has its largest-magnitude component positive
/// (the first such component on ties): the reporting convention for an axis
/// whose sign the data leave free.
inline double canonicalSign(const Eigen::Vector3d& v) {
  int best = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(v[i]) > std::abs(v[best])) best = i;
  return v[best] < 0.0 ? -1.0 : 1.0;
}

/// The angle between two directions in radians, accurate for small angles
/// (atan2 of ‖a × b‖ and a · b rather than acos).
inline double angleBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

/// The angle between two lines (directions up to sign), in [0, π/2].
inline double angleBetweenLines(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), std::abs(a.dot(b)));
}

/// A unit vector orthogonal to the unit vector a (a × the basis vector least
/// aligned with a, normalized).
inline Eigen::Vector3d orthogonalUnit(const Eigen::Vector3d& a) {
  Eigen::Index i;
  a.cwiseAbs().minCoeff(&i);
  return a.cross(Eigen::Vector3d::Unit(i)).normalized();
}

/// A unit basis (3 × 2) of the plane perpendicular to a: the coordinates of
/// a gyroscope bias the joint's constraint can observe.
inline Eigen::Matrix<double, 3, 2> perpendicularBasis(const Eigen::Vector3d& a) {
  Eigen::Matrix<double, 3, 2> B;
  B.col(0) = orthogonalUnit(a);
  B.col(1) = a.normalized().cross(B.col(0));
  return B;
}

}  // namespace calibration
}  // namespace lieflow
