/// \file
/// The integrators every unconstrained system runs (internal to joints/): a
/// single body (RotorSystem, FreeBodySystem) and a tree in joint coordinates
/// (ArticulatedSystem) share the explicit Lie-group steppers, the adaptive
/// rkmk45 and generalized-α; simulation.cpp adds lgvi and splitting for the
/// single body.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "integrators/adaptive.hpp"
#include "integrators/commutator_free.hpp"
#include "integrators/generalized_alpha.hpp"
#include "integrators/integrate.hpp"
#include "integrators/rkmk.hpp"
#include "joints/simulation_observer.hpp"

namespace lieflow {
namespace simulation_detail {

/// rkmk45 (Dormand–Prince 5(4), adaptive; rtol, atol from o) on `system`
/// from y0, its states moved by `projection` (integrators/adaptive.hpp;
/// NoProjection for a system without constraints).
template <typename System, typename Projection = NoProjection>
SimulationResult runAdaptive(const Simulation::Model& model, const System& system, const typename System::State& y0,
                             const SimulationOptions& o, const std::vector<std::string>& columns,
                             const std::function<void(const std::vector<double>&)>& row, Projection projection = {}) {
  using State = typename System::State;
  AdaptiveOptions a;
  a.rtol = option(o, "rtol", a.rtol);
  a.atol = option(o, "atol", a.atol);
  a.max_steps = o.max_steps;
  a.heartbeat = o.progress;
  const RkmkStepper<State> stepper(ButcherTableau::dormandPrince54());
  return observeRun(model, system, o, stepCount(0.0, o.t_end, o.dt), columns, row, [&](auto& observer) {
    return integrateAdaptive(stepper, system, y0, 0.0, o.t_end, o.dt, a, observer, projection);
  });
}

/// Runs o.integrator on `system` from y0 if it is one of rkmk-euler,
/// rkmk-heun, rkmk3, rkmk4, cg3, cf4, genalpha, rkmk45; nothing otherwise.
template <typename System>
std::optional<SimulationResult> runUnconstrained(const Simulation::Model& model, const System& system,
                                                 const typename System::State& y0, const SimulationOptions& o,
                                                 const std::vector<std::string>& columns,
                                                 const std::function<void(const std::vector<double>&)>& row) {
  using State = typename System::State;
  const std::string& name = o.integrator;
  auto fixed = [&](auto stepper) { return runFixedStep(model, system, y0, o, columns, row, std::move(stepper)); };
  if (name == "rkmk-euler") return fixed(RkmkStepper<State>(ButcherTableau::euler()));
  if (name == "rkmk-heun") return fixed(RkmkStepper<State>(ButcherTableau::heun()));
  if (name == "rkmk3") return fixed(RkmkStepper<State>(ButcherTableau::kutta3()));
  if (name == "rkmk4") return fixed(RkmkStepper<State>(ButcherTableau::rk4()));
  if (name == "cg3") return fixed(CrouchGrossman3Stepper<State>());
  if (name == "cf4") return fixed(CommutatorFree4Stepper<State>());
  if (name == "genalpha") {
    // Without constraints (`index` chooses a constrained formulation: it has
    // nothing to choose here).
    GeneralizedAlphaOptions g;
    g.rho_inf = option(o, "rho_inf", g.rho_inf);
    g.tolerance = option(o, "tolerance", g.tolerance);
    g.max_iterations = static_cast<int>(option(o, "max_iterations", g.max_iterations));
    return fixed(GeneralizedAlphaStepper<State>(g));
  }
  if (name == "rkmk45") return runAdaptive(model, system, y0, o, columns, row);
  return std::nullopt;
}

}  // namespace simulation_detail
}  // namespace lieflow
