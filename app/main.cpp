/// \file
/// `lieflow`: the command-line entry point. Dispatches to one function per
/// subcommand (app/commands.hpp); with no arguments it runs the main job.
#include <exception>
#include <iostream>
#include <new>
#include <string>

#include "app/cli.hpp"
#include "app/commands.hpp"
#include "app/flag_spelling.hpp"
#include "liegroup/invalid_input.hpp"

namespace {

constexpr const char* kMainUsage =
    "usage: lieflow [COMMAND] [OPTIONS]\n"
    "\n"
    "Geometric integration of rigid bodies on Lie groups.\n"
    "With no COMMAND, runs the main job: a short work-precision study of the\n"
    "default scene (heavy-top) that prints a table and writes CSV and plots to out/main-study/.\n"
    "\n"
    "commands (each takes --help):\n"
    "  simulate SCENE   run a scene, write its trajectory CSV and/or --stats JSON\n"
    "  study SCENE      work-precision study: error against run time, drift plots\n"
    "  stability [SCENE...]  largest bounded h*omega per integrator (stiff spring, fast top)\n"
    "  integrators      list the integrators with their order and properties\n"
    "  scenes           list the built-in scenes\n"
    "  import MODEL     a MuJoCo MJCF (.xml) or URDF (.urdf) model as a scene file; simulate,\n"
    "                   study and stability also take model files as SCENE\n"
    "  view RUN.csv --scene SCENE  a run as a self-contained HTML replay (opens offline)\n"
    "  liegroup         precision and speed tables of the SO(3)/SE(3) library\n"
    "  calibrate hinge|universal RECORDING.csv  fit joint axes to a recording (needs Ceres)\n"
    "  calibrate spring RECORDING.csv --scene SCENE  fit a joint's stiffness, damping\n"
    "                   and rest angle to its recorded angle (needs Ceres)\n"
    "\n"
    "exit status: 0 success, 1 computation failed, 2 bad input or usage\n"
    "limits: --max-steps, --max-input-mb, --max-bodies (simulate, study, stability) and\n"
    "--max-rows, --max-substeps (calibrate) raise the resource limits; errors name them\n";

int dispatch(int argc, char** argv) {
  using namespace lieflow::app;
  if (argc <= 1) return runMainJob(0, nullptr);
  const std::string command = argv[1];
  const int rest_argc = argc - 2;
  char** rest_argv = argv + 2;
  if (command == "--help" || command == "-h" || command == "help") {
    std::cout << kMainUsage;
    return kSuccess;
  }
  if (command == "simulate") return runSimulate(rest_argc, rest_argv);
  if (command == "study") return runStudy(rest_argc, rest_argv);
  if (command == "stability") return runStabilityCommand(rest_argc, rest_argv);
  if (command == "integrators") return runIntegrators(rest_argc, rest_argv);
  if (command == "scenes") return runScenes(rest_argc, rest_argv);
  if (command == "liegroup") return runLiegroup(rest_argc, rest_argv);
  if (command == "import") return runImport(rest_argc, rest_argv);
  if (command == "view") return runView(rest_argc, rest_argv);
#ifdef LIEFLOW_HAVE_CERES
  if (command == "calibrate") return runCalibrate(rest_argc, rest_argv);
#else
  if (command == "calibrate")
    throw UsageError("calibrate: this lieflow was built without Ceres (apt-get install libceres-dev, then "
                     "rebuild with -DLIEFLOW_BUILD_CALIBRATION=ON)");
#endif
  throw UsageError("unknown command '" + command + "' (see lieflow --help)");
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return dispatch(argc, argv);
  } catch (const lieflow::app::UsageError& e) {
    std::cerr << "lieflow: " << lieflow::app::spellFlags(e.what()) << "\n";
    return lieflow::app::kBadInput;
  } catch (const lieflow::InvalidInput& e) {
    std::cerr << "lieflow: " << lieflow::app::spellFlags(e.what()) << "\n";
    return lieflow::app::kBadInput;
  } catch (const std::bad_alloc&) {
    std::cerr << "lieflow: out of memory: the work asked for more memory than this machine gives it\n";
    return lieflow::app::kComputationFailed;
  } catch (const std::exception& e) {
    std::cerr << "lieflow: error: " << lieflow::app::spellFlags(e.what()) << "\n";
    return lieflow::app::kComputationFailed;
  }
}
