/// \file
/// libFuzzer target: the bytes split at NUL into an argv for the command-line
/// reader (the options of `lieflow simulate`), then the typed values, the
/// --options list and the resource limits read from it. Each must return or
/// throw UsageError / InvalidInput (exit 2 in the command).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "app/arguments.hpp"
#include "app/cli.hpp"
#include "app/run_setup.hpp"
#include "liegroup/invalid_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::string> words(1);
  for (std::size_t i = 0; i < size; ++i) {
    if (data[i] == 0)
      words.emplace_back();
    else
      words.back() += static_cast<char>(data[i]);
  }
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(&w[0]);
  try {
    std::set<std::string> flags = {"--integrator", "--dt", "--t-end", "--out", "--every", "--options", "--seed",
                                   "--noise-gyro", "--integrators"};
    flags.insert(lieflow::app::runLimitFlags().begin(), lieflow::app::runLimitFlags().end());
    const lieflow::app::Arguments args(static_cast<int>(argv.size()), argv.data(), flags, {"--stats", "--quiet"});
    (void)args.positiveNumber("--dt", 1.0);
    (void)args.positiveInt("--every", 1);
    (void)args.nonNegativeLong("--seed", 1);
    (void)args.positiveNumbers("--integrators");
    (void)lieflow::app::parseOptionList(args.list("--options"));
    (void)lieflow::app::resourceLimitsFrom(args);
  } catch (const lieflow::app::UsageError&) {
  } catch (const lieflow::InvalidInput&) {
  }
  return 0;
}
