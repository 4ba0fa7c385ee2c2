/// \file
/// `lieflow study SCENE ...` and the main job (`lieflow` with no arguments).
#include <iostream>

#include "app/arguments.hpp"
#include "app/cli.hpp"
#include "app/commands.hpp"
#include "app/flag_spelling.hpp"
#include "app/output_files.hpp"
#include "app/replay_output.hpp"
#include "app/run_setup.hpp"
#include "app/study.hpp"
#include "app/study_request.hpp"

namespace lieflow {
namespace app {
namespace {

constexpr const char* kStudyUsage =
    "usage: lieflow study SCENE [--integrators a,b,...] [--dt h1,h2,...] [--t-end T] [--out DIR]\n"
    "                     [--min-time SECONDS] [--options KEY=VALUE,...] [--no-plots] [--view]\n"
    "                     [--formulation maximal|joint] [--with-mujoco]\n"
    "                     [--ignore LIST] [--keyframe K] [--floating-base] [--spin WX,WY,WZ]\n"
    "                     [--max-steps N] [--max-input-mb N] [--max-bodies N]\n"
    "\n"
    "Work-precision study of SCENE: each integrator at each step; error at t_end\n"
    "against the exact flow (torque-free scenes), a converged rkmk45 reference, or\n"
    "(scenes with joints) a projected rkmk4 run at a step 32 times below the smallest\n"
    "(whose own error is estimated and printed: by Richardson where runs at twice and four\n"
    "times its step show fourth order, else as its difference from the run at twice the\n"
    "step, which round-off rules); run time = median of repeated runs\n"
    "(repeated until --min-time seconds, default 0.2, were spent; at least 3 and at\n"
    "most 50 runs: the output says when 50 runs took less than --min-time).\n"
    "--options applies each KEY to the integrators that take it (e.g. rho_inf=0.9).\n"
    "Scenes with joints run in joint coordinates wherever they represent the scene and the\n"
    "integrator runs there, else in maximal coordinates; --formulation maximal|joint chooses\n"
    "(lieflow simulate --help). The reference keeps maximal coordinates, independent of the runs.\n"
    "SCENE may be a model file (MJCF .xml, URDF .urdf: lieflow import --help). On a model\n"
    "file, --with-mujoco runs MuJoCo's Euler, RK4 and implicit integrators beside lieflow's\n"
    "at the same steps (rows mujoco-euler, mujoco-rk4, mujoco-implicit; what --ignore leaves\n"
    "out is switched off in MuJoCo too), measured against the same reference, which MuJoCo\n"
    "RK4 at the reference's step checks; without MuJoCo in the build the rows say so.\n"
    "Writes DIR/study.csv, DIR/drift.csv and the plots DIR/work_precision.png,\n"
    "DIR/energy_drift.png, DIR/momentum_drift.png (default DIR: study-SCENENAME);\n"
    "DIR is created and checked writable before the study starts. --view also writes\n"
    "DIR/replay.html, a replay of the reference run (lieflow view --help).\n"
    "Progress goes to stderr; the table to stdout.\n";

int studyAndReport(const Simulation& sim, double t_end, StudyOptions options, bool view = false) {
  OutputDirectory out(options.out_dir);
  // --view: the reference run's rows, kept within the replay's frame budget.
  replay::FrameDecimator frames(replay::kDefaultFrameBudget);
  if (view) options.replay_sink = [&frames](const std::vector<double>& row) { frames.offer(row); };
  const StudyResult result = runStudy(sim, t_end, options);
  writeStudyFiles(result, options.out_dir);
  out.keep();
  printStudyTable(std::cout, result);
  std::cout << "\nwrote " << options.out_dir << "/study.csv, " << options.out_dir << "/drift.csv\n";
  if (options.plots) {
    std::string why;
    if (plotStudy(options.out_dir, &why))
      std::cout << "plots: " << options.out_dir << "/work_precision.png, energy_drift.png, momentum_drift.png\n";
    else
      std::cerr << "lieflow: plots skipped: " << why << "\n";
  }
  if (view) {
    const replay::RunTable run = replay::tableOf(frames, sim.columns(), "the study's reference run");
    replay::ReplayOptions replay_options;
    replay_options.title = sim.scene().name + ": the study's reference (" + result.reference + ")";
    writeReplayFile(options.out_dir + "/replay.html", "--view", sim.scene(), run, replay_options, true);
    std::cout << "replay: " << options.out_dir << "/replay.html (the reference run, " << run.rows.size()
              << " frames)\n";
  }
  for (const StudyRow& r : result.rows)
    if (r.failed) std::cout << "note: " << r.integrator << " at dt = " << r.dt << " failed: " << spellFlags(r.failure) << "\n";
  if (result.capped_timings > 0)
    std::cout << "note: " << result.capped_timings << " of " << result.rows.size() << " runs were timed "
              << options.max_repeats << " times in less than --min-time " << options.min_timing_seconds
              << " s (the repeat limit); their median is over " << options.max_repeats << " runs\n";
  return kSuccess;
}

}  // namespace

int runStudy(int argc, char** argv) {
  const Arguments args(argc, argv, studyValueFlags(), studySwitches());
  if (args.help()) {
    std::cout << kStudyUsage;
    return kSuccess;
  }
  StudyRequest request = studyRequestFrom(args);
  request.options.progress = &std::cerr;
  return studyAndReport(*request.simulation, request.t_end, request.options, args.has("--view"));
}

int runMainJob(int, char**) {
  // A short work-precision study of the default scene.
  const Simulation sim(loadScene("heavy-top"));
  StudyOptions options;
  options.dts = {4e-3, 2e-3, 1e-3, 5e-4};
  options.out_dir = "out/main-study";
  options.min_timing_seconds = 0.05;
  options.progress = &std::cerr;
  std::cout << "# lieflow main job: work-precision study of the heavy top (Bruls-Cardona-Arnold 2012)\n\n";
  return studyAndReport(sim, sim.scene().t_end, options);
}

}  // namespace app
}  // namespace lieflow
