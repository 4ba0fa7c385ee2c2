// The joint-coordinate formulation (--formulation joint,
// dynamics/joint_space/articulated_system.hpp) against an independent
// reference: the maximal formulation (bodies' poses, joint constraint rows,
// multipliers from a Schur-complement solve), which shares nothing with the
// articulated-body algorithm but the scene. Both integrate the same equations
// of motion, so at h = 1e-3 their trajectories differ by the two methods'
// truncation errors only; every CSV column is compared (bodies' poses and
// velocities, joint angles, rates and moments, energy, momentum).
#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <iostream>
#include <string>
#include <utility>
#include <vector>

#include "model/scene.hpp"
#include "simulation/simulation.hpp"
#include "liegroup/invalid_input.hpp"
#include "tests/simulation/scene_trajectory.hpp"
#include "tests/order_slope.hpp"

namespace lieflow {
namespace {

using scene_testing::RunEnds;
using scene_testing::runEnds;

/// Largest difference between two rows' columns; `where` names the column.
/// Quaternions are compared as they are: both formulations write the sign
/// that continues the scene's initial quaternion.
double rowDifference(const std::vector<std::string>& cols, const std::vector<double>& a,
                     const std::vector<double>& b, std::string* where) {
  double worst = 0.0;
  for (std::size_t i = 0; i < cols.size(); ++i) {
    const double d = std::abs(a[i] - b[i]);
    if (d > worst) {
      worst = d;
      *where = cols[i];
    }
  }
  return worst;
}

void expectSameMotion(const Simulation& sim, double t_end, double tolerance) {
  const RunEnds maximal = runEnds(sim, "maximal", "rkmk4", 1e-3, t_end);
  const RunEnds joint = runEnds(sim, "joint", "rkmk4", 1e-3, t_end);
  ASSERT_FALSE(maximal.result.failed) << maximal.result.failure;
  ASSERT_FALSE(joint.result.failed) << joint.result.failure;
  EXPECT_EQ(joint.result.formulation, "joint");
  EXPECT_EQ(maximal.result.formulation, "maximal");
  std::string where;
  // t = 0: the same projected initial state (velocities in the mass metric).
  EXPECT_LT(rowDifference(maximal.columns, maximal.first, joint.first, &where), 1e-12) << where;
  EXPECT_LT(rowDifference(maximal.columns, maximal.last, joint.last, &where), tolerance) << where;
  EXPECT_EQ(joint.result.momentum_conserved, maximal.result.momentum_conserved);
}

class ArticulatedBuiltin : public ::testing::TestWithParam<std::string> {};

TEST_P(ArticulatedBuiltin, FollowsTheMaximalFormulation) {
  const Simulation sim(loadScene(GetParam()));
  std::string why;
  ASSERT_TRUE(sim.hasJointFormulation(&why)) << why;
  expectSameMotion(sim, 2.0, 1e-7);
}

// Revolute chains, springs, dashpots, moments from tables, prescribed motion
// (driven-arm's yaw), free pairs of rotation-only bodies on a hinge and on a
// universal joint (their momentum conserved), and a free rack held to its
// pinion by the gear rows alone (a floating root with coupling rows).
INSTANTIATE_TEST_SUITE_P(Scenes, ArticulatedBuiltin,
                         ::testing::Values("pendulum", "double-pendulum", "chain-6", "spring-hinge", "driven-arm",
                                           "hinge-pair", "universal-pair", "rack-pinion"));

/// Spherical joints between bodies, joints given with the child as their main
/// body (universal and revolute), a universal joint's spring and dashpot, a
/// sine moment, and initial velocities that do not satisfy the joints (both
/// formulations project them in the mass metric).
constexpr const char* kMixedTree = R"({
  "name": "mixed-tree", "gravity": [0, 0, -9.81],
  "bodies": [
    {"name": "a", "mass": 1.2, "inertia": [0.02, 0.03, 0.025], "position": [0, 0, -0.3],
     "angular_velocity": [1.0, 0.5, -0.2]},
    {"name": "b", "mass": 0.8, "inertia": [0.01, 0.012, 0.006], "position": [0, 0, -0.85],
     "angular_velocity": [0.3, -0.4, 0.8], "velocity": [0.1, 0, 0]},
    {"name": "c", "mass": 0.5, "inertia": [0.002, 0.004, 0.005], "position": [0.35, 0, -0.95],
     "angular_velocity": [0, 0, 2.0]},
    {"name": "d", "mass": 0.7, "inertia": [0.004, 0.003, 0.002], "position": [0.5, 0, -1.15],
     "angular_velocity": [1.0, 1.0, 0]}
  ],
  "joints": [
    {"name": "top", "type": "spherical", "main": "ground", "secondary": "a",
     "anchor_main": [0, 0, 0], "anchor_secondary": [0, 0, 0.3]},
    {"name": "cross", "type": "universal", "main": "b", "secondary": "a",
     "anchor_main": [0, 0, 0.25], "anchor_secondary": [0, 0, -0.3],
     "axis1_main": [1, 0, 0], "axis2_secondary": [0, 1, 0], "initial_angles": [0.1, -0.2],
     "spring1": {"stiffness": 2.0, "rest_angle": 0.3}, "damper2": {"damping": 0.05}},
    {"name": "hinge", "type": "revolute", "main": "c", "secondary": "b",
     "anchor_main": [-0.15, 0, 0], "anchor_secondary": [0.2, 0, -0.1], "axis_main": [0, 0, 1],
     "moment": {"type": "sine", "amplitude": 0.3, "frequency": 1.5}},
    {"name": "ball", "type": "spherical", "main": "c", "secondary": "d",
     "anchor_main": [0.15, 0, 0], "anchor_secondary": [0, 0, 0.2]}
  ]
})";

