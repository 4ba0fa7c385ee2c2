// The compound pendulum shared by the constrained-integrator tests, with its
// independent 1-D reference.
#pragma once

#include <cmath>

#include "dynamics/maximal/multibody_system.hpp"

namespace lieflow {
namespace multibody {
namespace testing_support {

/// A compound pendulum (rod of mass m, CoM at distance L below the hinge, hinge
/// axis y through the world origin, tilted by θ₀ at t = 0) with a torsional
/// spring k (rest angle φ_r), a dashpot c and an applied moment M(t) on the
/// joint coordinate φ = θ − θ₀ (zero at assembly):
///   I_o θ̈ = −m g L sin θ − k (φ − φ_r) − c φ̇ + M(t),   I_o = I_yy + m L².
struct Pendulum {
  double m = 1.3, L = 0.7, Iyy = 0.05, g = 9.81;
  double theta0, k, rest, c;
  TimeFunction moment;
  MultibodySystem system;
  MultibodyGroupState y0;

  explicit Pendulum(double theta0_, double k_ = 0.0, double rest_ = 0.0, double c_ = 0.0,
                    TimeFunction moment_ = TimeFunction::constant(0.0))
      : theta0(theta0_), k(k_), rest(rest_), c(c_), moment(moment_), system(build()),
        y0(system.makeState(initial())) {}

  /// κ = m g L / I_o of the free pendulum θ̈ = −κ sin θ.
  double kappa() const { return m * g * L / (Iyy + m * L * L); }

  MultibodyState initial() const {
    MultibodyState s;
    const SO3d R = SO3d::exp(theta0 * Eigen::Vector3d::UnitY());
    s.poses = {constraints::BodyPose<double>{R, R * Eigen::Vector3d(0, 0, -L)}};
    s.velocities = {constraints::BodyVelocity<double>{}};
    return s;
  }

  MultibodySystem build() const {
    using Eigen::Vector3d;
    MultibodyModel model;
    model.gravity = Vector3d(0, 0, -g);
    model.addBody(RigidBody{"rod", m, Vector3d(0.04, Iyy, 0.03).asDiagonal(), false});
    const MultibodyState s = initial();
    model.addJoint(Joint{"hinge", kGround, 0,
                         constraints::assembleRevoluteJoint<double>(constraints::groundPose<double>(), s.poses[0],
                                                                    Vector3d::Zero(), Vector3d(0, 0, L),
                                                                    Vector3d::UnitY(), Vector3d::UnitY())});
    CoordinateDrive d;
    d.stiffness = k;
    d.rest_angle = rest;
    d.damping = c;
    d.moment = moment;
    return MultibodySystem(model, {{d, CoordinateDrive{}}});
  }

  /// Classical RK4 on the 1-D equation with `steps` steps: the reference θ(T).
  double reference(double T, int steps = 200000) const {
    const double Io = Iyy + m * L * L;
    auto acc = [&](double t, double th, double om) {
      return (-m * g * L * std::sin(th) - k * (th - theta0 - rest) - c * om + moment(t)) / Io;
    };
    const double h = T / steps;
    double th = theta0, om = 0.0;
    for (int i = 0; i < steps; ++i) {
      const double t = i * h;
      const double k1a = om, k1b = acc(t, th, om);
      const double k2a = om + 0.5 * h * k1b, k2b = acc(t + 0.5 * h, th + 0.5 * h * k1a, om + 0.5 * h * k1b);
      const double k3a = om + 0.5 * h * k2b, k3b = acc(t + 0.5 * h, th + 0.5 * h * k2a, om + 0.5 * h * k2b);
      const double k4a = om + h * k3b, k4b = acc(t + h, th + h * k3a, om + h * k3b);
      th += h / 6 * (k1a + 2 * k2a + 2 * k3a + k4a);
      om += h / 6 * (k1b + 2 * k2b + 2 * k3b + k4b);
    }
    return th;
  }
};

}  // namespace testing_support
}  // namespace multibody
}  // namespace lieflow
