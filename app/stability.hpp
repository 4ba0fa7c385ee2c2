/// \file
/// Stability study: for each integrator, the largest h·ω_c for which a run
/// stays bounded (no blow-up, no failed solve, and the energy stays within
/// (0, 2E₀): relative energy error below 1, so decay counts as bounded and
/// growth does not),
/// where ω_c is the scene's fastest time scale: the spin rate ‖ω₀‖ or the
/// spring frequency √(k/I_min), whichever is larger.
#pragma once

#include <functional>
#include <map>
#include <ostream>
#include <string>
#include <vector>

#include "model/scene_time_scale.hpp"
#include "simulation/simulation.hpp"

namespace lieflow {
namespace app {

struct StabilityOptions {
  std::vector<std::string> integrators;  ///< empty: all that can run the scene
  /// --formulation of the runs (empty: the default; SimulationOptions::formulation).
  std::string formulation;
  /// Grid of h·ω_c scanned upward (log-spaced), then refined by bisection.
  double h_omega_min = 0.01;
  double h_omega_max = 100.0;
  int grid_points = 25;
  int bisections = 8;
  /// Each run covers this many periods 2π/ω_c, and at least min_steps steps.
  double periods = 40.0;
  long min_steps = 200;
  /// "Bounded": relative energy error stays below this.
  double energy_bound = 1.0;
  /// Integrator options from --options (each to the integrators that take it).
  std::map<std::string, double> integrator_options;
  long max_steps = kMaxSteps;
  std::ostream* progress = nullptr;
  /// As StudyOptions::heartbeat: before every run and during long ones.
  std::function<void()> heartbeat;
};

struct StabilityRow {
  std::string scene;
  std::string integrator;
  double omega_c = 0.0;
  /// Largest h·ω_c found bounded (the grid top if nothing failed).
  double h_omega_max = 0.0;
  /// true: bounded on the whole grid.
  bool unbounded_grid = false;
  /// What the first unbounded run did (blow-up, solver failure, energy).
  std::string first_failure;
  /// The integrator options in force ("rho_inf=0.5, tolerance=1e-12, ...").
  std::string options;
};

std::vector<StabilityRow> runStability(const Simulation& simulation, const StabilityOptions& options);

void writeStabilityCsv(const std::vector<StabilityRow>& rows, const std::string& path);
void printStabilityTable(std::ostream& out, const std::vector<StabilityRow>& rows);
/// DIR/stability.png from DIR/stability.csv (scripts/plot_stability.py).
bool plotStability(const std::string& dir, std::string* why);

}  // namespace app
}  // namespace lieflow
