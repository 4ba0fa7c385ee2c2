/// \file
/// MJCF keyframes as the start of an imported model (--keyframe) and MuJoCo
/// beside lieflow on the same model (peers/mujoco/mujoco_peer.hpp): the
/// same start, the same trajectory at a small step, MuJoCo's own measures of
/// its drifts, and the orders of its integrators.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <string>

#include "model/import/model_import.hpp"
#include "peers/mujoco/mujoco_peer.hpp"
#include "liegroup/invalid_input.hpp"
#include "tests/model/model_files.hpp"
#include "tests/simulation/scene_trajectory.hpp"

#ifdef LIEFLOW_HAVE_MUJOCO
#include <mujoco/mujoco.h>
#endif

namespace lieflow {
namespace {

using namespace scene_testing;  // NOLINT: Trajectory, simulate, model, refusal

ModelImportOptions keyframe(const std::string& key) {
  ModelImportOptions o;
  o.keyframe = key;
  return o;
}

TEST(MjcfKeyframe, NamedOrIndexedKeyframesStartTheSceneAndUnknownOnesAreListed) {
  if (!canReadMjcf()) GTEST_SKIP() << "this build has no MJCF reader";
  const SceneDescription at_rest = importModel(model("spinning.xml"), {});
  const SceneDescription rest = importModel(model("spinning.xml"), keyframe("rest"));
  const SceneDescription spin = importModel(model("spinning.xml"), keyframe("spin"));
  const SceneDescription one = importModel(model("spinning.xml"), keyframe("1"));
  ASSERT_EQ(spin.bodies.size(), 4u);
  for (std::size_t b = 0; b < spin.bodies.size(); ++b) {
    EXPECT_EQ(rest.bodies[b].position, at_rest.bodies[b].position);
    EXPECT_EQ(rest.bodies[b].angular_velocity.norm(), 0.0);
    EXPECT_EQ(one.bodies[b].velocity, spin.bodies[b].velocity);
    EXPECT_GT(spin.bodies[b].angular_velocity.norm(), 1.0);  // every body turns with the core
  }
  // The core's free joint: position (0.1, 0, 1.2) plus its centre's offset,
  // the hinge bent to 0.3 rad.
  EXPECT_NEAR(spin.bodies[0].position.z() - at_rest.bodies[0].position.z(), 0.2, 1e-15);
  const std::string why = refusal(model("spinning.xml"), keyframe("jump"));
  EXPECT_NE(why.find("spinning.xml: `keyframe`"), std::string::npos) << why;
  EXPECT_NE(why.find("no keyframe 'jump' (it has rest, spin)"), std::string::npos) << why;
  EXPECT_NE(refusal(model("spinning.xml"), keyframe("2")).find("no keyframe '2'"), std::string::npos);
  if (canReadUrdf()) {
    EXPECT_NE(refusal(model("arm6.urdf"), keyframe("0")).find("a URDF has no keyframes"), std::string::npos);
  }
}

#ifdef LIEFLOW_HAVE_MUJOCO
TEST(MjcfKeyframe, AKeyframeRunsAsMuJoCoRunsItFromThatKeyframe) {
  // Both fourth order at h = 1e-4 for 0.5 s from the bent, spinning key.
  const double h = 1e-4, t_end = 0.5;
  const SceneDescription scene = importModel(model("spinning.xml"), keyframe("spin"));
  const Trajectory tr = simulate(scene, "rkmk4", h, t_end, 5000);
  char error[512] = "";
  std::unique_ptr<mjModel, void (*)(mjModel*)> m(mj_loadXML(model("spinning.xml").c_str(), nullptr, error, sizeof error),
                                                 mj_deleteModel);
  ASSERT_TRUE(m) << error;
  m->opt.integrator = mjINT_RK4;
  m->opt.timestep = h;
  std::unique_ptr<mjData, void (*)(mjData*)> d(mj_makeData(m.get()), mj_deleteData);
  mj_resetDataKeyframe(m.get(), d.get(), mj_name2id(m.get(), mjOBJ_KEY, "spin"));
  for (long k = 0; k < std::lround(t_end / h); ++k) mj_step(m.get(), d.get());
  mj_kinematics(m.get(), d.get());
  double worst_angle = 0.0, travel = 0.0;
  const std::size_t last = tr.rows.size() - 1;
  for (const BodyDescription& b : scene.bodies) {
    const int id = mj_name2id(m.get(), mjOBJ_BODY, b.name.c_str());
    const Eigen::Quaterniond q(d->xquat[4 * id], d->xquat[4 * id + 1], d->xquat[4 * id + 2], d->xquat[4 * id + 3]);
    worst_angle = std::max(worst_angle, tr.orientation(last, b.name).angularDistance(q));
    travel = std::max(travel, tr.orientation(last, b.name).angularDistance(b.orientation));
  }
  std::cout << "[ measured ] spinning.xml from keyframe 'spin', lieflow rkmk4 vs MuJoCo RK4 at h = 1e-4 after 0.5 s: "
               "orientations within "
            << worst_angle << " rad (bodies turned up to " << travel << " rad)\n";
  EXPECT_LE(worst_angle, 1e-8);
  EXPECT_GT(travel, 0.3);
}

TEST(MujocoPeer, RunsTheSameModelAndMeasuresItsOwnDrifts) {
  const ModelImportOptions options = keyframe("spin");
  const SceneDescription scene = importModel(model("spinning.xml"), options);
  const MujocoPeer peer(model("spinning.xml"), options, scene);
  const double t_end = 0.5;
  const Trajectory reference = simulate(scene, "rkmk4", 1e-4, t_end, 5000);
  const Eigen::Quaterniond q_ref = reference.orientation(reference.rows.size() - 1, "core");
  // MuJoCo's RK4 at fourth order, its Euler at first, against lieflow's run.
  double rk[2], euler[2];
  for (int i = 0; i < 2; ++i) {
    const double h = i == 0 ? 4e-3 : 2e-3;
    const MujocoPeerRun r = peer.run("mujoco-rk4", h, t_end, false, 1);
    const MujocoPeerRun e = peer.run("mujoco-euler", h / 4, t_end, false, 1);
    ASSERT_FALSE(r.failed || e.failed) << r.failure << e.failure;
    EXPECT_EQ(r.steps, std::lround(t_end / h));
    rk[i] = r.orientations[0].angularDistance(q_ref);
    euler[i] = e.orientations[0].angularDistance(q_ref);
  }
  std::cout << "[ measured ] spinning.xml, MuJoCo vs lieflow's reference after 0.5 s: RK4 h = 4e-3, 2e-3: " << rk[0]
            << ", " << rk[1] << " rad; Euler h = 1e-3, 5e-4: " << euler[0] << ", " << euler[1] << " rad\n";
  // MuJoCo 2.2.2's RK4 converges at order 2 here, not 4: it sums the stage
  // angular velocities of the free joint in the body frame, without the
  // dexp⁻¹ correction a Lie-group Runge–Kutta method needs (measured also on
  // the core alone: 2.0e-6, 5.0e-7, 1.3e-7 rad at h = 4e-3, 2e-3, 1e-3).
  EXPECT_GT(std::log2(rk[0] / rk[1]), 1.8);
  EXPECT_NEAR(std::log2(euler[0] / euler[1]), 1.0, 0.3);
  // Observed: MuJoCo's own energy and momenta. Free in space under gravity,
  // its angular momentum about the centre of mass is conserved (RK4 to its
  // error), and its energy plus the dashpots' work too.
  const MujocoPeerRun observed = peer.run("mujoco-rk4", 1e-3, t_end, true, 50);
  ASSERT_FALSE(observed.failed) << observed.failure;
  ASSERT_EQ(observed.samples.size(), 11u);
  EXPECT_NEAR(observed.samples.back().t, t_end, 1e-12);
  EXPECT_GT(observed.samples.back().dissipated_work, 0.0);
  EXPECT_GT(observed.energy_drift, 1e-4);  // the dashpots take energy
  EXPECT_LT(observed.energy_balance_drift, 1e-5);
  EXPECT_LT(observed.com_momentum_drift, 1e-6);  // RK4's own error: not a quadratic invariant of it
  EXPECT_GT(observed.momentum_drift, 1e-3);  // gravity turns L about the origin
  // MuJoCo's energy at the start is lieflow's (the same model, the same state).
  const Simulation sim(scene);
  SimulationOptions o;
  o.integrator = "rkmk4";
  o.dt = 1e-3;
  o.t_end = 1e-3;
  std::vector<double> first;
  sim.run(o, [&](const std::vector<double>& row) {
    if (first.empty()) first = row;
  });
  const std::vector<std::string> columns = sim.columns();
  const double e0 = first[std::find(columns.begin(), columns.end(), "energy") - columns.begin()];
  std::cout << "[ measured ] spinning.xml at the keyframe: energy lieflow " << e0 << " J, MuJoCo "
            << observed.samples.front().energy << " J\n";
  EXPECT_NEAR(observed.samples.front().energy, e0, 1e-12 * std::abs(e0));
}

TEST(MujocoPeer, RefusesASceneThatIsNotItsModel) {
  const SceneDescription pendulum = loadScene("double-pendulum");
  try {
    const MujocoPeer peer(model("spinning.xml"), {}, pendulum);
    ADD_FAILURE() << "a scene with other bodies was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("body 'upper' is not a MuJoCo body"), std::string::npos) << e.what();
  }
}
#else
TEST(MujocoPeer, WithoutMuJoCoSaysWhatToInstall) {
  std::string why;
  EXPECT_FALSE(mujocoPeerAvailable(&why));
  EXPECT_NE(why.find("libmujoco-dev"), std::string::npos);
}
#endif

}  // namespace
}  // namespace lieflow
