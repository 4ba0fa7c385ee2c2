#include "app/arguments.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>

#include "app/cli.hpp"
#include "app/flag_spelling.hpp"
#include "model/import/model_import.hpp"
#include "liegroup/input_number.hpp"

namespace lieflow {
namespace app {

Arguments::Arguments(int argc, char** argv, const std::set<std::string>& value_flags,
                     const std::set<std::string>& switches) {
  for (int i = 0; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      help_ = true;
    } else if (arg.rfind("--", 0) == 0) {
      std::string flag = arg, value;
      const auto eq = arg.find('=');
      const bool inline_value = eq != std::string::npos;
      if (inline_value) {
        flag = arg.substr(0, eq);
        value = arg.substr(eq + 1);
      }
      if (switches.count(flag)) {
        if (inline_value) throw UsageError(flag + " takes no value");
        switches_set_.insert(flag);
      } else if (value_flags.count(flag)) {
        if (!inline_value) {
          if (i + 1 >= argc) throw UsageError(flag + ": missing value");
          const std::string next = argv[i + 1];
          if (value_flags.count(next) || switches.count(next) || next == "--help")
            throw UsageError(flag + ": missing value (the next word, " + next + ", is an option)");
          value = argv[++i];
        }
        if (values_.count(flag)) throw UsageError(flag + " given twice");
        if (value.empty()) throw UsageError(flag + ": empty value");
        values_[flag] = value;
      } else {
        throw UsageError("unknown option '" + flag + "'");
      }
    } else {
      positional_.push_back(arg);
    }
  }
}

bool Arguments::has(const std::string& flag) const {
  return values_.count(flag) > 0 || switches_set_.count(flag) > 0;
}

std::string Arguments::value(const std::string& flag, const std::string& fallback) const {
  const auto it = values_.find(flag);
  return it == values_.end() ? fallback : it->second;
}

std::string quotedValue(const std::string& text) {
  constexpr std::size_t kShown = 40;
  return "'" + (text.size() <= kShown ? text : text.substr(0, kShown) + "…") + "'";
}

double parseNumber(const std::string& what, const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0') throw UsageError(what + ": expected a number, got " + quotedValue(text));
  if (const std::string problem = inputNumberProblem(v); !problem.empty())
    throw UsageError(what + ": " + quotedValue(text) + " " +
                     (std::isfinite(v) ? problem.substr(problem.find(" is beyond") + 1) : std::string("is not finite")));
  return v;
}

double parsePositiveNumber(const std::string& what, const std::string& text) {
  const double v = parseNumber(what, text);
  if (!(v > 0.0)) throw UsageError(what + ": expected a positive number, got " + quotedValue(text));
  return v;
}

double Arguments::positiveNumber(const std::string& flag, double fallback) const {
  if (!values_.count(flag)) return fallback;
  return parsePositiveNumber(flag, values_.at(flag));
}

/// The largest value positiveInt takes (an int's range, rounded down).
constexpr long kMaxPositiveInt = 1000000000;

int Arguments::positiveInt(const std::string& flag, int fallback) const {
  if (!values_.count(flag)) return fallback;
  const std::string& text = values_.at(flag);
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno == ERANGE || v < 1 || v > kMaxPositiveInt)
    throw UsageError(flag + ": expected an integer from 1 to " + std::to_string(kMaxPositiveInt) + ", got " +
                     quotedValue(text));
  return static_cast<int>(v);
}

long Arguments::nonNegativeLong(const std::string& flag, long fallback) const {
  return boundedLong(flag, fallback, 0, std::numeric_limits<long>::max());
}

long Arguments::boundedLong(const std::string& flag, long fallback, long min, long max) const {
  if (!values_.count(flag)) return fallback;
  const std::string& text = values_.at(flag);
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno == ERANGE || v < min || v > max)
    throw UsageError(flag + ": expected an integer from " + std::to_string(min) + " to " + std::to_string(max) +
                     ", got " + quotedValue(text));
  return v;
}

const std::set<std::string>& modelSwitches() {
  static const std::set<std::string> switches = {"--floating-base", "--verbose"};
  return switches;
}

const std::set<std::string>& runLimitFlags() {
  static const std::set<std::string> flags = {"--max-steps", "--max-input-mb", "--max-bodies", "--ignore",
                                              "--keyframe", "--spin"};
  return flags;
}

