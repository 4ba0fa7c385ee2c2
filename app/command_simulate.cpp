/// \file
/// `lieflow simulate SCENE ...`: runs one scene with one integrator, writes
/// the trajectory CSV and/or prints the `--stats` JSON object.
#include <functional>
#include <iostream>
#include <memory>
#include <sstream>

#include <nlohmann/json.hpp>

#include "app/arguments.hpp"
#include "app/cli.hpp"
#include "app/commands.hpp"
#include "app/csv_writer.hpp"
#include "app/flag_spelling.hpp"
#include "app/output_files.hpp"
#include "app/progress.hpp"
#include "app/recording_noise.hpp"
#include "app/replay_output.hpp"
#include "app/run_setup.hpp"
#include "app/simulate_request.hpp"
#include "simulation/simulation.hpp"
#include "liegroup/invalid_input.hpp"
#include "liegroup/number_text.hpp"

namespace lieflow {
namespace app {
namespace {

constexpr const char* kSimulateUsage =
    "usage: lieflow simulate SCENE [--integrator NAME] [--dt H] [--t-end T] [--out FILE.csv]\n"
    "                        [--every N] [--stats] [--options KEY=VALUE,...] [--view FILE.html]\n"
    "                        [--formulation maximal|joint]\n"
    "                        [--noise-gyro S] [--noise-angle S] [--noise-quat S] [--seed N]\n"
    "                        [--imu] [--noise-acc S] [--bias-gyro S]\n"
    "                        [--ignore LIST] [--keyframe K] [--floating-base] [--spin WX,WY,WZ]\n"
    "                        [--max-steps N] [--max-input-mb N] [--max-bodies N] [--quiet]\n"
    "\n"
    "Simulates SCENE (a JSON scene file, a built-in scene: lieflow scenes, or a model file:\n"
    "MJCF .xml, URDF .urdf, read as lieflow import --help says).\n"
    "  --ignore LIST      what a model file may leave out (contacts,limits,...; lieflow import --help)\n"
    "  --keyframe K       an MJCF model's keyframe (name or index) as the start (default: qpos0, at rest)\n"
    "  --floating-base    a URDF's root link on a free joint to the world (default: fixed to it)\n"
    "  --spin WX,WY,WZ    every free tree turning rigidly at that rate (rad/s, world axes) about its\n"
    "                     centre of mass, added to its start (lieflow import --help)\n"
    "  --integrator NAME  integrator (lieflow integrators); default: the scene's, else rkmk4\n"
    "  --dt H             step (output interval for rkmk45); default: the scene's, else MuJoCo's\n"
    "                     0.002 s or 0.05/omega for the scene's fastest spin or spring; at most t_end\n"
    "  --t-end T          end time; default: the scene's t_end\n"
    "  --options K=V,...  integrator options, e.g. rho_inf=0.8 (genalpha), rtol=1e-10 (rkmk45)\n"
    "  --formulation F    a scene with joints in joint coordinates (a tree of revolute, universal,\n"
    "                     prismatic and spherical joints from the ground; rkmk*, cg3, cf4, genalpha,\n"
    "                     radau5, lgvi (not on slides or spherical joints); a\n"
    "                     joint closing a loop and gear rows on multipliers: rkmk-euler, rkmk-heun,\n"
    "                     rkmk3, rkmk4, rkmk6, cg3, cf4, radau5) or in maximal coordinates (bodies' poses, the\n"
    "                     joints as constraints). Default: joint wherever it represents the scene\n"
    "                     and runs the integrator (2-3x faster per step), else maximal\n"
    "  --view FILE.html   also write a replay of the run there (lieflow view --help); no CSV on\n"
    "                     stdout then unless --out\n"
    "  --out FILE.csv     write the trajectory CSV there (default: stdout, unless --stats); it is\n"
    "                     written as FILE.csv.partial and renamed when the run succeeded\n"
    "  --every N          write every N-th step (first and last rows always)\n"
    "  --check-every N    check energy and momentum drift, invariants, constraint error and\n"
    "                     blow-up every N-th step (default: at the rows written, every --every;\n"
    "                     every state is checked for overflow)\n"
    "  --stats            print one JSON object: integrator, formulation, dt, steps, checked_every,\n"
    "                     wall_seconds, ns_per_step, energy_drift, momentum_drift,\n"
    "                     constraint_error, newton_iterations_mean, invariants, failed, failure\n"
    "  --imu              also write each body's accelerometer B.ax, B.ay, B.az: the specific\n"
    "                     force R^T(a - g) [m/s^2] at its sensor point (the scene's \"sensor\",\n"
    "                     body axes from the centre of mass; default the centre of mass)\n"
    "  --noise-gyro S     add N(0, S^2) rad/s to every B.wx, B.wy, B.wz written (a gyroscope)\n"
    "  --bias-gyro S      add a constant bias per gyroscope axis, drawn once from N(0, S^2) rad/s\n"
    "  --noise-acc S      add N(0, S^2) m/s^2 to every B.ax, B.ay, B.az written (needs --imu)\n"
    "  --noise-angle S    add N(0, S^2) rad to every joint angle J.phi, J.phi1, J.phi2 written\n"
    "  --noise-quat S     rotate every written quaternion by exp(d), d ~ N(0, S^2 I) rad (body frame)\n"
    "  --seed N           seed of the noise generator (default 1)\n"
    "  --max-steps N      most steps a run may take (default 1e8)\n"
    "  --max-input-mb N   largest scene file read, in MiB (default 1024)\n"
    "  --max-bodies N     most bodies in a scene (default 100000)\n"
    "  --quiet            no progress lines on stderr (they appear after 2 s of running)\n"
    "exit status: 0 success, 1 the simulation failed (blow-up, non-convergence, a non-finite\n"
    "value), 2 bad input\n";

}  // namespace

int runSimulate(int argc, char** argv) {
  const Arguments args(argc, argv, simulateValueFlags(), simulateSwitches());
  if (args.help()) {
    std::cout << kSimulateUsage;
    return kSuccess;
  }
  SimulateRequest request = simulateRequestFrom(args);
  const Simulation& simulation = *request.simulation;
  SimulationOptions& options = request.options;
  const NoiseOptions& noise = request.noise;
  ProgressReporter progress("simulate " + simulation.scene().name + " with " + options.integrator, options.t_end);
  if (!args.has("--quiet")) options.progress = std::ref(progress);

  const bool stats = args.has("--stats");
  // An integrator the scene cannot run (in this formulation) is bad input
  // found before a header is written.
  std::string why;
  if (!simulation.supports(options.integrator, &why, options.formulation)) {
    const bool formulation = options.formulation == "joint" && !simulation.hasJointFormulation(nullptr);
    throw InvalidInput(formulation ? "--formulation" : "--integrator", why);
  }
  // The output file is opened (as FILE.partial) before the run: an
  // unwritable place is found before any work is done.
  std::unique_ptr<AtomicOutputFile> file;
  if (args.has("--out")) file = std::make_unique<AtomicOutputFile>(args.value("--out", ""), "--out");
  // --view: the replay's frames are kept as the rows go by (O(budget) memory).
  const bool view = args.has("--view");
  std::unique_ptr<AtomicOutputFile> view_file;
  if (view) view_file = std::make_unique<AtomicOutputFile>(args.value("--view", ""), "--view");
  replay::FrameDecimator frames(replay::kDefaultFrameBudget);
  std::ostream* csv_stream = file ? &file->stream() : (stats || view ? nullptr : &std::cout);
  RecordingNoise noisy(simulation.columns(options.imu), noise);
  std::function<void(const std::vector<double>&)> sink;
  std::unique_ptr<CsvWriter> csv;
  if (csv_stream) {
    csv = std::make_unique<CsvWriter>(*csv_stream);
    csv->header(simulation.columns(options.imu));
  }
  if (csv_stream || view) {
    std::vector<double> r;
    sink = [&, r](const std::vector<double>& row) mutable {
      const std::vector<double>* written = &row;
      if (noise.any()) {
        r = row;
        noisy.apply(&r);
        written = &r;
      }
      if (csv) csv->row(*written);
      if (view) frames.offer(*written);
    };
  }
  SimulationResult result;
  try {
    result = simulation.run(options, sink);
  } catch (const NonFiniteOutput& e) {
    const std::string kept = file ? file->abandon() : "";
    std::cerr << "lieflow: simulation of " << simulation.scene().source << " with " << options.integrator
              << ": the output would hold a non-finite number: " << spellFlags(e.what())
              << (noise.any() ? " (after the --noise-* perturbation)" : "") << (kept.empty() ? "" : "; " + kept)
              << "\n";
    return kComputationFailed;
  }
  if (result.failed) {
    const std::string kept = file ? file->abandon() : "";
    if (stats) std::cout << jsonLine(statsJson(result)) << "\n";
    std::cerr << "lieflow: simulation of " << simulation.scene().source << " with " << result.integrator
              << " failed: " << spellFlags(result.failure) << (kept.empty() ? "" : "; " + kept) << "\n";
    return kComputationFailed;
  }
  if (file) file->commit();
  if (view) {
    view_file.reset();  // (writeReplayFile opens its own PATH.partial)
    const replay::RunTable run =
        replay::tableOf(frames, simulation.columns(options.imu), "the run of " + simulation.scene().source);
    replay::ReplayOptions replay_options;
    replay_options.title = simulation.scene().name + ": " + options.integrator + ", h = " + formatNumber(options.dt);
    writeReplayFile(args.value("--view", ""), "--view", simulation.scene(), run, replay_options, args.has("--quiet"));
  }
  if (stats) std::cout << jsonLine(statsJson(result)) << "\n";
  return kSuccess;
}

}  // namespace app
}  // namespace lieflow