TEST(Articulated, MixedTreeFollowsTheMaximalFormulation) {
  const Simulation sim(parseScene(kMixedTree, "mixed-tree.json"));
  std::string why;
  ASSERT_TRUE(sim.hasJointFormulation(&why)) << why;
  expectSameMotion(sim, 1.0, 1e-7);
}

TEST(Articulated, Rkmk4ConvergesAtOrderFour) {
  const Simulation sim(parseScene(kMixedTree, "mixed-tree.json"));
  const RunEnds reference = runEnds(sim, "joint", "rkmk4", 1.25e-4, 0.5);
  std::vector<double> hs, errors;
  for (double h : {4e-3, 2e-3, 1e-3}) {
    const RunEnds r = runEnds(sim, "joint", "rkmk4", h, 0.5);
    std::string where;
    hs.push_back(h);
    errors.push_back(rowDifference(r.columns, r.last, reference.last, &where));
  }
  const double slope = testing_support::logLogSlope(hs, errors);
  EXPECT_GT(slope, 3.8) << errors[0] << " " << errors[1] << " " << errors[2];
  EXPECT_LT(slope, 4.3);
}

TEST(Articulated, GeneralizedAlphaConvergesAtOrderTwo) {
  // No constraints in joint coordinates: second order in positions at ρ∞ = 1
  // and 0.8 (Arnold & Brüls 2007), against rkmk4 at a small step.
  const Simulation sim(parseScene(kMixedTree, "mixed-tree.json"));
  const RunEnds reference = runEnds(sim, "joint", "rkmk4", 1e-4, 0.5);
  for (double rho : {1.0, 0.8}) {
    std::vector<double> hs, errors;
    for (double h : {4e-3, 2e-3, 1e-3}) {
      SimulationOptions o;
      o.integrator = "genalpha";
      o.formulation = "joint";
      o.dt = h;
      o.t_end = 0.5;
      o.integrator_options = {{"rho_inf", rho}};
      std::vector<double> last;
      const SimulationResult r = sim.run(o, [&](const std::vector<double>& row) { last = row; });
      ASSERT_FALSE(r.failed) << r.failure;
      std::string where;
      hs.push_back(h);
      errors.push_back(rowDifference(reference.columns, last, reference.last, &where));
    }
    const double slope = testing_support::logLogSlope(hs, errors);
    EXPECT_GT(slope, 1.8) << "rho_inf " << rho << ": " << errors[0] << " " << errors[2];
    EXPECT_LT(slope, 2.3) << "rho_inf " << rho;
  }
}

