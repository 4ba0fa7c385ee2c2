// Forward dynamics in ceres::Jet, as the spring fits evaluate it
// (dynamics/joint_space/scalar_dynamics.hpp): the Newton–Euler columns
// (n + 1 passes with compact inertias and an n × n solve, O(n²)) against the
// articulated-body algorithm (O(n), 6 × 6 articulated inertias) on the same
// tree passes, on chains of n revolute joints (axes alternating between two
// directions, every joint sprung and damped) at a random state whose angles
// and rates carry derivatives (ceres::Jet<double, 8>, as a fit's residual).
// After the table: per n the ratio of the two, measured side by side, and
// the largest n where the Newton–Euler columns are faster — what
// ScalarDynamics::kNewtonEulerMaxDofs holds. One thread.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <ceres/jet.h>

#include "dynamics/joint_space/articulated_scene.hpp"
#include "dynamics/joint_space/scalar_dynamics.hpp"
#include "model/scene.hpp"

namespace {

using namespace lieflow;
using namespace lieflow::articulated;
using Jet = ceres::Jet<double, 8>;
using VecJ = Eigen::Matrix<Jet, Eigen::Dynamic, 1>;

/// A chain of n links of 0.5 m hanging from the ground, joint k about y for
/// even k and about x for odd k, each with a spring and a dashpot.
std::string chainScene(int n) {
  std::string bodies, joints;
  for (int k = 0; k < n; ++k) {
    const std::string name = "b" + std::to_string(k), parent = k == 0 ? "ground" : "b" + std::to_string(k - 1);
    bodies += std::string(k ? ", " : "") + "{\"name\": \"" + name +
              "\", \"mass\": 1.0, \"inertia\": [0.1, 0.08, 0.05], \"position\": [0, 0, " +
              std::to_string(-0.5 * k - 0.25) + "]}";
    joints += std::string(k ? ", " : "") + "{\"name\": \"j" + std::to_string(k) +
              "\", \"type\": \"revolute\", \"main\": \"" + parent + "\", \"secondary\": \"" + name +
              "\", \"anchor_main\": [0, 0, " + (k == 0 ? "0" : "-0.25") +
              "], \"anchor_secondary\": [0, 0, 0.25], \"axis_main\": " + (k % 2 ? "[1, 0, 0]" : "[0, 1, 0]") +
              ", \"spring\": {\"stiffness\": 4.0}, \"damper\": {\"damping\": 0.05}}";
  }
  return "{\"name\": \"chain\", \"gravity\": [0, 0, -9.81], \"bodies\": [" + bodies + "], \"joints\": [" + joints +
         "]}";
}

struct Chain {
  SceneDescription scene;
  std::unique_ptr<ArticulatedScene> tree;
  VecJ q, u;
};

Chain& chain(int n) {
  static std::map<int, Chain> chains;
  auto it = chains.find(n);
  if (it != chains.end()) return it->second;
  Chain& c = chains[n];
  c.scene = parseScene(chainScene(n), "chain.json");
  c.tree = assembleArticulated(c.scene);
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> angle(-0.8, 0.8), rate(-2.0, 2.0);
  c.q.resize(n);
  c.u.resize(n);
  for (int j = 0; j < n; ++j) {
    c.q[j] = Jet(angle(gen), j % 8);
    c.u[j] = Jet(rate(gen), (j + 4) % 8);
  }
  return c;
}

template <bool kNewtonEuler>
void BM_ForwardDynamics(benchmark::State& st) {
  Chain& c = chain(static_cast<int>(st.range(0)));
  const ArticulatedModel& model = c.tree->system->model();
  const ScalarDynamics<Jet> dynamics(model);
  const CoordinateForces<Jet> forces = modelForces<Jet>(model);
  for (auto _ : st) {
    VecJ udot = kNewtonEuler ? dynamics.newtonEulerAccelerations(0.1, c.q, c.u, forces)
                             : dynamics.articulatedBodyAccelerations(0.1, c.q, c.u, forces);
    benchmark::DoNotOptimize(udot.data());
  }
}
BENCHMARK_TEMPLATE(BM_ForwardDynamics, true)->Name("BM_NewtonEulerColumns")->DenseRange(2, 12, 1)->Arg(16)->Arg(24);
BENCHMARK_TEMPLATE(BM_ForwardDynamics, false)->Name("BM_ArticulatedBody")->DenseRange(2, 12, 1)->Arg(16)->Arg(24);

/// Collects each run's CPU time by name, besides the console table.
class Collect : public benchmark::ConsoleReporter {
 public:
  std::map<std::string, double> ns;
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) ns[r.benchmark_name()] = r.GetAdjustedCPUTime();
    ConsoleReporter::ReportRuns(runs);
  }
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  Collect reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  std::printf("\n   n  Newton-Euler columns / articulated-body algorithm (ceres::Jet<double, 8>)\n");
  int largest_faster = 0;  // the end of the run of n from 2 where the columns are faster
  bool unbroken = true;
  for (int n : {2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 16, 24}) {
    const auto a = reporter.ns.find("BM_NewtonEulerColumns/" + std::to_string(n));
    const auto b = reporter.ns.find("BM_ArticulatedBody/" + std::to_string(n));
    if (a == reporter.ns.end() || b == reporter.ns.end()) continue;
    const double ratio = a->second / b->second;
    unbroken = unbroken && ratio < 1.0;
    if (unbroken) largest_faster = n;
    std::printf("%4d  %.2f\n", n, ratio);
  }
  std::printf("largest n of an unbroken run from 2 where the columns are faster: %d\n", largest_faster);
  benchmark::Shutdown();
  return 0;
}
