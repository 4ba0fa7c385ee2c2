/// \file
/// Plots are drawn by the Python scripts in scripts/ with Debian's python3 and
/// matplotlib (python3-matplotlib, installed by scripts/setup.sh).
#pragma once

#include <string>

namespace lieflow {
namespace app {

/// Runs scripts/SCRIPT DIR (or $LIEFLOW_SCRIPTS_DIR/SCRIPT). Returns false and
/// says why when the script, python3 or matplotlib is missing or it fails.
bool runPlotScript(const std::string& script, const std::string& dir, std::string* why);

}  // namespace app
}  // namespace lieflow
