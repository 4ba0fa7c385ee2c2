/// \file
/// The test models of tests/data/models/ and the refusal of a model file,
/// for the model import tests (model_import_test.cpp, mujoco_peer_test.cpp).
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "model/import/model_import.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {
namespace scene_testing {

/// tests/data/models/FILE.
inline std::string model(const std::string& file) {
  return std::string(LIEFLOW_SOURCE_DIR) + "/tests/data/models/" + file;
}

/// InvalidInput's message for importing `path` (fails the test if accepted).
inline std::string refusal(const std::string& path, const ModelImportOptions& options = ModelImportOptions()) {
  try {
    importModel(path, options);
    ADD_FAILURE() << "accepted: " << path;
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "";
}

}  // namespace scene_testing
}  // namespace lieflow
