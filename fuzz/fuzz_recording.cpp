/// \file
/// libFuzzer target: any bytes as a recording CSV. parseRecording must
/// return a recording or throw lieflow::InvalidInput.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "calibration/recording.hpp"
#include "liegroup/invalid_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try {
    const lieflow::calibration::Recording r = lieflow::calibration::parseRecording(in, "fuzz.csv", 10000);
    (void)r.bodyList();
  } catch (const lieflow::InvalidInput&) {
  }
  return 0;
}
