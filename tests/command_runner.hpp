/// \file
/// Runs the built `lieflow` command as a user or a script would and
/// collects its exit status (or the signal that ended it), stdout and stderr.
/// Output files are named after the running test, since ctest runs tests in
/// parallel processes.
#pragma once

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

namespace lieflow {
namespace testing_support {

inline const std::string& lieflowBinary() {
  static const std::string path = std::string(LIEFLOW_BINARY_DIR) + "/app/lieflow";
  return path;
}

struct CommandOutcome {
  int status;  ///< exit status, or −1 when a signal ended the command
  int signal;  ///< the signal, or 0
  std::string out;
  std::string err;
};

/// A path in the test's temporary directory, unique to the running test.
inline std::string testFile(const std::string& suffix) {
  return testing::TempDir() + "lieflow_" + testing::UnitTest::GetInstance()->current_test_info()->name() + suffix;
}

inline std::string slurp(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

/// Whether this build runs under AddressSanitizer (which reserves terabytes
/// of address space for its shadow memory: no address-space limit then).
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kAddressSanitizer = true;
#else
constexpr bool kAddressSanitizer = false;
#endif
#else
constexpr bool kAddressSanitizer = false;
#endif

/// Runs `lieflow ARGS` (ARGS is passed through the shell), with its address
/// space limited to `memory_mib` MiB when given (not under AddressSanitizer):
/// an input that makes memory grow without end fails the test instead of
/// filling the machine.
inline CommandOutcome runLieflow(const std::string& args, long memory_mib = 0) {
  const std::string out_file = testFile("_out.txt"), err_file = testFile("_err.txt");
  const std::string limit = memory_mib > 0 && !kAddressSanitizer
                                ? "ulimit -v " + std::to_string(memory_mib * 1024) + "; "
                                : std::string();
  const int raw = std::system((limit + lieflowBinary() + " " + args + " >" + out_file + " 2>" + err_file).c_str());
  const bool exited = WIFEXITED(raw);
  return {exited ? WEXITSTATUS(raw) : -1, WIFSIGNALED(raw) ? WTERMSIG(raw) : 0, slurp(out_file), slurp(err_file)};
}

}  // namespace testing_support
}  // namespace lieflow
