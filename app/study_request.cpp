#include "app/study_request.hpp"

#include <utility>

#include "app/cli.hpp"
#include "app/run_setup.hpp"
#include "app/simulate_request.hpp"
#include "model/import/model_import.hpp"

namespace lieflow {
namespace app {
namespace {

std::set<std::string> withRunLimits(std::set<std::string> flags) {
  flags.insert(runLimitFlags().begin(), runLimitFlags().end());
  return flags;
}

std::set<std::string> withModelSwitches(std::set<std::string> switches) {
  switches.insert(modelSwitches().begin(), modelSwitches().end());
  return switches;
}

}  // namespace

const std::set<std::string>& studyValueFlags() {
  static const std::set<std::string> flags =
      withRunLimits({"--integrators", "--dt", "--t-end", "--out", "--min-time", "--options", "--formulation"});
  return flags;
}

const std::set<std::string>& studySwitches() {
  static const std::set<std::string> switches = withModelSwitches({"--no-plots", "--with-mujoco", "--view"});
  return switches;
}

StudyRequest studyRequestFrom(const Arguments& args, std::optional<SceneDescription> scene) {
  const ResourceLimits limits = resourceLimitsFrom(args);
  StudyRequest request;
  request.simulation = simulationFrom(args, std::move(scene), "study");
  const SceneDescription& s = request.simulation->scene();
  StudyOptions& options = request.options;
  options.max_steps = limits.max_steps;
  options.integrator_options = parseOptionList(args.list("--options"));
  options.integrators = args.list("--integrators");
  options.formulation = args.value("--formulation", "");
  options.dts = args.positiveNumbers("--dt");
  options.out_dir = args.value("--out", "study-" + s.name);
  options.min_timing_seconds = args.positiveNumber("--min-time", options.min_timing_seconds);
  options.plots = !args.has("--no-plots");
  if (args.has("--with-mujoco")) {
    // MuJoCo reads the model file itself (MJCF, or URDF through its own
    // URDF reader): a scene given as JSON (Python) or a JSON or built-in
    // scene has no model file to give it.
    const std::string model = args.positional().empty() ? std::string() : args.positional().front();
    if (model.empty() || !isModelFile(model))
      throw UsageError("--with-mujoco: MuJoCo runs beside lieflow on a model file (SCENE ending in .xml or .urdf), "
                       "not on '" +
                       (model.empty() ? std::string("a scene given as JSON") : model) + "'");
    options.mujoco_model = model;
    options.mujoco_import = modelImportOptionsFrom(args, model);
  }
  request.t_end = args.positiveNumber("--t-end", s.has_t_end ? s.t_end : 0.0);
  if (!(request.t_end > 0.0)) throw UsageError("the scene has no t_end: give --t-end");
  return request;
}

const std::set<std::string>& stabilityValueFlags() {
  static const std::set<std::string> flags = withRunLimits({"--integrators", "--out", "--options", "--formulation"});
  return flags;
}

const std::set<std::string>& stabilitySwitches() {
  static const std::set<std::string> switches = withModelSwitches({"--no-plots"});
  return switches;
}

StabilityRequest stabilityRequestFrom(const Arguments& args, std::vector<SceneDescription> scenes) {
  const ResourceLimits limits = resourceLimitsFrom(args);
  StabilityRequest request;
  request.options.integrators = args.list("--integrators");
  request.options.formulation = args.value("--formulation", "");
  request.options.integrator_options = parseOptionList(args.list("--options"));
  request.options.max_steps = limits.max_steps;
  request.out_dir = args.value("--out", "stability");
  request.plots = !args.has("--no-plots");
  if (!scenes.empty()) {
    if (!args.positional().empty()) throw UsageError("stability: give the scenes once");
    for (SceneDescription& scene : scenes) request.simulations.emplace_back(std::move(scene));
    return request;
  }
  std::vector<std::string> names = args.positional();
  if (names.empty()) names = {"stiff-spring", "fast-top"};
  for (const std::string& name : names) request.simulations.emplace_back(sceneFrom(args, name));
  return request;
}

std::vector<StabilityRow> runStability(const StabilityRequest& request) {
  std::vector<StabilityRow> rows;
  for (const Simulation& sim : request.simulations) {
    const std::vector<StabilityRow> r = runStability(sim, request.options);
    rows.insert(rows.end(), r.begin(), r.end());
  }
  return rows;
}

}  // namespace app
}  // namespace lieflow
