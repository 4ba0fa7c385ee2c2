/// \file
/// calibrate against the inputs that crashed, hung or printed NaN: absurd
/// starts (a segfault in the covariance after a failed solve), time columns
/// scaled by 1e-300, 1e300 or into milliseconds (an endless fit), endless
/// streams and row limits, and Ceres' own log lines on the user's terminal.
/// Each must end in exit 1 or 2 with lieflow's own message, never a signal.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "tests/command_runner.hpp"

namespace lieflow {
namespace {

using testing_support::runLieflow;
using testing_support::testFile;

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

/// The free decay of spring-hinge over 3 s at 1 ms (the recording).
std::string decayRecording() {
  const std::string path = testFile("_decay.csv");
  const auto o = runLieflow("simulate spring-hinge --dt 1e-3 --t-end 3 --out " + path);
  EXPECT_EQ(o.status, 0) << o.err;
  return path;
}

/// The recording with its time column multiplied by `factor`.
std::string scaledTime(const std::string& path, double factor, const std::string& suffix) {
  std::ifstream in(path);
  const std::string out_path = testFile(suffix);
  std::ofstream out(out_path);
  std::string line;
  std::getline(in, line);
  out << line << "\n";
  char buffer[40];
  while (std::getline(in, line)) {
    const auto comma = line.find(',');
    std::snprintf(buffer, sizeof buffer, "%.17g", std::strtod(line.substr(0, comma).c_str(), nullptr) * factor);
    out << buffer << line.substr(comma) << "\n";
  }
  return out_path;
}

void expectCleanFailure(const testing_support::CommandOutcome& o, int status, const std::string& args) {
  EXPECT_EQ(o.signal, 0) << args << " died from signal " << o.signal;
  EXPECT_EQ(o.status, status) << args << "\n" << o.err;
  EXPECT_TRUE(contains(o.err, "lieflow: ")) << o.err;
  // Ceres' glog lines are for --verbose only.
  EXPECT_FALSE(contains(o.err, "trust_region_minimizer")) << o.err;
  EXPECT_FALSE(contains(o.err, "InitGoogleLogging")) << o.err;
  for (const char* bad : {"nan", "inf"}) EXPECT_FALSE(contains(o.out, bad)) << o.out;
}

TEST(CalibrateRobustness, AbsurdStartsFailWithoutACrash) {
  const std::string rec = decayRecording();
  for (const char* start : {"--damping-start 1e25", "--damping-start 700"}) {
    const std::string args = "calibrate spring " + rec + " --scene spring-hinge " + start;
    const auto o = runLieflow(args);
    expectCleanFailure(o, 1, args);
    EXPECT_TRUE(contains(o.err, "the fit failed")) << o.err;
    EXPECT_FALSE(contains(o.err, "Ceres")) << o.err;  // said in lieflow's words
  }
  // Beyond the bound of every number read: refused naming the flag.
  for (const char* start : {"--damping-start 1e300", "--stiffness-start 1e100", "--rest-angle-start 1e300"}) {
    const std::string args = "calibrate spring " + rec + " --scene spring-hinge " + start;
    const auto o = runLieflow(args);
    expectCleanFailure(o, 2, args);
    EXPECT_TRUE(contains(o.err, std::string(start).substr(0, std::string(start).find(' ')) + ": '")) << o.err;
  }
  const std::string args = "calibrate spring " + rec + " --scene spring-hinge --stiffness-start 1e20";
  const auto o = runLieflow(args);
  expectCleanFailure(o, 2, args);
  EXPECT_TRUE(contains(o.err, "rad/s")) << o.err;
  // --verbose shows the solver's own lines.
  EXPECT_TRUE(contains(runLieflow("calibrate spring " + rec + " --scene spring-hinge --damping-start 700 --verbose").err,
                       "trust_region_minimizer"));
}

TEST(CalibrateRobustness, TimeColumnsInOtherUnitsAreRefusedNamingTheColumn) {
  const std::string rec = decayRecording();
  struct Case {
    double factor;
    const char* suffix;
  };
  for (const Case& c : {Case{1000.0, "_ms.csv"}, Case{1e-300, "_tiny.csv"}, Case{1e300, "_huge.csv"}}) {
    const std::string path = scaledTime(rec, c.factor, c.suffix);
    const std::string args = "calibrate spring " + path + " --scene spring-hinge";
    const auto o = runLieflow(args);
    expectCleanFailure(o, 2, args);
    // A time of 1e300 is refused where it is read (beyond ±1e30).
    EXPECT_TRUE(contains(o.err, path + ": t") || contains(o.err, ", column t: ")) << o.err;
  }
  // The substep limit, and the option that raises it.
  const auto o = runLieflow("calibrate spring " + rec + " --scene spring-hinge --max-substeps 100");
  EXPECT_EQ(o.status, 2);
  EXPECT_TRUE(contains(o.err, "--max-substeps")) << o.err;
}

TEST(CalibrateRobustness, EndlessStreamsAndRowLimitsAreRefused) {
  const auto zero = runLieflow("calibrate hinge /dev/zero");
  EXPECT_EQ(zero.status, 2);
  EXPECT_TRUE(contains(zero.err, "NUL byte")) << zero.err;
  const std::string err = testing_support::testFile("_err.txt");
  const int raw = std::system(("yes | " + testing_support::lieflowBinary() +
                               " calibrate hinge /dev/stdin --max-input-mb 1 >/dev/null 2>" + err).c_str());
  EXPECT_TRUE(WIFEXITED(raw) && WEXITSTATUS(raw) == 2) << testing_support::slurp(err);
  EXPECT_TRUE(contains(testing_support::slurp(err), "--max-input-mb")) << testing_support::slurp(err);
  const std::string rec = decayRecording();
  const auto rows = runLieflow("calibrate spring " + rec + " --scene spring-hinge --max-rows 100");
  EXPECT_EQ(rows.status, 2);
  EXPECT_TRUE(contains(rows.err, "--max-rows")) << rows.err;
}

}  // namespace
}  // namespace lieflow

namespace lieflow {
namespace {

/// A recording above 64 MB is announced before it is read: its rows and the
/// memory the fit will need (a 10⁶-row fit used to run 13 s in silence).
TEST(CalibrateRobustness, LargeRecordingsAreAnnouncedWithTheirMemory) {
  const std::string path = testing_support::testFile("_large.csv");
  {
    std::ofstream f(path);
    f << "t,a.wx,a.wy,a.wz,b.wx,b.wy,b.wz\n";
    const std::string tail = ",0.123456789012345,0.234567890123456,0.345678901234567,"
                             "0.456789012345678,0.567890123456789,0.678901234567890\n";
    char t[32];
    for (long i = 0; i < 620000; ++i) {
      std::snprintf(t, sizeof t, "%.17g", 1e-3 * static_cast<double>(i));
      f << t << tail;
    }
  }
  // --max-rows stops the read right after the announcement.
  const auto o = testing_support::runLieflow("calibrate hinge " + path + " --max-rows 10");
  EXPECT_EQ(o.status, 2);
  EXPECT_NE(o.err.find("about 6.2e+05 rows; the fit needs about 0.59 GB of memory"), std::string::npos) << o.err;
  std::remove(path.c_str());
}

}  // namespace
}  // namespace lieflow
