/// \file
/// The explicit Lie-group steppers in index-1 form, projected onto the
/// constraints after every step (integrators/projected_stepper.hpp), for the
/// systems with constraints (internal to joints/): the maximal formulation's
/// MultibodySystem and, with loops or gear rows, the joint formulation's
/// ArticulatedSystem.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "integrators/butcher_tableau.hpp"
#include "integrators/commutator_free.hpp"
#include "integrators/projected_stepper.hpp"
#include "integrators/rkmk.hpp"
#include "joints/simulation_observer.hpp"
#include "joints/simulation_unconstrained.hpp"

namespace lieflow {
namespace simulation_detail {

/// Runs o.integrator, projected, on `system` from y0 if it is one of
/// rkmk-euler, rkmk-heun, rkmk3, rkmk4, cg3, cf4 (after every step) or
/// rkmk45 (after every accepted step and at every output:
/// integrators/adaptive.hpp); nothing otherwise.
template <typename System>
std::optional<SimulationResult> runProjected(const Simulation::Model& model, const System& system,
                                             const typename System::State& y0, const SimulationOptions& o,
                                             const std::vector<std::string>& columns,
                                             const std::function<void(const std::vector<double>&)>& row) {
  using State = typename System::State;
  const std::string& name = o.integrator;
  auto projected = [&](auto inner) {
    return runFixedStep(model, system, y0, o, columns, row, ProjectedStepper<decltype(inner)>(std::move(inner)));
  };
  if (name == "rkmk-euler") return projected(RkmkStepper<State>(ButcherTableau::euler()));
  if (name == "rkmk-heun") return projected(RkmkStepper<State>(ButcherTableau::heun()));
  if (name == "rkmk3") return projected(RkmkStepper<State>(ButcherTableau::kutta3()));
  if (name == "rkmk4") return projected(RkmkStepper<State>(ButcherTableau::rk4()));
  if (name == "cg3") return projected(CrouchGrossman3Stepper<State>());
  if (name == "cf4") return projected(CommutatorFree4Stepper<State>());
  if (name == "rkmk45") {
    const ProjectionOptions p;
    return runAdaptive(model, system, y0, o, columns, row, [&system, p](double t, State* y, std::string* why) {
      int iterations = 0;
      return system.projectPositions(t, y, p.tolerance, p.max_iterations, &iterations, why) &&
             system.projectVelocities(t, y, why);
    });
  }
  return std::nullopt;
}

}  // namespace simulation_detail
}  // namespace lieflow
