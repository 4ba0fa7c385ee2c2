/// \file
/// The two model readers behind importModel (model_import.hpp). Each turns a
/// file into a ModelDescription (model_description.hpp) at the model's
/// reference configuration, or throws InvalidInput naming the file, the
/// element and its line. Built with its library (urdfdom, MuJoCo) when found;
/// otherwise it refuses the format naming the Debian package to install.
#pragma once

#include <string>
#include <vector>

#include "model/import/model_description.hpp"
#include "model/import/model_import.hpp"

namespace lieflow {
namespace model_import {

/// The elements of a model that lieflow cannot represent, by category
/// (ignorableFeatures()): each reader lists them, then resolve() refuses the
/// model naming all of them, or, for the categories the user lets go,
/// records them in ModelDescription::ignored.
class UnsupportedFeatures {
 public:
  /// `element` as elementLabel() writes it ("geom 'floor' (line 12)").
  void add(const std::string& category, const std::string& element) { items_.push_back({category, element}); }
  /// Throws InvalidInput (field: the file) listing every element of a
  /// category not in options.ignore and the --ignore that would drop them;
  /// otherwise appends "CATEGORY: ELEMENT" lines to model->ignored.
  void resolve(const ModelImportOptions& options, ModelDescription* model) const;

 private:
  struct Item {
    std::string category, element;
  };
  std::vector<Item> items_;
};

/// A URDF robot (urdf_import.cpp). The root link is the ground (a fixed
/// base) unless a `floating` joint frees a link; the reference configuration
/// is every joint coordinate at 0.
ModelDescription readUrdf(const std::string& text, const std::string& path, const ModelImportOptions& options);

/// An MJCF model compiled by MuJoCo (mjcf_import.cpp) from `path` (its
/// includes and meshes are found relative to it); `text` is the file's
/// contents, read for element lines. The reference configuration is qpos0.
/// Its files are checked first, before the compiler runs (checkMjcfFiles,
/// mjcf_files.hpp): their size, the bodies they declare, their numbers.
ModelDescription readMjcf(const std::string& text, const std::string& path, const ModelImportOptions& options,
                          const ResourceLimits& limits);

}  // namespace model_import
}  // namespace lieflow
