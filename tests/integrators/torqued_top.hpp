/// \file
/// The smooth rotor problem of the integrator tests: an asymmetric body on a
/// pivot under gravity (the heavy top of Brüls–Cardona–Arnold's kind) with,
/// optionally, a time-dependent body torque, and its initial state.
#pragma once

#include <cmath>

#include "dynamics/rigid_body/rigid_body_system.hpp"

namespace lieflow {
namespace testing_support {

template <typename T>
RigidBodyParameters<T> torquedTop(bool with_torque = true) {
  RigidBodyParameters<T> p;
  p.mass = T(2.0);
  p.inertia = Vector3<T>(T(1.0), T(2.0), T(3.5)).asDiagonal();
  p.has_pivot = true;
  p.com_from_pivot = Vector3<T>(T(0.1), T(0.3), T(0.2));
  p.gravity = Vector3<T>(T(0), T(0), T(-9.81));
  if (with_torque)
    p.torque_body = [](const T& t) {
      using std::cos;
      using std::sin;
      return Vector3<T>(sin(t), T(0.2), cos(T(2) * t));
    };
  return p;
}

inline RotorState<double> initialRotor() {
  RotorState<double> y;
  y.R = SO3d::exp(Eigen::Vector3d(0.1, 0.2, 0.3));
  y.omega << 1.0, 2.5, -0.7;
  return y;
}

}  // namespace testing_support
}  // namespace lieflow
