/// \file
/// Simulation-level behaviour that the command relies on: zero-energy starts,
/// blow-up detection, and the drift statistics.
#include <gtest/gtest.h>

#include "joints/simulation.hpp"

namespace lieflow {
namespace {

/// A pendulum released from rest with its centre of mass at the pivot's
/// height: E₀ = 0 exactly, which must not read as an infinite energy error.
const char* kPendulumAtRest = R"({
  "name": "rest", "gravity": [0, 0, -9.81],
  "bodies": [{"name": "top", "mass": 15.0, "inertia": [0.234375, 0.46875, 0.234375]}],
  "joints": [{"name": "pivot", "type": "spherical", "main": "ground", "secondary": "top",
              "anchor_main": [0, 0, 0], "anchor_secondary": [0, -1, 0]}],
  "integrator": {"name": "rkmk4", "dt": 0.001}, "t_end": 2.0
})";

TEST(Simulation, ZeroInitialEnergyIsNotABlowUp) {
  const Simulation sim(parseScene(kPendulumAtRest, "rest.json"));
  SimulationOptions o;
  o.integrator = "rkmk4";
  o.dt = 1e-3;
  o.t_end = 2.0;
  const SimulationResult r = sim.run(o);
  EXPECT_FALSE(r.failed) << r.failure;
  // Absolute drift (E₀ = 0), in joules: RK4 at h = 1e-3 keeps it tiny
  // against the ~150 J exchanged between potential and kinetic energy.
  EXPECT_LT(r.energy_drift, 1e-6);
  // The body really swings: it falls about 1 m below the pivot height.
  EXPECT_LT(r.final_row[1 + 7 + 2], -0.5);
}

TEST(Simulation, EnergyGrowthStopsAnExplicitMethodBeyondItsLimit) {
  const Simulation sim(loadScene("heavy-top"));
  SimulationOptions o;
  o.integrator = "rkmk-euler";
  o.dt = 1e-3;
  o.t_end = 2.0;
  const SimulationResult r = sim.run(o);
  EXPECT_TRUE(r.failed);
  EXPECT_NE(r.failure.find("blow-up"), std::string::npos) << r.failure;
  EXPECT_LT(r.steps, 2000);
}

}  // namespace
}  // namespace lieflow
