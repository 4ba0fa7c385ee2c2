// Error against run time on mechanisms, lieflow beside MuJoCo on the same
// model (papers/mechanism-work-precision/): for each scene (default
// double-pendulum, chain-10 and cardan-shaft-free, end time T = 2 s), every
// lieflow integrator that runs it — in joint coordinates and in maximal
// coordinates (rkmk4, cf4, rkmk45 over a range of tolerances, lgvi,
// genalpha) — and MuJoCo's RK4, Euler and implicit
// integrators over a range of steps. The error is the largest distance [m]
// between a body's centre of mass at T and the reference's, and for a
// rotation-only body (its centre held) the angle [rad] between its
// orientation and the reference's; the run time is the median wall time of
// the whole run (repeated until 0.2 s were spent, at most 201 times).
//
// cardan-shaft-free: the built-in Cardan shaft with its input's prescribed
// motion removed (both shafts spin freely, joined by the cross: a closed
// loop of one degree of freedom, whose speed ratio swings between cos β and
// 1/cos β). It runs in joint coordinates with the loop closed by multipliers
// (rkmk4, cf4) and in maximal coordinates. MuJoCo closes the loop with soft
// equality constraints (peers/mujoco/tree_mjcf.hpp: a connect and a fixed-length
// tendon for the cross; solimp 0.9999): with its default time constant
// (solref 0.02 s) and with the stiffest one, 2h, whose softness vanishes as
// h → 0 (its runs then converge at second order in h, whatever the
// integrator: the loop's softness is the error).
//
// The reference: lieflow's rkmk4 in joint coordinates at h = 1e-5, checked
// against the same at 2e-5 (its own error, printed) and against MuJoCo's RK4
// at 1e-5 (the two engines on the same model, printed). The MuJoCo model is
// written from lieflow's tree (peers/mujoco/tree_mjcf.hpp) and starts from lieflow's
// initial state; their initial centres of mass agree to ~1e-16 m (printed).
//
// usage: study_mechanism_work_precision OUT.csv [T [SCENE...]]
#include <mujoco/mujoco.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "model/import/mjcf_model.hpp"
#include "peers/mujoco/tree_mjcf.hpp"
#include "dynamics/joint_space/articulated_scene.hpp"
#include "model/scene.hpp"
#include "simulation/simulation.hpp"

