/// \file
/// The multibody invariants beside the spatial angular momentum
/// (simulation/invariants.hpp): the angular momentum about the centre of mass of
/// a free-floating mechanism under gravity, `L_com`, and the energy balance
/// E + W of a mechanism whose only non-conservative forces are its dashpots,
/// `energy_balance`, in both formulations.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <string>

#include "simulation/invariants.hpp"
#include "model/scene.hpp"
#include "simulation/simulation.hpp"

namespace lieflow {
namespace {

/// Two bars on a sprung, damped hinge, free in space under gravity, thrown
/// turning about a tilted axis so that the hinge flexes.
constexpr const char* kTumblingPair = R"({
  "name": "tumbling-pair", "gravity": [0, 0, -9.81],
  "bodies": [
    {"name": "a", "mass": 2.0, "inertia": [0.02, 0.09, 0.1], "position": [0, 0, 1],
     "angular_velocity": [0.5, -1.0, 2.0], "velocity": [0.3, 0, 2.0]},
    {"name": "b", "mass": 1.0, "inertia": [0.01, 0.04, 0.045], "position": [0.5, 0, 1],
     "angular_velocity": [0.5, -1.0, 3.5], "velocity": [0.3, 1.375, 2.5]}],
  "joints": [
    {"name": "hinge", "type": "revolute", "main": "a", "secondary": "b",
     "anchor_main": [0.25, 0, 0], "anchor_secondary": [-0.25, 0, 0], "axis_main": [0, 0, 1],
     "spring": {"stiffness": 3.0, "rest_angle": 0.0}, "damper": {"damping": 0.2}}]
})";

/// The built-in double pendulum with a dashpot at the elbow.
constexpr const char* kDampedDoublePendulum = R"({
  "name": "damped-double-pendulum", "gravity": [0, 0, -9.81],
  "bodies": [
    {"name": "upper", "mass": 1.0, "inertia": [0.08333333333333333, 0.08333333333333333, 0.001],
     "orientation": [0.8775825618903728, 0, 0.479425538604203, 0], "position": [-0.42073549240394825, 0, -0.2701511529340699]},
    {"name": "lower", "mass": 1.0, "inertia": [0.08333333333333333, 0.08333333333333333, 0.001],
     "orientation": [0.5403023058681398, 0, 0.8414709848078965, 0], "position": [-1.2961196982207374, 0, -0.3322288875945686]}],
  "joints": [
    {"name": "shoulder", "type": "revolute", "main": "ground", "secondary": "upper", "anchor_main": [0, 0, 0],
     "anchor_secondary": [0, 0, 0.5], "axis_main": [0, 1, 0], "initial_angle": 1.0},
    {"name": "elbow", "type": "revolute", "main": "upper", "secondary": "lower", "anchor_main": [0, 0, -0.5],
     "anchor_secondary": [0, 0, 0.5], "axis_main": [0, 1, 0], "initial_angle": 1.0, "damper": {"damping": 0.5}}]
})";

struct Drifts {
  double L_com = -1.0, balance = -1.0, energy = 0.0;
};

Drifts run(const std::string& integrator, double h, double t_end, const std::string& formulation = "") {
  const Simulation sim(parseScene(kTumblingPair, "tumbling-pair"));
  SimulationOptions o;
  o.integrator = integrator;
  o.dt = h;
  o.t_end = t_end;
  o.formulation = formulation;
  const SimulationResult r = sim.run(o);
  EXPECT_FALSE(r.failed) << r.failure;
  Drifts d;
  d.energy = r.energy_drift;
  for (const auto& [name, drift] : r.invariants) {
    if (name == "L_com") d.L_com = drift;
    if (name == "energy_balance") d.balance = drift;
  }
  return d;
}

TEST(MultibodyInvariants, AFreeMechanismUnderGravityKeepsItsMomentumAboutItsCentre) {
  const Simulation sim(parseScene(kTumblingPair, "tumbling-pair"));
  const std::vector<std::string> names = sim.invariantNames();
  ASSERT_EQ(names, (std::vector<std::string>{"L_com", "energy_balance"}));
  // lgvi keeps it to round-off in both formulations (RATTLE on the bodies;
  // in joint coordinates the step's centroidal coordinates, articulated_
  // system.hpp); the explicit methods to their error (the internal forces
  // are equal and opposite at one point).
  const Drifts lgvi = run("lgvi", 1e-3, 5.0, "joint");
  const Drifts lgvi_maximal = run("lgvi", 1e-3, 5.0, "maximal");
  const Drifts rk = run("rkmk4", 1e-3, 5.0);
  std::cout << "[ measured ] tumbling pair, 5 s at h = 1e-3: L_com drift lgvi " << lgvi.L_com << " (maximal "
            << lgvi_maximal.L_com << "), rkmk4 " << rk.L_com << "; energy drift " << lgvi.energy
            << " (the dashpot dissipates)\n";
  EXPECT_LT(lgvi.L_com, 1e-12);
  EXPECT_LT(lgvi_maximal.L_com, 1e-12);
  EXPECT_LT(rk.L_com, 1e-10);
  EXPECT_GT(lgvi.energy, 5e-4);
}

