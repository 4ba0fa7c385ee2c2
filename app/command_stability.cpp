/// \file
/// `lieflow stability [SCENE...]`: the largest bounded h·ω per integrator.
#include <iostream>

#include "app/arguments.hpp"
#include "app/cli.hpp"
#include "app/commands.hpp"
#include "app/output_files.hpp"
#include "app/run_setup.hpp"
#include "app/stability.hpp"
#include "app/study_request.hpp"

namespace lieflow {
namespace app {

int runStabilityCommand(int argc, char** argv) {
  const Arguments args(argc, argv, stabilityValueFlags(), stabilitySwitches());
  if (args.help()) {
    std::cout << "usage: lieflow stability [SCENE...] [--integrators a,b,...] [--options KEY=VALUE,...]\n"
                 "                         [--out DIR] [--no-plots] [--max-steps N] [--max-input-mb N] [--max-bodies N]\n"
                 "                         [--formulation maximal|joint] [--ignore LIST] [--keyframe K] [--floating-base] [--spin WX,WY,WZ]\n"
                 "\n"
                 "For each integrator and scene (default: stiff-spring and fast-top), the\n"
                 "largest h*omega_c for which a run of 40 periods stays bounded (no blow-up,\n"
                 "no failed solve, energy within (0, 2 E0)), omega_c being the scene's\n"
                 "spin rate or spring frequency sqrt(k/I_min). Scans h*omega_c from 0.01 to\n"
                 "100 and refines by bisection. Writes DIR/stability.csv and DIR/stability.png\n"
                 "(default DIR: stability; created and checked writable first). --options applies\n"
                 "each KEY to the integrators that take it (e.g. rho_inf=0.8 for genalpha); the\n"
                 "table and CSV give the options in force for every integrator.\n";
    return kSuccess;
  }
  StabilityRequest request = stabilityRequestFrom(args);
  request.options.progress = &std::cerr;
  const std::string& dir = request.out_dir;
  OutputDirectory out(dir);
  const std::vector<StabilityRow> rows = runStability(request);
  writeStabilityCsv(rows, dir + "/stability.csv");
  out.keep();
  printStabilityTable(std::cout, rows);
  std::cout << "\nwrote " << dir << "/stability.csv\n";
  if (request.plots) {
    std::string why;
    if (plotStability(dir, &why))
      std::cout << "plot: " << dir << "/stability.png\n";
    else
      std::cerr << "lieflow: plot skipped: " << why << "\n";
  }
  return kSuccess;
}

}  // namespace app
}  // namespace lieflow
