/// \file
/// Heap allocations per step of a stepper on a jointed scene, through
/// Simulation::run (diagnostics off, no row sink): the allocations of a
/// 2000-step run against those of a 1000-step run, for bench_step_allocations
/// and lieflow_allocation_tests. Includes bench/support/counting_new.hpp, so
/// the same rule holds: one translation unit per executable.
#pragma once

#include <string>
#include <vector>

#include "bench/support/counting_new.hpp"
#include "model/scene.hpp"
#include "simulation/simulation.hpp"

namespace lieflow {
namespace bench {

/// The built-in scenes with joints, then chain-10.
inline std::vector<std::string> jointedScenes() {
  std::vector<std::string> names;
  for (const BuiltinScene& b : builtinScenes())
    if (!loadScene(b.name).joints.empty()) names.push_back(b.name);
  names.push_back("chain-10");
  return names;
}

struct StepAllocations {
  bool ran = false;  ///< a step h ≥ 1e-6 ran 2000 steps (else nothing was counted)
  double dt = 0.0;   ///< that h
  long steps_1000 = 0, steps_2000 = 0;  ///< allocations of runs of 1000 and 2000 steps
};

/// h = 1e-3, or a tenth of it until 2000 steps run (stiff-hinge under
/// explicit Euler, fast-top's spin under the exponential LGVI); that first
/// run is the warm-up (function-local statics, the stepper's first step),
/// then runs of 1000 and 2000 steps are counted.
inline StepAllocations countStepAllocations(const Simulation& sim, const std::string& integrator,
                                            const std::string& formulation = "") {
  StepAllocations out;
  out.dt = 1e-3;
  auto run = [&](long steps) {
    SimulationOptions o;
    o.integrator = integrator;
    o.formulation = formulation;
    o.dt = out.dt;
    o.t_end = steps * out.dt;
    o.diagnostics = false;
    const long before = allocationCount();
    out.ran = !sim.run(o).failed;
    return allocationCount() - before;
  };
  for (run(2000); !out.ran && out.dt > 1e-6; run(2000)) out.dt /= 10;
  if (!out.ran) return out;
  out.steps_1000 = run(1000);
  out.steps_2000 = run(2000);
  return out;
}

}  // namespace bench
}  // namespace lieflow