TEST(Articulated, GeneralizedAlphaRunsLongAtRhoInfOne) {
  // 100 s at ρ∞ = 1 on the conservative tree scenes: the energy stays
  // bounded (measured: pendulum 4.8e-5 at h = 0.01, double pendulum 4.5e-3
  // at h = 0.01, chain-6 0.11 at h = 0.002; maximal coordinates, index 2:
  // 2.3e-4, 1.2e-2, 0.19).
  const std::pair<const char*, std::pair<double, double>> cases[] = {
      {"pendulum", {0.01, 1e-4}}, {"double-pendulum", {0.01, 0.01}}, {"chain-6", {0.002, 0.15}}};
  for (const auto& [name, run] : cases) {
    const Simulation sim(loadScene(name));
    SimulationOptions o;
    o.integrator = "genalpha";
    o.formulation = "joint";
    o.dt = run.first;
    o.t_end = 100.0;
    const SimulationResult r = sim.run(o);
    ASSERT_FALSE(r.failed) << name << ": " << r.failure;
    EXPECT_LT(r.energy_drift, run.second) << name;
  }
}

TEST(Articulated, ConservesEnergyWithoutForceElements) {
  // chain-10 under gravity, no springs or dashpots: energy drift O(h⁴).
  const Simulation sim(loadScene("chain-10"));
  const RunEnds r = runEnds(sim, "joint", "rkmk4", 5e-4, 1.0);
  ASSERT_FALSE(r.result.failed) << r.result.failure;
  EXPECT_LT(r.result.energy_drift, 1e-7);
  EXPECT_EQ(r.result.constraint_error, 0.0);
}

TEST(Articulated, AdaptiveRunsInJointCoordinates) {
  const Simulation sim(loadScene("double-pendulum"));
  const RunEnds coarse = runEnds(sim, "joint", "rkmk45", 0.01, 1.0);
  const RunEnds fine = runEnds(sim, "joint", "rkmk4", 1e-4, 1.0);
  ASSERT_FALSE(coarse.result.failed) << coarse.result.failure;
  std::string where;
  EXPECT_LT(rowDifference(coarse.columns, coarse.last, fine.last, &where), 1e-5) << where;
}

std::string refusal(const Simulation& sim, const std::string& formulation, const std::string& integrator,
                    std::string* field) {
  SimulationOptions o;
  o.integrator = integrator;
  o.formulation = formulation;
  o.dt = 1e-3;
  o.t_end = 0.01;
  try {
    sim.run(o);
  } catch (const InvalidInput& e) {
    *field = e.field();
    return e.reason();
  }
  return "";
}

