// No heap allocation per step: every explicit projected stepper and the
// RATTLE LGVI on every built-in jointed scene (and chain-10), through
// Simulation::run with diagnostics off. Counting replacements of operator new
// and of malloc and its family (bench/support/counting_new.hpp, in this
// executable only: lieflow_tests keeps the sanitizers' own) see every
// allocation, C++, Eigen's and C libraries'; the allocations of a 2000-step
// run must equal those of a 1000-step run (setup allocates, steps must not).
//
// generalized-α: its steps allocate nothing either, except when the sparse
// LU of its Newton matrix chooses new pivots (KLU's klu_factor allocates its
// factors; integrators/fixed_pattern_lu.hpp), which happens a few times per
// thousand steps on a swinging chain: the extra allocations of the longer
// run are bounded by the extra pivot choices.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "bench/multibody/chain_scene.hpp"
#include "bench/support/jointed_step_allocations.hpp"
#include "integrators/constrained_generalized_alpha.hpp"
#include "integrators/integrate.hpp"
#include "dynamics/maximal/kkt_assembly.hpp"
#include "dynamics/maximal/multibody_scene.hpp"
#include "model/scene.hpp"
#include "simulation/simulation.hpp"

namespace lieflow {
namespace {

class StepAllocations : public ::testing::TestWithParam<std::string> {};

TEST_P(StepAllocations, NoneAfterTheFirstStep) {
  const Simulation sim(loadScene(GetParam()));
  for (const char* integrator :
       {"rkmk-euler", "rkmk-heun", "rkmk3", "rkmk4", "rkmk6", "cg3", "cf4", "lgvi", "radau5"}) {
    SCOPED_TRACE(integrator);
    const bench::StepAllocations a = bench::countStepAllocations(sim, integrator);
    ASSERT_TRUE(a.ran) << "no step size down to 1e-6 runs 2000 steps";
    EXPECT_EQ(a.steps_2000, a.steps_1000)
        << "h = " << a.dt << ": " << (a.steps_2000 - a.steps_1000) / 1000.0 << " allocations per step";
  }
}

TEST_P(StepAllocations, NoneInJointCoordinates) {
  const Simulation sim(loadScene(GetParam()));
  std::string why;
  if (!needsMultibody(sim.scene()) || !sim.hasJointFormulation(&why)) GTEST_SKIP() << why;
  for (const char* integrator :
       {"rkmk-euler", "rkmk-heun", "rkmk3", "rkmk4", "rkmk6", "cg3", "cf4", "genalpha", "lgvi", "radau5"}) {
    SCOPED_TRACE(integrator);
    // lgvi needs a tree without gimbals, offset universals, prescribed motion or loops.
    if (!sim.supports(integrator, &why, "joint")) continue;
    const bench::StepAllocations a = bench::countStepAllocations(sim, integrator, "joint");
    ASSERT_TRUE(a.ran) << "no step size down to 1e-6 runs 2000 steps";
    EXPECT_EQ(a.steps_2000, a.steps_1000)
        << "h = " << a.dt << ": " << (a.steps_2000 - a.steps_1000) / 1000.0 << " allocations per step";
  }
}

/// KLU's klu_factor allocates the numeric object's blocks: at most this many
/// per pivot choice (measured: 17 on rack-pinion).
constexpr long kAllocationsPerPivotChoice = 32;

TEST_P(StepAllocations, GeneralizedAlphaOnlyWhenItChoosesPivots) {
  const SceneDescription scene = loadScene(GetParam());
  if (!needsMultibody(scene)) GTEST_SKIP() << "a single body on a spherical joint: a rotor, no multibody system";
  const std::unique_ptr<MultibodyScene> ms = assembleMultibody(scene);
  const multibody::MultibodySystem& system = *ms->system;
  struct Count {
    long allocations = 0;
    int pivot_choices = 0;
  };
  auto run = [&](long steps) {
    ConstrainedGeneralizedAlphaStepper<multibody::MultibodySystem> stepper;
    const double h = 1e-3;
    integrateFixedStep(stepper, system, ms->y0, 0.0, 0.5 * h, h, [](long, double, const auto&) { return true; });
    const long before = bench::allocationCount();
    const int pivots_before = stepper.pivotChoices();
    const RunSummary summary = integrateFixedStep(stepper, system, ms->y0, 0.0, steps * h, h,
                                                  [](long, double, const auto&) { return true; });
    EXPECT_FALSE(summary.failed) << summary.failure;
    return Count{bench::allocationCount() - before, stepper.pivotChoices() - pivots_before};
  };
  const Count a = run(1000), b = run(2000);
  const long extra_allocations = b.allocations - a.allocations;
  const int extra_pivot_choices = b.pivot_choices - a.pivot_choices;
  EXPECT_LE(extra_allocations, kAllocationsPerPivotChoice * std::max(0, extra_pivot_choices))
      << extra_allocations << " allocations in 1000 more steps with " << extra_pivot_choices
      << " more pivot choices";
}

TEST(StepAllocationsInLoops, NoneInJointCoordinates) {
  // A loop whose closing joint is a ball joint between translating bodies
  // (the benchmark's chain of 6 rods with its tip held), beside the Cardan
  // shaft above (a cross between two held shafts).
  const Simulation sim(bench::closedChainScene(6, bench::kChainSeed));
  for (const char* integrator : {"rkmk-euler", "rkmk4", "cf4"}) {
    SCOPED_TRACE(integrator);
    const bench::StepAllocations a = bench::countStepAllocations(sim, integrator, "joint");
    ASSERT_TRUE(a.ran) << "no step size down to 1e-6 runs 2000 steps";
    EXPECT_EQ(a.steps_2000, a.steps_1000)
        << "h = " << a.dt << ": " << (a.steps_2000 - a.steps_1000) / 1000.0 << " allocations per step";
  }
}

TEST(StepAllocationsInJointCoordinates, NoneOnFreeRootsSphericalJointsDashpotsAndCouplingRows) {
  // What lgvi and genalpha take in joint coordinates beyond the built-in
  // scenes: a trunk hinged to the ground with a sprung, damped arm coupled to
  // a second arm (a mimic row) and a ball-jointed head, the same trunk
  // floating (a free root: lgvi's centroidal step), and floating without the
  // mimic beside a second free body (two trees: genalpha's Newton matrix
  // factored block by block).
  for (const int variant : {0, 1, 2}) {
    const bool floating = variant > 0;
    SCOPED_TRACE(variant == 0 ? "hinged" : variant == 1 ? "floating" : "two trees");
    std::string text = R"({"name": "coupled", "gravity": [0, 0, -9.81],
      "bodies": [
        {"name": "trunk", "mass": 3, "inertia": [0.05, 0.08, 0.06], "angular_velocity": [1, -0.5, 2]},
        {"name": "left", "mass": 0.8, "inertia": [0.002, 0.01, 0.01], "position": [0.35, 0, 0]},
        {"name": "right", "mass": 0.6, "inertia": [0.002, 0.008, 0.008], "position": [-0.35, 0, 0]},
        {"name": "head", "mass": 0.7, "inertia": [0.004, 0.005, 0.006], "position": [0, 0, 0.3],
         "angular_velocity": [2, 0.5, -1]}],
      "joints": [
        PIVOT
        {"name": "hl", "type": "revolute", "main": "trunk", "secondary": "left", "anchor_main": [0.2, 0, 0],
         "anchor_secondary": [-0.15, 0, 0], "axis_main": [0, 1, 0], "spring": {"stiffness": 4},
         "damper": {"damping": 0.05}},
        {"name": "hr", "type": "revolute", "main": "trunk", "secondary": "right", "anchor_main": [-0.2, 0, 0],
         "anchor_secondary": [0.15, 0, 0], "axis_main": [0, 1, 0]},
        {"name": "neck", "type": "spherical", "main": "trunk", "secondary": "head", "anchor_main": [0, 0, 0.15],
         "anchor_secondary": [0, 0, -0.15]},
        {"name": "mimic", "type": "coupling", "ratio": 1.5, "main": "left", "secondary": "right",
         "carrier": "trunk", "axis_main": [0, 1, 0], "axis_secondary": [0, 1, 0], "motion_main": "turn",
         "motion_secondary": "turn"}]})";
    const std::string pivot = floating ? "" : R"({"name": "pivot", "type": "revolute", "main": "ground",
        "secondary": "trunk", "anchor_main": [0, 0, 0], "anchor_secondary": [0, 0, 0], "axis_main": [0, 0, 1]},)";
    text.replace(text.find("PIVOT"), 5, pivot);
    if (variant == 2) {
      const std::size_t mimic = text.find(R"(,
        {"name": "mimic")");
      text.replace(mimic, text.rfind("]}") - mimic, "");
      text.replace(text.find("}],"), 3, R"(},
        {"name": "ball", "mass": 0.5, "inertia": [0.001, 0.002, 0.003], "position": [2, 0, 0],
         "angular_velocity": [0.3, 4, 1]}],)");
    }
    const Simulation sim(parseScene(text, "coupled.json"));
    for (const char* integrator : {"rkmk4", "lgvi", "genalpha", "radau5"}) {
      SCOPED_TRACE(integrator);
      std::string why;
      if (!sim.supports(integrator, &why, "joint")) continue;  // genalpha: no free root in joint coordinates yet
      const bench::StepAllocations a = bench::countStepAllocations(sim, integrator, "joint");
      ASSERT_TRUE(a.ran) << "no step size down to 1e-6 runs 2000 steps";
      EXPECT_EQ(a.steps_2000, a.steps_1000)
          << "h = " << a.dt << ": " << (a.steps_2000 - a.steps_1000) / 1000.0 << " allocations per step";
    }
  }
}

