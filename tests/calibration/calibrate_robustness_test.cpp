/// \file
/// calibrate against the inputs that crashed, hung or printed NaN: absurd
/// starts (a segfault in the covariance after a failed solve), time columns
/// scaled by 1e-300, 1e300 or into milliseconds (an endless fit), endless
/// streams and row limits, and Ceres' own log lines on the user's terminal.
/// Each must end in exit 1 or 2 with lieflow's own message, never a signal.
#include <gtest/gtest.h>

#include <cstdio>
#include <algorithm>
#include <cmath>
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

/// A start the recording cannot show (a damping that decays within a sample,
/// a stiffness beyond Nyquist) or from which the model leaves the finite
/// numbers is bad input naming that option (it segfaulted in the covariance,
/// then failed blaming the time column or the other options).
TEST(CalibrateRobustness, AbsurdStartsAreRefusedNamingTheOption) {
  const std::string rec = decayRecording();
  struct Case {
    const char* options;
    const char* field;
  };
  for (const Case& c : {Case{"--damping-start 1e300", "lieflow: --damping-start: 1e+300 N m s/rad"},
                        Case{"--hold-damping --damping-start 1e10", "lieflow: --damping-start: 1e+10 N m s/rad"},
                        Case{"--stiffness-start 1e100", "lieflow: --stiffness-start: 1e+100 N m/rad"},
                        Case{"--rest-angle-start 1e300", "lieflow: --rest-angle-start: the model integrated"}}) {
    const std::string args = "calibrate spring " + rec + " --scene spring-hinge " + c.options;
    const auto o = runLieflow(args);
    expectCleanFailure(o, 2, args);
    EXPECT_TRUE(contains(o.err, c.field)) << o.err;
  }
  // The largest the recording allows is said (1 ms samples, inertia 0.24 kg m^2).
  EXPECT_TRUE(contains(runLieflow("calibrate spring " + rec + " --scene spring-hinge --damping-start 1e300").err,
                       "a damping of at most 753.982 N m s/rad"));
}

/// A damping start in the hundreds (ζ ≈ 170) on a 1 kHz recording: the
/// substeps now follow the dashpot's rate c/I too, so RK4 stays stable and
/// the fit reaches the truth (it failed, blaming the data: "barely moves").
TEST(CalibrateRobustness, DampingStartsInTheHundredsConverge) {
  const std::string rec = testFile("_short.csv");
  ASSERT_EQ(runLieflow("simulate spring-hinge --dt 1e-3 --t-end 1.2 --out " + rec).status, 0);
  const auto o = runLieflow("calibrate spring " + rec + " --scene spring-hinge --damping-start 700");
  ASSERT_EQ(o.status, 0) << o.err;
  const auto at = o.out.find("\"stiffness\":");
  ASSERT_NE(at, std::string::npos) << o.out;
  EXPECT_NEAR(std::strtod(o.out.c_str() + at + 12, nullptr), 12.0, 1e-6) << o.out;
}

/// A residual as large as the motion after the solve is the fit's failure
/// from its start, not data that "barely move": the message says so and
/// names the start option (the angle moves 0.39 rad RMS, its noise is 1e-7).
TEST(CalibrateRobustness, ALocalMinimumBlamesTheStartNotTheData) {
  const std::string rec = decayRecording();
  const std::string args = "calibrate spring " + rec + " --scene spring-hinge --rest-angle-start 1e5";
  const auto o = runLieflow(args);
  expectCleanFailure(o, 1, args);
  EXPECT_TRUE(contains(o.err, "does not follow the recorded angle")) << o.err;
  EXPECT_TRUE(contains(o.err, "(--rest-angle-start), or none")) << o.err;
  EXPECT_FALSE(contains(o.err, "barely moves")) << o.err;
}

