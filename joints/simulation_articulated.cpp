// Running a scene in joint coordinates (--formulation joint).
#include "joints/articulated/articulated_second_order.hpp"
#include "joints/simulation_model.hpp"
#include "joints/simulation_unconstrained.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {

SimulationResult runArticulated(const Simulation::Model& model, const SimulationOptions& o,
                                const std::vector<std::string>& columns,
                                const std::function<void(const std::vector<double>&)>& row) {
  if (auto result = simulation_detail::runUnconstrained(model, *model.articulated->system, model.articulated->y0, o,
                                                        columns, row))
    return *result;
  throw InvalidInput("--integrator", "'" + o.integrator + "' is not available in joint coordinates");
}

}  // namespace lieflow
