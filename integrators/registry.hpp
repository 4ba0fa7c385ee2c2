/// \file
/// The integrators the `lieflow` command knows, with their order and
/// properties (what `lieflow integrators` prints). Pure data: the factory that
/// builds each stepper for a given system lives with the scene assembly.
#pragma once

#include <string>
#include <vector>

namespace lieflow {

struct IntegratorInfo {
  std::string name;
  /// Order of accuracy (orientation and velocities).
  int order;
  bool is_implicit;
  bool is_symplectic;
  /// Preserves the spatial angular momentum of a torque-free body to round-off.
  bool preserves_momentum;
  bool is_adaptive;
  /// Options it accepts in the scene's "integrator" object, with defaults.
  std::vector<std::pair<std::string, double>> options;
  std::string description;
};

inline const std::vector<IntegratorInfo>& integratorRegistry() {
  static const std::vector<IntegratorInfo> registry = {
      {"rkmk-euler", 1, false, false, false, false, {}, "Runge-Kutta-Munthe-Kaas, forward Euler tableau (Lie-Euler)"},
      {"rkmk-heun", 2, false, false, false, false, {}, "Runge-Kutta-Munthe-Kaas, Heun's tableau"},
      {"rkmk3", 3, false, false, false, false, {}, "Runge-Kutta-Munthe-Kaas, Kutta's third-order tableau, dexp^-1 to ad^1"},
      {"rkmk4", 4, false, false, false, false, {}, "Runge-Kutta-Munthe-Kaas, classical RK4 tableau, dexp^-1 to ad^2"},
      {"rkmk45", 5, false, false, false, true, {{"rtol", 1e-8}, {"atol", 1e-10}},
       "Runge-Kutta-Munthe-Kaas, Dormand-Prince 5(4) with adaptive steps on the group (dt = output interval)"},
      {"cg3", 3, false, false, false, false, {}, "Crouch-Grossman order 3 (Owren-Marthinsen coefficients)"},
      {"cf4", 4, false, false, false, false, {}, "commutator-free order 4 (Celledoni-Marthinsen-Owren 2003)"},
      {"lgvi", 2, true, true, true, false, {{"tolerance", 1e-14}, {"max_iterations", 20}, {"cayley", 0}},
       "Lie group variational integrator (Lee-Leok-McClamroch 2005), Newton with analytic Jacobian; "
       "the exp map needs h|omega| < 1, cayley=1 selects the Cayley-map variant (Kobilarov-Marsden) without that limit"},
      {"splitting", 2, false, true, true, false, {},
       "explicit symplectic rotation splitting (McLachlan 1993, Dullweber-Leimkuhler-McLachlan 1997), kick-drift-kick with torques"},
      {"genalpha", 2, true, false, false, false, {{"rho_inf", 1.0}, {"tolerance", 1e-12}, {"max_iterations", 20}},
       "Lie group generalized-alpha (Bruls-Cardona-Arnold 2012); rho_inf = 1 no numerical damping"},
      {"exact", 0, false, true, true, false, {},
       "exact torque-free flow by Jacobi elliptic functions (free body only; order 0 = exact)"},
  };
  return registry;
}

/// The entry of that name, or nullptr.
inline const IntegratorInfo* findIntegrator(const std::string& name) {
  for (const IntegratorInfo& info : integratorRegistry())
    if (info.name == name) return &info;
  return nullptr;
}

}  // namespace lieflow
