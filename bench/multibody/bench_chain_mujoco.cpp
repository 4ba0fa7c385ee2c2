// MuJoCo beside bench_chain.cpp: the same chain of N rods on revolute joints
// (chain_scene.hpp) as an MJCF model, stepped by mj_step with MuJoCo's RK4, implicit and
// semi-implicit Euler integrators at h = 1e-3, released at rest like
// BM_ChainStep_rkmk4:
//  * BM_ChainStep_mujoco_rk4/N, BM_ChainStep_mujoco_euler/N,
//    BM_ChainStep_mujoco_implicit/N (MuJoCo 2.2's "implicit": Euler with the
//    velocity derivatives of the passive forces taken implicitly): one mj_step.
//
// Compiled only when CMake found MuJoCo (CMakeLists.txt: the detection of
// bench/integrators, define LIEFLOW_BENCH_CHAIN_MUJOCO); bench_chain.cpp's
// summary then prints these families' t(1000)/t(100) too, and lieflow's time
// per step over MuJoCo's at each N.
//
// The model: nested bodies rod0 ⊃ rod1 ⊃ …, body i's frame at its hinge
// (rod0's at the world origin, rod i's 0.5 m along its parent's x), one hinge
// joint per body about z (i even) or y (i odd) in its frame — the frame
// lieflow's axes are given in, since a hinge turns the body about its own axis
// — and <inertial pos="0.25 0 0" mass=m_i fullinertia=…> with lieflow's masses
// and inertia (about the centre of mass, body axes). No geoms, contacts
// disabled, no damping, armature or limits; gravity (0, 0, −9.81). qpos = the
// joint angles of lieflow's initial state (recovered from its poses), qvel = 0.
//
// Checks (counters of the benchmark, so they travel with the JSON output):
//  * pose_diff: max over the bodies of |Δ CoM| [m] and ‖Δ R‖ between MuJoCo's
//    initial kinematics and lieflow's initial poses (an error above 1e-9
//    stops the benchmark: the two would not be the same chain);
//  * com_diff_0.1s (N ≤ 300): max |Δ CoM| [m] after 100 steps (t = 0.1 s)
//    between this MuJoCo integrator and lieflow's projected RKMK4, both at
//    h = 1e-3 — the same motion, up to the integrators' errors.
//
// MuJoCo works in joint coordinates: for a serial chain its joint-space
// inertia M is dense (every joint carries all the bodies after it, nM =
// N(N+1)/2, counter nM), and every mj_forward builds M by the
// composite-rigid-body algorithm and factorizes it (mj_factorM → mj_factorI,
// L'DL over the kinematic tree, which has no branch to exploit here: about
// N³/6 multiply-adds). The measured cost per step is what it is;
// bench_chain.cpp prints its ratios beside lieflow's.
#include <benchmark/benchmark.h>
#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "bench/multibody/chain_scene.hpp"
#include "model/import/mjcf_model.hpp"
#include "integrators/butcher_tableau.hpp"
#include "integrators/projected_stepper.hpp"
#include "integrators/rkmk.hpp"
#include "dynamics/maximal/multibody_system.hpp"

namespace lieflow {
namespace bench {

/// "MuJoCo 2.2.2 (header 222)": the library version, for the benchmark context.
std::string chainMujocoDescription() {
  return std::string("MuJoCo ") + mj_versionString() + " (header " + std::to_string(mjVERSION_HEADER) + ")";
}

}  // namespace bench
}  // namespace lieflow

