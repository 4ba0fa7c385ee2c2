/// \file
/// Resolution of the run settings of a command from its flags and the scene:
/// a flag wins over the scene's value; a setting that neither gives is an
/// error naming both places.
#pragma once

#include <nlohmann/json.hpp>

#include "app/arguments.hpp"
#include "app/flag_spelling.hpp"
#include "simulation/simulation.hpp"

namespace lieflow {
namespace app {

/// The integrator a scene that names none runs with (named on stderr and in
/// --stats): fourth order, explicit, on the joints' groups.
inline constexpr const char* kDefaultIntegrator = "rkmk4";
/// MuJoCo's default <option timestep>, the step its users know.
inline constexpr double kDefaultStep = 0.002;
/// The default step is at most this over the scene's fastest angular rate
/// (spin, or a spring's √(k/I)): h·ω = 0.05 keeps rkmk4's error per period
/// near (hω)⁴ ≈ 6e-6 and far from its stability limit h·ω ≈ 2.8.
inline constexpr double kDefaultStepTimesFrequency = 0.05;

/// The step of a scene that gives none: min(kDefaultStep,
/// kDefaultStepTimesFrequency / ω), rounded down to 1, 2 or 5 × 10^k.
double defaultStep(const SceneDescription& scene);

/// Integrator, dt, t_end and options for `scene` given --integrator, --dt,
/// --t-end and --options. The scene's integrator options apply only when the
/// integrator is the scene's own.
SimulationOptions simulationOptionsFrom(const SceneDescription& scene, const Arguments& args);

/// The `--stats` JSON object of a run (keys of ../shared/DESIGN.md; null
/// where a figure does not apply: momentum_drift when the scene does not
/// conserve momentum, newton_iterations_mean for explicit methods, both drift
/// figures when the run failed).
nlohmann::ordered_json statsJson(const SimulationResult& result);

/// `j` as one line of JSON, as every command prints its result; bytes that
/// are not UTF-8 (a name taken from a file) are replaced, never thrown on;
/// the library's `option` names spelled as flags (flag_spelling.hpp).
inline std::string jsonLine(const nlohmann::ordered_json& j) {
  return spellFlagsIn(j).dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

/// Parses "k=v,k=v" into a map; UsageError naming --options if malformed.
std::map<std::string, double> parseOptionList(const std::vector<std::string>& items);

/// The options of one integrator in a study or stability scan: the scene's
/// own (when it is the scene's integrator), then those of `command_line`
/// that this integrator accepts (recorded in command_line_options).
void applyIntegratorOptions(const SceneDescription& scene, const std::map<std::string, double>& command_line,
                            SimulationOptions* options);

/// Every --options key must be accepted by at least one of `integrators`
/// (UsageError naming the key otherwise).
void checkOptionKeysUsed(const std::map<std::string, double>& command_line,
                         const std::vector<std::string>& integrators);

/// "rho_inf=1, tolerance=1e-12, max_iterations=20": every option of the
/// integrator with the value in force (defaults filled in); "" if it has none.
std::string describeOptions(const SimulationOptions& options);

}  // namespace app
}  // namespace lieflow
