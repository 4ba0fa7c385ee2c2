/// \file
/// Running a scene: assembly of the scene into the system it needs (a scene
/// pays only for what it contains: a rotation-only body is a RotorSystem on
/// SO(3) × ℝ³, a body on a spherical joint to ground is a RotorSystem about
/// the pivot with no constraint solve, a free body is a FreeBodySystem), the
/// choice of stepper by name, the trajectory rows of the CSV contract and the
/// drift statistics of `--stats`.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "model/resource_limits.hpp"
#include "model/scene.hpp"

namespace lieflow {

struct SimulationOptions {
  std::string integrator;
  double dt = 0.0;
  double t_end = 0.0;
  /// Where dt and t_end came from, for messages: the option ("`dt`", the
  /// default; the command line says --dt), the scene's field ("arm.xml: integrator.dt", an MJCF model's
  /// timestep), or the command that chose them ("the study's steps").
  std::string dt_source = "`dt`";
  std::string t_end_source = "`t_end`";
  /// Output every N-th step (the first and the last rows are always output).
  int every = 1;
  std::map<std::string, double> integrator_options;
  /// The keys of `integrator_options` given on the command line (--options),
  /// so that an error names the place the value came from.
  std::set<std::string> command_line_options;
  /// Most steps (accepted plus rejected) the run may take: a step count above
  /// it is refused before the run (InvalidInput naming --max-steps), an
  /// adaptive run that reaches it fails saying so.
  long max_steps = kMaxSteps;
  /// Called with (t, steps so far) every few ten thousand steps, for
  /// progress reports of long runs (may be empty).
  std::function<void(double, long)> progress;
  /// Called with each output row's time and the current relative error of
  /// each invariant (invariantNames() order), beside the row sink.
  std::function<void(double, const std::vector<double>&)> invariant_sink;
  /// Steps between the checks of the run's figures (energy and momentum
  /// drift, the invariants, the constraint error and the blow-up test):
  /// 0 checks them at the output steps (every `every`-th and the last), so
  /// that a run with few rows costs what its stepper costs; 1 at every step
  /// (study and stability do: their drift figures and blow-up test are the
  /// result). Every step's state is checked for finiteness whatever it is
  /// (integrateFixedStep, integrateAdaptive), so a run that overflows stops
  /// there; a dashpot's power is taken at every step for energy_balance.
  int check_every = 0;
  /// Compute energy/momentum statistics (off: only the final
  /// state is observed, so the timing measures the stepping alone, and a
  /// blow-up is caught only once the state is non-finite).
  bool diagnostics = true;
  /// "maximal" (bodies' poses with multipliers for the joints), "joint" (the
  /// joints' own coordinates, dynamics/joint_space/articulated_scene.hpp) or empty for the
  /// default, Simulation::defaultFormulation.
  std::string formulation;
  /// Rows carry each body's accelerometer reading B.ax, B.ay, B.az after its
  /// other columns (columns(true)): the specific force f = Rᵀ(a_s − g) at the
  /// body's sensor point s (BodyDescription::sensor), body axes, gravity
  /// included, as an inertial sensor reports it (../shared/DESIGN.md).
  bool imu = false;
};

struct SimulationResult {
  std::string integrator;
  /// The formulation the run used ("maximal" or "joint"; a scene without
  /// constraint rows has one formulation, reported as "joint").
  std::string formulation;
  double dt = 0.0;
  long steps = 0;
  long rejected_steps = 0;
  double wall_seconds = 0.0;
  double ns_per_step = 0.0;
  /// The interval of the checks in steps (SimulationOptions::check_every
  /// resolved: `every` when that was 0).
  long checked_every = 1;
  /// max |E − E₀|/|E₀| over the checked steps (absolute when E₀ = 0).
  double energy_drift = 0.0;
  /// Whether the spatial angular momentum is conserved by this scene, and
  /// max ‖L − L₀‖/‖L₀‖ if it is.
  bool momentum_conserved = false;
  double momentum_drift = 0.0;
  /// max position-level constraint residual (0: no constraints to violate).
  double constraint_error = 0.0;
  /// The scene's conserved quantities (simulation/invariants.hpp) with their
  /// maximal relative drift, when the run did not fail.
  std::vector<std::pair<std::string, double>> invariants;
  bool implicit = false;
  double newton_iterations_mean = 0.0;
  /// Steps taken as substeps because their implicit solve failed whole
  /// (lgvi in joint coordinates; --stats `substepped_steps` when > 0).
  long substepped_steps = 0;
  bool failed = false;
  std::string failure;
  /// The last row (time t_reached), whatever `every` is; empty when the run
  /// failed at its first state (nothing finite to report).
  std::vector<double> final_row;
};

/// A scene assembled for simulation.
class Simulation {
 public:
  /// Validates the scene's structure (bodies and joints it can simulate,
  /// consistency of positions with joints); throws InvalidInput naming the
  /// source, the field and the reason.
  explicit Simulation(SceneDescription scene);
  ~Simulation();
  Simulation(Simulation&&) noexcept;
  Simulation& operator=(Simulation&&) noexcept;

  const SceneDescription& scene() const { return scene_; }

  /// CSV column names (README "Trajectory and recording CSV"); with `imu`,
  /// B.ax, B.ay, B.az after each body's columns (SimulationOptions::imu).
  std::vector<std::string> columns(bool imu = false) const;

  /// Names of the quantities this scene conserves (simulation/invariants.hpp),
  /// in the order of SimulationResult::invariants.
  std::vector<std::string> invariantNames() const;

  /// Whether the integrator can run this scene (e.g. `exact` needs a
  /// torque-free body); if not, `why` says so.
  /// `formulation` as in SimulationOptions (empty: the default, in which
  /// the integrator runs the scene when either formulation can).
  bool supports(const std::string& integrator, std::string* why, const std::string& formulation = "") const;

  /// Whether the scene can run in joint coordinates; if not, `why` says so.
  bool hasJointFormulation(std::string* why) const;

  /// The formulation `integrator` runs this scene in when none is asked for
  /// (../shared/DESIGN.md, "Default formulation"): the fastest that
  /// represents it, "joint" wherever joint coordinates represent the scene
  /// and the integrator runs there (a tree, or loops and gear rows with the
  /// explicit steppers: 2 to 3 times fewer operations per step than bodies'
  /// poses with multipliers, bench/multibody; on floating robots in motion
  /// genalpha too, simulation.cpp has the figures), else "maximal". A scene
  /// without joints has one formulation, "joint".
  std::string defaultFormulation(const std::string& integrator) const;
  /// Why `integrator` runs this scene in joint coordinates only when asked
  /// for (its cell of the table of steppers says so: genalpha on loops);
  /// empty where the default may be joint coordinates.
  std::string jointOnlyWhenAskedFor(const std::string& integrator) const;

  /// Whether the scene is a mechanism, whose maximal formulation imposes
  /// constraints with multipliers (a single body, free or on the reduced
  /// model of its one joint to the ground, is not).
  bool hasConstraints() const;

  /// Runs the scene; calls `row` with each output row (may be empty).
  /// Throws InvalidInput for an unknown integrator, bad options or dt.
  SimulationResult run(const SimulationOptions& options,
                       const std::function<void(const std::vector<double>&)>& row = {}) const;

  struct Model;

 private:
  SceneDescription scene_;
  std::unique_ptr<Model> model_;
};

}  // namespace lieflow
