/// \file
/// bench_step_allocations: heap allocations per single-body step ("single-body
/// steps allocate nothing on the heap"). A counting replacement of the global
/// operator new sees every C++ allocation (std::function, std::string, Eigen
/// dynamic storage, ...). Each stepper is constructed and stepped once first
/// (construction may allocate, and genalpha initializes its history), then the
/// allocations over kSteps further steps are counted, for every stepper on the
/// benchmark free body (FreeBodySystem), its RotorSystem, and a torqued rotor
/// (heavy top about a pivot with a torsional spring: the torque paths). The
/// drivers are checked by the difference between 1000 and 2000 steps:
/// integrateFixedStep and Simulation::run (diagnostics off and on). Then every
/// constrained stepper on every built-in jointed scene and chain-10, through
/// Simulation::run (2000 steps against 1000).
///
/// Prints one line per case; exit status 1 if anything allocates per step, else 0.
#include <cstdio>
#include <string>
#include <vector>

#include "bench/integrators/free_body_scene.hpp"
#include "bench/support/counting_new.hpp"
#include "bench/support/jointed_step_allocations.hpp"
#include "integrators/adaptive.hpp"
#include "integrators/commutator_free.hpp"
#include "integrators/generalized_alpha.hpp"
#include "integrators/integrate.hpp"
#include "integrators/lgvi.hpp"
#include "integrators/rkmk.hpp"
#include "integrators/splitting.hpp"
#include "model/scene.hpp"
#include "simulation/simulation.hpp"


using namespace lieflow;  // NOLINT: a one-purpose program
constexpr long kSteps = 1000;
int failures = 0;

template <class System, class Stepper>
void check(const char* group, const char* name, const System& sys, typename System::State y0,
           Stepper stepper) {
  const double h = bench::FreeBodyScene().h;
  StepReport report;
  auto y = stepper.step(sys, 0.0, y0, h, &report);  // warm-up (genalpha: history)
  const long before = bench::allocationCount();
  for (long k = 1; k <= kSteps; ++k) y = stepper.step(sys, k * h, y, h, &report);
  const long allocs = bench::allocationCount() - before;
  std::printf("%-6s %-22s %6ld allocations in %ld steps%s\n", group, name, allocs, kSteps,
              allocs ? "   <-- ALLOCATES" : "");
  failures += allocs != 0;
  if (!isFinite(y)) std::printf("  (non-finite state!)\n");
}

template <class System>
void checkAll(const char* g, const System& sys, const typename System::State& y0) {
  using S = typename System::State;
  check(g, "rkmk-euler", sys, y0, RkmkStepper<S>(ButcherTableau::euler()));
  check(g, "rkmk-heun", sys, y0, RkmkStepper<S>(ButcherTableau::heun()));
  check(g, "rkmk3", sys, y0, RkmkStepper<S>(ButcherTableau::kutta3()));
  check(g, "rkmk4", sys, y0, RkmkStepper<S>(ButcherTableau::rk4()));
  check(g, "dopri5-step", sys, y0, RkmkStepper<S>(ButcherTableau::dormandPrince54()));
  {
    const RkmkStepper<S> dp(ButcherTableau::dormandPrince54());
    const double h = bench::FreeBodyScene().h;
    typename S::Tangent err;
    auto y = dp.stepWithError(sys, 0.0, y0, h, &err);
    const long before = bench::allocationCount();
    for (long k = 1; k <= kSteps; ++k) y = dp.stepWithError(sys, k * h, y, h, &err);
    const long allocs = bench::allocationCount() - before;
    std::printf("%-6s %-22s %6ld allocations in %ld steps%s\n", g, "dopri5-step+error", allocs,
                kSteps, allocs ? "   <-- ALLOCATES" : "");
    failures += allocs != 0;
  }
  check(g, "cg3", sys, y0, CrouchGrossman3Stepper<S>());
  check(g, "cf4", sys, y0, CommutatorFree4Stepper<S>());
  check(g, "lgvi", sys, y0, LgviStepper<S>());
  LgviOptions c;
  c.map = LgviMap::kCayley;
  check(g, "lgvi-cayley", sys, y0, LgviStepper<S>(c));
  check(g, "splitting", sys, y0, SplittingStepper<S>(sys.inertia()));
  SplittingOptions a;
  a.scheme = SplittingScheme::kAxisRotations;
  check(g, "splitting-axis", sys, y0, SplittingStepper<S>(sys.inertia(), a));
  check(g, "genalpha", sys, y0, GeneralizedAlphaStepper<S>());
}

