// Running a scene in joint coordinates (--formulation joint).
#include "integrators/joint_space_variational.hpp"
#include "joints/articulated/articulated_coupled_alpha.hpp"
#include "joints/articulated/articulated_second_order.hpp"
#include "joints/simulation_model.hpp"
#include "joints/simulation_projected.hpp"
#include "joints/simulation_unconstrained.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {

bool runsWithLoopsInJointCoordinates(const std::string& integrator, std::string* why) {
  for (const char* name : {"rkmk-euler", "rkmk-heun", "rkmk3", "rkmk4", "rkmk45", "cg3", "cf4"})
    if (integrator == name) return true;
  if (why) {
    if (integrator == "lgvi")
      *why = "'lgvi' in joint coordinates takes coupling rows but no loop-closing joints or gear rows";
    else if (integrator == "genalpha")
      *why = "'genalpha' in joint coordinates takes coupling rows but no loop-closing joints or gear rows";
    else
      *why = "'" + integrator + "' is not available in joint coordinates";
    *why += "; a scene with a closed loop runs in joint coordinates with rkmk-euler, rkmk-heun, rkmk3, rkmk4, "
            "rkmk45, cg3 or cf4, or in maximal coordinates with every integrator (--formulation maximal)";
  }
  return false;
}

SimulationResult runArticulated(const Simulation::Model& model, const SimulationOptions& o,
                                const std::vector<std::string>& columns,
                                const std::function<void(const std::vector<double>&)>& row) {
  const articulated::ArticulatedSystem& system = *model.articulated->system;
  const articulated::ArticulatedState& y0 = model.articulated->y0;
  if (system.hasClosures() && o.integrator == "genalpha" && system.couplingRows().size() != 0) {
    // Coupling rows only: genalpha in their kernel's coordinates.
    GeneralizedAlphaOptions g;
    g.rho_inf = simulation_detail::option(o, "rho_inf", g.rho_inf);
    g.tolerance = simulation_detail::option(o, "tolerance", g.tolerance);
    g.max_iterations = static_cast<int>(simulation_detail::option(o, "max_iterations", g.max_iterations));
    return simulation_detail::runFixedStep(
        model, system, y0, o, columns, row,
        articulated::CoupledGeneralizedAlphaStepper(system, system.couplingRows(), g));
  }
  if (system.hasClosures() && o.integrator != "lgvi") {
    // Loops: the explicit steppers in index-1 form, projected onto the
    // closing joints' rows after every step (as in maximal coordinates).
    if (auto result = simulation_detail::runProjected(model, system, y0, o, columns, row)) return *result;
    std::string why;
    runsWithLoopsInJointCoordinates(o.integrator, &why);
    throw InvalidInput("--integrator", why);
  }
  if (auto result = simulation_detail::runUnconstrained(model, system, y0, o, columns, row)) return *result;
  if (o.integrator == "lgvi") {
    // The variational integrator in joint coordinates, with coupling rows
    // as multipliers (Simulation::supports checks that it covers the scene).
    if (simulation_detail::option(o, "cayley", 0.0) != 0.0)
      throw InvalidInput("cayley", "has no meaning in joint coordinates (lgvi there turns its rotations by exp)");
    JointSpaceVariationalOptions v;
    v.tolerance = simulation_detail::option(o, "tolerance", v.tolerance);
    v.max_iterations = static_cast<int>(simulation_detail::option(o, "max_iterations", v.max_iterations));
    return simulation_detail::runFixedStep(model, system, y0, o, columns, row,
                                           JointSpaceVariationalStepper<articulated::ArticulatedSystem>(v));
  }
  throw InvalidInput("--integrator", "'" + o.integrator + "' is not available in joint coordinates");
}

}  // namespace lieflow
