/// \file
/// libFuzzer target: any bytes as a model file, read by the importer with
/// its library (MuJoCo's compiler for fuzz_mjcf, urdfdom for fuzz_urdf;
/// LIEFLOW_FUZZ_MODEL_SUFFIX says which). importModel must return a scene or
/// throw lieflow::InvalidInput; anything else (a crash, another exception, a
/// sanitizer report, a hang, memory beyond the fuzzer's limit) is a finding.
/// The bytes are written to a file of this process first: both libraries
/// read models from paths (MJCF includes and meshes resolve beside it).
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <string>

#include "model/import/model_import.hpp"
#include "liegroup/invalid_input.hpp"

namespace {

const std::string& modelPath() {
  static const std::string path = "/tmp/lieflow-fuzz-" + std::to_string(getpid()) + LIEFLOW_FUZZ_MODEL_SUFFIX;
  return path;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  {
    std::ofstream file(modelPath(), std::ios::binary | std::ios::trunc);
    file.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  lieflow::ModelImportOptions options = lieflow::parseIgnoreList("all");
  lieflow::ResourceLimits limits;
  limits.max_input_bytes = 1 << 20;  // includes and assets count too
  limits.max_bodies = limits.max_mjcf_bodies = 500;
  try {
    const lieflow::SceneDescription scene = lieflow::importModel(modelPath(), options, limits);
    (void)scene.bodyIndices();
  } catch (const lieflow::InvalidInput&) {
  }
  return 0;
}
