/// \file
/// libFuzzer target: any bytes as a scene file. parseScene must return a
/// scene or throw lieflow::InvalidInput; anything else (a crash, another
/// exception, a sanitizer report, a hang) is a finding.
#include <cstddef>
#include <cstdint>
#include <string>

#include "model/scene.hpp"
#include "liegroup/invalid_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const lieflow::SceneDescription scene = lieflow::parseScene(text, "fuzz.json", /*max_bodies=*/1000);
    (void)scene.bodyIndices();
  } catch (const lieflow::InvalidInput&) {
  }
  return 0;
}
