/// \file
/// The single free rigid body that bench_integrators and bench_work_precision
/// time and measure, in the one definition that lieflow's systems, the exact
/// reference flow and the MuJoCo peer (mujoco_peer.hpp) are all built from.
///
/// Torque-free, no gravity: the exact motion is known (Euler–Poinsot,
/// dynamics/rigid_body/exact_free_body.hpp), so every error is measured against it.
/// The inertia is asymmetric (three distinct principal moments) and its
/// principal axes are turned away from the body axes, so the body-frame
/// inertia J = A diag(I) Aᵀ is a full matrix (A = principal_axes: principal
/// frame → body frame; MuJoCo's <inertial quat=…>). The angular velocity is
/// generic: all components non-zero, far from the separatrix L² = 2E·I_mid.
#pragma once

#include <cmath>
#include <cstdio>
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "dynamics/rigid_body/exact_free_body.hpp"
#include "dynamics/rigid_body/rigid_body_system.hpp"

namespace lieflow {
namespace bench {

struct FreeBodyScene {
  double mass = 2.0;
  /// Principal moments (kg m²), distinct, triangle inequality satisfied.
  Eigen::Vector3d principal_moments = Eigen::Vector3d(0.9, 1.6, 2.2);
  /// Rotation taking principal-frame vectors to body-frame vectors.
  Eigen::Quaterniond principal_axes = Eigen::Quaterniond(0.9, 0.2, -0.3, 0.25).normalized();
  /// Initial orientation (body → world), position (world), body angular
  /// velocity and world centre-of-mass velocity.
  Eigen::Quaterniond q0 = Eigen::Quaterniond(0.8, -0.1, 0.5, 0.3).normalized();
  Eigen::Vector3d p0 = Eigen::Vector3d(0.1, -0.2, 0.3);
  Eigen::Vector3d omega0_body = Eigen::Vector3d(1.2, -2.0, 0.7);
  Eigen::Vector3d v0_world = Eigen::Vector3d(0.3, -0.4, 0.5);
  /// The step of the per-step micro-benchmarks (MuJoCo's default is 2e-3).
  double h = 1e-3;

  /// J = A diag(I) Aᵀ, symmetrized exactly.
  Eigen::Matrix3d inertia() const {
    const Eigen::Matrix3d A = principal_axes.toRotationMatrix();
    const Eigen::Matrix3d J = A * principal_moments.asDiagonal() * A.transpose();
    return 0.5 * (J + J.transpose());
  }

  RigidBodyParameters<double> parameters() const {
    RigidBodyParameters<double> p;
    p.mass = mass;
    p.inertia = inertia();
    p.gravity.setZero();
    return p;
  }

  FreeBodySystem<double> freeBodySystem() const { return FreeBodySystem<double>(parameters()); }
  RotorSystem<double> rotorSystem() const { return RotorSystem<double>(parameters()); }

  FreeBodyState<double> freeBodyState() const {
    FreeBodyState<double> y;
    y.R = SO3d(q0);
    y.p = p0;
    y.omega = omega0_body;
    y.v = v0_world;
    return y;
  }
  RotorState<double> rotorState() const {
    RotorState<double> y;
    y.R = SO3d(q0);
    y.omega = omega0_body;
    return y;
  }

  ExactFreeRigidBody exact() const { return ExactFreeRigidBody(inertia(), q0, omega0_body); }

  /// One line for the program headers.
  std::string describe() const {
    char buf[400];
    std::snprintf(buf, sizeof buf,
                  "free body: m = %g kg, principal moments (%g, %g, %g) kg m^2 about axes "
                  "turned by q = (%.3f, %.3f, %.3f, %.3f), omega0 = (%g, %g, %g) rad/s body, "
                  "v0 = (%g, %g, %g) m/s, no gravity, no torque",
                  mass, principal_moments.x(), principal_moments.y(), principal_moments.z(),
                  principal_axes.w(), principal_axes.x(), principal_axes.y(), principal_axes.z(),
                  omega0_body.x(), omega0_body.y(), omega0_body.z(), v0_world.x(), v0_world.y(),
                  v0_world.z());
    return buf;
  }
};

/// Angle (rad) of the rotation between two unit quaternions, a⁻¹ b, to full
/// relative accuracy for small angles (2 atan2(‖v‖, |w|), no acos).
inline double orientationError(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  const Eigen::Quaterniond d = a.conjugate() * b;
  return 2.0 * std::atan2(d.vec().norm(), std::abs(d.w()));
}

}  // namespace bench
}  // namespace lieflow
