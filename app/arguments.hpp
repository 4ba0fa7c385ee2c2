/// \file
/// A strict command-line reader: positional arguments plus `--flag value` and
/// `--switch` options from a declared set; anything else is a usage error
/// (exit status 2) that names the option.
#pragma once

#include <map>
#include <set>
#include <string>
#include <vector>

#include "model/import/import_options.hpp"
#include "model/resource_limits.hpp"
#include "model/scene.hpp"

namespace lieflow {
namespace app {

class Arguments {
 public:
  /// `value_flags` take a value, `switches` do not. "--help"/"-h" is always known.
  Arguments(int argc, char** argv, const std::set<std::string>& value_flags,
            const std::set<std::string>& switches);

  bool help() const { return help_; }
  const std::vector<std::string>& positional() const { return positional_; }
  bool has(const std::string& flag) const;
  std::string value(const std::string& flag, const std::string& fallback) const;

  /// Typed values; a malformed value is a UsageError naming the flag.
  double positiveNumber(const std::string& flag, double fallback) const;
  int positiveInt(const std::string& flag, int fallback) const;
  long nonNegativeLong(const std::string& flag, long fallback) const;
  std::vector<std::string> list(const std::string& flag) const;
  std::vector<double> positiveNumbers(const std::string& flag) const;
  /// A non-negative integer no larger than `max` (overflow and fractions are
  /// errors naming the flag).
  long boundedLong(const std::string& flag, long fallback, long min, long max) const;

 private:
  bool help_ = false;
  std::vector<std::string> positional_;
  std::map<std::string, std::string> values_;
  std::set<std::string> switches_set_;
};

/// `text` quoted for a message, cut to its first 40 characters ("'1000…'").
std::string quotedValue(const std::string& text);

/// Parses a number as every command-line number is read: the whole text,
/// finite and within ±kMaxInputMagnitude (liegroup/input_number.hpp); a
/// UsageError naming `what` otherwise.
double parseNumber(const std::string& what, const std::string& text);

/// parseNumber, and positive.
double parsePositiveNumber(const std::string& what, const std::string& text);

/// The resource limits (model/resource_limits.hpp) raised by the options
/// --max-steps, --max-input-mb, --max-bodies, --max-rows, --max-substeps,
/// where `args` has them.
ResourceLimits resourceLimitsFrom(const Arguments& args);
/// The limit flags of the commands that run scenes (simulate, study,
/// stability): --max-steps, --max-input-mb, --max-bodies, --ignore (what a
/// model file may leave out) and --keyframe (an MJCF keyframe as the start).
const std::set<std::string>& runLimitFlags();
/// The switches of the commands that read model files (simulate, study,
/// stability, import): --floating-base (a URDF's root on a free joint).
const std::set<std::string>& modelSwitches();

/// How SCENE is imported when it is a model file: the --ignore list, the
/// --keyframe and --floating-base of `args` (UsageError when SCENE is not a
/// model file, or for --floating-base not a URDF).
ModelImportOptions modelImportOptionsFrom(const Arguments& args, const std::string& scene);

/// An import's notes as the command prints them: the "ignored CATEGORY:
/// ELEMENT" notes one line per category with their count and first three
/// elements ("ignored contacts: 42 elements (geom 'floor' (line 12), ...,
/// and 39 more; --verbose lists them)"), then the other notes; with
/// `verbose` every note as it is.
std::vector<std::string> summarizedNotes(const std::vector<std::string>& notes, bool verbose);

/// SCENE (a built-in name, a JSON file or a model file) with the limits,
/// the --ignore list and the --keyframe of `args`; what a model import left
/// out is printed to stderr (summarizedNotes; every element with --verbose).
SceneDescription sceneFrom(const Arguments& args, const std::string& scene);

}  // namespace app
}  // namespace lieflow
