/// \file
/// What a model importer may leave out (`--ignore`): model_import.hpp.
#pragma once

#include <set>
#include <string>

namespace lieflow {

struct ModelImportOptions {
  /// Feature categories (ignorableFeatures(), model_import.hpp) the importer
  /// may leave out; each left-out element is listed in the scene's import_notes.
  std::set<std::string> ignore;
  bool ignores(const std::string& category) const { return ignore.count(category) > 0; }
};

}  // namespace lieflow