/// Prismatic joints in joint coordinates: a cart sliding on a tilted rail
/// (spring, dashpot, initial speed), a pendulum hinged on it, a bead sliding
/// along the pendulum on a joint whose main body is the child (spring, sine
/// force), and a shuttle on the cart with a prescribed slide.
constexpr const char* kSlidingTree = R"({
  "name": "sliding-tree", "gravity": [0, 0, -9.81],
  "bodies": [
    {"name": "cart", "mass": 2.0, "inertia": [0.02, 0.03, 0.04], "velocity": [0.49029033784546, 0, 0.09805806756909]},
    {"name": "arm", "mass": 0.6, "inertia": [0.01, 0.012, 0.002], "position": [0, 0, -0.3],
     "angular_velocity": [0, 2.0, 0]},
    {"name": "bead", "mass": 0.2, "inertia": [0.0004, 0.0004, 0.0002], "position": [0, 0, -0.4]},
    {"name": "shuttle", "mass": 0.3, "inertia": [0.001, 0.002, 0.002], "position": [0.1, 0.2, 0]}
  ],
  "joints": [
    {"name": "rail", "type": "prismatic", "main": "ground", "secondary": "cart",
     "anchor_main": [0, 0, 0], "anchor_secondary": [0, 0, 0], "axis_main": [0.9805806756909202, 0, 0.19611613513818404],
     "spring": {"stiffness": 20.0, "rest_position": 0.05}, "damper": {"damping": 0.5}},
    {"name": "pivot", "type": "revolute", "main": "cart", "secondary": "arm",
     "anchor_main": [0, 0, 0], "anchor_secondary": [0, 0, 0.3], "axis_main": [0, 1, 0]},
    {"name": "slide", "type": "prismatic", "main": "bead", "secondary": "arm",
     "anchor_main": [0, 0, 0], "anchor_secondary": [0, 0, -0.1], "axis_main": [0, 0, 1],
     "spring": {"stiffness": 50.0, "rest_position": 0.02},
     "force": {"type": "sine", "amplitude": 0.5, "frequency": 2.0}},
    {"name": "shuttle_guide", "type": "prismatic", "main": "cart", "secondary": "shuttle",
     "anchor_main": [0.1, 0.2, 0], "anchor_secondary": [0, 0, 0], "axis_main": [0, 1, 0],
     "prescribed": {"type": "sine", "amplitude": 0.05, "frequency": 1.0}}
  ]
})";

TEST(Articulated, PrismaticJointsFollowTheMaximalFormulation) {
  const Simulation sim(parseScene(kSlidingTree, "sliding-tree.json"));
  std::string why;
  ASSERT_TRUE(sim.hasJointFormulation(&why)) << why;
  expectSameMotion(sim, 1.0, 1e-7);
  // The slides' columns: x, xdot and the force along the axis agree too
  // (expectSameMotion compares every column); and the bead really slides.
  const RunEnds joint = runEnds(sim, "joint", "rkmk4", 1e-3, 1.0);
  const auto column = [&](const std::string& name) {
    const auto it = std::find(joint.columns.begin(), joint.columns.end(), name);
    return static_cast<std::size_t>(it - joint.columns.begin());
  };
  EXPECT_GT(std::abs(joint.last[column("slide.x")]), 1e-3);
  EXPECT_NEAR(joint.last[column("shuttle_guide.x")], 0.05 * std::sin(2.0 * 3.141592653589793 * 1.0), 1e-12);
  // genalpha in joint coordinates on the same tree converges to the same motion.
  const RunEnds ga = runEnds(sim, "joint", "genalpha", 1e-4, 1.0);
  ASSERT_FALSE(ga.result.failed) << ga.result.failure;
  std::string where;
  EXPECT_LT(rowDifference(joint.columns, joint.last, ga.last, &where), 1e-4) << where;
  // lgvi in joint coordinates takes the slides but not the prescribed shuttle: it says so.
  std::string field;
  EXPECT_NE(refusal(sim, "joint", "lgvi", &field).find("'shuttle' has a prescribed joint angle"), std::string::npos);
}

