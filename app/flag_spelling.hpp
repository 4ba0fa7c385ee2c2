/// \file
/// The library names an option as its member in backquotes ("`max_steps`",
/// liegroup/invalid_input.hpp); the command line, and the Python module
/// whose functions take the same flags, spell it as the flag: --max-steps.
/// Every text the library writes passes through here before a user reads it
/// (errors, the JSON lines, a study's failures, the integrator list).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace lieflow {
namespace app {

/// `text` with every backquoted lower-case name (`fit_gyro_bias`) written as
/// its flag (--fit-gyro-bias); other backquotes are left as they are.
std::string spellFlags(const std::string& text);

/// The same for every string of `j`, keys left as they are.
nlohmann::ordered_json spellFlagsIn(nlohmann::ordered_json j);

}  // namespace app
}  // namespace lieflow