int main() {
  const bench::FreeBodyScene scene;
  const auto free_sys = scene.freeBodySystem();
  const auto rotor_sys = scene.rotorSystem();
  checkAll("free", free_sys, scene.freeBodyState());
  checkAll("rotor", rotor_sys, scene.rotorState());

  // A torqued rotor (heavy top about a pivot + a torsional spring): the torque paths.
  RigidBodyParameters<double> p = scene.parameters();
  p.gravity = Eigen::Vector3d(0, 0, -9.81);
  p.has_pivot = true;
  p.com_from_pivot = Eigen::Vector3d(0.1, 0.0, 0.3);
  p.spring_stiffness = 0.5;
  const RotorSystem<double> top(p);
  checkAll("top", top, scene.rotorState());

  // integrateFixedStep with a no-op observer: allocations must not grow with n.
  {
    using S = FreeBodyState<double>;
    auto run = [&](long n) {
      const long before = bench::allocationCount();
      integrateFixedStep(RkmkStepper<S>(ButcherTableau::rk4()), free_sys, scene.freeBodyState(),
                         0.0, n * scene.h, scene.h, [](long, double, const S&) { return true; });
      return bench::allocationCount() - before;
    };
    const long a1 = run(1000), a2 = run(2000);
    std::printf(
        "integrateFixedStep(rkmk4): %ld allocations for 1000 steps, %ld for 2000 (per step: "
        "%.3f)\n",
        a1, a2, (a2 - a1) / 1000.0);
    failures += a2 != a1;
  }
  // Simulation::run of the same body as a scene, diagnostics off and on (no row sink).
  {
    SceneDescription d;
    d.name = "alloc";
    d.source = "alloc_check";
    BodyDescription b;
    b.name = "body";
    b.mass = scene.mass;
    b.inertia = scene.inertia();
    b.orientation = scene.q0;
    b.position = scene.p0;
    b.velocity = scene.v0_world;
    b.angular_velocity = scene.omega0_body;
    b.has_position = b.has_velocity = true;
    d.bodies.push_back(b);
    const Simulation sim(d);
    for (const char* integ : {"rkmk4", "cf4", "lgvi", "splitting", "genalpha", "rkmk45"})
      for (bool diag : {false, true}) {
        auto run = [&](long n) {
          SimulationOptions o;
          o.integrator = integ;
          o.dt = scene.h;
          o.t_end = n * scene.h;
          o.diagnostics = diag;
          const long before = bench::allocationCount();
          sim.run(o);
          return bench::allocationCount() - before;
        };
        run(10);  // first use: function-local statics (registry)
        const long a1 = run(1000), a2 = run(2000);
        std::printf(
            "Simulation::run(%s, diagnostics %s): %ld allocations for 1000 steps, %ld for 2000 "
            "(per step: %.3f)\n",
            integ, diag ? "on " : "off", a1, a2, (a2 - a1) / 1000.0);
        failures += a2 != a1;
      }
  }
  // Every constrained stepper on every built-in jointed scene and on
  // chain-10, through Simulation::run (diagnostics off, no row sink): the
  // allocations of 2000 steps against those of 1000.
  for (const std::string& name : bench::jointedScenes()) {
    const Simulation sim(loadScene(name));
    for (const char* integ : {"rkmk-euler", "rkmk-heun", "rkmk3", "rkmk4", "cg3", "cf4", "lgvi", "genalpha"}) {
      const bench::StepAllocations a = bench::countStepAllocations(sim, integ);
      if (!a.ran) {
        std::printf("%-15s %-10s fails at every h down to 1e-6: not counted   <-- FAILS\n", name.c_str(), integ);
        ++failures;
        continue;
      }
      std::printf("%-15s %-10s h = %-6g %7ld allocations for 1000 steps, %7ld for 2000 (per step: %.3f)%s\n",
                  name.c_str(), integ, a.dt, a.steps_1000, a.steps_2000, (a.steps_2000 - a.steps_1000) / 1000.0,
                  a.steps_2000 != a.steps_1000 ? "   <-- ALLOCATES" : "");
      failures += a.steps_2000 != a.steps_1000;
    }
  }
  std::printf("%s\n",
              failures ? "SOME PATHS ALLOCATE PER STEP" : "no per-step heap allocation found");
  return failures ? 1 : 0;
}
