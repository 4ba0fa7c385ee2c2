/// \file
/// The Google Benchmark plumbing shared by bench_liegroup, bench_integrators
/// and the calibration benchmarks: default flags for a noisy 2-core machine, a
/// console reporter that keeps the median CPU time of every benchmark's
/// repetitions for the summary tables the programs print at the end, and the
/// main that runs them with it.
#pragma once

#include <algorithm>
#include <cstdio>
#include <map>
#include <string>
#include <unistd.h>
#include <vector>

#include <benchmark/benchmark.h>

namespace lieflow {
namespace bench {

inline double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

inline std::string fixed(double x, int digits) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*f", digits, x);
  return buf;
}

/// argv with the defaults placed before the user's arguments, so that any of
/// them given on the command line wins: 5 repetitions of `min_time` seconds
/// in random interleaved order (a burst of load hits different benchmarks in
/// different repetitions), and only the aggregates on screen. `storage` keeps
/// the strings alive; the returned vector ends with nullptr.
inline std::vector<char*> argumentsWithDefaults(int argc, char** argv, const std::string& min_time,
                                                std::vector<std::string>* storage) {
  *storage = {"--benchmark_repetitions=5", "--benchmark_min_time=" + min_time,
              "--benchmark_enable_random_interleaving=true",
              "--benchmark_display_aggregates_only=true"};
  std::vector<char*> args = {argv[0]};
  for (std::string& flag : *storage) args.push_back(&flag[0]);
  for (int i = 1; i < argc; ++i) args.push_back(argv[i]);
  args.push_back(nullptr);
  return args;
}

/// The console reporter, recording each benchmark's CPU ns per iteration
/// (divided by `perIteration(name)`, e.g. the steps one iteration runs).
class MedianReporter : public benchmark::ConsoleReporter {
 public:
  explicit MedianReporter(OutputOptions options) : benchmark::ConsoleReporter(options) {}

  void ReportRuns(const std::vector<Run>& reports) override {
    benchmark::ConsoleReporter::ReportRuns(reports);
    for (const Run& run : reports) {
      if (run.error_occurred) continue;
      const std::string name = run.run_name.str();
      const double ns = run.GetAdjustedCPUTime() * 1e9 /
                        benchmark::GetTimeUnitMultiplier(run.time_unit) / perIteration(name);
      if (run.run_type == Run::RT_Iteration)
        iteration_ns_[name].push_back(ns);
      else if (run.aggregate_name == "median")
        median_ns_[name] = ns;
    }
  }

  /// CPU ns of a benchmark: the median of its repetitions (from the
  /// iteration runs when they were reported, else Google Benchmark's median
  /// aggregate, when *repetitions is set to −1). Negative when it did not run.
  double medianNs(const std::string& name, int* repetitions = nullptr) const {
    const auto it = iteration_ns_.find(name);
    if (it != iteration_ns_.end() && !it->second.empty()) {
      if (repetitions) *repetitions = static_cast<int>(it->second.size());
      return median(it->second);
    }
    const auto m = median_ns_.find(name);
    if (m == median_ns_.end()) return -1.0;
    if (repetitions) *repetitions = -1;
    return m->second;
  }

 protected:
  virtual double perIteration(const std::string& /*name*/) const { return 1.0; }

 private:
  std::map<std::string, std::vector<double>> iteration_ns_;
  std::map<std::string, double> median_ns_;
};

/// The main of a program whose cases are registered already: Google
/// Benchmark's flags with argumentsWithDefaults(min_time), every case run with
/// a MedianReporter (coloured on a terminal), then `summary(reporter)` for the
/// tables printed after the benchmark's own. Returns the exit status (2 for
/// an unrecognized argument).
template <typename Summary>
int runWithMedianReporter(int argc, char** argv, const std::string& min_time, Summary summary) {
  std::vector<std::string> defaults;
  std::vector<char*> args = argumentsWithDefaults(argc, argv, min_time, &defaults);
  int args_count = static_cast<int>(args.size()) - 1;
  benchmark::Initialize(&args_count, args.data());
  if (benchmark::ReportUnrecognizedArguments(args_count, args.data())) return 2;
  const bool color = isatty(fileno(stdout)) != 0;
  MedianReporter reporter(color ? benchmark::ConsoleReporter::OO_ColorTabular
                                : benchmark::ConsoleReporter::OO_Tabular);
  benchmark::RunSpecifiedBenchmarks(&reporter);
  benchmark::Shutdown();
  summary(reporter);
  return 0;
}

}  // namespace bench
}  // namespace lieflow
