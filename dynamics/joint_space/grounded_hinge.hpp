/// \file
/// One body on a revolute joint to the ground in closed form: the one-joint
/// spring fit's model (calibration/spring_residuals.hpp) and ScalarDynamics'
/// path for such a tree, whose constants ScalarDynamics reads off its general
/// passes (scalar_dynamics.hpp); tests/dynamics/scalar_dynamics_test.cpp
/// compares the closed form with those passes and with the simulator's
/// articulated-body algorithm.
#pragma once

#include <cmath>

#include "dynamics/joint_space/articulated_model.hpp"

namespace lieflow {
namespace articulated {

/// The closed form of one revolute joint from the ground (the one-joint spring
/// fit's model). The body turns about a fixed axis a, so its inertia about a
/// is the same at every angle, and a · (ω × Iω) and the moment of the
/// centripetal force vanish for ω = a q̇: h(q, q̇) = −Q_g(q). The weight's
/// moment about a turns with the body, Q_g(q) = g₀ + g_c cos q + g_s sin q
/// (Rodrigues' formula), so the three constants are read off the general
/// algorithm at q = 0, π/2 and π, and the inertia from one unit-u̇ pass.
struct GroundedHinge {
  bool valid = false;
  double inertia = 1.0, gravity_const = 0.0, gravity_cos = 0.0, gravity_sin = 0.0;
};

/// Whether the model is one body on a revolute joint from the ground.
inline bool isGroundedHinge(const ArticulatedModel& model) {
  return model.bodyCount() == 1 && model.bodies[0].kind == JointKind::kRevolute && model.bodies[0].parent == kGround;
}

/// q̈ = (Q_g(q) − k (q − q₀) − c q̇ + M) / I of a GroundedHinge (M: the
/// applied moment at the step's time).
template <typename T>
T groundedHingeAcceleration(const GroundedHinge& h, const T& q, const T& u, const T& stiffness, const T& damping,
                            const T& rest, double moment) {
  using std::cos;
  using std::sin;
  // The constants multiply as doubles (a Jet times a double scales it).
  const T Q = (h.gravity_const + moment) + h.gravity_cos * cos(q) + h.gravity_sin * sin(q) - stiffness * (q - rest) -
              damping * u;
  return Q * (1.0 / h.inertia);
}

}  // namespace articulated
}  // namespace lieflow
