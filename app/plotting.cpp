#include "app/plotting.hpp"

#include <cstdlib>
#include <filesystem>

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

}  // namespace

bool runPlotScript(const std::string& script_name, const std::string& dir, std::string* why) {
  const char* env_dir = std::getenv("LIEFLOW_SCRIPTS_DIR");
  const std::string script =
      (env_dir ? std::string(env_dir) : std::string(LIEFLOW_SOURCE_DIR) + "/scripts") + "/" + script_name;
  if (!std::filesystem::exists(script)) {
    *why = "plot script " + script + " not found (set LIEFLOW_SCRIPTS_DIR)";
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
