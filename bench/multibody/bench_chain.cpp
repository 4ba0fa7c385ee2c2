// A chain of N rods joined by revolute joints (first to ground, hinge axes
// alternating z / y in the parent frame), random consistent state:
//  * BM_ChainCachedSolve: the constrained acceleration solve alone, with the
//    cached ConstrainedAccelerationSolver (pattern analysed once, factorize +
//    solve per iteration);
//  * BM_ChainStep_<integrator>: one full step of a constrained integrator on
//    the MultibodySystem (projected RKMK4 and CF4: 4 acceleration solves +
//    position and velocity projections; lgvi: the RATTLE step; genalpha: the
//    stabilized index-2 generalized-α step at ρ∞ = 1, the defaults, and
//    genalpha_index3 at ρ∞ = 0.9, since ρ∞ = 1 is unstable at index 3 on
//    chains); BM_ChainStep_joint_<integrator>: the same chain in joint
//    coordinates (the articulated-body algorithm; joint_lgvi the variational
//    integrator on the joint angles, integrators/joint_space_variational.hpp;
//    the counter `iterations` is the mean passes of an implicit step's
//    iteration). Every kResetSteps steps (1 s) the chain starts
//    again from rest, outside the timing, as the MuJoCo runs do;
//  * BM_LoopStep_rkmk4/N, BM_LoopStep_joint_rkmk4/N: the chain closed into
//    a loop (a ball joint holds its tip), projected rkmk4 in maximal and in
//    joint coordinates (the ball joint's rows on multipliers).
//
// After the benchmarks, prints time(1000)/time(100) for each family against
// the target ≤ 11 (issue 12) (cost per step linear in N) and time(100)/time(10), medians
// over --benchmark_repetitions. Built with MuJoCo (CMakeLists.txt), the binary
// also times the same chain in MuJoCo (bench_chain_mujoco.cpp:
// BM_ChainStep_mujoco_rk4/N, BM_ChainStep_mujoco_euler/N), prints their ratios
// (for comparison: the target is lieflow's) and lieflow's time per step over
// MuJoCo's at each N.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <unistd.h>

#include "bench/multibody/chain_scene.hpp"
#include "integrators/butcher_tableau.hpp"
#include "integrators/commutator_free.hpp"
#include "integrators/constrained_generalized_alpha.hpp"
#include "integrators/constrained_lgvi.hpp"
#include "integrators/projected_stepper.hpp"
#include "integrators/rkmk.hpp"
#include "dynamics/maximal/constrained_acceleration.hpp"
#include "dynamics/maximal/kkt_assembly.hpp"
#include "integrators/generalized_alpha.hpp"
#include "integrators/joint_space_variational.hpp"
#include "dynamics/joint_space/articulated_second_order.hpp"
#include "dynamics/joint_space/articulated_scene.hpp"
#include "dynamics/maximal/multibody_scene.hpp"
#include "dynamics/maximal/multibody_system.hpp"

