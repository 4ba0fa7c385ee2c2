// The RATTLE-type constrained Lie group variational integrator
// (integrators/constrained_lgvi.hpp) on MultibodySystem, against independent
// references: a compound pendulum (with spring, dashpot and applied moment)
// against RK4 on its 1-D equation; a 3-D double pendulum's energy over 10⁴
// steps; the spatial angular momentum of free-floating jointed pairs; a gear
// train on the ground against its exact kinematics (turns about the gear axes,
// α φ₁ + φ₂ = 0 at position level); a gear on a turning carrier against
// projected RK4 at a tiny step; prescribed motion; the unconstrained limit
// against the single-body LGVI; reported failure.
#include "integrators/constrained_lgvi.hpp"
#include "tests/dynamics/pendulum_fixture.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numeric>
#include <string>
#include <vector>

#include "integrators/butcher_tableau.hpp"
#include "integrators/integrate.hpp"
#include "integrators/lgvi.hpp"
#include "integrators/projected_stepper.hpp"
#include "integrators/rigid_body_state.hpp"
#include "dynamics/rigid_body/rigid_body_system.hpp"
#include "integrators/rkmk.hpp"
#include "dynamics/maximal/chain_builder.hpp"
#include "dynamics/maximal/multibody_system.hpp"

namespace lieflow {
namespace multibody {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using Stepper = ConstrainedLgviStepper<MultibodySystem>;

// ---- helpers -----------------------------------------------------------------

/// Runs the stepper over [0, T] with step h; observe(t, y, report) after every
/// step; adds up the reported iterations. Fails the test on a reported failure.
MultibodyGroupState run(const Stepper& stepper, const MultibodySystem& system, const MultibodyGroupState& y0,
                        double T, double h,
                        const std::function<void(double, const MultibodyGroupState&, const StepReport&)>& observe = {},
                        long* iterations = nullptr) {
  MultibodyGroupState y = y0;
  const long n = stepCount(0.0, T, h);
  for (long k = 0; k < n; ++k) {
    StepReport report;
    y = stepper.step(system, k * h, y, h, &report);
    EXPECT_TRUE(report.converged) << report.failure << ": " << report.detail << " at step " << k;
    if (!report.converged) return y;
    if (iterations) *iterations += report.newton_iterations;
    if (observe) observe((k + 1) * h, y, report);
  }
  return y;
}

double slope(double e_coarse, double e_fine) { return std::log2(e_coarse / e_fine); }

Matrix3d inertiaWithProducts(double a, double b, double c) {
  const Matrix3d Q = Eigen::AngleAxisd(0.4, Vector3d(1.0, 2.0, -0.5).normalized()).toRotationMatrix();
  return Q * Vector3d(a, b, c).asDiagonal() * Q.transpose();
}

// ---- pendulum ----------------------------------------------------------------

using testing_support::Pendulum;


/// |θ(T) − θ_ref(T)| at h, h/2, h/4 and the two measured orders.
void expectSecondOrder(const Pendulum& P, const ConstrainedLgviOptions& options, double T, double h) {
  const double ref = P.reference(T);
  const Stepper stepper(options);
  std::vector<double> err;
  for (double step : {h, h / 2, h / 4}) {
    double max_phi = 0.0;
    const MultibodyGroupState y = run(stepper, P.system, P.y0, T, step, [&](double t, const MultibodyGroupState& s,
                                                                           const StepReport&) {
      max_phi = std::max(max_phi, P.system.constraintError(t, s));
    });
    EXPECT_LE(max_phi, options.tolerance);
    err.push_back(std::abs(P.theta0 + y.angles[0] - ref));
  }
  const double p1 = slope(err[0], err[1]), p2 = slope(err[1], err[2]);
  std::printf("pendulum: |theta - theta_ref| at h = %g, %g, %g: %.3g %.3g %.3g, orders %.3f %.3f\n", h, h / 2, h / 4,
              err[0], err[1], err[2], p1, p2);
  EXPECT_NEAR(p1, 2.0, 0.15) << "errors " << err[0] << " " << err[1] << " " << err[2];
  EXPECT_NEAR(p2, 2.0, 0.15) << "errors " << err[0] << " " << err[1] << " " << err[2];
}

TEST(RattleLgvi, PendulumIsSecondOrderAgainstOneDimensionalReference) {
  expectSecondOrder(Pendulum(1.2), {}, 2.0, 0.02);
}

TEST(RattleLgvi, CayleyPendulumIsSecondOrder) {
  ConstrainedLgviOptions options;
  options.rotation.map = LgviMap::kCayley;
  expectSecondOrder(Pendulum(1.2), options, 2.0, 0.02);
}

// Spring, dashpot (discrete Lagrange–d'Alembert with trapezoidal forcing: the
// end kick is implicit in the dashpot) and a time-dependent applied moment
// keep second order.
TEST(RattleLgvi, ForcedDampedPendulumIsSecondOrder) {
  expectSecondOrder(Pendulum(0.8, 3.0, 0.2, 0.15, TimeFunction::sine(0.6, 0.7, 0.3)), {}, 2.0, 0.02);
}

// ---- double pendulum: energy ---------------------------------------------------

TEST(RattleLgvi, DoublePendulumEnergyBoundedWithoutDriftAndConstraintsMet) {
  // Two rods on revolute joints (first axis z, second y in the parent frame,
  // so the motion is three-dimensional) under gravity, a torsional spring on
  // the second joint, random consistent start (chain_builder.hpp).
  MultibodyState s0;
  const MultibodyModel model = randomRevoluteChain(2, true, inertiaWithProducts(0.002, 0.01, 0.01), 11, &s0);
  CoordinateDrive spring;
  spring.stiffness = 0.4;
  spring.rest_angle = 0.3;
  const MultibodySystem system(model, {{CoordinateDrive{}, CoordinateDrive{}}, {spring, CoordinateDrive{}}});
  const MultibodyGroupState y0 = system.makeState(s0);
  const double h = 1e-3, T = 10.0;
  const double E0 = system.energy(y0);
  std::vector<double> E;
  double max_phi = 0.0, max_dphi = 0.0;
  long iterations = 0;
  const Stepper stepper;
  run(stepper, system, y0, T, h,
      [&](double t, const MultibodyGroupState& y, const StepReport& report) {
        E.push_back(system.energy(y));
        max_phi = std::max(max_phi, system.constraintError(t, y));
        max_dphi = std::max(max_dphi, system.velocityConstraintError(t, y));
        EXPECT_LE(report.residual, 1e-12);
      },
      &iterations);
  const std::size_t tenth = E.size() / 10;
  const auto mean = [&](std::size_t a) {
    return std::accumulate(E.begin() + a, E.begin() + a + tenth, 0.0) / static_cast<double>(tenth);
  };
  double max_err = 0.0;
  for (double e : E) max_err = std::max(max_err, std::abs(e - E0));
  const double drift = std::abs(mean(E.size() - tenth) - mean(0));
  std::printf("double pendulum: E0 = %.6g, max|E-E0|/|E0| = %.3g, |mean(last tenth) - mean(first tenth)|/|E0| = %.3g, "
              "max|Phi| = %.3g, max|J u - b| = %.3g, corrections/step = %.3f\n",
              E0, max_err / std::abs(E0), drift / std::abs(E0), max_phi, max_dphi, double(iterations) / E.size());
  EXPECT_LE(max_err, 1e-4 * std::abs(E0));
  EXPECT_LE(drift, 0.05 * max_err);
  EXPECT_LE(max_phi, 1e-10);
  EXPECT_LE(max_dphi, 1e-10);
}

// ---- free-floating pairs: angular momentum -------------------------------------

/// Two bodies joined at the world point (0.3, 0.05, 0) by a ball joint or a
/// hinge (with spring and dashpot), no gravity, no joint to ground: nothing
/// exerts an external moment. Velocities projected onto the joint.
struct FloatingPair {
  MultibodyState s0;
  MultibodySystem system;
  MultibodyGroupState y0;
  static MultibodySystem build(bool revolute, double k, double c, MultibodyState* s) {
    MultibodyModel model;
    model.gravity.setZero();
    model.addBody(RigidBody{"a", 1.7, inertiaWithProducts(0.05, 0.08, 0.11), false});
    model.addBody(RigidBody{"b", 0.9, inertiaWithProducts(0.03, 0.02, 0.04), false});
    const constraints::BodyPose<double> pa{SO3d::exp(Vector3d(0.2, -0.4, 0.1)), Vector3d(0.1, 0.2, -0.3)};
    const constraints::BodyPose<double> pb{SO3d::exp(Vector3d(-0.5, 0.3, 0.7)), Vector3d(0.5, -0.1, 0.2)};
    const Vector3d anchor(0.3, 0.05, 0.0);  // world
    const Vector3d sa = pa.R.inverse() * (anchor - pa.p), sb = pb.R.inverse() * (anchor - pb.p);
    std::vector<CoordinateDrives> drives(1);
    if (revolute) {
      const Vector3d axis = Vector3d(0.3, -1.0, 0.5).normalized();  // main frame
      model.addJoint(Joint{"hinge", 0, 1,
                           constraints::assembleRevoluteJoint<double>(pa, pb, sa, sb, axis,
                                                                      pb.R.inverse() * (pa.R * axis))});
      drives[0][0].stiffness = k;
      drives[0][0].rest_angle = 0.2;
      drives[0][0].damping = c;
    } else {
      model.addJoint(Joint{"ball", 0, 1, constraints::SphericalJoint<double>{sa, sb}});
    }
    s->poses = {pa, pb};
    s->velocities = {constraints::BodyVelocity<double>{Vector3d(0.3, -0.2, 0.1), Vector3d(1.5, -2.0, 0.7)},
                     constraints::BodyVelocity<double>{Vector3d(-0.4, 0.6, 0.2), Vector3d(-3.0, 1.0, 2.5)}};
    return MultibodySystem(model, drives);
  }
  FloatingPair(bool revolute, double k = 0.0, double c = 0.0)
      : system(build(revolute, k, c, &s0)), y0(system.makeState(s0)) {
    std::string why;
    EXPECT_TRUE(system.projectVelocities(0.0, &y0, &why)) << why;
  }
};

/// max ‖L − L₀‖/‖L₀‖ over 10⁴ steps of 1e-3, and E(T) − E₀.
void expectMomentumConserved(const FloatingPair& P, double* energy_change) {
  ASSERT_TRUE(P.system.conservesAngularMomentum());
  const Vector3d L0 = P.system.angularMomentum(P.y0);
  double max_rel = 0.0, max_phi = 0.0;
  // The point rows of a joint are covariant, not invariant, under a global
  // rotation: their reactions have a net moment O(|Φ| |λ|), so the momentum
  // error follows the constraint tolerance (measured max ‖L − L₀‖/‖L₀‖:
  // 1.6e-12 at tolerance 1e-10, 7e-13 at 1e-12, 3e-14 — rounding — at 1e-13).
  ConstrainedLgviOptions options;
  options.tolerance = 1e-13;
  const Stepper stepper(options);
  const MultibodyGroupState y = run(stepper, P.system, P.y0, 10.0, 1e-3,
                                    [&](double t, const MultibodyGroupState& s, const StepReport&) {
                                      max_rel = std::max(max_rel, (P.system.angularMomentum(s) - L0).norm() / L0.norm());
                                      max_phi = std::max(max_phi, P.system.constraintError(t, s));
                                    });
  *energy_change = P.system.energy(y) - P.system.energy(P.y0);
  std::printf("floating pair: max|L-L0|/|L0| = %.3g, max|Phi| = %.3g, E(T) - E0 = %.3g (E0 = %.6g)\n", max_rel,
              max_phi, *energy_change, P.system.energy(P.y0));
  EXPECT_LE(max_rel, 1e-12);
  EXPECT_LE(max_phi, options.tolerance);
}

TEST(RattleLgvi, FreeFloatingSphericalPairConservesAngularMomentumAndEnergy) {
  const FloatingPair P(false);
  double dE = 0.0;
  expectMomentumConserved(P, &dE);
  EXPECT_LE(std::abs(dE), 1e-4 * P.system.energy(P.y0));
}

TEST(RattleLgvi, FreeFloatingSpringDashpotHingeConservesAngularMomentumAndDissipates) {
  const FloatingPair P(true, 5.0, 0.02);
  double dE = 0.0;
  expectMomentumConserved(P, &dE);
  EXPECT_LT(dE, -1e-3 * P.system.energy(P.y0));  // the dashpot dissipates
}

// ---- gears -------------------------------------------------------------------

/// Two rotation-only wheels (products of inertia: the gear rows carry the
/// gyroscopic moments) geared to a carrier with ratio α: the carrier is the
/// ground, or a rotation-only body turning freely.
struct GearTrain {
  constraints::NodeAxes<double> n1, n2;
  double alpha = 1.7;
  int wheel1 = 0, wheel2 = 1;
  MultibodySystem system;
  MultibodyGroupState y0;

