// Dynamics of constrained multibody systems (joints/multibody/multibody_system.hpp)
// stepped by the projected Lie-group steppers, against independent results.
#include <cmath>

#include <gtest/gtest.h>

#include "integrators/butcher_tableau.hpp"
#include "integrators/commutator_free.hpp"
#include "integrators/integrate.hpp"
#include "integrators/projected_stepper.hpp"
#include "integrators/rkmk.hpp"
#include "joints/multibody/multibody_system.hpp"

namespace lieflow {
namespace multibody {
namespace {

using Eigen::Vector3d;

// A compound pendulum: rod of mass m, CoM at distance L below the hinge,
// hinge axis y through the world origin. Angle θ about y; θ̈ = −(m g L / I_o) sin θ
// with I_o = I_yy + m L².
struct Pendulum {
  double m = 1.3, L = 0.7, Iyy = 0.05, g = 9.81;
  MultibodyState s0;
  MultibodySystem system;
  MultibodySystem::State y0;
  static MultibodySystem build(double m, double L, double Iyy, double g, double theta0,
                               MultibodyState* s) {
    MultibodyModel model;
    model.gravity = Vector3d(0, 0, -g);
    model.addBody(RigidBody{"rod", m, Vector3d(0.04, Iyy, 0.03).asDiagonal(), false});
    const SO3d R = SO3d::exp(theta0 * Vector3d::UnitY());
    const constraints::BodyPose<double> pose{R, R * Vector3d(0, 0, -L)};
    model.addJoint(Joint{"hinge", kGround, 0,
                         constraints::assembleRevoluteJoint<double>(
                             constraints::groundPose<double>(), pose, Vector3d::Zero(),
                             Vector3d(0, 0, L), Vector3d::UnitY(), Vector3d::UnitY())});
    s->poses = {pose};
    s->velocities = {constraints::BodyVelocity<double>{}};
    return MultibodySystem(model, {});
  }
  explicit Pendulum(double theta0) : system(build(m, L, Iyy, g, theta0, &s0)), y0(system.makeState(s0)) {}
};

// Classical RK4 on θ̈ = −κ sin θ with a tiny step: the 1-D reference.
double pendulumReference(double theta0, double kappa, double T) {
  const int n = 200000;
  const double h = T / n;
  double th = theta0, om = 0.0;
  auto f = [&](double a, double b, double* da, double* db) {
    *da = b;
    *db = -kappa * std::sin(a);
  };
  for (int i = 0; i < n; ++i) {
    double k1a, k1b, k2a, k2b, k3a, k3b, k4a, k4b;
    f(th, om, &k1a, &k1b);
    f(th + 0.5 * h * k1a, om + 0.5 * h * k1b, &k2a, &k2b);
    f(th + 0.5 * h * k2a, om + 0.5 * h * k2b, &k3a, &k3b);
    f(th + h * k3a, om + h * k3b, &k4a, &k4b);
    th += h / 6 * (k1a + 2 * k2a + 2 * k3a + k4a);
    om += h / 6 * (k1b + 2 * k2b + 2 * k3b + k4b);
  }
  return th;
}

TEST(MultibodyDynamics, PendulumMatchesOneDimensionalReference) {
  const double theta0 = 1.2, T = 2.0;
  Pendulum P(theta0);
  const double kappa = P.m * P.g * P.L / (P.Iyy + P.m * P.L * P.L);
  const double ref = pendulumReference(theta0, kappa, T);
  ProjectedStepper<RkmkStepper<MultibodyGroupState>> stepper(RkmkStepper<MultibodyGroupState>(ButcherTableau::rk4()));
  MultibodyGroupState y = P.y0;
  double max_err = 0.0;
  const RunSummary run = integrateFixedStep(stepper, P.system, y, 0.0, T, 1e-3,
                                            [&](long, double t, const MultibodyGroupState& s) {
                                              max_err = std::max(max_err, P.system.constraintError(t, s));
                                              y = s;
                                              return true;
                                            });
  ASSERT_FALSE(run.failed) << run.failure;
  // The joint angle is zero at assembly (t = 0): θ = θ₀ + φ_J.
  EXPECT_NEAR(theta0 + y.angles[0], ref, 1e-10);
  EXPECT_LE(max_err, 1e-12);
}

}  // namespace
}  // namespace multibody
}  // namespace lieflow