/// A floating mechanism: a trunk no joint holds (a root on a free joint in
/// joint coordinates), a sprung, damped limb on a hinge and a second limb on
/// a universal joint whose main body is the child, thrown turning and moving
/// under gravity; and a second free body of its own (two floating roots).
constexpr const char* kFloatingTree = R"({
  "name": "floating-tree", "gravity": [0, 0, -9.81],
  "bodies": [
    {"name": "trunk", "mass": 3.0, "inertia": [0.05, 0.08, 0.06], "position": [0, 0, 1.0],
     "angular_velocity": [1.5, -2.0, 3.0], "velocity": [0.5, 0.2, 2.0]},
    {"name": "limb", "mass": 0.8, "inertia": [0.01, 0.012, 0.003], "position": [0.3, 0, 1.0],
     "angular_velocity": [0, 0, 1.0]},
    {"name": "foot", "mass": 0.4, "inertia": [0.002, 0.003, 0.004], "position": [-0.3, 0, 0.9]},
    {"name": "stone", "mass": 0.5, "inertia": [0.001, 0.002, 0.003], "position": [2, 0, 0],
     "angular_velocity": [3, 1, 0.5], "velocity": [0, 1, 0]}
  ],
  "joints": [
    {"name": "hip", "type": "revolute", "main": "trunk", "secondary": "limb",
     "anchor_main": [0.15, 0, 0], "anchor_secondary": [-0.15, 0, 0], "axis_main": [0, 1, 0],
     "spring": {"stiffness": 5.0, "rest_angle": 0.2}, "damper": {"damping": 0.02}},
    {"name": "ankle", "type": "universal", "main": "foot", "secondary": "trunk",
     "anchor_main": [0.15, 0, 0.05], "anchor_secondary": [-0.15, 0, -0.05],
     "axis1_main": [0, 0, 1], "axis2_secondary": [1, 0, 0], "spring1": {"stiffness": 2.0, "rest_angle": 0}}
  ]
})";

TEST(Articulated, FloatingRootsFollowTheMaximalFormulation) {
  const Simulation sim(parseScene(kFloatingTree, "floating-tree.json"));
  std::string why;
  ASSERT_TRUE(sim.hasJointFormulation(&why)) << why;
  expectSameMotion(sim, 1.0, 1e-7);
  // Without gravity its angular momentum about the centre of mass is kept
  // (L_com): to the integrator's error with dashpots taking energy.
  SceneDescription weightless = parseScene(kFloatingTree, "floating-tree.json");
  weightless.gravity.setZero();
  const Simulation free(weightless);
  const RunEnds joint = runEnds(free, "joint", "rkmk4", 1e-3, 2.0);
  ASSERT_FALSE(joint.result.failed) << joint.result.failure;
  double l_com = -1.0;
  for (const auto& [name, drift] : joint.result.invariants)
    if (name == "L_com") l_com = drift;
  std::cout << "[ measured ] floating tree in joint coordinates, no gravity, rkmk4 h = 1e-3 over 2 s: L_com drift "
            << l_com << "\n";
  EXPECT_GE(l_com, 0.0);
  EXPECT_LT(l_com, 5e-9);
  // lgvi runs a free root in joint coordinates, by default
  // (articulated_variational_test.cpp checks it), and genalpha with the
  // root's 6 × 6 block in the mass matrix converges to the same motion.
  EXPECT_EQ(sim.defaultFormulation("lgvi"), "joint");
  EXPECT_EQ(sim.defaultFormulation("rkmk4"), "joint");
  EXPECT_EQ(sim.defaultFormulation("genalpha"), "joint");
  const RunEnds rk = runEnds(sim, "joint", "rkmk4", 1e-3, 1.0);
  std::vector<double> errors;
  for (double h : {2e-3, 1e-3}) {
    const RunEnds ga = runEnds(sim, "joint", "genalpha", h, 1.0);
    ASSERT_FALSE(ga.result.failed) << ga.result.failure;
    std::string where;
    errors.push_back(rowDifference(rk.columns, rk.last, ga.last, &where));
  }
  std::cout << "[ measured ] floating tree, genalpha (joint) against rkmk4 after 1 s at h = 2e-3, 1e-3: " << errors[0]
            << ", " << errors[1] << "\n";
  EXPECT_LT(errors[1], 5e-3);
  EXPECT_NEAR(std::log2(errors[0] / errors[1]), 2.0, 0.3);
}

