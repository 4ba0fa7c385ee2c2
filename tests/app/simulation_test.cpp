/// \file
/// Simulation-level behaviour that the command relies on: zero-energy starts,
/// blow-up detection, the drift statistics, and the default formulation.
#include <gtest/gtest.h>

#include <iostream>
#include <string>
#include <vector>

#include "integrators/registry.hpp"
#include "simulation/simulation.hpp"
#include "simulation/stepper_table_rows.hpp"
#include "liegroup/invalid_input.hpp"

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

TEST(Simulation, TheDefaultFormulationIsJointCoordinatesWhereverTheyRunTheScene) {
  // ../shared/DESIGN.md "Default formulation": the fastest formulation that
  // represents the scene (issue 30: joint coordinates 2-3x faster per step).
  struct Case {
    const char* scene;
    const char* integrator;
    const char* expected;
  };
  for (const Case& c : {Case{"chain-10", "rkmk4", "joint"}, Case{"double-pendulum", "lgvi", "joint"},
                        Case{"double-pendulum", "genalpha", "joint"}, Case{"cardan-shaft", "rkmk4", "joint"},
                        Case{"cardan-shaft", "lgvi", "maximal"}, Case{"rack-pinion", "rkmk4", "joint"},
                        Case{"slider-crank", "cf4", "joint"}, Case{"slider-crank", "genalpha", "maximal"},
                        Case{"gimbal-upside-down", "cf4", "maximal"}, Case{"heavy-top", "splitting", "joint"}}) {
    const Simulation sim(std::string(c.scene) == "gimbal-upside-down"
                             ? loadScene(std::string(LIEFLOW_SOURCE_DIR) + "/tests/data/scenes/gimbal-upside-down.json")
                             : loadScene(c.scene));
    EXPECT_EQ(sim.defaultFormulation(c.integrator), c.expected) << c.scene << " " << c.integrator;
  }
  // On every built-in scene and integrator: the default is joint exactly
  // where joint coordinates run it (unless the table of steppers keeps that
  // cell for when it is asked for), the run says which it used, and it is the
  // same run, bit for bit, as the formulation asked for by name.
  for (const BuiltinScene& b : builtinScenes()) {
    const Simulation sim(loadScene(b.name));
    for (const IntegratorInfo& info : integratorRegistry()) {
      if (!sim.supports(info.name, nullptr)) continue;
      // (where its cell runs only when asked for: genalpha on loops, maximal)
      const std::string expected = !sim.hasConstraints() || (sim.supports(info.name, nullptr, "joint") &&
                                                              sim.jointOnlyWhenAskedFor(info.name).empty())
                                       ? "joint"
                                       : "maximal";
      EXPECT_EQ(sim.defaultFormulation(info.name), expected) << b.name << " " << info.name;
      SimulationOptions o;
      o.integrator = info.name;
      o.dt = 1e-3;
      o.t_end = 4e-3;
      const SimulationResult by_default = sim.run(o);
      EXPECT_EQ(by_default.formulation, expected) << b.name << " " << info.name;
      o.formulation = expected == "joint" && !sim.hasConstraints() ? "" : expected;
      const SimulationResult named = sim.run(o);
      EXPECT_EQ(by_default.final_row, named.final_row) << b.name << " " << info.name;
    }
  }
}

