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
#include "joints/multibody/kkt_assembly.hpp"
#include "joints/multibody_scene.hpp"

namespace lieflow {
namespace {

class StepAllocations : public ::testing::TestWithParam<std::string> {};

TEST_P(StepAllocations, NoneAfterTheFirstStep) {
  const Simulation sim(loadScene(GetParam()));
  for (const char* integrator : {"rkmk-euler", "rkmk-heun", "rkmk3", "rkmk4", "cg3", "cf4", "lgvi"}) {
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
  for (const char* integrator : {"rkmk-euler", "rkmk-heun", "rkmk3", "rkmk4", "cg3", "cf4", "genalpha", "lgvi"}) {
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

INSTANTIATE_TEST_SUITE_P(JointedScenes, StepAllocations, ::testing::ValuesIn(bench::jointedScenes()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           std::string name = info.param;
                           for (char& c : name)
                             if (c == '-') c = '_';
                           return name;
                         });

}  // namespace
}  // namespace lieflow
