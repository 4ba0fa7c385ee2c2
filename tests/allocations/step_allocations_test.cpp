// No heap allocation per step: every explicit projected stepper and the
// RATTLE LGVI on every built-in jointed scene (and chain-10), through
// Simulation::run with diagnostics off. A counting replacement of the global
// operator new (bench/support/counting_new.hpp, in this executable only:
// lieflow_tests keeps the sanitizers' own) sees every C++ allocation; the
// allocations of a 2000-step run must equal those of a 1000-step run (setup
// allocates, steps must not).
//
// generalized-α is not listed: its Newton matrix is factored by Eigen's
// SparseLU, which allocates in every factorize (bench_step_allocations
// reports it).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "bench/support/jointed_step_allocations.hpp"

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

INSTANTIATE_TEST_SUITE_P(JointedScenes, StepAllocations, ::testing::ValuesIn(bench::jointedScenes()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           std::string name = info.param;
                           for (char& c : name)
                             if (c == '-') c = '_';
                           return name;
                         });

}  // namespace
}  // namespace lieflow