/// MuJoCo's humanoid's joints in joint coordinates: a floating pelvis with
/// a sprung gimbal hip (three hinges through one point, as the humanoid's
/// hips) and below it an offset universal ankle (two hinges at two points, as
/// its ankles), thrown turning.
constexpr const char* kGimbalLeg = R"({
  "name": "gimbal-leg", "gravity": [0, 0, -9.81],
  "bodies": [
    {"name": "pelvis", "mass": 4.0, "inertia": [0.04, 0.05, 0.06], "angular_velocity": [1.0, -0.5, 2.0],
     "velocity": [0.3, 0, 1.0]},
    {"name": "thigh", "mass": 1.5, "inertia": [0.02, 0.02, 0.004], "position": [0, 0, -0.3],
     "angular_velocity": [0.5, 2.0, -1.0]},
    {"name": "foot", "mass": 0.5, "inertia": [0.001, 0.003, 0.003], "position": [0.02, 0, -0.6]}
  ],
  "joints": [
    {"name": "hip", "type": "gimbal", "main": "pelvis", "secondary": "thigh",
     "anchor_main": [0, 0, -0.1], "anchor_secondary": [0, 0, 0.2],
     "axis1_main": [1, 0, 0], "axis2_main": [0, 0, 1], "axis3_main": [0, 1, 0],
     "spring1": {"stiffness": 3.0, "rest_angle": 0.3}, "spring2": {"stiffness": 2.0, "rest_angle": -0.2},
     "damper3": {"damping": 0.05}},
    {"name": "ankle", "type": "universal", "offset": true, "main": "thigh", "secondary": "foot",
     "anchor_main": [0, 0, -0.2], "anchor_secondary": [0.05, 0, 0.04],
     "axis1_main": [0, 1, 0], "axis2_secondary": [1, 0, 0],
     "spring1": {"stiffness": 1.5, "rest_angle": 0.2}, "spring2": {"stiffness": 1.0, "rest_angle": 0}}
  ]
})";

TEST(Articulated, GimbalsAndOffsetUniversalJointsFollowTheMaximalFormulation) {
  const Simulation sim(parseScene(kGimbalLeg, "gimbal-leg.json"));
  std::string why;
  ASSERT_TRUE(sim.hasJointFormulation(&why)) << why;
  // Every column: the poses, the three hip angles, rates and moments, the
  // ankle's (its second moment about the line through the foot's anchor).
  expectSameMotion(sim, 1.0, 1e-7);
  // lgvi takes gimbals and offset universal joints in joint coordinates
  // (articulated_variational_test.cpp's floating rig checks it).
  EXPECT_EQ(sim.defaultFormulation("lgvi"), "joint");
  // A gimbal whose main body hangs from its secondary (b from a, a from the
  // ground) is not taken: maximal coordinates run it.
  const Simulation upside(parseScene(R"({"name": "upside", "gravity": [0, 0, -9.81],
    "bodies": [{"name": "a", "mass": 1, "inertia": [0.01, 0.01, 0.01], "position": [0, 0, -0.2]},
               {"name": "b", "mass": 1, "inertia": [0.01, 0.01, 0.01], "position": [0, 0, -0.6]}],
    "joints": [{"name": "top", "type": "revolute", "main": "ground", "secondary": "a", "anchor_main": [0, 0, 0],
                "anchor_secondary": [0, 0, 0.2], "axis_main": [0, 1, 0]},
               {"name": "g", "type": "gimbal", "main": "b", "secondary": "a", "anchor_main": [0, 0, 0.2],
                "anchor_secondary": [0, 0, -0.2], "axis1_main": [1, 0, 0], "axis2_main": [0, 1, 0],
                "axis3_main": [0, 0, 1]}]})",
                                     "upside.json"));
  EXPECT_FALSE(upside.hasJointFormulation(&why));
  EXPECT_NE(why.find("from their main body"), std::string::npos) << why;
  EXPECT_EQ(upside.defaultFormulation("rkmk4"), "maximal");
}

