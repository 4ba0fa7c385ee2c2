#include "app/stability.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <Eigen/Eigenvalues>

#include "app/flag_spelling.hpp"
#include "app/plotting.hpp"
#include "app/progress.hpp"
#include "app/run_setup.hpp"
#include "integrators/registry.hpp"
#include "liegroup/invalid_input.hpp"
#include "liegroup/number_text.hpp"

namespace lieflow {
namespace app {
namespace {

struct Probe {
  bool bounded = false;
  std::string why;
};

/// The run settings of `integrator` (its options in force) at step h.
SimulationOptions probeRun(const Simulation& sim, const std::string& integrator, double h,
                           const StabilityOptions& o) {
  SimulationOptions run;
  run.integrator = integrator;
  run.formulation = o.formulation;
  run.dt = h;
  run.dt_source = "the stability scan's step";
  run.t_end_source = "its run time";
  run.max_steps = o.max_steps;
  run.check_every = 1;  // the energy bound and the blow-up test hold at every step
  if (o.heartbeat) {
    o.heartbeat();
    run.progress = [heartbeat = o.heartbeat](double, long) { heartbeat(); };
  }
  applyIntegratorOptions(sim.scene(), o.integrator_options, &run);
  return run;
}

Probe probe(const Simulation& sim, const std::string& integrator, double omega_c, double h_omega,
            const StabilityOptions& o) {
  constexpr double kTwoPi = 6.283185307179586;
  SimulationOptions run = probeRun(sim, integrator, h_omega / omega_c, o);
  run.t_end = std::max(o.periods * kTwoPi / omega_c, static_cast<double>(o.min_steps) * run.dt);
  const SimulationResult r = sim.run(run);
  Probe p;
  if (r.failed) {
    p.why = r.failure;
  } else if (!(r.energy_drift <= o.energy_bound)) {
    std::ostringstream s;
    s << "energy error " << r.energy_drift << " > " << o.energy_bound;
    p.why = s.str();
  } else {
    p.bounded = true;
  }
  return p;
}

}  // namespace

/// Seconds between the progress lines of a long scan.
constexpr double kProgressLineSeconds = 5.0;

std::vector<StabilityRow> runStability(const Simulation& sim, const StabilityOptions& o) {
  const double omega_c = characteristicFrequency(sim.scene());
  std::vector<std::string> integrators = o.integrators;
  if (integrators.empty())
    for (const IntegratorInfo& info : integratorRegistry())
      if (info.order != 0 && !info.is_adaptive && sim.supports(info.name, nullptr, o.formulation))
        integrators.push_back(info.name);
  for (const std::string& name : integrators) {
    std::string why;
    if (!sim.supports(name, &why, o.formulation)) throw InvalidInput("--integrators", why);
  }
  checkOptionKeysUsed(o.integrator_options, integrators);
  std::vector<StabilityRow> rows;
  // A line for each probe that follows seconds of work (a scan of a large
  // scene runs minutes between the integrators' lines).
  LineThrottle lines(kProgressLineSeconds, kProgressLineSeconds);
  const auto report = [&](const std::string& name, double h_omega) {
    if (!o.progress || !lines.due()) return;
    *o.progress << "stability: " << sim.scene().name << " " << name << ": probing h*omega_c = " << formatNumber(h_omega)
                << "\n";
  };
  for (const std::string& name : integrators) {
    if (o.progress) *o.progress << "stability: " << sim.scene().name << " " << name << "\n";
    lines.restart();
    StabilityRow row;
    row.scene = sim.scene().name;
    row.integrator = name;
    row.omega_c = omega_c;
    row.options = describeOptions(probeRun(sim, name, 1.0, o));
    const double ratio = std::pow(o.h_omega_max / o.h_omega_min, 1.0 / (o.grid_points - 1));
    double stable = 0.0, unstable = 0.0;
    for (int i = 0; i < o.grid_points; ++i) {
      const double h_omega = o.h_omega_min * std::pow(ratio, i);
      report(name, h_omega);
      const Probe p = probe(sim, name, omega_c, h_omega, o);
      if (!p.bounded) {
        unstable = h_omega;
        row.first_failure = p.why;
        break;
      }
      stable = h_omega;
    }
    if (unstable == 0.0) {
      row.unbounded_grid = true;
      row.h_omega_max = stable;
    } else if (stable > 0.0) {
      // Bisection in log h between the last bounded and the first unbounded step.
      for (int k = 0; k < o.bisections; ++k) {
        const double mid = std::sqrt(stable * unstable);
        report(name, mid);
        if (probe(sim, name, omega_c, mid, o).bounded)
          stable = mid;
        else
          unstable = mid;
      }
      row.h_omega_max = stable;
    }
    rows.push_back(row);
  }
  return rows;
}

void writeStabilityCsv(const std::vector<StabilityRow>& rows, const std::string& path) {
  std::filesystem::create_directories(std::filesystem::path(path).parent_path().empty()
                                          ? "."
                                          : std::filesystem::path(path).parent_path());
  std::ofstream f(path);
  if (!f) throw InvalidInput(path, "cannot open for writing");
  f << "scene,integrator,omega_c,h_omega_max,bounded_on_whole_grid,first_failure,options\n";
  for (const StabilityRow& r : rows) {
    std::string why = spellFlags(r.first_failure);
    std::replace(why.begin(), why.end(), '"', '\'');
    f << r.scene << "," << r.integrator << "," << r.omega_c << "," << r.h_omega_max << ","
      << (r.unbounded_grid ? "true" : "false") << ",\"" << why << "\",\"" << r.options << "\"\n";
  }
}

void printStabilityTable(std::ostream& out, const std::vector<StabilityRow>& rows) {
  out << "| scene | integrator | options | omega_c [rad/s] | largest bounded h*omega_c | first unbounded run |\n";
  out << "|---|---|---|---|---|---|\n";
  for (const StabilityRow& r : rows) {
    char h[32];
    std::snprintf(h, sizeof h, "%.3g", r.h_omega_max);
    out << "| " << r.scene << " | " << r.integrator << " | " << (r.options.empty() ? "-" : r.options) << " | "
        << r.omega_c << " | "
        << (r.unbounded_grid ? std::string(">= ") + h : (r.h_omega_max > 0 ? h : "< grid start")) << " | "
        << (r.unbounded_grid ? "bounded on the whole grid" : spellFlags(r.first_failure)) << " |\n";
  }
}

bool plotStability(const std::string& dir, std::string* why) {
  return runPlotScript("plot_stability.py", dir, why);
}

}  // namespace app
}  // namespace lieflow