TEST(StepAllocationsInJointCoordinates, NoneForLgviAndGenalphaOnALoop) {
  // The loop rows of a spatial four-bar closed by a ball joint: lgvi's pose
  // pass at q₀ ⊕ h v, G(q) and (G M⁻¹ Gᵀ)⁺ per step; genalpha's dense
  // iteration matrix and its differences.
  const Simulation sim(parseScene(R"({"name": "four-bar", "gravity": [0, 0, -9.81],
    "bodies": [
      {"name": "crank", "mass": 1.0, "inertia": [0.09, 0.09, 0.01], "position": [0, 0, 0.5],
       "angular_velocity": [0, 3, 0]},
      {"name": "coupler", "mass": 2.0, "inertia": [0.05, 0.9, 0.9], "position": [1.1, 0, 1.25]},
      {"name": "rocker", "mass": 1.5, "inertia": [0.3, 0.3, 0.02], "position": [2.1, 0, 0.75]}],
    "joints": [
      {"name": "crank-pivot", "type": "revolute", "main": "ground", "secondary": "crank",
       "anchor_main": [0, 0, 0], "anchor_secondary": [0, 0, -0.5], "axis_main": [0, 1, 0],
       "spring": {"stiffness": 5, "rest_angle": 0.3}, "damper": {"damping": 0.2}},
      {"name": "crank-coupler", "type": "universal", "main": "crank", "secondary": "coupler",
       "anchor_main": [0, 0, 0.5], "anchor_secondary": [-1.1, 0, -0.25], "axis1_main": [0, 1, 0],
       "axis2_secondary": [0, 0, 1]},
      {"name": "rocker-pivot", "type": "revolute", "main": "ground", "secondary": "rocker",
       "anchor_main": [2, 0, 0], "anchor_secondary": [-0.1, 0, -0.75], "axis_main": [0, 1, 0]},
      {"name": "coupler-rocker", "type": "spherical", "main": "coupler", "secondary": "rocker",
       "anchor_main": [1.1, 0, 0.25], "anchor_secondary": [0.1, 0, 0.75]}]})",
                                  "four-bar.json"));
  for (const char* integrator : {"lgvi", "genalpha"}) {
    SCOPED_TRACE(integrator);
    std::string why;
    ASSERT_TRUE(sim.supports(integrator, &why, "joint")) << why;
    const bench::StepAllocations a = bench::countStepAllocations(sim, integrator, "joint");
    ASSERT_TRUE(a.ran) << "no step size down to 1e-6 runs 2000 steps";
    EXPECT_EQ(a.steps_2000, a.steps_1000)
        << "h = " << a.dt << ": " << (a.steps_2000 - a.steps_1000) / 1000.0 << " allocations per step";
  }
}

INSTANTIATE_TEST_SUITE_P(JointedScenes, StepAllocations, ::testing::ValuesIn(bench::jointedScenes()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           std::string name = info.param;
                           for (char& c : name)
                             if (c == '-') c = '_';
                           return name;
                         });

}  // namespace
}  // namespace lieflow
