// A chain of N rods joined by revolute joints (first to ground, hinge axes
// alternating z / y in the parent frame), random consistent state:
//  * BM_ChainCachedSolve: the constrained acceleration solve alone, with the
//    cached ConstrainedAccelerationSolver (pattern analysed once, factorize +
//    solve per iteration);
//  * BM_ChainStep_<integrator>: one full step of a constrained integrator on
//    the MultibodySystem (projected RKMK4: 4 acceleration solves + position
//    and velocity projections).
//
// After the benchmarks, prints time(1000)/time(100) for each family against
// the target ≤ 12 (cost per step linear in N) and time(100)/time(10).
#include <benchmark/benchmark.h>

#include <cstdio>
#include <map>
#include <random>
#include <string>

#include "integrators/butcher_tableau.hpp"
#include "integrators/projected_stepper.hpp"
#include "integrators/rkmk.hpp"
#include "joints/multibody/chain_builder.hpp"
#include "joints/multibody/constrained_acceleration.hpp"
#include "joints/multibody/multibody_system.hpp"

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

/// One full step of `stepper` on the chain (h = 1e-3), state carried over.
template <typename Stepper>
void chainSteps(benchmark::State& st, Stepper stepper) {
  const int N = static_cast<int>(st.range(0));
  MultibodyState s;
  const MultibodySystem system(revoluteChain(N, 42, &s), {});
  // Released at rest (the random joint rates of the chain builder add up to
  // tip speeds of ~N rad/s, beyond what h = 1e-3 resolves at N = 1000).
  for (auto& v : s.velocities) v = BodyVelocity<double>{};
  MultibodyGroupState y = system.makeState(s);
  double t = 0.0;
  const double h = 1e-3;
  StepReport report;
  for (auto _ : st) {
    y = stepper.step(system, t, y, h, &report);
    t += h;
    if (!report.converged) {
      st.SkipWithError(report.failure);
      break;
    }
  }
  st.counters["constraint_error"] = system.constraintError(t, y);
  st.SetComplexityN(N);
}

void BM_ChainStep_rkmk4(benchmark::State& st) {
  chainSteps(st, ProjectedStepper<RkmkStepper<MultibodyGroupState>>(
                     RkmkStepper<MultibodyGroupState>(ButcherTableau::rk4())));
}
BENCHMARK(BM_ChainStep_rkmk4)->Arg(10)->Arg(100)->Arg(1000)->Unit(benchmark::kMicrosecond);

// Collects real time per iteration of every BM_.../N for the summary.
class SummaryReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) {
      const std::string name = r.benchmark_name();
      if (r.run_type != Run::RT_Iteration || r.iterations == 0) continue;
      const auto slash = name.rfind('/');
      if (slash == std::string::npos) continue;
      ns[name.substr(0, slash)][std::stoi(name.substr(slash + 1))] =
          r.real_accumulated_time / static_cast<double>(r.iterations) * 1e9;
    }
    ConsoleReporter::ReportRuns(runs);
  }
  std::map<std::string, std::map<int, double>> ns;
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  SummaryReporter rep;
  benchmark::RunSpecifiedBenchmarks(&rep);
  benchmark::Shutdown();
  std::printf("\n");
  for (auto& family : rep.ns) {
    auto& t = family.second;
    if (!(t[10] > 0 && t[100] > 0 && t[1000] > 0)) continue;
    const double r1 = t[1000] / t[100], r2 = t[100] / t[10];
    std::printf("SUMMARY %s: t(10) = %.2f us, t(100) = %.2f us, t(1000) = %.2f us; t(1000)/t(100) = %.2f "
                "(target <= 12: %s), t(100)/t(10) = %.2f\n",
                family.first.c_str(), t[10] * 1e-3, t[100] * 1e-3, t[1000] * 1e-3, r1,
                r1 <= 12.0 ? "met" : "NOT met", r2);
  }
  return 0;
}
