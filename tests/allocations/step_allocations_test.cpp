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

#include "bench/support/counting_new.hpp"
#include "joints/scene.hpp"
#include "joints/simulation.hpp"


namespace lieflow {
namespace {

std::vector<std::string> jointedScenes() {
  std::vector<std::string> names;
  for (const BuiltinScene& b : builtinScenes())
    if (!loadScene(b.name).joints.empty()) names.push_back(b.name);
  names.push_back("chain-10");
  return names;
}

class StepAllocations : public ::testing::TestWithParam<std::string> {};

TEST_P(StepAllocations, NoneAfterTheFirstStep) {
  const Simulation sim(loadScene(GetParam()));
  for (const char* integrator : {"rkmk-euler", "rkmk-heun", "rkmk3", "rkmk4", "cg3", "cf4", "lgvi"}) {
    SCOPED_TRACE(integrator);
    // h = 1e-3, or a tenth of it until the run succeeds (stiff-hinge under
    // explicit Euler, fast-top's spin under the exponential LGVI).
    double dt = 1e-3;
    bool failed = true;
    auto run = [&](long steps) {
      SimulationOptions o;
      o.integrator = integrator;
      o.dt = dt;
      o.t_end = steps * dt;
      o.diagnostics = false;
      const long before = bench::allocationCount();
      failed = sim.run(o).failed;
      return bench::allocationCount() - before;
    };
    for (run(2000); failed && dt > 1e-6; run(2000)) dt /= 10;
    ASSERT_FALSE(failed) << "no step size down to 1e-6 runs 2000 steps";
    const long a1000 = run(1000);
    const long a2000 = run(2000);
    EXPECT_EQ(a2000, a1000) << "h = " << dt << ": " << (a2000 - a1000) / 1000.0 << " allocations per step";
  }
}

INSTANTIATE_TEST_SUITE_P(JointedScenes, StepAllocations, ::testing::ValuesIn(jointedScenes()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           std::string name = info.param;
                           for (char& c : name)
                             if (c == '-') c = '_';
                           return name;
                         });

}  // namespace
}  // namespace lieflow
