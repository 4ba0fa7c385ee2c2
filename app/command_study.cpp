/// \file
/// `lieflow study SCENE ...` and the main job (`lieflow` with no arguments).
#include <iostream>

#include "app/arguments.hpp"
#include "app/cli.hpp"
#include "app/commands.hpp"
#include "app/study.hpp"

namespace lieflow {
namespace app {
namespace {

constexpr const char* kUsage =
    "usage: lieflow study SCENE [--integrators a,b,...] [--dt h1,h2,...] [--t-end T] [--out DIR]\n"
    "                     [--min-time SECONDS] [--no-plots]\n"
    "\n"
    "Work-precision study of SCENE: each integrator at each step; error at t_end\n"
    "against the exact flow (torque-free scenes) or a converged rkmk45 reference\n"
    "(whose own error is estimated and printed); run time = median of repeated runs\n"
    "(repeated until --min-time seconds, default 0.2, were spent; at least 3).\n"
    "Writes DIR/study.csv, DIR/drift.csv and the plots DIR/work_precision.png,\n"
    "DIR/energy_drift.png, DIR/momentum_drift.png (default DIR: study-SCENENAME).\n"
    "Progress goes to stderr; the table to stdout.\n";

int studyAndReport(const Simulation& sim, double t_end, StudyOptions options) {
  const StudyResult result = runStudy(sim, t_end, options);
  writeStudyFiles(result, options.out_dir);
  printStudyTable(std::cout, result);
  std::cout << "\nwrote " << options.out_dir << "/study.csv, " << options.out_dir << "/drift.csv\n";
  if (options.plots) {
    std::string why;
    if (plotStudy(options.out_dir, &why))
      std::cout << "plots: " << options.out_dir << "/work_precision.png, energy_drift.png, momentum_drift.png\n";
    else
      std::cerr << "lieflow: plots skipped: " << why << "\n";
  }
  for (const StudyRow& r : result.rows)
    if (r.failed) std::cout << "note: " << r.integrator << " at dt = " << r.dt << " failed: " << r.failure << "\n";
  return kSuccess;
}

}  // namespace

int runStudy(int argc, char** argv) {
  const Arguments args(argc, argv, {"--integrators", "--dt", "--t-end", "--out", "--min-time"},
                       {"--no-plots"});
  if (args.help()) {
    std::cout << kUsage;
    return kSuccess;
  }
  if (args.positional().size() != 1) throw UsageError("study needs exactly one SCENE (see lieflow study --help)");
  const Simulation sim(loadScene(args.positional()[0]));
  StudyOptions options;
  options.integrators = args.list("--integrators");
  options.dts = args.positiveNumbers("--dt");
  options.out_dir = args.value("--out", "study-" + sim.scene().name);
  options.min_timing_seconds = args.positiveNumber("--min-time", options.min_timing_seconds);
  options.plots = !args.has("--no-plots");
  options.progress = &std::cerr;
  const double t_end = args.positiveNumber("--t-end", sim.scene().has_t_end ? sim.scene().t_end : 0.0);
  if (!(t_end > 0.0)) throw UsageError("the scene has no t_end: give --t-end");
  return studyAndReport(sim, t_end, options);
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
