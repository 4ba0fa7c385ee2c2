#include "app/run_setup.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>

#include "app/arguments.hpp"
#include "app/cli.hpp"
#include "integrators/registry.hpp"
#include "model/scene_time_scale.hpp"
#include "liegroup/invalid_input.hpp"
#include "liegroup/number_text.hpp"

namespace lieflow {
namespace app {

std::map<std::string, double> parseOptionList(const std::vector<std::string>& items) {
  std::map<std::string, double> out;
  for (const std::string& item : items) {
    const auto eq = item.find('=');
    if (eq == std::string::npos || eq == 0)
      throw UsageError("--options: expected KEY=VALUE, got '" + item + "'");
    const std::string key = item.substr(0, eq);
    const double v = parseNumber("--options: " + key, item.substr(eq + 1));
    if (out.count(key)) throw UsageError("--options: " + key + " given twice");
    out[key] = v;
  }
  return out;
}

nlohmann::ordered_json statsJson(const SimulationResult& r) {
  nlohmann::ordered_json j;
  j["integrator"] = r.integrator;
  j["formulation"] = r.formulation;
  j["dt"] = r.dt;
  j["steps"] = r.steps;
  j["checked_every"] = r.checked_every;
  j["wall_seconds"] = r.wall_seconds;
  j["ns_per_step"] = r.ns_per_step;
  // A failed run has no meaningful drift: null rather than a reassuring 0.
  const nlohmann::ordered_json none(nullptr);
  j["energy_drift"] = r.failed ? none : nlohmann::ordered_json(r.energy_drift);
  j["momentum_drift"] = r.momentum_conserved && !r.failed ? nlohmann::ordered_json(r.momentum_drift) : none;
  j["constraint_error"] = r.constraint_error;
  j["newton_iterations_mean"] = r.implicit ? nlohmann::ordered_json(r.newton_iterations_mean) : nlohmann::ordered_json(nullptr);
  // Each conserved quantity of the scene with its maximal relative drift
  // (simulation/invariants.hpp); null values when the run failed.
  nlohmann::ordered_json invariants = nlohmann::ordered_json::object();
  for (const auto& inv : r.invariants) invariants[inv.first] = r.failed ? none : nlohmann::ordered_json(inv.second);
  j["invariants"] = invariants;
  j["failed"] = r.failed;
  j["failure"] = r.failure;
  if (r.rejected_steps > 0) j["rejected_steps"] = r.rejected_steps;
  if (r.substepped_steps > 0) j["substepped_steps"] = r.substepped_steps;
  return j;
}

void applyIntegratorOptions(const SceneDescription& scene, const std::map<std::string, double>& command_line,
                            SimulationOptions* o) {
  if (scene.has_integrator && scene.integrator.name == o->integrator) o->integrator_options = scene.integrator.options;
  const IntegratorInfo* info = findIntegrator(o->integrator);
  for (const auto& kv : command_line)
    if (info && info->option(kv.first)) {
      o->integrator_options[kv.first] = kv.second;
      o->command_line_options.insert(kv.first);
    }
}

void checkOptionKeysUsed(const std::map<std::string, double>& command_line,
                         const std::vector<std::string>& integrators) {
  for (const auto& kv : command_line) {
    bool used = false;
    for (const std::string& name : integrators) {
      const IntegratorInfo* info = findIntegrator(name);
      used = used || (info && info->option(kv.first));
    }
    if (!used) throw UsageError("--options: no integrator of this run takes '" + kv.first + "' (see lieflow integrators)");
  }
}

std::string describeOptions(const SimulationOptions& o) {
  const IntegratorInfo* info = findIntegrator(o.integrator);
  std::string text;
  if (!info) return text;
  for (const IntegratorOption& opt : info->options) {
    const auto it = o.integrator_options.find(opt.name);
    char value[32];
    std::snprintf(value, sizeof value, "%g", it == o.integrator_options.end() ? opt.default_value : it->second);
    text += (text.empty() ? "" : ", ") + opt.name + "=" + value;
  }
  return text;
}

double defaultStep(const SceneDescription& scene) {
  double h = kDefaultStep;
  try {
    h = std::min(h, kDefaultStepTimesFrequency / characteristicFrequency(scene));
  } catch (const InvalidInput&) {
    // No spin and no spring: MuJoCo's step stands.
  }
  // Rounded down to 1, 2 or 5 times a power of ten, a step a user can read.
  const double decade = std::pow(10.0, std::floor(std::log10(h)));
  for (const double m : {5.0, 2.0, 1.0})
    if (m * decade <= h) return m * decade;
  return decade;
}

SimulationOptions simulationOptionsFrom(const SceneDescription& scene, const Arguments& args) {
  SimulationOptions o;
  o.integrator = args.value("--integrator", scene.has_integrator ? scene.integrator.name : "");
  // A scene (a URDF, a JSON scene) that names no integrator runs with the
  // default, and says so: the step too when the scene has none.
  const bool default_integrator = o.integrator.empty();
  if (default_integrator) o.integrator = kDefaultIntegrator;
  if (scene.has_integrator && scene.integrator.name == o.integrator)
    o.integrator_options = scene.integrator.options;
  for (const auto& kv : parseOptionList(args.list("--options"))) {
    o.integrator_options[kv.first] = kv.second;
    o.command_line_options.insert(kv.first);
  }
  o.max_steps = resourceLimitsFrom(args).max_steps;
  o.formulation = args.value("--formulation", "");
  o.dt = args.positiveNumber("--dt", scene.has_integrator ? scene.integrator.dt : 0.0);
  const bool default_step = !(o.dt > 0.0);
  if (default_step) {
    o.dt = defaultStep(scene);
    o.dt_source = "the default step";
  } else if (!args.has("--dt")) {
    o.dt_source = scene.source + ": integrator.dt";
  }
  if (default_integrator || default_step) {
    std::ostringstream note;
    note << "lieflow: " << scene.source << " names no " << (default_integrator ? "integrator" : "step") << ": running "
         << o.integrator << " at dt = " << formatNumber(o.dt) << " s (the default";
    if (default_step)
      note << ": MuJoCo's step, or " << kDefaultStepTimesFrequency << "/omega for a faster spin or spring";
    note << "; " << (default_integrator ? "--integrator and " : "") << "--dt choose)\n";
    std::cerr << note.str();
  }
  o.t_end = args.positiveNumber("--t-end", scene.has_t_end ? scene.t_end : 0.0);
  if (!(o.t_end > 0.0))
    throw InvalidInput(scene.source + ": t_end", "missing (give --t-end or t_end in the scene)");
  if (!args.has("--t-end")) o.t_end_source = scene.source + ": t_end";
  return o;
}

}  // namespace app
}  // namespace lieflow
