// Constrained acceleration solve on a chain of N rods joined by revolute joints
// (first to ground, hinge axes alternating z / y in the parent frame), random
// consistent state, with the cached ConstrainedAccelerationSolver (pattern
// analysed once, factorize + solve per iteration).
//
// After the benchmarks, prints time(1000)/time(100) against the target ≤ 12
// (cost per step linear in N) and time(100)/time(10).
#include <benchmark/benchmark.h>

#include <cstdio>
#include <map>
#include <random>
#include <string>

#include "joints/multibody/chain_builder.hpp"
#include "joints/multibody/constrained_acceleration.hpp"

namespace {

using namespace lieflow;
using namespace lieflow::multibody;
using constraints::BodyPose;
using constraints::BodyVelocity;
using Eigen::Matrix3d;
using Eigen::Vector3d;

/// The chain of joints/multibody/chain_builder.hpp, axes alternating z / y,
/// with a full inertia (products of inertia included).
MultibodyModel revoluteChain(int N, unsigned seed, MultibodyState* state) {
  Matrix3d I;
  I << 0.002, 0.0002, -0.0005, 0.0002, 0.01, 0.0007, -0.0005, 0.0007, 0.01;
  return randomRevoluteChain(N, true, I, seed, state);
}

void BM_ChainCachedSolve(benchmark::State& st) {
  const int N = static_cast<int>(st.range(0));
  MultibodyState s;
  const MultibodyModel model = revoluteChain(N, 42, &s);
  ConstrainedAccelerationSolver solver(model);
  AccelerationSolution out;
  for (auto _ : st) {
    const bool ok = solver.solve(model, s, {}, out);
    benchmark::DoNotOptimize(ok);
    benchmark::DoNotOptimize(out.lambda.data());
  }
  if (!out.ok) st.SkipWithError(out.reason.c_str());
  st.counters["residual"] = out.constraint_residual;
  st.counters["analyze"] = solver.analyzeCount();
  st.SetComplexityN(N);
}
BENCHMARK(BM_ChainCachedSolve)->Arg(10)->Arg(100)->Arg(1000)->Unit(benchmark::kMicrosecond);

// For comparison: the free function (pattern analysed on every call).
void BM_ChainFreeFunction(benchmark::State& st) {
  const int N = static_cast<int>(st.range(0));
  MultibodyState s;
  const MultibodyModel model = revoluteChain(N, 42, &s);
  for (auto _ : st) {
    const auto out = solveConstrainedAccelerations(model, s);
    benchmark::DoNotOptimize(out.lambda.data());
  }
}
BENCHMARK(BM_ChainFreeFunction)->Arg(10)->Arg(100)->Arg(1000)->Unit(benchmark::kMicrosecond);

// Collects real time per iteration of BM_ChainCachedSolve/N for the summary.
class SummaryReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) {
      const std::string name = r.benchmark_name();
      if (r.run_type != Run::RT_Iteration || r.iterations == 0) continue;
      const std::string prefix = "BM_ChainCachedSolve/";
      if (name.rfind(prefix, 0) == 0)
        ns[std::stoi(name.substr(prefix.size()))] =
            r.real_accumulated_time / static_cast<double>(r.iterations) * 1e9;
    }
    ConsoleReporter::ReportRuns(runs);
  }
  std::map<int, double> ns;
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  SummaryReporter rep;
  benchmark::RunSpecifiedBenchmarks(&rep);
  benchmark::Shutdown();
  auto& t = rep.ns;
  if (t.count(10) && t.count(100) && t.count(1000)) {
    const double r1 = t[1000] / t[100], r2 = t[100] / t[10];
    std::printf("\nSUMMARY cached solve (revolute chain): t(10) = %.2f us, t(100) = %.2f us, "
                "t(1000) = %.2f us\n",
                t[10] * 1e-3, t[100] * 1e-3, t[1000] * 1e-3);
    std::printf("SUMMARY t(1000)/t(100) = %.2f (target <= 12: %s), t(100)/t(10) = %.2f\n", r1,
                r1 <= 12.0 ? "met" : "NOT met", r2);
  }
  return 0;
}
