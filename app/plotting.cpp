#include "app/plotting.hpp"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <vector>

#ifndef LIEFLOW_SOURCE_DIR
#define LIEFLOW_SOURCE_DIR "."
#endif

namespace lieflow {
namespace app {
namespace {

/// `text` as one single-quoted shell word ('it'\''s'): a directory named
/// by the user cannot break out of the command.
std::string shellQuoted(const std::string& text) {
  std::string out = "'";
  for (const char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

/// The directory of the binary (executable or shared module) this code was
/// linked into, empty when unknown.
std::filesystem::path binaryDirectory() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&binaryDirectory), &info) == 0 || info.dli_fname == nullptr) return {};
  std::error_code error;
  const auto path = std::filesystem::canonical(info.dli_fname, error);
  return error ? std::filesystem::path() : path.parent_path();
}

}  // namespace

bool runPlotScript(const std::string& script_name, const std::string& dir, std::string* why) {
  // Where the scripts are, first found wins: $LIEFLOW_SCRIPTS_DIR; an
  // installed tree (PREFIX/bin/lieflow -> PREFIX/share/lieflow/scripts); the
  // source tree this build came from.
  std::vector<std::filesystem::path> candidates;
  if (const char* env_dir = std::getenv("LIEFLOW_SCRIPTS_DIR")) {
    candidates.emplace_back(env_dir);
  } else {
    const auto binary_dir = binaryDirectory();
    if (!binary_dir.empty()) candidates.push_back(binary_dir.parent_path() / "share" / "lieflow" / "scripts");
    candidates.emplace_back(std::string(LIEFLOW_SOURCE_DIR) + "/scripts");
  }
  std::string script;
  for (const auto& candidate : candidates) {
    if (std::filesystem::exists(candidate / script_name)) {
      script = (candidate / script_name).string();
      break;
    }
  }
  if (script.empty()) {
    *why = "plot script " + script_name + " not found in " + candidates.front().string() +
           (candidates.size() > 1 ? " or " + candidates.back().string() : std::string()) +
           " (set LIEFLOW_SCRIPTS_DIR)";
    return false;
  }
  // Debian's python3 has python3-matplotlib; a user's own python3 may not.
  const std::string python = std::filesystem::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  if (std::system((python + " -c 'import matplotlib' >/dev/null 2>&1").c_str()) != 0) {
    *why = "matplotlib is not installed (apt-get install python3-matplotlib)";
    return false;
  }
  const std::string command = python + " " + shellQuoted(script) + " " + shellQuoted(dir);
  if (std::system(command.c_str()) != 0) {
    *why = "the plot script failed: " + command;
    return false;
  }
  return true;
}

}  // namespace app
}  // namespace lieflow
