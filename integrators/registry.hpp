/// \file
/// The integrators the `lieflow` command knows, with their order and
/// properties (what `lieflow integrators` prints). Pure data: the stepper each
/// one builds on each kind of system is its row of the table of steppers
/// (simulation/stepper_table_rows.hpp, in this order).
#pragma once

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "liegroup/number_text.hpp"

namespace lieflow {

/// One option an integrator accepts (in the scene's "integrator" object or
/// `--options`): its default and the values it admits. A value outside
/// [min, max] (or excluded_min: min itself is not admitted), or a fraction
/// where an integer is needed, is an input error naming the option.
struct IntegratorOption {
  std::string name;
  double default_value;
  double min;
  double max;
  bool integer = false;
  bool excluded_min = false;
  std::string meaning;

  /// Empty if `v` is admitted, else why not ("must be > 0", ...).
  std::string check(double v) const {
    if (!std::isfinite(v)) return "must be a finite number";
    if (integer && v != std::floor(v)) return "must be a whole number, got " + formatExact(v);
    if (excluded_min ? !(v > min) : !(v >= min))
      return "must be " + std::string(excluded_min ? "> " : ">= ") + formatExact(min) + ", got " + formatExact(v);
    if (!(v <= max)) return "must be <= " + formatExact(max) + ", got " + formatExact(v);
    return "";
  }
};

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
  std::vector<IntegratorOption> options;
  std::string description;
  /// How it runs scenes with joints in maximal coordinates, where it does
  /// (which system kinds it runs at all is the table of steppers',
  /// simulation/stepper_table.hpp).
  std::string joints_note;

  const IntegratorOption* option(const std::string& key) const {
    for (const IntegratorOption& o : options)
      if (o.name == key) return &o;
    return nullptr;
  }
};

inline const std::vector<IntegratorInfo>& integratorRegistry() {
  // Newton tolerances below 1e-16 cannot be met in double precision (the
  // residuals are relative to quantities of order one); 1000 iterations is
  // far beyond any converging Newton solve.
  const IntegratorOption max_iterations{"max_iterations", 20, 1, 1000, true, false, "Newton iterations per step"};
  static const std::vector<IntegratorInfo> registry = {
      {"rkmk-euler", 1, false, false, false, false, {}, "Runge-Kutta-Munthe-Kaas, forward Euler tableau (Lie-Euler)",
       "projected onto the constraints after every step"},
      {"rkmk-heun", 2, false, false, false, false, {}, "Runge-Kutta-Munthe-Kaas, Heun's tableau",
       "projected onto the constraints after every step"},
      {"rkmk3", 3, false, false, false, false, {}, "Runge-Kutta-Munthe-Kaas, Kutta's third-order tableau, dexp^-1 to ad^1",
       "projected onto the constraints after every step"},
      {"rkmk4", 4, false, false, false, false, {}, "Runge-Kutta-Munthe-Kaas, classical RK4 tableau, dexp^-1 to ad^2",
       "projected onto the constraints after every step"},
      {"rkmk6", 6, false, false, false, false, {},
       "Runge-Kutta-Munthe-Kaas, Butcher's seven-stage sixth-order tableau, dexp^-1 to ad^4: for errors near "
       "round-off at the least run time",
       "projected onto the constraints after every step"},
      {"rkmk45", 5, false, false, false, true,
       {{"rtol", 1e-8, 1e-15, 1.0, false, false, "relative tolerance of the local error"},
        {"atol", 1e-10, 0.0, 1.0, false, false, "absolute tolerance of the local error"}},
       "Runge-Kutta-Munthe-Kaas, Dormand-Prince 5(4) with adaptive steps on the group; dt = output interval, "
       "outputs by dense output on the group",
       "projected onto the constraints after every accepted step and at every output (the error "
       "estimate is taken before the projection)"},
      {"cg3", 3, false, false, false, false, {}, "Crouch-Grossman order 3 (Owren-Marthinsen coefficients)",
       "projected onto the constraints after every step"},
      {"cf4", 4, false, false, false, false, {}, "commutator-free order 4 (Celledoni-Marthinsen-Owren 2003)",
       "projected onto the constraints after every step"},
      {"lgvi", 2, true, true, true, false,
       {{"tolerance", 1e-14, 1e-16, 1.0, false, false, "Newton residual tolerance"}, max_iterations,
        {"cayley", 0, 0, 1, true, false, "1: Cayley map instead of exp"}},
       "Lie group variational integrator (Lee-Leok-McClamroch 2005), Newton with analytic Jacobian; "
       "the exp map needs h|omega| < 1, cayley=1 selects the Cayley-map variant (Kobilarov-Marsden) without that limit",
       "RATTLE with the constraint impulses; in joint coordinates the variational integrator on the joints' "
       "groups (midpoint kinetic, trapezoidal potential energy; coupling rows, loops and gear rows on multipliers)"},
      {"splitting", 2, false, true, true, false, {},
       "explicit symplectic rotation splitting (McLachlan 1993, Dullweber-Leimkuhler-McLachlan 1997), kick-drift-kick with torques",
       ""},
      {"genalpha", 2, true, false, false, false,
       {{"rho_inf", 1.0, 0.0, 1.0, false, false, "spectral radius at infinity (1: no numerical damping)"},
        {"tolerance", 1e-12, 1e-16, 1.0, false, false, "Newton residual tolerance"}, max_iterations,
        {"index", 2, 2, 3, true, false,
         "with joints: 2 stabilized index 2 (Arnold-Bruls-Cardona, stable at rho_inf = 1), 3 index 3 (needs rho_inf < 1)"}},
       "Lie group generalized-alpha (Bruls-Cardona-Arnold 2012); rho_inf = 1 no numerical damping",
       "stabilized index 2 by default (index=2: positions and velocities on the constraints); index=3 needs rho_inf < 1"},
      {"radau5", 5, true, false, false, false,
       {{"tolerance", 1e-10, 1e-16, 1.0, false, false, "Newton: estimated remaining error of the stage increments"},
        max_iterations,
        {"jacobian_reuse", 1e-3, 0.0, 1.0, false, false,
         "keep the Jacobian for the next step while Newton contracts faster than this"}},
       "Radau IIA, 3 stages (the method of Hairer-Wanner's RADAU5) in Runge-Kutta-Munthe-Kaas form: L-stable and "
       "stiffly accurate, for stiff dashpots and springs; simplified Newton with a finite-difference Jacobian kept "
       "while it converges",
       "projected onto the constraints after every step"},
      {"exact", 0, false, true, true, false, {},
       "exact torque-free flow by Jacobi elliptic functions (free body only; order 0 = exact)",
       ""},
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