namespace {

using namespace lieflow;
using namespace lieflow::multibody;
using constraints::BodyPose;
using constraints::BodyVelocity;
using Eigen::Matrix3d;
using Eigen::Vector3d;

using bench::revoluteChain;

void BM_ChainCachedSolve(benchmark::State& st) {
  const int N = static_cast<int>(st.range(0));
  MultibodyState s;
  const MultibodyModel model = revoluteChain(N, bench::kChainSeed, &s);
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
// N = 30 and 300 only fill in the curve of papers/chain-scaling/ (the summary
// uses 10, 100, 1000).
BENCHMARK(BM_ChainCachedSolve)
    ->Arg(10)->Arg(30)->Arg(100)->Arg(300)->Arg(1000)
    ->Unit(benchmark::kMicrosecond);

// For comparison: the free function (pattern analysed on every call).
void BM_ChainFreeFunction(benchmark::State& st) {
  const int N = static_cast<int>(st.range(0));
  MultibodyState s;
  const MultibodyModel model = revoluteChain(N, bench::kChainSeed, &s);
  for (auto _ : st) {
    const auto out = solveConstrainedAccelerations(model, s);
    benchmark::DoNotOptimize(out.lambda.data());
  }
}
BENCHMARK(BM_ChainFreeFunction)->Arg(10)->Arg(100)->Arg(1000)->Unit(benchmark::kMicrosecond);

/// The chain starts again from rest every kResetSteps steps (1 s at h =
/// 1e-3), outside the timing, as bench_chain_mujoco.cpp's runs do.
constexpr long kResetSteps = 1000;

/// The timed loop: one step of h = 1e-3 per iteration from *y at *t, the
/// state carried over, back to y0 every kResetSteps steps outside the timing;
/// a step that fails stops the benchmark with its reason.
template <typename Stepper, typename System, typename State>
void timedSteps(benchmark::State& st, Stepper& stepper, const System& system, const State& y0, State* y, double* t) {
  const double h = bench::kChainStep;
  StepReport report;
  long steps = 0;
  double iterations = 0.0;
  for (auto _ : st) {
    *y = stepper.step(system, *t, *y, h, &report);
    *t += h;
    iterations += report.newton_iterations;
    if (!report.converged) {
      st.SkipWithError(report.failure);
      break;
    }
    if (++steps % kResetSteps == 0) {
      st.PauseTiming();
      *y = y0;
      *t = 0.0;
      st.ResumeTiming();
    }
  }
  // Mean iterations per step of an implicit stepper (0 for explicit ones).
  if (steps > 0) st.counters["iterations"] = iterations / static_cast<double>(steps);
}

/// One full step of `stepper` on the chain (h = 1e-3), state carried over.
template <typename Stepper>
void chainSteps(benchmark::State& st, Stepper stepper) {
  const int N = static_cast<int>(st.range(0));
  MultibodyState s;
  const MultibodySystem system(revoluteChain(N, bench::kChainSeed, &s), {});
  // Released at rest (the random joint rates of the chain builder add up to
  // tip speeds of ~N rad/s, beyond what h = 1e-3 resolves at N = 1000).
  for (auto& v : s.velocities) v = BodyVelocity<double>{};
  const MultibodyGroupState y0 = system.makeState(s);
  MultibodyGroupState y = y0;
  double t = 0.0;
  timedSteps(st, stepper, system, y0, &y, &t);
  st.counters["constraint_error"] = system.constraintError(t, y);
  st.SetComplexityN(N);
}

void BM_ChainStep_rkmk4(benchmark::State& st) {
  chainSteps(st, ProjectedStepper<RkmkStepper<MultibodyGroupState>>(
                     RkmkStepper<MultibodyGroupState>(ButcherTableau::rk4())));
}
BENCHMARK(BM_ChainStep_rkmk4)
    ->Arg(1)->Arg(2)->Arg(10)->Arg(30)->Arg(100)->Arg(300)->Arg(1000)
    ->Unit(benchmark::kMicrosecond);

void BM_ChainStep_cf4(benchmark::State& st) {
  chainSteps(st, ProjectedStepper<CommutatorFree4Stepper<MultibodyGroupState>>(
                     CommutatorFree4Stepper<MultibodyGroupState>()));
}
BENCHMARK(BM_ChainStep_cf4)->Arg(1)->Arg(2)->Arg(10)->Arg(30)->Arg(100)->Unit(benchmark::kMicrosecond);

void BM_ChainStep_lgvi(benchmark::State& st) {
  chainSteps(st, ConstrainedLgviStepper<MultibodySystem>(ConstrainedLgviOptions{}));
}
BENCHMARK(BM_ChainStep_lgvi)->Arg(1)->Arg(2)->Arg(10)->Arg(30)->Arg(100)->Unit(benchmark::kMicrosecond);

void BM_ChainStep_genalpha(benchmark::State& st) {
  chainSteps(st, ConstrainedGeneralizedAlphaStepper<MultibodySystem>(ConstrainedGeneralizedAlphaOptions{}));
}
BENCHMARK(BM_ChainStep_genalpha)->Arg(1)->Arg(2)->Arg(10)->Arg(30)->Unit(benchmark::kMicrosecond);

void BM_ChainStep_genalpha_index3(benchmark::State& st) {
  ConstrainedGeneralizedAlphaOptions o;
  o.rho_inf = 0.9;
  o.index = 3;
  chainSteps(st, ConstrainedGeneralizedAlphaStepper<MultibodySystem>(o));
}
BENCHMARK(BM_ChainStep_genalpha_index3)->Arg(1)->Arg(2)->Arg(10)->Arg(30)->Unit(benchmark::kMicrosecond);

/// One step of `stepper` on the same chain in joint coordinates
/// (--formulation joint: the articulated-body algorithm per stage).
template <typename Stepper>
void chainJointSteps(benchmark::State& st, Stepper stepper) {
  const int N = static_cast<int>(st.range(0));
  const auto scene = assembleArticulated(bench::revoluteChainScene(N, bench::kChainSeed));
  const articulated::ArticulatedSystem& system = *scene->system;
  const articulated::ArticulatedState y0 = scene->y0;
  articulated::ArticulatedState y = y0;
  double t = 0.0;
  timedSteps(st, stepper, system, y0, &y, &t);
  st.counters["energy"] = system.energy(t, y);
  st.SetComplexityN(N);
}

void BM_ChainStep_joint_rkmk4(benchmark::State& st) {
  chainJointSteps(st, RkmkStepper<articulated::ArticulatedState>(ButcherTableau::rk4()));
}
BENCHMARK(BM_ChainStep_joint_rkmk4)
    ->Arg(1)->Arg(2)->Arg(10)->Arg(30)->Arg(100)->Arg(300)->Arg(1000)
    ->Unit(benchmark::kMicrosecond);

void BM_ChainStep_joint_cf4(benchmark::State& st) {
  chainJointSteps(st, CommutatorFree4Stepper<articulated::ArticulatedState>());
}
BENCHMARK(BM_ChainStep_joint_cf4)->Arg(1)->Arg(2)->Arg(10)->Arg(30)->Arg(100)->Unit(benchmark::kMicrosecond);

void BM_ChainStep_joint_genalpha(benchmark::State& st) {
  chainJointSteps(st, GeneralizedAlphaStepper<articulated::ArticulatedState>(GeneralizedAlphaOptions{}));
}
BENCHMARK(BM_ChainStep_joint_genalpha)->Arg(1)->Arg(2)->Arg(10)->Arg(30)->Unit(benchmark::kMicrosecond);

void BM_ChainStep_joint_lgvi(benchmark::State& st) {
  chainJointSteps(st, JointSpaceVariationalStepper<articulated::ArticulatedSystem>(JointSpaceVariationalOptions{}));
}
BENCHMARK(BM_ChainStep_joint_lgvi)->Arg(1)->Arg(2)->Arg(10)->Arg(30)->Arg(100)->Unit(benchmark::kMicrosecond);

/// One projected rkmk4 step on the chain closed into a loop (chain_scene.hpp:
/// a ball joint holds the tip where it starts), released at rest: in maximal
/// coordinates (BM_LoopStep_rkmk4) and in joint coordinates with the ball
/// joint's rows on multipliers (BM_LoopStep_joint_rkmk4).
void BM_LoopStep_rkmk4(benchmark::State& st) {
  const int N = static_cast<int>(st.range(0));
  const auto scene = assembleMultibody(bench::closedChainScene(N, bench::kChainSeed));
  const MultibodySystem& system = *scene->system;
  const MultibodyGroupState y0 = scene->y0;
  MultibodyGroupState y = y0;
  double t = 0.0;
  ProjectedStepper<RkmkStepper<MultibodyGroupState>> stepper(RkmkStepper<MultibodyGroupState>(ButcherTableau::rk4()));
  timedSteps(st, stepper, system, y0, &y, &t);
  st.counters["constraint_error"] = system.constraintError(t, y);
}
BENCHMARK(BM_LoopStep_rkmk4)->Arg(4)->Arg(10)->Arg(30)->Arg(100)->Unit(benchmark::kMicrosecond);

void BM_LoopStep_joint_rkmk4(benchmark::State& st) {
  const int N = static_cast<int>(st.range(0));
  const auto scene = assembleArticulated(bench::closedChainScene(N, bench::kChainSeed));
  const articulated::ArticulatedSystem& system = *scene->system;
  const articulated::ArticulatedState y0 = scene->y0;
  articulated::ArticulatedState y = y0;
  double t = 0.0;
  ProjectedStepper<RkmkStepper<articulated::ArticulatedState>> stepper(
      RkmkStepper<articulated::ArticulatedState>(ButcherTableau::rk4()));
  timedSteps(st, stepper, system, y0, &y, &t);
  st.counters["constraint_error"] = system.constraintError(t, y);
}
BENCHMARK(BM_LoopStep_joint_rkmk4)->Arg(4)->Arg(10)->Arg(30)->Arg(100)->Unit(benchmark::kMicrosecond);

// Collects real time per iteration of every BM_.../N for the summary (every
// repetition with --benchmark_repetitions; the summary takes their median).
class SummaryReporter : public benchmark::ConsoleReporter {
 public:
  explicit SummaryReporter(OutputOptions options) : ConsoleReporter(options) {}
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) {
      const std::string name = r.benchmark_name();
      if (r.run_type != Run::RT_Iteration || r.iterations == 0 || r.error_occurred) continue;
      const auto slash = name.rfind('/');
      if (slash == std::string::npos) continue;
      ns[name.substr(0, slash)][std::stoi(name.substr(slash + 1))].push_back(
          r.real_accumulated_time / static_cast<double>(r.iterations) * 1e9);
    }
    ConsoleReporter::ReportRuns(runs);
  }
  /// Median real ns per iteration of family/N (0 when not run).
  double median(const std::string& family, int n) const {
    const auto f = ns.find(family);
    if (f == ns.end()) return 0.0;
    const auto it = f->second.find(n);
    if (it == f->second.end() || it->second.empty()) return 0.0;
    std::vector<double> v = it->second;
    std::sort(v.begin(), v.end());
    const size_t k = v.size() / 2;
    return v.size() % 2 ? v[k] : 0.5 * (v[k - 1] + v[k]);
  }
  std::map<std::string, std::map<int, std::vector<double>>> ns;
};

}  // namespace

