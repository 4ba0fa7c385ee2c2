// Running a scene in joint coordinates (--formulation joint).
#include "integrators/adaptive.hpp"
#include "integrators/commutator_free.hpp"
#include "integrators/generalized_alpha.hpp"
#include "integrators/integrate.hpp"
#include "integrators/rkmk.hpp"
#include "joints/articulated/articulated_second_order.hpp"
#include "joints/simulation_model.hpp"
#include "joints/simulation_observer.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {

using namespace simulation_detail;

SimulationResult runArticulated(const Simulation::Model& model, const SimulationOptions& o,
                                const std::vector<std::string>& columns,
                                const std::function<void(const std::vector<double>&)>& row) {
  using State = articulated::ArticulatedState;
  const articulated::ArticulatedSystem& system = *model.articulated->system;
  const State& y0 = model.articulated->y0;
  const std::string& name = o.integrator;
  const long n = stepCount(0.0, o.t_end, o.dt);
  auto fixed = [&](auto stepper) {
    return observeRun(model, system, o, n, columns, row, [&](auto& observer) {
      return integrateFixedStep(stepper, system, y0, 0.0, o.t_end, o.dt, observer);
    });
  };
  if (name == "rkmk-euler") return fixed(RkmkStepper<State>(ButcherTableau::euler()));
  if (name == "rkmk-heun") return fixed(RkmkStepper<State>(ButcherTableau::heun()));
  if (name == "rkmk3") return fixed(RkmkStepper<State>(ButcherTableau::kutta3()));
  if (name == "rkmk4") return fixed(RkmkStepper<State>(ButcherTableau::rk4()));
  if (name == "cg3") return fixed(CrouchGrossman3Stepper<State>());
  if (name == "cf4") return fixed(CommutatorFree4Stepper<State>());
  if (name == "genalpha") {
    // No constraints in joint coordinates: the method of Arnold & Brüls 2007
    // on the joints' groups; `index` has nothing to choose here.
    GeneralizedAlphaOptions g;
    g.rho_inf = option(o, "rho_inf", g.rho_inf);
    g.tolerance = option(o, "tolerance", g.tolerance);
    g.max_iterations = static_cast<int>(option(o, "max_iterations", g.max_iterations));
    return fixed(GeneralizedAlphaStepper<State>(g));
  }
  if (name == "rkmk45") {
    AdaptiveOptions a;
    a.rtol = option(o, "rtol", a.rtol);
    a.atol = option(o, "atol", a.atol);
    a.max_steps = o.max_steps;
    a.heartbeat = o.progress;
    const RkmkStepper<State> stepper(ButcherTableau::dormandPrince54());
    return observeRun(model, system, o, n, columns, row, [&](auto& observer) {
      return integrateAdaptive(stepper, system, y0, 0.0, o.t_end, o.dt, a, observer);
    });
  }
  throw InvalidInput("--integrator", "'" + name + "' is not available in joint coordinates");
}

}  // namespace lieflow