ModelImportOptions modelImportOptionsFrom(const Arguments& args, const std::string& scene) {
  ModelImportOptions import = parseIgnoreList(args.value("--ignore", ""));
  if (!import.ignore.empty() && !isModelFile(scene))
    throw UsageError("--ignore: '" + scene + "' is not a model file (.xml, .urdf); only models have parts to ignore");
  import.keyframe = args.value("--keyframe", "");
  if (args.has("--keyframe") && import.keyframe.empty()) throw UsageError("--keyframe: expected a keyframe name or index");
  if (!import.keyframe.empty() && !isModelFile(scene))
    throw UsageError("--keyframe: '" + scene + "' is not an MJCF model (.xml); only MJCF models have keyframes");
  import.floating_base = args.has("--floating-base");
  if (import.floating_base && !isUrdfFile(scene))
    throw UsageError("--floating-base: '" + scene + "' is not a URDF (.urdf); a scene or an MJCF model says "
                     "which bodies are free itself");
  if (args.has("--spin")) {
    if (!isModelFile(scene))
      throw UsageError("--spin: '" + scene + "' is not a model file (.xml, .urdf); a scene file gives its bodies' "
                       "velocities itself");
    const std::string text = args.value("--spin", "");
    const std::vector<std::string> values = text.empty() ? std::vector<std::string>{} : args.list("--spin");
    if (values.size() != 3 || text.back() == ',')
      throw UsageError("--spin: expected three numbers WX,WY,WZ (rad/s, world axes), got " + quotedValue(text));
    for (int i = 0; i < 3; ++i) import.spin[i] = parseNumber("--spin", values[i]);
    import.has_spin = true;
  }
  return import;
}

std::vector<std::string> summarizedNotes(const std::vector<std::string>& notes, bool verbose) {
  if (verbose) return notes;
  // "ignored CATEGORY: ELEMENT" notes, one line per category in the order
  // the categories first appear; the other notes as they are.
  constexpr std::size_t kNamesShown = 3;
  const std::string prefix = "ignored ";
  std::vector<std::string> out, order;
  std::map<std::string, std::vector<std::string>> elements;
  for (const std::string& note : notes) {
    const std::size_t colon = note.find(": ");
    if (note.rfind(prefix, 0) != 0 || colon == std::string::npos) {
      out.push_back(note);
      continue;
    }
    const std::string category = note.substr(prefix.size(), colon - prefix.size());
    if (!elements.count(category)) order.push_back(category);
    elements[category].push_back(note.substr(colon + 2));
  }
  std::vector<std::string> summary;
  for (const std::string& category : order) {
    const std::vector<std::string>& e = elements[category];
    std::string line = prefix + category + ": " + std::to_string(e.size()) + (e.size() == 1 ? " element (" : " elements (");
    for (std::size_t i = 0; i < std::min(e.size(), kNamesShown); ++i) line += (i ? ", " : "") + e[i];
    if (e.size() > kNamesShown) line += ", and " + std::to_string(e.size() - kNamesShown) + " more; --verbose lists them";
    summary.push_back(line + ")");
  }
  summary.insert(summary.end(), out.begin(), out.end());
  return summary;
}

SceneDescription sceneFrom(const Arguments& args, const std::string& scene) {
  SceneDescription s = loadScene(scene, resourceLimitsFrom(args), modelImportOptionsFrom(args, scene));
  for (const std::string& note : summarizedNotes(s.import_notes, args.has("--verbose")))
    std::cerr << "lieflow: " << scene << ": " << spellFlags(note) << "\n";
  return s;
}

ResourceLimits resourceLimitsFrom(const Arguments& args) {
  constexpr long kMaxLimit = std::numeric_limits<long>::max() / 2;
  ResourceLimits limits;
  limits.max_steps = args.boundedLong("--max-steps", limits.max_steps, 1, kMaxLimit);
  const long mb = args.boundedLong("--max-input-mb", static_cast<long>(limits.max_input_bytes >> 20), 1, 1L << 40);
  limits.max_input_bytes = static_cast<std::uint64_t>(mb) << 20;
  limits.max_bodies = args.boundedLong("--max-bodies", limits.max_bodies, 1, kMaxLimit);
  if (args.has("--max-bodies")) limits.max_mjcf_bodies = limits.max_bodies;
  limits.max_rows = args.boundedLong("--max-rows", limits.max_rows, 1, kMaxLimit);
  limits.max_substeps = args.boundedLong("--max-substeps", limits.max_substeps, 1, kMaxLimit);
  return limits;
}

std::vector<std::string> Arguments::list(const std::string& flag) const {
  std::vector<std::string> out;
  if (!values_.count(flag)) return out;
  std::stringstream s(values_.at(flag));
  std::string item;
  while (std::getline(s, item, ',')) {
    if (item.empty()) throw UsageError(flag + ": empty entry in '" + values_.at(flag) + "'");
    out.push_back(item);
  }
  if (out.empty()) throw UsageError(flag + ": expected a comma-separated list");
  return out;
}

std::vector<double> Arguments::positiveNumbers(const std::string& flag) const {
  std::vector<double> out;
  for (const std::string& item : list(flag)) out.push_back(parsePositiveNumber(flag, item));
  return out;
}

}  // namespace app
}  // namespace lieflow