#ifdef LIEFLOW_BENCH_CHAIN_MUJOCO
namespace lieflow {
namespace bench {
std::string chainMujocoDescription();  // bench_chain_mujoco.cpp
}  // namespace bench
}  // namespace lieflow
#endif

int main(int argc, char** argv) {
  // Colours as Google Benchmark's own console reporter: only on a terminal,
  // never with --benchmark_color=false (read before Initialize consumes it).
  bool color = isatty(STDOUT_FILENO) != 0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--benchmark_color=false" || a == "--benchmark_color=no") color = false;
    if (a == "--benchmark_color=true" || a == "--benchmark_color=yes") color = true;
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
#ifdef LIEFLOW_BENCH_CHAIN_MUJOCO
  benchmark::AddCustomContext("lieflow_mujoco", lieflow::bench::chainMujocoDescription());
#else
  benchmark::AddCustomContext("lieflow_mujoco", "not built in (CMake found no MuJoCo)");
#endif
  SummaryReporter rep(color ? benchmark::ConsoleReporter::OO_ColorTabular
                            : benchmark::ConsoleReporter::OO_Tabular);
  benchmark::RunSpecifiedBenchmarks(&rep);
  benchmark::Shutdown();
  std::printf("\n");
  for (const auto& family : rep.ns) {
    const std::string& name = family.first;
    const double t10 = rep.median(name, 10), t100 = rep.median(name, 100), t1000 = rep.median(name, 1000);
    if (!(t10 > 0 && t100 > 0 && t1000 > 0)) continue;
    const double r1 = t1000 / t100, r2 = t100 / t10;
    // The target (cost per step linear in N) is lieflow's; MuJoCo's ratios are
    // printed for comparison.
    const bool peer = name.find("mujoco") != std::string::npos;
    std::printf("SUMMARY %s: t(10) = %.2f us, t(100) = %.2f us, t(1000) = %.2f us; t(1000)/t(100) = %.2f "
                "(%s%s), t(100)/t(10) = %.2f\n",
                name.c_str(), t10 * 1e-3, t100 * 1e-3, t1000 * 1e-3, r1,
                peer ? "MuJoCo, for comparison; lieflow's target <= 11: " : "target <= 11: ",
                r1 <= 11.0 ? "met" : "NOT met", r2);
  }
  // lieflow's steps against MuJoCo's, N by N: the explicit fourth-order
  // methods against RK4 and Euler, RATTLE against Euler, generalized-α
  // against MuJoCo's implicit integrator.
  const std::pair<const char*, const char*> pairs[] = {
      {"BM_ChainStep_rkmk4", "BM_ChainStep_mujoco_rk4"},  {"BM_ChainStep_cf4", "BM_ChainStep_mujoco_rk4"},
      {"BM_ChainStep_joint_rkmk4", "BM_ChainStep_mujoco_rk4"}, {"BM_ChainStep_joint_cf4", "BM_ChainStep_mujoco_rk4"},
      {"BM_ChainStep_rkmk4", "BM_ChainStep_mujoco_euler"}, {"BM_ChainStep_lgvi", "BM_ChainStep_mujoco_euler"},
      {"BM_ChainStep_joint_lgvi", "BM_ChainStep_mujoco_euler"},
      {"BM_ChainStep_genalpha", "BM_ChainStep_mujoco_implicit"},
      {"BM_ChainStep_joint_genalpha", "BM_ChainStep_mujoco_implicit"},
      {"BM_ChainStep_genalpha_index3", "BM_ChainStep_mujoco_implicit"},
      // A loop: joint coordinates (multipliers on the ABA) against maximal.
      {"BM_LoopStep_joint_rkmk4", "BM_LoopStep_rkmk4"}};
  for (const auto& pair : pairs) {
    const char* lieflow_family = pair.first;
    const char* peer = pair.second;
    if (!rep.ns.count(peer) || !rep.ns.count(lieflow_family)) continue;
    std::string line;
    for (int n : {1, 2, 4, 10, 30, 100, 300, 1000}) {
      const double a = rep.median(lieflow_family, n), b = rep.median(peer, n);
      if (!(a > 0 && b > 0)) continue;
      char buf[96];
      std::snprintf(buf, sizeof buf, "%sN = %d: %.3g", line.empty() ? "" : ", ", n, a / b);
      line += buf;
    }
    if (!line.empty())
      std::printf("SUMMARY time per step %s / %s (> 1: %s slower): %s\n", lieflow_family, peer,
                  std::string(peer).find("mujoco") != std::string::npos ? "lieflow" : "the first", line.c_str());
  }
  return 0;
}