namespace {

using namespace lieflow;
using Clock = std::chrono::steady_clock;

constexpr double kReferenceStep = 1e-5;
/// A run is repeated until kMinTimingSeconds were spent, at most kMaxRepeats
/// times (at least once): the median of up to 201 runs, so that the shortest
/// runs (0.1 ms, 25 steps) are timed as well as the longest.
constexpr double kMinTimingSeconds = 0.2;
constexpr int kMaxRepeats = 201;
/// The solref time constants of a loop's equality constraints MuJoCo runs
/// with, in steps h (0: MuJoCo's default 0.02 s). 2h is the stiffest its
/// refsafe flag lets through (shorter ones are raised to 2h) and the most
/// accurate: on the free Cardan shaft 10h gave 38–180× larger errors at the
/// same h, the default a floor of 0.15 rad.
constexpr double kLoopStiffness[] = {0.0, 2.0};

/// The end of a run by body name: the centre of mass, or the orientation of
/// a rotation-only body (its centre is held).
struct Pose {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  bool rotation_only = false;
};
using Positions = std::map<std::string, Pose>;

/// max over bodies of |Δ centre of mass| [m], or of the rotation angle
/// between the orientations [rad] for a rotation-only body.
double maxDistance(const Positions& a, const Positions& b) {
  double worst = 0.0;
  for (const auto& [name, x] : a) {
    const Pose& y = b.at(name);
    worst = std::max(worst, x.rotation_only ? x.q.angularDistance(y.q) : (x.p - y.p).norm());
  }
  return worst;
}

/// A scene of the study by name: a built-in one, or cardan-shaft-free.
SceneDescription studyScene(const std::string& name) {
  if (name != "cardan-shaft-free") return loadScene(name);
  SceneDescription s = loadScene("cardan-shaft");
  s.name = name;
  for (JointDescription& j : s.joints)
    for (CoordinateDescription& c : j.coordinates) c.prescribed.reset();
  return s;
}

struct Measured {
  double seconds = 0.0;
  long steps = 0;
  bool failed = false;
  std::string failure;
  Positions positions;
};

/// Median of the wall times of `run` (each returns its own seconds).
Measured timed(const std::function<Measured()>& run) {
  std::vector<double> times;
  Measured m;
  double spent = 0.0;
  while (times.size() < static_cast<std::size_t>(kMaxRepeats) && (times.empty() || spent < kMinTimingSeconds)) {
    m = run();
    if (m.failed) return m;
    times.push_back(m.seconds);
    spent += m.seconds;
  }
  std::sort(times.begin(), times.end());
  m.seconds = times[times.size() / 2];
  return m;
}

Measured runLieflow(const Simulation& sim, const std::string& formulation, const std::string& integrator, double dt,
                    double t_end, double rtol) {
  SimulationOptions o;
  o.integrator = integrator;
  o.formulation = formulation;
  o.dt = dt;
  o.t_end = t_end;
  o.diagnostics = false;
  o.max_steps = 100000000;
  if (rtol > 0.0) o.integrator_options = {{"rtol", rtol}, {"atol", rtol * 1e-3}};
  const SimulationResult r = sim.run(o);
  Measured m;
  m.seconds = r.wall_seconds;
  m.steps = r.steps;
  m.failed = r.failed;
  m.failure = r.failure;
  const std::vector<std::string> columns = sim.columns();
  auto value = [&](const std::string& column) {
    const auto it = std::find(columns.begin(), columns.end(), column);
    if (it == columns.end()) throw std::runtime_error("no column " + column);
    return r.final_row[it - columns.begin()];
  };
  for (const BodyDescription& b : sim.scene().bodies) {
    Pose x;
    x.rotation_only = b.rotation_only;
    if (b.rotation_only) {
      x.q = Eigen::Quaterniond(value(b.name + ".qw"), value(b.name + ".qx"), value(b.name + ".qy"),
                               value(b.name + ".qz"));
      if (!x.q.coeffs().allFinite()) m.failed = true;
    } else {
      for (int k = 0; k < 3; ++k) x.p[k] = value(b.name + "." + "xyz"[k]);
      if (!x.p.allFinite()) m.failed = true;
    }
    m.positions[b.name] = x;
  }
  return m;
}

/// MuJoCo's run of the tree with `integrator` at step h, the loops' equality
/// constraints at solref time constant `loop_timeconst` (0: MuJoCo's default).
Measured runMujoco(const ArticulatedScene& tree, const SceneDescription& scene, const std::string& integrator,
                   double h, double t_end, double loop_timeconst = 0.0) {
  mujoco_peer::MjcfOptions options;
  options.integrator = integrator;
  options.h = h;
  options.loop_timeconst = loop_timeconst;
  const model_import::MjcfModel model = model_import::compileModelFiles(
      {{"tree.xml", mujoco_peer::mjcfFromTree(tree.system->model(), options)}}, "tree.xml");
  const mjModel* m = model.get();
  const model_import::MjcfData d = model_import::makeMjcfData(m, "tree.xml");
  const long steps = std::lround(t_end / h);
  return timed([&] {
    mujoco_peer::setMujocoState(tree.system->model(), tree.y0, m, d.get());
    const auto start = Clock::now();
    for (long k = 0; k < steps; ++k) mj_step(m, d.get());
    Measured r;
    r.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    r.steps = steps;
    mj_kinematics(m, d.get());
    for (const BodyDescription& b : scene.bodies) {
      const int id = mj_name2id(m, mjOBJ_BODY, b.name.c_str());
      Pose x;
      x.rotation_only = b.rotation_only;
      x.p = Eigen::Vector3d(d->xipos[3 * id], d->xipos[3 * id + 1], d->xipos[3 * id + 2]);
      x.q = Eigen::Quaterniond(d->xquat[4 * id], d->xquat[4 * id + 1], d->xquat[4 * id + 2], d->xquat[4 * id + 3]);
      if (!x.p.allFinite() || !x.q.coeffs().allFinite() || d->warning[mjWARN_BADQACC].number > 0) {
        r.failed = true;
        r.failure = "MuJoCo's state became non-finite (mjWARN_BADQACC)";
      }
      r.positions[b.name] = x;
    }
    return r;
  });
}

/// The largest difference between MuJoCo's kinematics of the initial state
/// and lieflow's: centres of mass [m] and orientations [rad].
double initialDifference(const ArticulatedScene& tree) {
  const model_import::MjcfModel m = model_import::compileModelFiles(
      {{"tree.xml", mujoco_peer::mjcfFromTree(tree.system->model(), {})}}, "tree.xml");
  const model_import::MjcfData d = model_import::makeMjcfData(m.get(), "tree.xml");
  mujoco_peer::setMujocoState(tree.system->model(), tree.y0, m.get(), d.get());
  mj_kinematics(m.get(), d.get());
  tree.system->kinematics(0.0, tree.y0);
  double worst = 0.0;
  for (int i = 0; i < tree.system->bodyCount(); ++i) {
    const int id = mj_name2id(m.get(), mjOBJ_BODY, tree.system->model().names[i].c_str());
    const Eigen::Vector3d p(d->xipos[3 * id], d->xipos[3 * id + 1], d->xipos[3 * id + 2]);
    const Eigen::Quaterniond q(d->xquat[4 * id], d->xquat[4 * id + 1], d->xquat[4 * id + 2], d->xquat[4 * id + 3]);
    worst = std::max({worst, (p - tree.system->centreOfMass(i)).norm(),
                      q.angularDistance(Eigen::Quaterniond(tree.system->rotation(i)))});
  }
  return worst;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: study_mechanism_work_precision OUT.csv [T [SCENE...]]\n";
    return 2;
  }
  const std::string out_path = argv[1];
  const double t_end = argc > 2 ? std::stod(argv[2]) : 2.0;
  std::vector<std::string> scenes;
  for (int i = 3; i < argc; ++i) scenes.push_back(argv[i]);
  if (scenes.empty()) scenes = {"double-pendulum", "chain-10", "cardan-shaft-free"};
  std::ofstream out(out_path);
  out << "scene,engine,formulation,integrator,dt,rtol,steps,seconds,error,failed\n";
  out.precision(17);
  std::printf("MuJoCo %s, T = %g s\n", mj_versionString(), t_end);
  for (const std::string& name : scenes) {
    const SceneDescription scene = studyScene(name);
    const Simulation sim(scene);
    const std::unique_ptr<ArticulatedScene> tree = assembleArticulated(scene);
    // MuJoCo runs what MJCF can say (peers/mujoco/tree_mjcf.hpp); a loop it closes
    // with soft equality constraints, at each of kLoopStiffness.
    bool with_mujoco = true;
    try {
      mujoco_peer::mjcfFromTree(tree->system->model(), {});
    } catch (const std::invalid_argument& e) {
      with_mujoco = false;
      std::printf("%s: MuJoCo not run: %s\n", name.c_str(), e.what());
    }
    const bool loops = tree->system->hasClosures();
    // The reference and its checks.
    const Positions reference = runLieflow(sim, "joint", "rkmk4", kReferenceStep, t_end, 0.0).positions;
    const double self = maxDistance(runLieflow(sim, "joint", "rkmk4", 2 * kReferenceStep, t_end, 0.0).positions,
                                    reference);
    std::printf("%s: reference lieflow joint rkmk4 h = %g; against h = %g: %.3g\n", name.c_str(), kReferenceStep,
                2 * kReferenceStep, self);
    const double maximal = maxDistance(runLieflow(sim, "maximal", "rkmk4", kReferenceStep, t_end, 0.0).positions,
                                       reference);
    std::printf("%s: against lieflow maximal rkmk4 at h = %g: %.3g\n", name.c_str(), kReferenceStep, maximal);
    if (with_mujoco) {
      const double stiffest = loops ? kLoopStiffness[1] * kReferenceStep : 0.0;
      const Measured peer = runMujoco(*tree, scene, "RK4", kReferenceStep, t_end, stiffest);
      std::printf("%s: against MuJoCo RK4 at h = %g%s: %.3g; initial poses, MuJoCo against lieflow: %.3g\n",
                  name.c_str(), kReferenceStep, loops ? " (loop solref 2h)" : "",
                  maxDistance(peer.positions, reference), initialDifference(*tree));
    }
    auto row = [&](const char* engine, const std::string& formulation, const std::string& integrator, double dt,
                   double rtol, const Measured& m) {
      const double error = m.failed ? 0.0 : maxDistance(m.positions, reference);
      out << name << "," << engine << "," << formulation << "," << integrator << "," << dt << ",";
      if (rtol > 0) out << rtol;
      out << "," << m.steps << "," << m.seconds << ",";
      if (!m.failed) out << error;
      out << "," << (m.failed ? "true" : "false") << "\n";
      char what[64];
      std::snprintf(what, sizeof what, "%.3g", error);
      std::printf("  %-7s %-8s %-9s dt=%-10g rtol=%-7g steps=%-8ld %10.3g s  error %s\n", engine,
                  formulation.c_str(), integrator.c_str(), dt, rtol, m.steps, m.seconds,
                  m.failed ? ("failed: " + m.failure).c_str() : what);
      std::fflush(stdout);
    };
    std::vector<double> steps4, steps2, steps1;
    for (double h = 0.08; h > 1.2e-4; h /= 2) steps4.push_back(h);
    for (double h = 1e-2; h > 3e-5; h /= 2) steps2.push_back(h);
    for (double h = 4e-3; h > 7e-6; h /= 2) steps1.push_back(h);
    for (const char* integrator : {"rkmk4", "cf4"})
      for (double h : steps4)
        row("lieflow", "joint", integrator, h, 0, timed([&] { return runLieflow(sim, "joint", integrator, h, t_end, 0); }));
    for (const char* formulation : {"joint", "maximal"})
      if (sim.supports("rkmk45", nullptr, formulation))
        for (double rtol = 1e-2; rtol > 1e-13; rtol /= 10)
          row("lieflow", formulation, "rkmk45", t_end, rtol,
              timed([&] { return runLieflow(sim, formulation, "rkmk45", t_end, t_end, rtol); }));
    for (const char* integrator : {"rkmk4", "cf4"})
      for (double h : steps4)
        row("lieflow", "maximal", integrator, h, 0,
            timed([&] { return runLieflow(sim, "maximal", integrator, h, t_end, 0); }));
    for (const char* formulation : {"joint", "maximal"})
      for (const char* integrator : {"lgvi", "genalpha"})
        if (sim.supports(integrator, nullptr, formulation))
          for (double h : steps2)
            row("lieflow", formulation, integrator, h, 0,
                timed([&] { return runLieflow(sim, formulation, integrator, h, t_end, 0); }));
    if (!with_mujoco) continue;
    for (double stiffness : loops ? std::vector<double>(std::begin(kLoopStiffness), std::end(kLoopStiffness))
                                  : std::vector<double>{0.0}) {
      // The name says the loops' solref time constant: MuJoCo's default, or k h.
      auto label = [&](const std::string& integrator) {
        if (!loops) return integrator;
        char s[64];
        if (stiffness == 0.0)
          std::snprintf(s, sizeof s, " (loop solref 0.02 s)");
        else
          std::snprintf(s, sizeof s, " (loop solref %gh)", stiffness);
        return integrator + s;
      };
      auto mujoco = [&](const std::string& integrator, double h) {
        try {
          row("mujoco", "joint", label(integrator), h, 0,
              runMujoco(*tree, scene, integrator, h, t_end, stiffness * h));
        } catch (const std::runtime_error& e) {
          Measured failed;
          failed.failed = true;
          failed.failure = e.what();
          row("mujoco", "joint", label(integrator), h, 0, failed);
        }
      };
      for (double h : steps4) mujoco("RK4", h);
      for (const char* integrator : {"Euler", "implicit"})
        for (double h : steps1) mujoco(integrator, h);
    }
  }
  std::printf("wrote %s\n", out_path.c_str());
  return 0;
}
