/// \file
/// bench_liegroup: Google Benchmark micro-benchmarks of liegroup/, each
/// lieflow operation registered right beside its Eigen baseline (what each
/// baseline computes: liegroup_measure/speed_cases.hpp and bench/README.md).
///
/// After Google Benchmark's own table it prints, for each lieflow operation,
/// the ratio of its CPU time to its baseline's in this run (median over
/// --benchmark_repetitions when given) and PASS / MISS against the target.
/// The exit status is 0 whatever the ratios are: machines are noisy and the
/// timing is informational (2 only for unknown arguments).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <string>
#include <unistd.h>
#include <vector>

#include <benchmark/benchmark.h>

#include "bench/benchmark_support.hpp"

#include "liegroup_measure/liegroup_measure.hpp"
#include "liegroup_measure/markdown_table.hpp"
#include "liegroup_measure/speed_cases.hpp"

namespace {

using lieflow::measure::SpeedInputs;
using lieflow::measure::SpeedTarget;

/// The same elements as measureSpeed.
const SpeedInputs& inputs() {
  static const SpeedInputs in(SpeedInputs::kDefaultSeed);
  return in;
}

/// Times Case::run over the input arrays, one element per iteration.
template <typename Case>
void runCase(benchmark::State& state) {
  const SpeedInputs& in = inputs();
  std::size_t i = 0;
  for (auto _ : state) {
    auto result = Case::run(in, i);
    benchmark::DoNotOptimize(result);
    i = (i + 1) & SpeedInputs::kMask;
  }
}

/// "SO3 exp" -> "SO3_exp".
std::string slug(const std::string& s) {
  std::string r = s;
  std::replace(r.begin(), r.end(), ' ', '_');
  return r;
}

struct Pair {
  SpeedTarget target;
  std::string op_name;
  std::string baseline_name;
};

std::vector<Pair> registerPairs() {
  std::vector<Pair> pairs;
  lieflow::measure::forEachSpeedPair([&](auto op, auto base, const SpeedTarget& target) {
    Pair p{target, slug(target.operation) + "/lieflow",
           slug(target.operation) + "/" + slug(target.baseline)};
    benchmark::RegisterBenchmark(p.op_name.c_str(), &runCase<decltype(op)>);
    benchmark::RegisterBenchmark(p.baseline_name.c_str(), &runCase<decltype(base)>);
    pairs.push_back(p);
  });
  return pairs;
}

using lieflow::bench::fixed;

/// The console reporter, plus the ratio summary at the end.
class RatioReporter : public lieflow::bench::MedianReporter {
 public:
  RatioReporter(OutputOptions options, std::vector<Pair> pairs)
      : MedianReporter(options), pairs_(std::move(pairs)) {}

  /// CPU ns per operation (see MedianReporter::medianNs).
  double nsPerOp(const std::string& name, int* repetitions) const { return medianNs(name, repetitions); }

  void Finalize() override {
    benchmark::ConsoleReporter::Finalize();
    std::ostream& out = GetOutputStream();
    std::vector<std::vector<std::string>> lines;
    int repetitions = 0;
    for (const Pair& p : pairs_) {
      int reps_op = 0, reps_base = 0;
      const double t_op = nsPerOp(p.op_name, &reps_op);
      const double t_base = nsPerOp(p.baseline_name, &reps_base);
      if (t_op < 0 || t_base < 0) continue;  // filtered out
      repetitions = reps_op;
      const double ratio = t_op / t_base;
      const bool has_target = !std::isnan(p.target.max_ratio);
      const std::string others = p.target.others;
      lines.push_back({p.target.operation, fixed(t_op, 2), p.target.baseline, fixed(t_base, 2),
                       fixed(ratio, 2), has_target ? "<= " + fixed(p.target.max_ratio, 2) : "-",
                       has_target ? (ratio <= p.target.max_ratio ? "PASS" : "MISS") : "-",
                       others.empty() ? "-" : others});
    }
    if (lines.empty()) return;
    out << "\n## lieflow / Eigen CPU-time ratios in this run\n\n";
    lieflow::measure::detail::printMarkdownTable(
        out,
        {"operation", "ns/op", "Eigen baseline", "ns/op", "ratio", "target", "result",
         "Sophus / manif / smooth"},
        lines, {1, 3, 4});
    out << "\nns/op: CPU time per operation"
        << (repetitions < 0   ? ", median of the repetitions"
            : repetitions > 1 ? ", median of " + std::to_string(repetitions) + " repetitions"
                              : "")
        << "; ratio = lieflow / Eigen baseline. Sophus / manif / smooth: their ratios to the"
           " same baselines, measured elsewhere (context). Timing is informational: the exit"
           " status is 0 whatever the result. "
        << lieflow::measure::buildDescription() << ".\n";
  }

 private:
  std::vector<Pair> pairs_;
};

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> defaults;
  std::vector<char*> args = lieflow::bench::argumentsWithDefaults(argc, argv, "0.1", &defaults);
  int args_count = static_cast<int>(args.size()) - 1;

  std::vector<Pair> pairs = registerPairs();
  benchmark::Initialize(&args_count, args.data());
  if (benchmark::ReportUnrecognizedArguments(args_count, args.data())) return 2;
  benchmark::AddCustomContext("lieflow_build", lieflow::measure::buildDescription());
  benchmark::AddCustomContext(
      "lieflow_inputs", std::to_string(SpeedInputs::kSize) +
                            " random elements per array, cycled (liegroup_measure/speed_cases.hpp)");
  const bool color = isatty(fileno(stdout)) != 0;
  RatioReporter reporter(color ? benchmark::ConsoleReporter::OO_ColorTabular
                               : benchmark::ConsoleReporter::OO_Tabular,
                         std::move(pairs));
  benchmark::RunSpecifiedBenchmarks(&reporter);
  benchmark::Shutdown();
  return 0;
}