  explicit GearTrain(bool moving_carrier) : system(build(moving_carrier)) {
    MultibodyState s;
    if (moving_carrier) {
      s.poses.push_back({SO3d::exp(Vector3d(0.1, 0.3, -0.2)), Vector3d::Zero()});
      s.velocities.push_back({Vector3d::Zero(), Vector3d(0.4, -0.3, 1.1)});
    }
    s.poses.push_back({SO3d::exp(Vector3d(0.3, -0.2, 0.5)), Vector3d::Zero()});
    s.poses.push_back({SO3d::exp(Vector3d(-0.6, 0.1, 0.2)), Vector3d::Zero()});
    s.velocities.push_back({Vector3d::Zero(), 2.0 * n1.r + Vector3d(0.3, 0.1, -0.2)});
    s.velocities.push_back({Vector3d::Zero(), Vector3d(0.1, 0.2, 0.3)});
    y0 = system.makeState(s);
    std::string why;
    EXPECT_TRUE(system.projectVelocities(0.0, &y0, &why)) << why;
  }

  MultibodySystem build(bool moving_carrier) {
    n1 = constraints::makeNodeAxes<double>(Vector3d(1, 2, 0.5).normalized(), Vector3d(-2, 1, 0).normalized());
    n2 = constraints::makeNodeAxes<double>(Vector3d(0.2, -0.3, 1).normalized(), Vector3d(1, 0, -0.2).normalized());
    MultibodyModel model;
    int carrier = kGround;
    if (moving_carrier) {
      carrier = model.addBody(RigidBody{"carrier", 1.0, inertiaWithProducts(0.5, 0.7, 0.9), true});
      wheel1 = 1;
      wheel2 = 2;
    }
    model.addBody(RigidBody{"wheel1", 1.0, inertiaWithProducts(0.02, 0.03, 0.05), true});
    model.addBody(RigidBody{"wheel2", 1.0, inertiaWithProducts(0.04, 0.01, 0.02), true});
    Gear gear{"gear", {{carrier, wheel1, wheel2, kGround}}, constraints::makeGearJoint(alpha, n1, n2)};
    return MultibodySystem(model, {}, {gear});
  }
};

// On the ground the wheels turn uniformly about their r axes with α φ̇₁ + φ̇₂ = 0.
// The gear rows act on the mid-step velocity, where h B ξ = (α f₁·r₁ + f₂·r₂,
// f_i·s_i, f_i·t_i) does not depend on q: each step turns wheel i about r_i
// and α φ₁ + φ₂ = 0 holds at position level, both to the iteration tolerance
// per step (no truncation error), and ω stays constant. The rate of the
// discrete rotation differs from ω by O(h²) (for a free spin the LGVI turns
// by asin(h ω) per step).
TEST(RattleLgvi, GearTrainOnGroundTurnsUniformly) {
  const GearTrain G(false);
  const Vector3d w1 = G.y0.bodies.velocities[0].omega, w2 = G.y0.bodies.velocities[1].omega;
  const double rate1 = w1.dot(G.n1.r), rate2 = w2.dot(G.n2.r);
  ASSERT_NEAR((w1 - rate1 * G.n1.r).norm(), 0.0, 1e-14);
  ASSERT_NEAR(G.alpha * rate1 + rate2, 0.0, 1e-14);
  double max_bu = 0.0, max_off_axis = 0.0, max_relation = 0.0;
  std::array<double, 2> phi{};  // accumulated turn of each wheel about its r axis
  MultibodyGroupState previous = G.y0;
  const double T = 3.0, h = 1e-2;
  const Stepper stepper;
  const MultibodyGroupState y = run(stepper, G.system, G.y0, T, h, [&](double t, const MultibodyGroupState& s,
                                                                       const StepReport&) {
    max_bu = std::max(max_bu, G.system.velocityConstraintError(t, s));
    for (int i = 0; i < 2; ++i) {
      const Vector3d axis = i == 0 ? G.n1.r : G.n2.r;
      const Vector3d turn = (previous.bodies.poses[i].R.inverse() * s.bodies.poses[i].R).log();
      max_off_axis = std::max(max_off_axis, (turn - turn.dot(axis) * axis).norm());
      phi[i] += turn.dot(axis);
    }
    max_relation = std::max(max_relation, std::abs(G.alpha * phi[0] + phi[1]));
    previous = s;
  });
  std::printf("gear on ground: max off-axis turn %.3g, max |alpha phi1 + phi2| = %.3g, phase error %.3g rad\n",
              max_off_axis, max_relation, std::abs(phi[0] - rate1 * T));
  const double tol = stepper.options().tolerance;
  EXPECT_LE(max_off_axis, tol);
  EXPECT_LE(max_relation, (T / h) * tol);
  EXPECT_LE(max_bu, 1e-13);
  EXPECT_LE((y.bodies.velocities[0].omega - w1).norm(), 1e-10);
  EXPECT_LE((y.bodies.velocities[1].omega - w2).norm(), 1e-10);
  EXPECT_LE(std::abs(phi[0] - rate1 * T), 10 * h * h);  // second-order phase error
}

// On a freely turning carrier the gear rows depend on the configuration; the
// symmetric mid-step rows keep second order (reference: projected RK4-RKMK at
// a 25× smaller step).
TEST(RattleLgvi, GearOnTurningCarrierIsSecondOrder) {
  const GearTrain G(true);
  const double T = 1.0;
  ProjectedStepper<RkmkStepper<MultibodyGroupState>> rk4{RkmkStepper<MultibodyGroupState>(ButcherTableau::rk4())};
  MultibodyGroupState ref = G.y0;
  const RunSummary summary = integrateFixedStep(rk4, G.system, G.y0, 0.0, T, 2e-4,
                                                [&](long, double, const MultibodyGroupState& s) {
                                                  ref = s;
                                                  return true;
                                                });
  ASSERT_FALSE(summary.failed) << summary.failure;
  const Stepper stepper;
  std::vector<double> err;
  for (double h : {0.02, 0.01, 0.005}) {
    const MultibodyGroupState y = run(stepper, G.system, G.y0, T, h);
    double e = 0.0;
    for (int i = 0; i < 3; ++i)
      e = std::max({e, (ref.bodies.poses[i].R.inverse() * y.bodies.poses[i].R).log().norm(),
                    (ref.bodies.velocities[i].omega - y.bodies.velocities[i].omega).norm()});
    err.push_back(e);
  }
  std::printf("gear on turning carrier: errors %.3g %.3g %.3g, orders %.3f %.3f\n", err[0], err[1], err[2],
              slope(err[0], err[1]), slope(err[1], err[2]));
  EXPECT_NEAR(slope(err[0], err[1]), 2.0, 0.15);
  EXPECT_NEAR(slope(err[1], err[2]), 2.0, 0.15);
}

// ---- prescribed motion ---------------------------------------------------------

TEST(RattleLgvi, PrescribedHingeAngleIsFollowedEveryStep) {
  Pendulum P(0.5);
  // Rebuild with a prescribed φ(t) = 0.4 sin(2π·0.8 t) (0 at t = 0).
  MultibodyModel model = P.system.model();
  auto drives = P.system.drives();
  drives[0][0] = CoordinateDrive{};
  drives[0][0].prescribed = TimeFunction::sine(0.4, 0.8);
  const MultibodySystem system(model, drives);
  MultibodyGroupState y0 = system.makeState(P.y0.bodies);
  std::string why;
  ASSERT_TRUE(system.projectVelocities(0.0, &y0, &why)) << why;
  const TimeFunction f = *drives[0][0].prescribed;
  double max_err = 0.0;
  const Stepper stepper;
  run(stepper, system, y0, 2.0, 1e-3, [&](double t, const MultibodyGroupState& s, const StepReport&) {
    max_err = std::max(max_err, std::abs(s.angles[0] - f(t)));
    max_err = std::max(max_err, system.constraintError(t, s));
  });
  EXPECT_LE(max_err, 1e-12);
}

// ---- no constraints ------------------------------------------------------------

// Without joints the scheme is the single-body LGVI with velocity Verlet
// (integrators/lgvi.hpp): a free body under gravity agrees with LgviStepper on
// FreeBodyState to rounding, and the centre of mass follows the exact parabola.
TEST(RattleLgvi, WithoutJointsItIsTheSingleBodyLgvi) {
  RigidBodyParameters<double> params;
  params.mass = 2.5;
  params.inertia = inertiaWithProducts(1.0, 2.0, 3.0);
  params.gravity = Vector3d(0.3, -0.2, -9.81);
  const FreeBodySystem<double> free_system(params);
  FreeBodyState<double> f0;
  f0.R = SO3d::exp(Vector3d(0.3, -0.7, 0.2));
  f0.p = Vector3d(1.0, -2.0, 3.0);
  f0.omega = Vector3d(0.3, 1.0, -0.6);
  f0.v = Vector3d(0.5, 4.0, 6.0);

  MultibodyModel model;
  model.gravity = params.gravity;
  model.addBody(RigidBody{"body", params.mass, params.inertia, false});
  const MultibodySystem system(model, {});
  MultibodyState s;
  s.poses = {constraints::BodyPose<double>{f0.R, f0.p}};
  s.velocities = {constraints::BodyVelocity<double>{f0.v, f0.omega}};
  const double h = 0.01, T = 2.0;
  const MultibodyGroupState y = run(Stepper{}, system, system.makeState(s), T, h);
  const LgviStepper<FreeBodyState<double>> lgvi;
  FreeBodyState<double> f = f0;
  for (int k = 0; k < 200; ++k) f = lgvi.step(free_system, k * h, f, h);
  EXPECT_LE((f.R.inverse() * y.bodies.poses[0].R).log().norm(), 1e-13);
  EXPECT_LE((f.omega - y.bodies.velocities[0].omega).norm(), 1e-13);
  const Vector3d p_exact = f0.p + T * f0.v + 0.5 * T * T * params.gravity;
  EXPECT_LE((y.bodies.poses[0].p - p_exact).norm(), 1e-12 * p_exact.norm());
  EXPECT_LE((y.bodies.velocities[0].v - (f0.v + T * params.gravity)).norm(), 1e-12);
}

// ---- failure -----------------------------------------------------------------

TEST(RattleLgvi, NonConvergenceIsReportedWithoutNaN) {
  const Pendulum P(1.2);
  const Stepper stepper;
  ConstrainedLgviOptions cayley_options;  // solvable rotation update at any h
  cayley_options.rotation.map = LgviMap::kCayley;
  const Stepper cayley(cayley_options);
  for (double h : {5.0, 50.0}) {
    for (const Stepper* s : {&stepper, &cayley}) {
      StepReport report;
      const MultibodyGroupState y = s->step(P.system, 0.0, P.y0, h, &report);
      std::printf("h = %g: %s: %s\n", h, report.failure, report.detail.c_str());
      EXPECT_FALSE(report.converged) << "h = " << h;
      EXPECT_NE(std::string(report.failure), "");
      EXPECT_FALSE(report.detail.empty());
      EXPECT_TRUE(isFinite(y));
      EXPECT_EQ(y.bodies.poses[0].p, P.y0.bodies.poses[0].p);  // the step is not taken
    }
  }
  // Through the driver: the run stops and says why.
  const RunSummary run = integrateFixedStep(stepper, P.system, P.y0, 0.0, 10.0, 5.0,
                                            [](long, double, const MultibodyGroupState&) { return true; });
  EXPECT_TRUE(run.failed);
  EXPECT_NE(run.failure.find("constrained LGVI"), std::string::npos) << run.failure;
  // Too few iterations allowed at a normal step.
  ConstrainedLgviOptions options;
  options.max_iterations = 1;
  options.tolerance = 1e-15;
  StepReport report;
  const MultibodyGroupState y = Stepper(options).step(P.system, 0.0, P.y0, 0.05, &report);
  std::printf("max_iterations = 1: %s: %s\n", report.failure, report.detail.c_str());
  EXPECT_FALSE(report.converged);
  EXPECT_NE(std::string(report.failure).find("constraint iteration"), std::string::npos);
  EXPECT_TRUE(isFinite(y));
}

TEST(RattleLgvi, OptionsAreChecked) {
  ConstrainedLgviOptions bad;
  bad.tolerance = 0.0;
  EXPECT_THROW(Stepper{bad}, InvalidInput);
  bad = {};
  bad.max_iterations = 0;
  EXPECT_THROW(Stepper{bad}, InvalidInput);
}

}  // namespace
}  // namespace multibody
}  // namespace lieflow
