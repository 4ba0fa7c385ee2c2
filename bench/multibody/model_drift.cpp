// study_model_drift: long runs of an MJCF model by lieflow's integrators and
// by MuJoCo's beside them (peers/mujoco/mujoco_peer.hpp), measuring what a
// free-floating mechanism with dashpots conserves: its angular momentum
// about the centre of mass (L_com) and its energy plus the work its dashpots
// dissipated (energy_balance), both relative to their initial values, as
// each engine measures them (lieflow: simulation/invariants.hpp; MuJoCo: its own
// energy, body velocities and dashpot power). papers/humanoid-free-fall runs it.
//
//   study_model_drift MODEL.xml OUT_DIR T_END SAMPLES IGNORE KEYFRAME RUN...
//   RUN = INTEGRATOR:DT (lieflow's names, or mujoco-euler|rk4|implicit)
//
// Writes OUT_DIR/summary.csv (integrator,dt,steps,wall_seconds,ns_per_step,
// energy_drift,L_com_drift,energy_balance_drift,failed,failure: the drifts
// the largest over every step, the time a second run with the measuring
// off) and OUT_DIR/samples.csv (integrator,dt,t,L_com_error,
// energy_balance_error at about SAMPLES instants per run).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <string>
#include <vector>

#include "integrators/integrate.hpp"
#include "model/import/model_import.hpp"
#include "peers/mujoco/mujoco_peer.hpp"
#include "simulation/simulation.hpp"

namespace {

using namespace lieflow;  // NOLINT: a one-purpose program

struct Row {
  std::string integrator;
  double dt = 0.0;
  long steps = 0;
  double wall = 0.0, energy = 0.0, L_com = -1.0, balance = -1.0;
  bool failed = false;
  std::string failure;
};

bool isPeer(const std::string& name) { return name.rfind("mujoco-", 0) == 0; }

}  // namespace

int main(int argc, char** argv) {
  if (argc < 8) {
    std::fprintf(stderr, "usage: %s MODEL.xml OUT_DIR T_END SAMPLES IGNORE KEYFRAME INTEGRATOR:DT...\n", argv[0]);
    return 2;
  }
  try {
    const std::string path = argv[1], out = argv[2];
    const double t_end = std::atof(argv[3]);
    const long samples = std::atol(argv[4]);
    ModelImportOptions options = parseIgnoreList(argv[5]);
    options.keyframe = argv[6];
    const SceneDescription scene = importModel(path, options);
    const Simulation sim(scene);
    const MujocoPeer peer(path, options, scene);
    const std::vector<std::string> names = sim.invariantNames();
    std::ofstream summary(out + "/summary.csv"), trace(out + "/samples.csv");
    summary << "integrator,dt,steps,wall_seconds,ns_per_step,energy_drift,L_com_drift,energy_balance_drift,failed,"
               "failure\n";
    trace << "integrator,dt,t,L_com_error,energy_balance_error\n";
    trace.precision(6);
    summary.precision(6);
    for (int a = 7; a < argc; ++a) {
      const std::string run = argv[a];
      const std::size_t colon = run.find(':');
      Row r;
      r.integrator = run.substr(0, colon);
      r.dt = std::atof(run.substr(colon + 1).c_str());
      const long steps = stepCount(0.0, t_end, r.dt);
      const long every = std::max(1L, steps / std::max(1L, samples));
      std::fprintf(stderr, "study_model_drift: %s at dt %g for %g s\n", r.integrator.c_str(), r.dt, t_end);
      if (isPeer(r.integrator)) {
        const MujocoPeerRun d = peer.run(r.integrator, r.dt, t_end, true, every);
        r.steps = d.steps;
        r.failed = d.failed;
        r.failure = d.failure;
        r.energy = d.energy_drift;
        r.L_com = d.com_momentum_drift;
        r.balance = d.energy_balance_drift;
        if (!d.failed) {
          const MujocoPeerSample& s0 = d.samples.front();
          for (const MujocoPeerSample& s : d.samples)
            trace << r.integrator << "," << r.dt << "," << s.t << ","
                  << (s.L_com - s0.L_com).norm() / s0.L_com.norm() << ","
                  << std::abs(s.energy + s.dissipated_work - s0.energy) / std::abs(s0.energy) << "\n";
          r.wall = peer.run(r.integrator, r.dt, t_end, false, 1).wall_seconds;
        }
      } else {
        SimulationOptions o;
        o.integrator = r.integrator;
        o.dt = r.dt;
        o.t_end = t_end;
        o.every = static_cast<int>(every);
        o.check_every = 1;  // the drifts of every step, as MuJoCo's are measured
        o.max_steps = steps + 1;
        o.invariant_sink = [&](double t, const std::vector<double>& errors) {
          trace << r.integrator << "," << r.dt << "," << t;
          for (const char* wanted : {"L_com", "energy_balance"}) {
            trace << ",";
            for (std::size_t i = 0; i < names.size(); ++i)
              if (names[i] == wanted) trace << errors[i];
          }
          trace << "\n";
        };
        const SimulationResult d = sim.run(o, [](const std::vector<double>&) {});
        r.steps = d.steps;
        r.failed = d.failed;
        r.failure = d.failure;
        r.energy = d.energy_drift;
        for (const auto& [name, drift] : d.invariants) {
          if (name == "L_com") r.L_com = drift;
          if (name == "energy_balance") r.balance = drift;
        }
        if (!d.failed) {
          o.diagnostics = false;
          o.invariant_sink = nullptr;
          r.wall = sim.run(o).wall_seconds;
        }
      }
      std::string failure = r.failure;
      for (char& c : failure)
        if (c == '"') c = '\'';
      summary << r.integrator << "," << r.dt << "," << r.steps << ",";
      if (r.failed)
        summary << ",,,,,true,\"" << failure << "\"\n";
      else
        summary << r.wall << "," << 1e9 * r.wall / r.steps << "," << r.energy << "," << r.L_com << "," << r.balance
                << ",false,\"\"\n";
      summary.flush();
      trace.flush();
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "study_model_drift: %s\n", e.what());
    return 2;
  }
  return 0;
}
