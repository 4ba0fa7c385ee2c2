#include "app/simulate_request.hpp"

#include <utility>
#include <vector>

#include "app/cli.hpp"
#include "app/run_setup.hpp"

namespace lieflow {
namespace app {
namespace {

/// The noise options; noise on columns the scene does not have is an error.
NoiseOptions noiseFrom(const Arguments& args, const std::vector<std::string>& columns) {
  NoiseOptions noise;
  noise.gyro = args.has("--noise-gyro") ? args.positiveNumber("--noise-gyro", 0.0) : 0.0;
  noise.angle = args.has("--noise-angle") ? args.positiveNumber("--noise-angle", 0.0) : 0.0;
  noise.quaternion = args.has("--noise-quat") ? args.positiveNumber("--noise-quat", 0.0) : 0.0;
  noise.acc = args.has("--noise-acc") ? args.positiveNumber("--noise-acc", 0.0) : 0.0;
  noise.gyro_bias = args.has("--bias-gyro") ? args.positiveNumber("--bias-gyro", 0.0) : 0.0;
  noise.seed = static_cast<unsigned long long>(args.nonNegativeLong("--seed", 1));
  const RecordingNoise probe(columns, noise);
  if (noise.acc > 0.0 && !probe.hasAccelerometerColumns())
    throw UsageError("--noise-acc: the rows have no accelerometer columns (B.ax, B.ay, B.az): add --imu");
  if (noise.angle > 0.0 && !probe.hasAngleColumns())
    throw UsageError("--noise-angle: the scene has no joint angle columns (J.phi, J.phi1, J.phi2) to perturb");
  if (args.has("--seed") && !noise.any())
    throw UsageError("--seed seeds the noise generator: give a --noise-* option too");
  return noise;
}

}  // namespace

std::unique_ptr<Simulation> simulationFrom(const Arguments& args, std::optional<SceneDescription> scene,
                                           const std::string& command) {
  if (scene) {
    if (!args.positional().empty()) throw UsageError(command + ": give the scene once");
    return std::make_unique<Simulation>(std::move(*scene));
  }
  if (args.positional().size() != 1)
    throw UsageError(command + " needs exactly one SCENE (see lieflow " + command + " --help)");
  return std::make_unique<Simulation>(sceneFrom(args, args.positional()[0]));
}

const std::set<std::string>& simulateValueFlags() {
  static const std::set<std::string> flags = [] {
    std::set<std::string> f = {"--integrator", "--dt",         "--t-end",       "--out",        "--every",
                               "--check-every", "--options",    "--formulation", "--noise-gyro", "--noise-angle", "--noise-quat", "--seed",
                               "--noise-acc",  "--bias-gyro", "--view"};
    f.insert(runLimitFlags().begin(), runLimitFlags().end());
    return f;
  }();
  return flags;
}

const std::set<std::string>& simulateSwitches() {
  static const std::set<std::string> switches = [] {
    std::set<std::string> s = {"--stats", "--quiet", "--imu"};
    s.insert(modelSwitches().begin(), modelSwitches().end());
    return s;
  }();
  return switches;
}

SimulateRequest simulateRequestFrom(const Arguments& args, std::optional<SceneDescription> scene) {
  SimulateRequest request;
  request.simulation = simulationFrom(args, std::move(scene), "simulate");
  request.options = simulationOptionsFrom(request.simulation->scene(), args);
  request.options.every = args.positiveInt("--every", 1);
  request.options.check_every = args.positiveInt("--check-every", 0);
  request.options.imu = args.has("--imu");
  request.noise = noiseFrom(args, request.simulation->columns(request.options.imu));
  return request;
}

}  // namespace app
}  // namespace lieflow
