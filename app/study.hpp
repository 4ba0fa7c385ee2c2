/// \file
/// Work-precision studies: every integrator over a range of steps, with the
/// run time (median of repeated runs) and the error at t_end against a
/// reference — the exact flow where the scene has one, else a converged
/// adaptive run whose own error is estimated and reported — plus energy and
/// momentum drift over time; written as CSV and drawn with matplotlib. On an
/// MJCF model, MuJoCo's own integrators may run beside lieflow's
/// (--with-mujoco): their rows are named mujoco-euler, mujoco-rk4 and
/// mujoco-implicit, their errors measured against MuJoCo's own converged run
/// (its RK4 at the reference's step): each engine's integrator error on its
/// own model, with how far the two references lie apart in words.
#pragma once

#include <functional>
#include <map>
#include <ostream>
#include <string>
#include <vector>

#include "model/import/import_options.hpp"
#include "simulation/simulation.hpp"

namespace lieflow {
namespace app {

struct StudyOptions {
  /// Empty: every integrator that can run the scene (the reference excluded).
  std::vector<std::string> integrators;
  /// --formulation of the runs (empty: the default; SimulationOptions::formulation);
  /// the reference solution keeps the default formulation (independent of it).
  std::string formulation;
  /// Empty: the scene's dt × {4, 2, 1, 1/2, 1/4}.
  std::vector<double> dts;
  std::string out_dir = "study";
  /// Each run is repeated until this much time was spent (at least
  /// min_repeats runs, at most max_repeats); the median time is reported.
  double min_timing_seconds = 0.2;
  int min_repeats = 3;
  int max_repeats = 50;
  bool plots = true;
  /// Integrator options from --options: each applies to the integrators that
  /// accept it (over the scene's own options for its integrator).
  std::map<std::string, double> integrator_options;
  long max_steps = kMaxSteps;
  /// --with-mujoco: the MJCF model the scene was imported from and how
  /// (--ignore, --keyframe); MuJoCo's integrators (peers/mujoco/mujoco_peer.hpp)
  /// then run beside lieflow's at the same steps. Empty: no MuJoCo rows.
  std::string mujoco_model;
  ModelImportOptions mujoco_import;
  /// --view: the reference run's rows go here as it runs (the replay's
  /// frames); a reference computed in one step (the exact flow) or with
  /// adaptive steps is run once more for it at t_end/kReplayIntervals
  /// output intervals. Empty: no replay.
  std::function<void(const std::vector<double>&)> replay_sink;
  /// Where progress goes (nullptr: silent).
  std::ostream* progress = nullptr;
  /// Called before every run and about every 0.25 s within one
  /// (SimulationOptions::progress); it may throw to stop the study (the
  /// Python module's Ctrl-C). May be empty.
  std::function<void()> heartbeat;
};

struct StudyRow {
  std::string integrator;
  double dt = 0.0;
  long steps = 0;
  int repeats = 0;
  double wall_seconds = 0.0;  ///< median over the repeats, diagnostics off
  double ns_per_step = 0.0;
  /// max over the bodies of the angle of R_ref(T)⁻¹ R(T), radians
  double orientation_error = 0.0;
  /// max_b ‖ω_b(T) − ω_b,ref(T)‖ / max_b ‖ω_b,ref(T)‖ (absolute when no body turns)
  double omega_error = 0.0;
  double energy_drift = 0.0;
  bool momentum_conserved = false;
  double momentum_drift = 0.0;
  /// Maximal relative drift of each invariant (StudyResult::invariant_names).
  std::vector<double> invariant_drifts;
  /// The integrator options in force ("rho_inf=1, tolerance=1e-12, ...").
  std::string options;
  bool implicit = false;
  double newton_iterations_mean = 0.0;
  bool failed = false;
  std::string failure;
  /// What this row's errors are measured against, when not the study's
  /// reference (MuJoCo's rows: MuJoCo's own converged run), and that run's
  /// own estimated orientation error. Empty: StudyResult::reference.
  std::string reference;
  double reference_error = 0.0;
};

struct DriftSample {
  std::string integrator;
  double dt = 0.0;
  double t = 0.0;
  double energy_error = 0.0;    ///< (E − E₀)/|E₀|
  double momentum_error = 0.0;  ///< ‖L − L₀‖/‖L₀‖ (when conserved)
  std::vector<double> invariant_errors;  ///< relative, StudyResult::invariant_names order
};

struct StudyResult {
  std::string scene;
  double t_end = 0.0;
  /// What the errors are measured against, in words, and the reference's
  /// own estimated orientation error.
  std::string reference;
  double reference_error = 0.0;
  std::vector<StudyRow> rows;
  std::vector<DriftSample> drift;
  bool momentum_conserved = false;
  /// The scene's conserved quantities (simulation/invariants.hpp).
  std::vector<std::string> invariant_names;
  /// Runs whose timing hit max_repeats before min_timing_seconds were spent.
  int capped_timings = 0;
};

/// Runs the study (throws InvalidInput for unknown integrators or steps).
StudyResult runStudy(const Simulation& simulation, double t_end, const StudyOptions& options);

/// study.csv and drift.csv in `dir` (created if needed).
void writeStudyFiles(const StudyResult& result, const std::string& dir);

/// Draws DIR/work_precision.png, energy_drift.png, momentum_drift.png with
/// scripts/plot_study.py under Debian's python3 + matplotlib. Returns false
/// and says why in `why` when plotting is not possible.
bool plotStudy(const std::string& dir, std::string* why);

/// A readable table of the rows (markdown).
void printStudyTable(std::ostream& out, const StudyResult& result);

}  // namespace app
}  // namespace lieflow