/// Options named as the cause when they are: --min-samples, --substeps,
/// --max-iterations (and the data when it is: the time column, below).
TEST(CalibrateRobustness, MessagesNameTheOptionThatCausedThem) {
  const std::string rec = decayRecording();
  const std::string spring = "calibrate spring " + rec + " --scene spring-hinge ";
  const auto few = runLieflow(spring + "--min-samples 100000");
  EXPECT_EQ(few.status, 1);
  EXPECT_TRUE(contains(few.err, "3001 samples; at least 100000 are needed (--min-samples)")) << few.err;
  const auto substeps = runLieflow(spring + "--substeps 10000");
  EXPECT_EQ(substeps.status, 2);
  EXPECT_TRUE(contains(substeps.err, "lieflow: --substeps: needs 30000000 integration substeps")) << substeps.err;
  EXPECT_TRUE(contains(substeps.err, "(raise it with --max-substeps)")) << substeps.err;
  // Why a fit stopped, in lieflow's words (Ceres' sentence follows).
  const auto short_fit = runLieflow(spring + "--max-iterations 1");
  EXPECT_EQ(short_fit.status, 1);
  EXPECT_TRUE(contains(short_fit.err, "the solver did not converge: multiple shooting (16 segments, 1 iterations): "
                                      "stopped at the iteration limit of 1 (--max-iterations) before a tolerance "
                                      "was met (Ceres: "))
      << short_fit.err;
  const auto fine = runLieflow(spring);
  EXPECT_EQ(fine.status, 0) << fine.err;
  EXPECT_TRUE(contains(fine.out, "single shooting (")) << fine.out;
  EXPECT_TRUE(contains(fine.out, "iterations): converged: the relative")) << fine.out;
}

/// Ceres' own log lines (glog) only with --verbose, on stderr, never in the
/// JSON on stdout.
TEST(CalibrateRobustness, SolverLogLinesOnlyWithVerbose) {
  const std::string rec = decayRecording();
  const std::string args = "calibrate spring " + rec + " --scene spring-hinge";
  const auto quiet = runLieflow(args);
  ASSERT_EQ(quiet.status, 0) << quiet.err;
  EXPECT_EQ(quiet.err, "");
  const auto verbose = runLieflow(args + " --verbose");
  ASSERT_EQ(verbose.status, 0) << verbose.err;
  EXPECT_TRUE(contains(verbose.err, "trust_region_minimizer.cc")) << verbose.err;
  EXPECT_TRUE(contains(verbose.err, "Terminating: ")) << verbose.err;
  EXPECT_EQ(verbose.out.rfind("{\"stiffness\":", 0), 0u) << verbose.out;
  EXPECT_EQ(std::count(verbose.out.begin(), verbose.out.end(), '\n'), 1) << verbose.out;
}

/// Gyroscope values no fit can square (a unit or export error) are bad input
/// naming the column (they ended in an internal "expected a Jacobian" error).
TEST(CalibrateRobustness, AbsurdGyroscopeValuesNameTheColumn) {
  const std::string rec = testFile("_rates.csv");
  {
    std::ofstream f(rec);
    f << "t,a.wx,a.wy,a.wz,b.wx,b.wy,b.wz\n";
    for (int k = 0; k < 200; ++k) {
      const double t = 0.01 * k;
      f << t << "," << 1e200 * std::cos(t) << "," << std::sin(3 * t) << ",0.5," << std::cos(2 * t) << ",1,"
        << std::sin(t) << "\n";
    }
  }
  const std::string args = "calibrate hinge " + rec;
  const auto o = runLieflow(args);
  expectCleanFailure(o, 2, args);
  EXPECT_TRUE(contains(o.err, rec + ": column a.wx: 1e+200 rad/s at t = 0 s (sample 1)")) << o.err;
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
    EXPECT_TRUE(contains(o.err, path + ": t: ")) << o.err;
    EXPECT_TRUE(contains(o.err, "is t in seconds?")) << o.err;
    // No "inf rad/s" or "(0 s)" from an overflowed start in the message.
    for (const char* bad : {"inf", "nan", "(0 s)"}) EXPECT_FALSE(contains(o.err, bad)) << o.err;
  }
  // The substep limit: the time column, the number needed and the option
  // that raises it.
  const auto o = runLieflow("calibrate spring " + rec + " --scene spring-hinge --max-substeps 100");
  EXPECT_EQ(o.status, 2);
  EXPECT_TRUE(contains(o.err, rec + ": t: needs 3000 integration substeps")) << o.err;
  EXPECT_TRUE(contains(o.err, "above the limit of 100 (raise it with --max-substeps)")) << o.err;
}

TEST(CalibrateRobustness, EndlessStreamsAndRowLimitsAreRefused) {
  const auto zero = runLieflow("calibrate hinge /dev/zero --max-input-mb 1");
  EXPECT_EQ(zero.status, 2);
  EXPECT_TRUE(contains(zero.err, "--max-input-mb")) << zero.err;
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
