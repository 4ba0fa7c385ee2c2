/// \file
/// `lieflow simulate SCENE ...`: runs one scene with one integrator, writes
/// the trajectory CSV and/or prints the `--stats` JSON object.
#include <fstream>
#include <functional>
#include <memory>
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "app/arguments.hpp"
#include "app/cli.hpp"
#include "app/commands.hpp"
#include "app/csv_writer.hpp"
#include "app/recording_noise.hpp"
#include "app/run_setup.hpp"
#include "joints/simulation.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {
namespace app {
namespace {

constexpr const char* kUsage =
    "usage: lieflow simulate SCENE [--integrator NAME] [--dt H] [--t-end T] [--out FILE.csv]\n"
    "                        [--every N] [--stats] [--options KEY=VALUE,...]\n"
    "\n"
    "Simulates SCENE (a JSON scene file or a built-in scene: lieflow scenes).\n"
    "  --integrator NAME  integrator (lieflow integrators); default: the scene's\n"
    "  --dt H             step (output interval for rkmk45); default: the scene's\n"
    "  --t-end T          end time; default: the scene's t_end\n"
    "  --options K=V,...  integrator options, e.g. rho_inf=0.8 (genalpha), rtol=1e-10 (rkmk45)\n"
    "  --out FILE.csv     write the trajectory CSV there (default: stdout, unless --stats)\n"
    "  --every N          write every N-th step (first and last rows always)\n"
    "  --stats            print one JSON object: integrator, dt, steps, wall_seconds,\n"
    "                     ns_per_step, energy_drift, momentum_drift, constraint_error,\n"
    "                     newton_iterations_mean, failed, failure\n"
    "  --noise-gyro S     add N(0, S^2) rad/s to every B.wx, B.wy, B.wz written (a gyroscope)\n"
    "  --noise-angle S    add N(0, S^2) rad to every joint angle J.phi, J.phi1, J.phi2 written\n"
    "  --noise-quat S     rotate every written quaternion by exp(d), d ~ N(0, S^2 I) rad (body frame)\n"
    "  --seed N           seed of the noise generator (default 1)\n"
    "exit status: 0 success, 1 the simulation failed (blow-up, non-convergence), 2 bad input\n";

}  // namespace

int runSimulate(int argc, char** argv) {
  const Arguments args(argc, argv,
                       {"--integrator", "--dt", "--t-end", "--out", "--every", "--options", "--noise-gyro",
                        "--noise-angle", "--noise-quat", "--seed"},
                       {"--stats"});
  if (args.help()) {
    std::cout << kUsage;
    return kSuccess;
  }
  if (args.positional().size() != 1)
    throw UsageError("simulate needs exactly one SCENE (see lieflow simulate --help)");
  const Simulation simulation(loadScene(args.positional()[0]));
  SimulationOptions options = simulationOptionsFrom(simulation.scene(), args);
  options.every = args.positiveInt("--every", 1);

  const bool stats = args.has("--stats");
  const std::string out_path = args.value("--out", "");
  std::ofstream file;
  if (!out_path.empty()) {
    file.open(out_path);
    if (!file) throw InvalidInput(out_path, "cannot open for writing");
  }
  std::ostream* csv_stream = !out_path.empty() ? static_cast<std::ostream*>(&file)
                                               : (stats ? nullptr : &std::cout);
  NoiseOptions noise;
  noise.gyro = args.has("--noise-gyro") ? args.positiveNumber("--noise-gyro", 0.0) : 0.0;
  noise.angle = args.has("--noise-angle") ? args.positiveNumber("--noise-angle", 0.0) : 0.0;
  noise.quaternion = args.has("--noise-quat") ? args.positiveNumber("--noise-quat", 0.0) : 0.0;
  noise.seed = static_cast<unsigned long long>(args.nonNegativeLong("--seed", 1));
  RecordingNoise noisy(simulation.columns(), noise);
  std::function<void(const std::vector<double>&)> sink;
  std::unique_ptr<CsvWriter> csv;
  if (csv_stream) {
    csv = std::make_unique<CsvWriter>(*csv_stream);
    csv->header(simulation.columns());
    sink = [&](const std::vector<double>& row) {
      if (!noise.any()) return csv->row(row);
      std::vector<double> r = row;
      noisy.apply(&r);
      csv->row(r);
    };
  }
  const SimulationResult result = simulation.run(options, sink);
  if (file.is_open()) {
    file.close();
    if (!file) throw InvalidInput(out_path, "write failed");
  }
  if (stats) std::cout << statsJson(result).dump() << "\n";
  if (result.failed) {
    std::cerr << "lieflow: simulation of " << simulation.scene().source << " with "
              << result.integrator << " failed: " << result.failure << "\n";
    return kComputationFailed;
  }
  return kSuccess;
}

}  // namespace app
}  // namespace lieflow