TEST(DissipatedWork, IsAFourthOrderQuadratureOnAnySpacing) {
  // ∫₀² (1 + sin² 3t) dt = 2 + 1 − sin(12)/12, from samples at steps h.
  const double exact = 3.0 - std::sin(12.0) / 12.0;
  auto error = [&](double h, bool uneven) {
    DissipatedWork w;
    double t = 0.0;
    for (int k = 0; t < 2.0 - 1e-12; ++k) {
      w.add(t, 1.0 + std::pow(std::sin(3.0 * t), 2));
      t = std::min(2.0, t + h * (uneven && k % 2 ? 1.5 : 1.0));
    }
    w.add(t, 1.0 + std::pow(std::sin(3.0 * t), 2));
    return std::abs(w.value() - exact);
  };
  const double e1 = error(0.02, false), e2 = error(0.01, false), u1 = error(0.02, true), u2 = error(0.01, true);
  std::cout << "[ measured ] DissipatedWork error at h = 0.02, 0.01: " << e1 << ", " << e2 << "; alternating steps "
            << u1 << ", " << u2 << "\n";
  EXPECT_NEAR(std::log2(e1 / e2), 4.0, 0.3);
  // Uneven steps: the end corrections assume even ones; second order then.
  EXPECT_NEAR(std::log2(u1 / u2), 2.0, 0.3);
  EXPECT_LT(e2, 5e-8);
}

TEST(MultibodyInvariants, EnergyPlusDissipatedWorkConvergesWithTheIntegrator) {
  // With W fourth order (DissipatedWork), rkmk4's balance drift falls by
  // about 2³ per halving of h here (its own energy error, projected in
  // maximal coordinates; 2⁴ on the double pendulum below): W is the work the
  // dashpot really did (a wrong W would leave a constant gap, the
  // trapezoidal sum alone a second-order one).
  const Drifts a = run("rkmk4", 4e-3, 2.0), b = run("rkmk4", 2e-3, 2.0), c = run("rkmk4", 1e-3, 2.0);
  std::cout << "[ measured ] tumbling pair, energy balance drift over 2 s, rkmk4 h = 4e-3, 2e-3, 1e-3: " << a.balance
            << ", " << b.balance << ", " << c.balance << " (energy itself " << c.energy << ")\n";
  EXPECT_NEAR(std::log2(a.balance / b.balance), 3.5, 0.9);
  EXPECT_NEAR(std::log2(b.balance / c.balance), 3.5, 0.9);
  EXPECT_LT(c.balance, 1e-6 * c.energy);
  // The variational integrator: bounded, no drift over a long run.
  const Drifts short_run = run("lgvi", 1e-3, 2.0), long_run = run("lgvi", 1e-3, 40.0);
  std::cout << "[ measured ] lgvi h = 1e-3: energy balance drift over 2 s " << short_run.balance << ", over 40 s "
            << long_run.balance << "\n";
  EXPECT_LT(long_run.balance, 3.0 * short_run.balance + 1e-9);
}

TEST(MultibodyInvariants, JointCoordinatesMeasureTheSameEnergyBalance) {
  // The double pendulum with a dashpot at the elbow (a tree on the ground:
  // the joint formulation covers it; only the energy balance is conserved).
  std::string text = kDampedDoublePendulum;
  const Simulation sim(parseScene(text, "damped-double-pendulum"));
  ASSERT_EQ(sim.invariantNames(), (std::vector<std::string>{"energy_balance"}));
  std::string why;
  ASSERT_TRUE(sim.hasJointFormulation(&why)) << why;
  double balance[2][2], energy = 0.0;
  for (int f = 0; f < 2; ++f)
    for (int i = 0; i < 2; ++i) {
      SimulationOptions o;
      o.integrator = "rkmk4";
      o.dt = i == 0 ? 2e-3 : 1e-3;
      o.t_end = 2.0;
      o.formulation = f == 0 ? "joint" : "maximal";
      const SimulationResult r = sim.run(o);
      ASSERT_FALSE(r.failed) << r.failure;
      balance[f][i] = r.invariants.at(0).second;
      energy = r.energy_drift;
    }
  std::cout << "[ measured ] damped double pendulum, rkmk4 over 2 s, energy balance drift at h = 2e-3, 1e-3: joint "
            << balance[0][0] << ", " << balance[0][1] << "; maximal " << balance[1][0] << ", " << balance[1][1]
            << " (energy itself " << energy << ")\n";
  EXPECT_GT(energy, 0.1);
  for (int f = 0; f < 2; ++f) {
    EXPECT_NEAR(std::log2(balance[f][0] / balance[f][1]), 4.0, 0.5) << f;
    EXPECT_LT(balance[f][1], 1e-6 * energy) << f;
  }
  // The same motion and the same quadrature of the same power: the two
  // formulations' balances agree to their integration error.
  EXPECT_NEAR(balance[0][1], balance[1][1], 0.2 * balance[1][1]);
}

TEST(MultibodyInvariants, DrivenOrGroundedScenesClaimNeither) {
  // A hinge to the ground passes external forces; a sine moment does work.
  const Simulation pendulum(loadScene("double-pendulum"));
  for (const std::string& n : pendulum.invariantNames()) EXPECT_NE(n, "L_com");
  std::string driven = kTumblingPair;
  driven.replace(driven.find("\"damper\""), 0, R"("moment": {"type": "sine", "amplitude": 0.1, "frequency": 1.0}, )");
  const Simulation sim(parseScene(driven, "driven"));
  const std::vector<std::string> names = sim.invariantNames();
  EXPECT_EQ(names, (std::vector<std::string>{"L_com"}));
}

}  // namespace
}  // namespace lieflow