/// A floating trunk with a loop: two hinged legs whose feet a bar joins on
/// ball joints (a four-bar hanging from a free root), thrown turning.
constexpr const char* kFloatingLoop = R"({
  "name": "floating-loop", "gravity": [0, 0, -9.81],
  "bodies": [
    {"name": "trunk", "mass": 3.0, "inertia": [0.05, 0.08, 0.06], "position": [0, 0, 1.0],
     "angular_velocity": [1.0, 2.0, 0.5], "velocity": [0.2, 0, 1.0]},
    {"name": "leg1", "mass": 0.6, "inertia": [0.004, 0.004, 0.001], "position": [0.1, 0, 0.8]},
    {"name": "leg2", "mass": 0.7, "inertia": [0.005, 0.005, 0.001], "position": [-0.1, 0, 0.8]},
    {"name": "bar", "mass": 0.3, "inertia": [0.0005, 0.002, 0.002], "position": [0, 0, 0.6]}
  ],
  "joints": [
    {"name": "hip1", "type": "revolute", "main": "trunk", "secondary": "leg1",
     "anchor_main": [0.1, 0, 0], "anchor_secondary": [0, 0, 0.2], "axis_main": [0, 1, 0],
     "spring": {"stiffness": 2.0, "rest_angle": 0.3}},
    {"name": "hip2", "type": "revolute", "main": "trunk", "secondary": "leg2",
     "anchor_main": [-0.1, 0, 0], "anchor_secondary": [0, 0, 0.2], "axis_main": [0, 1, 0]},
    {"name": "foot1", "type": "spherical", "main": "leg1", "secondary": "bar",
     "anchor_main": [0, 0, -0.2], "anchor_secondary": [0.1, 0, 0]},
    {"name": "foot2", "type": "spherical", "main": "leg2", "secondary": "bar",
     "anchor_main": [0, 0, -0.2], "anchor_secondary": [-0.1, 0, 0]}
  ]
})";

TEST(Articulated, FloatingRootsCloseLoopsAsTheMaximalFormulation) {
  const Simulation sim(parseScene(kFloatingLoop, "floating-loop.json"));
  std::string why;
  ASSERT_TRUE(sim.hasJointFormulation(&why)) << why;
  expectSameMotion(sim, 1.0, 1e-7);
  const RunEnds joint = runEnds(sim, "joint", "rkmk4", 1e-3, 1.0);
  ASSERT_FALSE(joint.result.failed) << joint.result.failure;
  EXPECT_LT(joint.result.constraint_error, 1e-10);
}

TEST(Articulated, RefusesWhatJointCoordinatesCannotHold) {
  std::string field;
  // A closed loop runs (articulated_loops_test.cpp), but not with the
  // integrators that have no multipliers or no projection.
  EXPECT_NE(refusal(Simulation(loadScene("cardan-shaft")), "joint", "genalpha", &field).find("prescribed"),
            std::string::npos);
  EXPECT_EQ(field, "`integrator`");
  // A gimbal hung from its secondary body (joint coordinates take it from
  // its main body; a weld is a tree joint now, slider-crank's among them).
  EXPECT_NE(refusal(Simulation(loadScene(std::string(LIEFLOW_SOURCE_DIR) + "/tests/data/scenes/gimbal-upside-down.json")),
                    "joint", "rkmk4", &field)
                .find("from their main body"),
            std::string::npos);
  EXPECT_EQ(field, "`formulation`");
  EXPECT_NE(refusal(Simulation(loadScene("slider-crank")), "joint", "splitting", &field).find("maximal"),
            std::string::npos);
  // An integrator written for maximal coordinates.
  const Simulation pendulum(loadScene("double-pendulum"));
  EXPECT_NE(refusal(pendulum, "joint", "splitting", &field).find("not available in joint coordinates"),
            std::string::npos);
  EXPECT_EQ(field, "`integrator`");
  // lgvi in joint coordinates needs angles (no SO(3) joint) and no prescribed motion.
  EXPECT_NE(refusal(Simulation(loadScene("driven-arm")), "joint", "lgvi", &field).find("prescribed joint angle"),
            std::string::npos);
  EXPECT_EQ(field, "`integrator`");
  EXPECT_NE(refusal(pendulum, "reduced", "rkmk4", &field).find("not a formulation"), std::string::npos);
  EXPECT_EQ(field, "`formulation`");
}

}  // namespace
}  // namespace lieflow