/// The table of steppers (simulation/stepper_table_rows.hpp) has one row per
/// integrator of the registry, in its order, and `supports`, the run and the
/// refusals read it alike: on every built-in scene, integrator and
/// formulation, a run goes exactly where `supports` says yes, and where it
/// says no the run is refused with the same reason.
TEST(Simulation, TheTableOfSteppersAnswersSupportsAndRunsAlike) {
  std::vector<std::string> rows;
  stepper_table::forEachRow([&](const auto& row) { rows.push_back(row.name); });
  std::vector<std::string> registry;
  for (const IntegratorInfo& info : integratorRegistry()) registry.push_back(info.name);
  EXPECT_EQ(rows, registry);
  int refused = 0, ran = 0;
  for (const BuiltinScene& b : builtinScenes()) {
    const Simulation sim(loadScene(b.name));
    for (const IntegratorInfo& info : integratorRegistry())
      for (const char* formulation : {"", "maximal", "joint"}) {
        SCOPED_TRACE(std::string(b.name) + " " + info.name + " '" + formulation + "'");
        if (!sim.hasConstraints() && *formulation) continue;  // one formulation: nothing to choose
        std::string why;
        const bool supported = sim.supports(info.name, &why, formulation);
        SimulationOptions o;
        o.integrator = info.name;
        o.formulation = formulation;
        o.dt = 1e-3;
        o.t_end = 2e-3;
        if (supported) {
          EXPECT_NO_THROW(sim.run(o));
          ++ran;
          continue;
        }
        ++refused;
        EXPECT_FALSE(why.empty());
        try {
          sim.run(o);
          ADD_FAILURE() << "ran although supports said: " << why;
        } catch (const InvalidInput& e) {
          // A joint formulation that cannot hold the scene is refused as
          // --formulation, its reason with the way out added.
          EXPECT_TRUE(e.reason() == why || e.reason().find(why.substr(why.find(':') + 1)) != std::string::npos)
              << e.reason() << " | " << why;
        }
      }
  }
  EXPECT_GT(ran, 100);
  EXPECT_GT(refused, 10);
  // Each refusal in joint coordinates names the integrators that have a stepper there.
  const Simulation cardan(loadScene("cardan-shaft"));
  std::string why;
  EXPECT_FALSE(cardan.supports("splitting", &why, "joint"));
  EXPECT_NE(why.find("available: rkmk-euler rkmk-heun rkmk3 rkmk4 rkmk6 rkmk45 cg3 cf4 lgvi genalpha radau5)"),
            std::string::npos)
      << why;
  // ... and a refusal by what the scene holds says where it runs.
  EXPECT_FALSE(cardan.supports("genalpha", &why, "joint"));
  EXPECT_NE(why.find("`formulation` maximal"), std::string::npos) << why;
}

/// The run's figures are checked at the output steps unless asked for more
/// often (SimulationOptions::check_every): the drifts at every 100th step lie
/// within those at every step (they are the maximum over a subset of the same
/// states), the trajectory is the same bit for bit, and a scene with dashpots
/// still integrates their power at every step, so its energy balance is the
/// same figure whichever steps are checked.
TEST(Simulation, FiguresAreCheckedAtTheRowsUnlessAskedForEveryStep) {
  for (const char* name : {"heavy-top", "chain-3"}) {
    SCOPED_TRACE(name);
    const Simulation sim(loadScene(name));
    SimulationOptions o;
    o.integrator = "rkmk4";
    o.dt = 1e-3;
    o.t_end = 2.0;
    o.every = 100;
    std::vector<std::vector<double>> rows_sparse, rows_dense;
    const SimulationResult sparse = sim.run(o, [&](const std::vector<double>& r) { rows_sparse.push_back(r); });
    o.check_every = 1;
    const SimulationResult dense = sim.run(o, [&](const std::vector<double>& r) { rows_dense.push_back(r); });
    EXPECT_EQ(sparse.checked_every, 100);
    EXPECT_EQ(dense.checked_every, 1);
    EXPECT_EQ(rows_sparse, rows_dense);
    EXPECT_LE(sparse.energy_drift, dense.energy_drift);
    EXPECT_GT(sparse.energy_drift, 0.0);
  }
  // Dashpots: chain-3 with a damper on each joint has energy_balance.
  SceneDescription damped = loadScene("chain-3");
  for (JointDescription& j : damped.joints) j.coordinates[0].damping = 0.02;
  const Simulation sim(damped);
  SimulationOptions o;
  o.integrator = "rkmk4";
  o.dt = 1e-3;
  o.t_end = 2.0;
  o.every = 2000;
  const SimulationResult sparse = sim.run(o);
  o.check_every = 1;
  const SimulationResult dense = sim.run(o);
  ASSERT_EQ(sparse.invariants.size(), dense.invariants.size());
  ASSERT_FALSE(sparse.invariants.empty());
  EXPECT_EQ(sparse.invariants.back().first, "energy_balance");
  std::cout << "[ measured ] chain-3 with dashpots, energy_balance drift checked at 2 rows: "
            << sparse.invariants.back().second << ", at every step: " << dense.invariants.back().second << "\n";
  // The work is the same quadrature over every step; only the maximum is
  // taken over fewer states.
  EXPECT_LE(sparse.invariants.back().second, dense.invariants.back().second);
  EXPECT_GT(sparse.invariants.back().second, 0.0);
  EXPECT_LT(dense.invariants.back().second, 1e-6);
}

}  // namespace
}  // namespace lieflow
