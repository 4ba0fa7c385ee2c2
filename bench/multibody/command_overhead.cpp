/// \file
/// What the command costs beyond its stepper (issue: "the command costs what
/// the stepper costs"): for the benchmark chain of bench_chain.cpp in joint
/// coordinates, N = 1, 10, 30, and each integrator family, rounds that
/// alternate
///   (a) the stepper alone, as BM_ChainStep_joint_<integrator> steps it
///       (y = stepper.step(system, t, y, h), h = 1e-3, the chain released at
///       rest), timed with std::chrono over the steps of the run, and
///   (b) the command a user runs on the same chain written as a scene file:
///       `lieflow simulate CHAIN.json --integrator X --dt 1e-3 --t-end T
///       --every 1000000000 --stats --out /dev/null`, its ns_per_step (the
///       run loop: stepper, observer, the checks at the rows);
/// and prints the median of each and their ratio (target <= 1.1).
///
/// Usage: study_command_overhead [LIEFLOW] [--rounds R] [--steps S]
/// (LIEFLOW: the lieflow command, default the one built beside this program).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/multibody/chain_scene.hpp"
#include "integrators/butcher_tableau.hpp"
#include "integrators/commutator_free.hpp"
#include "integrators/generalized_alpha.hpp"
#include "integrators/joint_space_variational.hpp"
#include "integrators/rkmk.hpp"
#include "dynamics/joint_space/articulated_second_order.hpp"
#include "dynamics/joint_space/articulated_scene.hpp"
#include "model/scene_writer.hpp"

namespace {

using namespace lieflow;

/// Nanoseconds per step of `stepper` over `steps` steps from y0.
template <typename Stepper>
double stepperNs(Stepper stepper, const articulated::ArticulatedSystem& system,
                 const articulated::ArticulatedState& y0, long steps) {
  articulated::ArticulatedState y = y0;
  double t = 0.0;
  StepReport report;
  double iterations = 0.0;
  const auto start = std::chrono::steady_clock::now();
  for (long k = 0; k < steps; ++k) {
    y = stepper.step(system, t, y, bench::kChainStep, &report);
    t += bench::kChainStep;
    iterations += report.newton_iterations;
  }
  const auto stop = std::chrono::steady_clock::now();
  if (!report.converged) {
    std::cerr << "study_command_overhead: the stepper failed: " << report.failure << "\n";
    std::exit(1);
  }
  if (std::getenv("LIEFLOW_DEBUG")) std::cerr << "iterations " << iterations / steps << "\n";
  return 1e9 * std::chrono::duration<double>(stop - start).count() / static_cast<double>(steps);
}

double stepperNs(const std::string& integrator, const articulated::ArticulatedSystem& system,
                 const articulated::ArticulatedState& y0, long steps) {
  if (integrator == "rkmk4")
    return stepperNs(RkmkStepper<articulated::ArticulatedState>(ButcherTableau::rk4()), system, y0, steps);
  if (integrator == "cf4") return stepperNs(CommutatorFree4Stepper<articulated::ArticulatedState>(), system, y0, steps);
  if (integrator == "genalpha")
    return stepperNs(GeneralizedAlphaStepper<articulated::ArticulatedState>(GeneralizedAlphaOptions{}), system, y0,
                     steps);
  return stepperNs(JointSpaceVariationalStepper<articulated::ArticulatedSystem>(JointSpaceVariationalOptions{}),
                   system, y0, steps);
}

/// The command's ns_per_step (--stats) on the scene file.
double commandNs(const std::string& lieflow, const std::string& scene, const std::string& integrator, long steps) {
  char t_end[64];
  std::snprintf(t_end, sizeof t_end, "%.6f", static_cast<double>(steps) * bench::kChainStep);
  const std::string command = lieflow + " simulate " + scene + " --integrator " + integrator +
                              " --dt 0.001 --t-end " + t_end + " --every 1000000000 --stats --quiet --out /dev/null";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) {
    std::cerr << "study_command_overhead: cannot run " << command << "\n";
    std::exit(1);
  }
  std::string out;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe)) out += buffer;
  if (pclose(pipe) != 0) {
    std::cerr << "study_command_overhead: " << command << " failed:\n" << out << "\n";
    std::exit(1);
  }
  const nlohmann::json stats = nlohmann::json::parse(out);
  if (stats.at("formulation") != "joint") {
    std::cerr << "study_command_overhead: the command ran " << stats.at("formulation") << " coordinates\n";
    std::exit(1);
  }
  return stats.at("ns_per_step").get<double>();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  std::string lieflow = LIEFLOW_COMMAND;
  int rounds = 7;
  long steps = 20000;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--rounds" && i + 1 < argc) {
      rounds = std::max(1, std::atoi(argv[++i]));
    } else if (a == "--steps" && i + 1 < argc) {
      steps = std::max(100L, std::atol(argv[++i]));
    } else {
      lieflow = a;
    }
  }
  std::printf("| N | integrator | stepper (us/step) | command (us/step) | command / stepper |\n");
  std::printf("|---|---|---|---|---|\n");
  for (const int n : {1, 10, 30}) {
    SceneDescription scene = bench::revoluteChainScene(n, bench::kChainSeed);
    const std::string file = "/tmp/lieflow-command-overhead-chain-" + std::to_string(n) + ".json";
    std::ofstream(file) << sceneToJson(scene);
    // The stepper runs the scene the command reads (the file read back).
    const auto assembled = assembleArticulated(loadScene(file));
    for (const std::string integrator : {"rkmk4", "cf4", "lgvi", "genalpha"}) {
      // Fewer steps for the implicit steppers at N = 30 (a round stays ~0.5 s).
      const long s = (integrator == "genalpha" || integrator == "lgvi") && n >= 10 ? steps / 4 : steps;
      std::vector<double> a, b;
      for (int r = 0; r < rounds; ++r) {
        a.push_back(stepperNs(integrator, *assembled->system, assembled->y0, s));
        b.push_back(commandNs(lieflow, file, integrator, s));
      }
      const double ma = median(a), mb = median(b);
      std::printf("| %d | %s | %.3f | %.3f | %.3f |\n", n, integrator.c_str(), ma / 1e3, mb / 1e3, mb / ma);
      std::fflush(stdout);
    }
  }
  return 0;
}