namespace {

using namespace lieflow;
using namespace lieflow::multibody;
using Eigen::Matrix3d;
using Eigen::Vector3d;

enum class MjIntegrator { kEuler, kRk4, kImplicit };

/// Hinge axis of joint i in its parent's (= its own) frame, as chain_builder.hpp.
Vector3d hingeAxis(int i) { return (i % 2) ? Vector3d(0, 1, 0) : Vector3d(0, 0, 1); }

/// lieflow's chain and its initial state (at rest, like BM_ChainStep_rkmk4).
struct LieflowChain {
  MultibodyModel model;
  MultibodyState state;
  std::vector<double> angles;  ///< joint angle i: R_i = R_{i−1} exp(angle_i a_i)
  explicit LieflowChain(int n) {
    model = bench::revoluteChain(n, bench::kChainSeed, &state);
    for (auto& v : state.velocities) v = BodyVelocity<double>{};
    SO3d parent = SO3d::identity();
    for (int i = 0; i < n; ++i) {
      const Vector3d theta = (parent.inverse() * state.poses[i].R).log();
      angles.push_back(theta.dot(hingeAxis(i)));
      parent = state.poses[i].R;
    }
  }
};

/// Bodies per MJCF file: tinyxml2 (9.0, which MuJoCo 2.2.2 parses with)
/// refuses documents nested more than about 100 elements deep (N = 100 in
/// one file fails: XML_ELEMENT_DEPTH_EXCEEDED), so the chain is
/// split into files of kBodiesPerFile nested bodies, each <include>d inside
/// the innermost body of the previous one (MJCF allows nested includes; the
/// assembled document is deep, but no single parse is).
constexpr int kBodiesPerFile = 40;

/// The chain as MJCF files, in memory: files[0] is the model, files[k]
/// holds bodies [kBodiesPerFile k, kBodiesPerFile (k + 1)). %.17g round-trips
/// every double.
std::vector<std::pair<std::string, std::string>> chainXml(const LieflowChain& c, MjIntegrator integrator,
                                                          double h) {
  const int n = static_cast<int>(c.model.bodies.size());
  auto fileName = [](int k) { return "lieflow_chain_" + std::to_string(k) + ".xml"; };
  std::vector<std::pair<std::string, std::string>> files;
  char buf[1024];
  std::snprintf(buf, sizeof buf,
                "<mujoco model=\"lieflow-chain-%d\">\n"
                "  <option timestep=\"%.17g\" gravity=\"0 0 -9.81\" integrator=\"%s\">\n"
                "    <flag contact=\"disable\"/>\n"
                "  </option>\n"
                "  <worldbody>\n"
                "    <include file=\"%s\"/>\n"
                "  </worldbody>\n"
                "</mujoco>\n",
                n, h, integrator == MjIntegrator::kRk4        ? "RK4"
                : integrator == MjIntegrator::kImplicit ? "implicit"
                                                        : "Euler", fileName(1).c_str());
  files.emplace_back(fileName(0), buf);
  for (int k = 1, first = 0; first < n; ++k, first += kBodiesPerFile) {
    const int last = std::min(n, first + kBodiesPerFile);
    std::string xml = "<mujoco>\n";
    for (int i = first; i < last; ++i) {
      const RigidBody& b = c.model.bodies[i];
      const Matrix3d& I = b.inertia;
      const Vector3d a = hingeAxis(i);
      // fullinertia = "ixx iyy izz ixy ixz iyz".
      std::snprintf(buf, sizeof buf,
                    "<body name=\"rod%d\" pos=\"%s\">\n"
                    "<joint name=\"hinge%d\" type=\"hinge\" pos=\"0 0 0\" axis=\"%g %g %g\"/>\n"
                    "<inertial pos=\"0.25 0 0\" mass=\"%.17g\" "
                    "fullinertia=\"%.17g %.17g %.17g %.17g %.17g %.17g\"/>\n",
                    i, i == 0 ? "0 0 0" : "0.5 0 0", i, a.x(), a.y(), a.z(), b.mass, I(0, 0), I(1, 1),
                    I(2, 2), I(0, 1), I(0, 2), I(1, 2));
      xml += buf;
    }
    if (last < n) xml += "<include file=\"" + fileName(k + 1) + "\"/>\n";
    for (int i = first; i < last; ++i) xml += "</body>\n";
    xml += "</mujoco>\n";
    files.emplace_back(fileName(k), std::move(xml));
  }
  return files;
}

using ModelPtr = model_import::MjcfModel;
using DataPtr = model_import::MjcfData;

/// Sets d to lieflow's initial state: joint angles, at rest, t = 0.
void resetChain(const mjModel* m, mjData* d, const LieflowChain& c) {
  mj_resetData(m, d);
  for (int i = 0; i < m->nq; ++i) d->qpos[i] = c.angles[i];
  mju_zero(d->qvel, m->nv);
  d->time = 0.0;
}

/// max over the bodies of |Δ CoM| and of ‖Δ R‖ (Frobenius) between MuJoCo's
/// kinematics at d (mj_kinematics called here) and lieflow's poses.
std::pair<double, double> poseDiff(const mjModel* m, mjData* d, const MultibodyState& s) {
  mj_kinematics(m, d);
  double dp = 0.0, dr = 0.0;
  for (int i = 0; i < static_cast<int>(s.poses.size()); ++i) {
    const int b = i + 1;  // body 0 is the world
    const Vector3d p(d->xipos[3 * b], d->xipos[3 * b + 1], d->xipos[3 * b + 2]);
    const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> R(d->xmat + 9 * b);
    dp = std::max(dp, (p - s.poses[i].p).norm());
    dr = std::max(dr, (Matrix3d(R) - s.poses[i].R.matrix()).norm());
  }
  return {dp, dr};
}

/// The timed runs start again from the initial state every kResetSteps steps
/// (1 s; outside the timing): the falling chain whips, and MuJoCo's
/// semi-implicit Euler at h = 1e-3 blows up after a few seconds (N = 30:
/// t ≈ 2.5 s), after which mj_step would time its reset-on-NaN path.
constexpr long kResetSteps = 1000;

constexpr int kCheckSteps = 100;   // t = 0.1 s at h = 1e-3
constexpr int kCheckMaxN = 300;    // the lieflow reference run is skipped above

/// lieflow's projected RKMK4 state after kCheckSteps steps from rest (cached per N).
const MultibodyState& lieflowAfterCheckSteps(int n) {
  static std::map<int, MultibodyState> cache;
  auto it = cache.find(n);
  if (it != cache.end()) return it->second;
  LieflowChain c(n);
  const MultibodySystem system(c.model, {});
  MultibodyGroupState y = system.makeState(c.state);
  ProjectedStepper<RkmkStepper<MultibodyGroupState>> stepper(
      RkmkStepper<MultibodyGroupState>(ButcherTableau::rk4()));
  StepReport report;
  double t = 0.0;
  for (int k = 0; k < kCheckSteps; ++k) {
    y = stepper.step(system, t, y, bench::kChainStep, &report);
    t += bench::kChainStep;
  }
  return cache.emplace(n, y.bodies).first->second;
}

/// Compiled models, per (N, integrator): compiling N = 1000 nested bodies
/// takes a while and Google Benchmark calls the function several times.
const mjModel* chainModel(int n, MjIntegrator integrator, std::string* error) {
  static std::map<std::pair<int, int>, ModelPtr> cache;
  const auto key = std::make_pair(n, static_cast<int>(integrator));
  auto it = cache.find(key);
  if (it != cache.end()) return it->second.get();
  ModelPtr m;
  try {
    m = model_import::compileModelFiles(chainXml(LieflowChain(n), integrator, bench::kChainStep), "chain");
  } catch (const std::exception& e) {
    *error = e.what();
    return nullptr;
  }
  if (m->nq != n || m->nv != n || m->nbody != n + 1) {
    *error = "unexpected model sizes (nq, nv, nbody)";
    return nullptr;
  }
  return cache.emplace(key, std::move(m)).first->second.get();
}

void mujocoChainSteps(benchmark::State& st, MjIntegrator integrator) {
  const int n = static_cast<int>(st.range(0));
  std::string error;
  const mjModel* m = chainModel(n, integrator, &error);
  if (!m) {
    st.SkipWithError(("MuJoCo: " + error).c_str());
    return;
  }
  DataPtr d(mj_makeData(m));
  if (!d) {
    st.SkipWithError("MuJoCo: mj_makeData failed");
    return;
  }
  const LieflowChain c(n);
  resetChain(m, d.get(), c);
  const auto diff0 = poseDiff(m, d.get(), c.state);
  if (!(diff0.first <= 1e-9 && diff0.second <= 1e-9)) {
    char msg[200];
    std::snprintf(msg, sizeof msg, "MuJoCo chain differs from lieflow's: |dCoM| %.3g m, |dR| %.3g", diff0.first,
                  diff0.second);
    st.SkipWithError(msg);
    return;
  }
  resetChain(m, d.get(), c);

  // MuJoCo warnings (NaN/huge qacc, ...) over the run; mj_resetData clears them.
  auto warnings = [&d] {
    long count = 0;
    for (int w = 0; w < mjNWARNING; ++w) count += d->warning[w].number;
    return count;
  };
  long steps = 0, warned = 0;
  for (auto _ : st) {
    mj_step(m, d.get());
    if (++steps % kResetSteps == 0) {
      st.PauseTiming();
      warned += warnings();
      resetChain(m, d.get(), c);
      st.ResumeTiming();
    }
  }
  warned += warnings();
  if (warned > 0) {
    st.SkipWithError(("MuJoCo warned " + std::to_string(warned) + " times during the run").c_str());
    return;
  }
  st.counters["pose_diff"] = std::max(diff0.first, diff0.second);
  st.counters["nM"] = m->nM;
  if (n <= kCheckMaxN) {
    static std::map<std::pair<int, int>, double> com_diff;  // per (N, integrator)
    const auto key = std::make_pair(n, static_cast<int>(integrator));
    if (!com_diff.count(key)) {
      const MultibodyState& ref = lieflowAfterCheckSteps(n);
      resetChain(m, d.get(), c);
      for (int i = 0; i < kCheckSteps; ++i) mj_step(m, d.get());
      com_diff[key] = poseDiff(m, d.get(), ref).first;
    }
    st.counters["com_diff_0.1s"] = com_diff[key];
  }
  st.SetComplexityN(n);
}

void BM_ChainStep_mujoco_rk4(benchmark::State& st) { mujocoChainSteps(st, MjIntegrator::kRk4); }
void BM_ChainStep_mujoco_euler(benchmark::State& st) { mujocoChainSteps(st, MjIntegrator::kEuler); }
void BM_ChainStep_mujoco_implicit(benchmark::State& st) { mujocoChainSteps(st, MjIntegrator::kImplicit); }

BENCHMARK(BM_ChainStep_mujoco_rk4)
    ->Arg(1)->Arg(2)->Arg(10)->Arg(30)->Arg(100)->Arg(300)->Arg(1000)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ChainStep_mujoco_euler)
    ->Arg(1)->Arg(2)->Arg(10)->Arg(30)->Arg(100)->Arg(300)->Arg(1000)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ChainStep_mujoco_implicit)->Arg(1)->Arg(2)->Arg(10)->Arg(30)->Unit(benchmark::kMicrosecond);

}  // namespace
