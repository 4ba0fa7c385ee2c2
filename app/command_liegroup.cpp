/// \file
/// `lieflow liegroup`: the precision and speed tables of liegroup/.
#include <iostream>

#include "app/arguments.hpp"
#include "app/cli.hpp"
#include "app/commands.hpp"
#include "liegroup_measure/liegroup_measure.hpp"

namespace lieflow {
namespace app {

int runLiegroup(int argc, char** argv) {
  const Arguments args(argc, argv, {"--samples", "--seconds"}, {});
  if (args.help()) {
    std::cout << "usage: lieflow liegroup [--samples N] [--seconds S]\n\n"
                 "Prints the precision of SO(3)/SE(3) exp/log round trips and Jacobians per\n"
                 "angle band (N random samples per band, default 20000) and the time per\n"
                 "operation beside its Eigen baseline (S seconds per operation, default 0.05).\n";
    return kSuccess;
  }
  if (!args.positional().empty()) throw UsageError("liegroup takes no positional arguments");
  const int samples = args.positiveInt("--samples", 20000);
  const double seconds = args.positiveNumber("--seconds", 0.05);
  std::cout << "# lieflow liegroup summary\n\n## Precision (" << samples
            << " random samples per band)\n\n";
  measure::printPrecisionTable(std::cout, measure::measurePrecision(samples, 20261122));
  std::cout << "\n## Speed (ratio to the Eigen baseline, same run)\n\n";
  measure::printSpeedTable(std::cout, measure::measureSpeed(seconds));
  return kSuccess;
}

}  // namespace app
}  // namespace lieflow
