// Loops in joint coordinates (dynamics/joint_space/articulated_closures.cpp):
// a closing joint imposed with multipliers on top of the articulated-body
// algorithm, the explicit steppers projected onto its rows. Against
// independent references: the Cardan joint's closed form (angle, rate and
// the moment the drive supplies, from the power balance), the maximal
// formulation on the same scenes, measured orders, conservation of energy.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <tuple>
#include <string>
#include <vector>

#include "dynamics/joint_space/articulated_scene.hpp"
#include "integrators/joint_space_variational.hpp"
#include "model/scene.hpp"
#include "simulation/simulation.hpp"
#include "liegroup/invalid_input.hpp"
#include "tests/simulation/scene_trajectory.hpp"
#include "tests/order_slope.hpp"

namespace lieflow {
namespace {

using scene_testing::runEnds;
using scene_testing::RunEnds;

/// A spatial four-bar under gravity (crank on a sprung hinge to the ground,
/// coupler on a universal joint at the crank, rocker on a hinge to the
/// ground; the coupler–rocker ball joint closes the loop: 1 degree of
/// freedom and the coupler's spin about its own line).
constexpr const char* kFourBar = R"({
  "name": "four-bar",
  "gravity": [0, 0, -9.81],
  "bodies": [
    {"name": "crank", "mass": 1.0, "inertia": [0.09, 0.09, 0.01], "position": [0, 0, 0.5],
     "angular_velocity": [0, 3, 0]},
    {"name": "coupler", "mass": 2.0, "inertia": [0.05, 0.9, 0.9], "position": [1.1, 0, 1.25]},
    {"name": "rocker", "mass": 1.5, "inertia": [0.3, 0.3, 0.02], "position": [2.1, 0, 0.75]}
  ],
  "joints": [
    {"name": "crank-pivot", "type": "revolute", "main": "ground", "secondary": "crank",
     "anchor_main": [0, 0, 0], "anchor_secondary": [0, 0, -0.5], "axis_main": [0, 1, 0],
     "spring": {"stiffness": 5, "rest_angle": 0.3}, "damper": {"damping": 0.2}},
    {"name": "crank-coupler", "type": "universal", "main": "crank", "secondary": "coupler",
     "anchor_main": [0, 0, 0.5], "anchor_secondary": [-1.1, 0, -0.25],
     "axis1_main": [0, 1, 0], "axis2_secondary": [0, 0, 1]},
    {"name": "rocker-pivot", "type": "revolute", "main": "ground", "secondary": "rocker",
     "anchor_main": [2, 0, 0], "anchor_secondary": [-0.1, 0, -0.75], "axis_main": [0, 1, 0]},
    {"name": "coupler-rocker", "type": "spherical", "main": "coupler", "secondary": "rocker",
     "anchor_main": [1.1, 0, 0.25], "anchor_secondary": [0.1, 0, 0.75]}
  ],
  "integrator": {"name": "rkmk4", "dt": 0.001},
  "t_end": 1.0
})";

SceneDescription fourBar() { return parseScene(kFourBar, "four-bar.json"); }

/// The four-bar with its ground replaced by a free frame (a floating tree
/// with a loop inside it: the frame, the crank and the rocker on their
/// pivots, the coupler closing the loop at the rocker), thrown turning.
SceneDescription floatingFourBar() {
  SceneDescription s = fourBar();
  s.name = "floating-four-bar";
  BodyDescription frame;
  frame.name = "frame";
  frame.mass = 4.0;
  frame.inertia = Eigen::Vector3d(0.6, 1.9, 1.5).asDiagonal();
  frame.position = Eigen::Vector3d(1.0, 0.0, 0.0);
  frame.angular_velocity = Eigen::Vector3d(0.4, -0.3, 0.8);
  s.bodies.insert(s.bodies.begin(), frame);
  for (JointDescription& j : s.joints)
    if (j.main == "ground") {
      j.main = "frame";
      j.anchor_main -= frame.position;
    }
  return s;
}

/// The built-in Cardan shaft with its input free (no prescribed motion):
/// both shafts spin, the speed ratio and the energy trade between them.
SceneDescription freeCardanShaft() {
  SceneDescription s = loadScene("cardan-shaft");
  for (JointDescription& j : s.joints) j.coordinates[0].prescribed.reset();
  s.bodies[1].inertia = Eigen::Vector3d(0.02, 0.01, 0.01).asDiagonal();
  return s;
}

/// The largest difference of two rows over the columns whose names end in
/// one of `suffixes` (".x": positions; "" every column).
double largestDifference(const RunEnds& a, const RunEnds& b, const std::vector<std::string>& suffixes) {
  double worst = 0.0;
  for (std::size_t c = 1; c < a.columns.size(); ++c)
    for (const std::string& s : suffixes)
      if (a.columns[c].size() >= s.size() && a.columns[c].compare(a.columns[c].size() - s.size(), s.size(), s) == 0)
        worst = std::max(worst, std::abs(a.last[c] - b.last[c]));
  return worst;
}

/// A run's last row and summary, with the largest value of one column over
/// its rows in *worst (the loop's constraint_error).
RunEnds runWatching(const Simulation& sim, const SimulationOptions& o, std::size_t column, double* worst) {
  RunEnds run;
  run.columns = sim.columns();
  run.result = sim.run(o, [&](const std::vector<double>& row) {
    *worst = std::max(*worst, row[column]);
    run.last = row;
  });
  return run;
}

TEST(ArticulatedLoops, CardanShaftFollowsItsClosedForm) {
  // Input at ω = 10 rad/s prescribed, shafts bent by β = 30°, the input angle
  // φ from the plane of the shafts: tan ψ = tan φ / cos β, ψ̇ = ω cos β /
  // (1 − sin²β cos²φ) (Hooke's joint). The output turns freely, so the drive
  // supplies its kinetic energy's rate: M ω = −J ψ̇ ψ̈ for the moment M on the
  // input bearing's main body (the ground); the output bearing carries none.
  const SceneDescription scene = loadScene("cardan-shaft");
  const scene_testing::Trajectory run = scene_testing::simulate(scene, "rkmk4", 1e-3, 1.0, 1, "joint");
  ASSERT_FALSE(run.result.failed) << run.result.failure;
  const double w = 10.0, c = std::cos(M_PI / 6), s2 = 0.25, J = 0.002;
  double angle = 0, rate = 0, moment = 0, bearing = 0, rows_error = 0;
  for (std::size_t r = 0; r < run.rows.size(); ++r) {
    const double phi = w * run.at(r, "t"), den = 1.0 - s2 * std::cos(phi) * std::cos(phi);
    const double psidot = w * c / den;
    const double psiddot = -w * w * c * s2 * 2.0 * std::cos(phi) * std::sin(phi) / (den * den);
    double psi = std::atan2(std::sin(phi), c * std::cos(phi));
    psi += 2 * M_PI * std::round((run.at(r, "output-bearing.phi") - psi) / (2 * M_PI));
    angle = std::max(angle, std::abs(run.at(r, "output-bearing.phi") - psi));
    rate = std::max(rate, std::abs(run.at(r, "output-bearing.phidot") - psidot));
    moment = std::max(moment, std::abs(run.at(r, "input-bearing.moment") * w + J * psidot * psiddot));
    bearing = std::max(bearing, std::abs(run.at(r, "output-bearing.moment")));
    rows_error = std::max(rows_error, run.at(r, "constraint_error"));
  }
  // Measured: 1.1e-12, 1.6e-12, 8.0e-13 (the power is up to 0.3 W), 3e-17;
  // the loop's rows at 1.0e-12 (the projection's tolerance).
  EXPECT_LT(angle, 1e-11);
  EXPECT_LT(rate, 1e-11);
  EXPECT_LT(moment, 1e-11);
  EXPECT_LT(bearing, 1e-12);
  EXPECT_LE(rows_error, 1e-12);
}

TEST(ArticulatedLoops, AgreeWithMaximalCoordinates) {
  // The same equations in two formulations: at a small step every column
  // (poses, rates, joint angles and moments, energy) agrees to the steps'
  // error. Measured at h = 2e-4: four-bar 1.6e-11, free Cardan shaft 1.7e-12,
  // gear-train 2.0e-13, differential 7.6e-14 (gear rows on the velocities).
  for (const auto& [name, scene, bound] :
       {std::tuple<const char*, SceneDescription, double>{"four-bar", fourBar(), 2e-10},
        {"free cardan shaft", freeCardanShaft(), 1e-10},
        {"gear-train", loadScene("gear-train"), 1e-10},
        {"differential", loadScene("differential"), 1e-10}}) {
    SCOPED_TRACE(name);
    const Simulation sim(scene);
    const RunEnds joint = runEnds(sim, "joint", "rkmk4", 2e-4, 1.0);
    const RunEnds maximal = runEnds(sim, "maximal", "rkmk4", 2e-4, 1.0);
    ASSERT_FALSE(joint.result.failed) << joint.result.failure;
    ASSERT_FALSE(maximal.result.failed) << maximal.result.failure;
    ASSERT_EQ(joint.columns, maximal.columns);
    EXPECT_LT(largestDifference(joint, maximal, {""}), bound);
    // Same start: the joint formulation's initial projection onto the loop
    // is the maximal one's.
    for (std::size_t c = 1; c < joint.first.size(); ++c)
      EXPECT_NEAR(joint.first[c], maximal.first[c], 1e-12) << joint.columns[c];
    EXPECT_LE(joint.result.constraint_error, 1e-12);
  }
}

TEST(ArticulatedLoops, AccelerometersSeeTheLoopsForces) {
  // --imu: the specific force at each body's centre of mass reads the
  // accelerations with the loop's multipliers (articulated_closures.cpp moves
  // the bodies' accelerations by Y λ), against maximal coordinates on the
  // four-bar every 0.1 s over 0.5 s at h = 2e-4. Measured 1.4e-14 m/s² (of up
  // to 9.8).
  const Simulation sim(fourBar());
  std::map<std::string, std::vector<std::vector<double>>> rows;
  for (const char* formulation : {"joint", "maximal"}) {
    SimulationOptions o = scene_testing::runOptions("rkmk4", formulation, 2e-4, 0.5);
    o.every = 500;
    o.imu = true;
    const SimulationResult r = sim.run(o, [&](const std::vector<double>& row) { rows[formulation].push_back(row); });
    ASSERT_FALSE(r.failed) << r.failure;
  }
  const std::vector<std::string> columns = sim.columns(true);
  ASSERT_EQ(rows["joint"].size(), rows["maximal"].size());
  int checked = 0;
  for (std::size_t c = 0; c < columns.size(); ++c) {
    const std::string& name = columns[c];
    if (name.size() < 3 || name.compare(name.size() - 3, 1, ".") != 0 || name[name.size() - 2] != 'a') continue;
    for (std::size_t r = 0; r < rows["joint"].size(); ++r)
      EXPECT_NEAR(rows["joint"][r][c], rows["maximal"][r][c], 1e-10) << name << " row " << r;
    ++checked;
  }
  EXPECT_EQ(checked, 9);  // three bodies' ax, ay, az
}

TEST(ArticulatedLoops, ProjectedStepsKeepTheirOrder) {
  // Positions at t = 1 against the same stepper at h = 1e-4: rkmk4 of order
  // 4, rkmk3 of order 3, rkmk-heun of order 2 — the projection keeps the
  // inner method's order (projected_stepper.hpp). Measured slopes 4.06 (errors
  // 8.9e-8, 5.2e-9, 3.2e-10), 2.9 for rkmk3, 2.03 for rkmk-heun. (cf4 is rkmk4 here: on the
  // angles, a vector space, the commutator-free method is classical RK4.)
  const Simulation sim(fourBar());
  for (const auto& [integrator, order] :
       {std::pair<const char*, double>{"rkmk4", 4.0}, {"rkmk3", 3.0}, {"rkmk-heun", 2.0}}) {
    SCOPED_TRACE(integrator);
    const RunEnds reference = runEnds(sim, "joint", integrator, 1e-4, 1.0);
    std::vector<double> h, error;
    for (double dt : {4e-3, 2e-3, 1e-3}) {
      const RunEnds run = runEnds(sim, "joint", integrator, dt, 1.0);
      ASSERT_FALSE(run.result.failed) << run.result.failure;
      h.push_back(dt);
      error.push_back(largestDifference(run, reference, {".x", ".y", ".z"}));
    }
    const double slope = testing_support::logLogSlope(h, error);
    EXPECT_GT(slope, order - 0.3);
    EXPECT_LT(slope, order + 0.7);
  }
}

TEST(ArticulatedLoops, FreeCardanShaftKeepsItsEnergy) {
  // No force, no dashpot: the energy is the first integral; rkmk4's drift
  // over 2 s at h = 1e-3 (the speed ratio swings between cos β and 1/cos β
  // twice a turn) is its local error only. Measured 2.0e-12 relative.
  const scene_testing::Trajectory run = scene_testing::simulate(freeCardanShaft(), "rkmk4", 1e-3, 2.0, 1, "joint");
  ASSERT_FALSE(run.result.failed) << run.result.failure;
  const double e0 = run.at(0, "energy");
  double drift = 0.0, low = 1e300, high = 0.0;
  for (std::size_t r = 0; r < run.rows.size(); ++r) {
    drift = std::max(drift, std::abs(run.at(r, "energy") - e0) / e0);
    const double ratio = run.at(r, "output-bearing.phidot") / run.at(r, "input-bearing.phidot");
    low = std::min(low, ratio);
    high = std::max(high, ratio);
  }
  EXPECT_LT(drift, 1e-10);
  // The loop transmits a varying ratio (between cos β and 1/cos β for a
  // steady input; here both shafts' speeds swing). Measured 0.866 to 1.155.
  EXPECT_LT(low, 0.95);
  EXPECT_GT(high, 1.05);
}

TEST(ArticulatedLoops, TheTreeKeepsTheJointsThatCarryForces) {
  // The free Cardan shaft with a sprung and damped cross: the spanning tree
  // takes the joints with force elements first (buildTree), so the cross is a
  // tree joint with coordinates and the output bearing closes the loop; the
  // motion is the maximal formulation's (every column at t = 1 s, h = 2e-4;
  // measured 2.9e-12).
  SceneDescription scene = freeCardanShaft();
  scene.joints[2].coordinates[0].stiffness = 0.3;
  scene.joints[2].coordinates[0].rest_angle = 0.1;
  scene.joints[2].coordinates[1].damping = 0.002;
  const Simulation sim(scene);
  std::string why;
  ASSERT_TRUE(sim.hasJointFormulation(&why)) << why;
  const RunEnds joint = runEnds(sim, "joint", "rkmk4", 2e-4, 1.0);
  const RunEnds maximal = runEnds(sim, "maximal", "rkmk4", 2e-4, 1.0);
  ASSERT_FALSE(joint.result.failed) << joint.result.failure;
  ASSERT_FALSE(maximal.result.failed) << maximal.result.failure;
  EXPECT_LT(largestDifference(joint, maximal, {""}), 1e-10);
}

TEST(ArticulatedLoops, AdaptiveStepsKeepTheLoopClosed) {
  // rkmk45 in index-1 form, projected after every accepted step and at every
  // output (integrators/adaptive.hpp), in both formulations: every output
  // row on the loop's rows to the projection's 1e-12, and the error against
  // joint rkmk4 at h = 1e-4 falling with the tolerance.
  const Simulation sim(fourBar());
  const RunEnds reference = runEnds(sim, "joint", "rkmk4", 1e-4, 1.0);
  ASSERT_FALSE(reference.result.failed) << reference.result.failure;
  const std::size_t error_column =
      std::find(reference.columns.begin(), reference.columns.end(), "constraint_error") - reference.columns.begin();
  for (const char* formulation : {"joint", "maximal"}) {
    double previous = 1.0;
    for (double rtol : {1e-5, 1e-7, 1e-9, 1e-11}) {
      SimulationOptions o = scene_testing::runOptions("rkmk45", formulation, 0.01, 1.0);
      o.integrator_options = {{"rtol", rtol}, {"atol", 1e-2 * rtol}};
      double worst_row = 0.0;
      const RunEnds run = runWatching(sim, o, error_column, &worst_row);
      ASSERT_FALSE(run.result.failed) << run.result.failure;
      const double error = largestDifference(run, reference, {".x", ".y", ".z"});
      std::printf("%s rkmk45 rtol %.0e: %ld steps (%ld rejected), position error %.2g m, max |Phi| %.2g\n",
                  formulation, rtol, run.result.steps, run.result.rejected_steps, error, worst_row);
      EXPECT_LE(worst_row, 1e-12) << formulation << " rtol " << rtol;
      EXPECT_LT(error, previous) << formulation << " rtol " << rtol;
      EXPECT_LE(error, rtol) << formulation << " rtol " << rtol;  // measured 0.02-0.25 rtol
      previous = error;
    }
  }
}

/// lgvi on `scene`'s loop in joint coordinates (its default formulation) at
/// h = 4, 2, 1 ms for 1 s: every row on Φ = 0 to 1e-13, no substeps, and the
/// positions at t = 1 s against joint rkmk4 at h = 1e-4 at order 2; the
/// energy balance's drifts in *balance (the dashpot's work counted).
void expectLgviLoopAtOrderTwo(const SceneDescription& scene, std::vector<double>* balance) {
  const Simulation sim(scene);
  EXPECT_EQ(sim.defaultFormulation("lgvi"), "joint");
  const RunEnds reference = runEnds(sim, "joint", "rkmk4", 1e-4, 1.0);
  ASSERT_FALSE(reference.result.failed) << reference.result.failure;
  const std::size_t error_column =
      std::find(reference.columns.begin(), reference.columns.end(), "constraint_error") - reference.columns.begin();
  std::vector<double> h, error;
  for (double dt : {4e-3, 2e-3, 1e-3}) {
    SimulationOptions o = scene_testing::runOptions("lgvi", "joint", dt, 1.0);
    o.check_every = 1;
    double worst_row = 0.0;
    const RunEnds run = runWatching(sim, o, error_column, &worst_row);
    ASSERT_FALSE(run.result.failed) << run.result.failure;
    EXPECT_EQ(run.result.substepped_steps, 0) << "h = " << dt;
    h.push_back(dt);
    error.push_back(largestDifference(run, reference, {".x", ".y", ".z"}));
    for (const auto& [name, drift] : run.result.invariants)
      if (name == "energy_balance") balance->push_back(drift);
    std::printf("%s lgvi (joint) h = %g: position error %.3g m, energy balance %.3g, max |Phi| %.2g, %.2f passes "
                "per step\n",
                scene.name.c_str(), dt, error.back(), balance->empty() ? -1.0 : balance->back(), worst_row,
                run.result.newton_iterations_mean);
    EXPECT_LE(worst_row, 1e-13) << "h = " << dt;
  }
  EXPECT_NEAR(testing_support::logLogSlope(h, error), 2.0, 0.3);
}

/// The largest |L(t) − L(0)| of lgvi in joint coordinates on `scene` over
/// `steps` steps of h, and |L(0)| in *L0.
double lgviMomentumDrift(const SceneDescription& scene, double h, int steps, double* L0_norm) {
  const auto assembled = assembleArticulated(scene);
  const articulated::ArticulatedSystem& sys = *assembled->system;
  articulated::ArticulatedState y = assembled->y0;
  const Eigen::Vector3d L0 = sys.angularMomentum(0.0, y);
  *L0_norm = L0.norm();
  JointSpaceVariationalStepper<articulated::ArticulatedSystem> stepper;
  StepReport report;
  double t = 0.0, worst = 0.0;
  for (int k = 0; k < steps; ++k) {
    y = stepper.step(sys, t, y, h, &report);
    if (!report.converged) {
      ADD_FAILURE() << report.failure << " " << report.detail;
      return std::numeric_limits<double>::infinity();
    }
    t += h;
    worst = std::max(worst, (sys.angularMomentum(t, y) - L0).norm());
  }
  return worst;
}

TEST(ArticulatedLoops, LgviClosesTheLoopAndConvergesAtOrderTwo) {
  // lgvi in joint coordinates with the loop's rows as RATTLE's multipliers
  // (joint_space_variational.hpp), the default formulation; the energy
  // balance at order 2 too. Measured: slopes 2.0 (6.8e-6 m at h = 1e-3), max
  // |Φ| 3.6e-14, 2.2-2.8 passes per step, no substeps.
  std::vector<double> balance;
  expectLgviLoopAtOrderTwo(fourBar(), &balance);
  ASSERT_EQ(balance.size(), 3u);
  EXPECT_NEAR(testing_support::logLogSlope({4e-3, 2e-3, 1e-3}, balance), 2.0, 0.3);
}

TEST(ArticulatedLoops, LgviClosesALoopInsideAFloatingTree) {
  // The floating four-bar: the loop's rows are among the bodies of one
  // floating tree, so they are the same in the step's coordinates (the
  // tree's centre of mass) as in the state's. Measured: 8.6e-7, 2.2e-7,
  // 5.4e-8 m, max |Φ| 1.8e-14, 2.0 passes per step.
  std::vector<double> balance;
  expectLgviLoopAtOrderTwo(floatingFourBar(), &balance);
}

TEST(ArticulatedLoops, LgviKeepsTheMomentumOfAFloatingLoopToRoundOff) {
  // Without gravity and dashpot the floating four-bar's discrete Lagrangian
  // is invariant under turns of the whole: lgvi keeps its angular momentum
  // about the origin to round-off over 2000 steps (discrete Noether).
  SceneDescription scene = floatingFourBar();
  scene.gravity.setZero();
  for (JointDescription& j : scene.joints)
    for (auto& c : j.coordinates) c.damping = 0.0;
  double L0 = 0.0;
  const double drift = lgviMomentumDrift(scene, 2e-3, 2000, &L0);
  std::printf("floating four-bar, lgvi (joint) h = 2e-3 over 4 s: |dL| %.3g of %.3g\n", drift, L0);
  EXPECT_LT(drift, 1e-11 * L0);
}

/// Two gears on axles of a free carrier (a floating tree whose gear row ties
/// two of its joints: 2 φ̇_pinion + φ̇_wheel = 0), turning without gravity.
constexpr const char* kFloatingGears = R"({
  "name": "floating-gears", "gravity": [0, 0, 0],
  "bodies": [
    {"name": "carrier", "mass": 3.0, "inertia": [0.05, 0.08, 0.06], "angular_velocity": [0.5, -0.3, 1.0]},
    {"name": "pinion", "mass": 0.5, "inertia": [0.001, 0.001, 0.0015], "position": [0.1, 0, 0],
     "angular_velocity": [0.5, -0.3, 11.0]},
    {"name": "wheel", "mass": 2.0, "inertia": [0.01, 0.01, 0.018], "position": [-0.2, 0, 0],
     "angular_velocity": [0.5, -0.3, -4.0]}
  ],
  "joints": [
    {"name": "pinion-axle", "type": "revolute", "main": "carrier", "secondary": "pinion",
     "anchor_main": [0.1, 0, 0], "anchor_secondary": [0, 0, 0], "axis_main": [0, 0, 1]},
    {"name": "wheel-axle", "type": "revolute", "main": "carrier", "secondary": "wheel",
     "anchor_main": [-0.2, 0, 0], "anchor_secondary": [0, 0, 0], "axis_main": [0, 0, 1]},
    {"name": "mesh", "type": "gear", "main": "pinion", "secondary": "wheel", "carrier": "carrier", "ratio": 2.0,
     "axes_main": {"r": [0, 0, 1], "s": [1, 0, 0]}, "axes_secondary": {"r": [0, 0, 1], "s": [1, 0, 0]}}
  ]
})";

TEST(ArticulatedLoops, LgviHoldsAGearRowOnAFloatingTree) {
  // The gear row's rows are on angular rates, which a shift of the tree's
  // centre of mass does not change: lgvi runs it in joint coordinates by
  // default, keeps the ratio of the axles' rates to rounding and the angular
  // momentum of the free system to round-off (discrete Noether).
  const SceneDescription scene = parseScene(kFloatingGears, "floating-gears.json");
  EXPECT_EQ(Simulation(scene).defaultFormulation("lgvi"), "joint");
  const scene_testing::Trajectory run = scene_testing::simulate(scene, "lgvi", 1e-3, 2.0, 1, "joint");
  ASSERT_FALSE(run.result.failed) << run.result.failure;
  double ratio = 0.0, turned = 0.0;
  for (std::size_t r = 0; r < run.rows.size(); ++r) {
    ratio = std::max(ratio, std::abs(2.0 * run.at(r, "pinion-axle.phidot") + run.at(r, "wheel-axle.phidot")));
    turned = std::max(turned, std::abs(run.at(r, "pinion-axle.phi") - run.at(0, "pinion-axle.phi")));
  }
  // (The run names no invariant: a gear row may hold a carrier to the
  // ground. Here the carrier floats, so L is the stepper's to keep.)
  double L0 = 0.0;
  const double drift = lgviMomentumDrift(scene, 1e-3, 2000, &L0);
  std::printf("floating gears, lgvi (joint) h = 1e-3 over 2 s: max |2 phidot_p + phidot_w| %.2g, |dL| %.3g of %.3g, "
              "the pinion turned %.3g rad\n",
              ratio, drift, L0, turned);
  EXPECT_GT(turned, 4.0);
  EXPECT_LT(ratio, 1e-11);
  EXPECT_LT(drift, 1e-11 * L0);
}

TEST(ArticulatedLoops, LgviKeepsTheFreeCardanShaftsEnergyWithoutDrift) {
  // No force, no dashpot: a variational integrator's energy error
  // oscillates at O(h²) and does not drift. Over 40 s (about 25 turns) at
  // h = 2e-3 the largest error of the last quarter is no larger than the
  // first quarter's (measured both 3.1e-7 relative), and the loop stays
  // closed to rounding (measured max |Φ| 8.8e-14).
  const scene_testing::Trajectory run =
      scene_testing::simulate(freeCardanShaft(), "lgvi", 2e-3, 40.0, 10, "joint");
  ASSERT_FALSE(run.result.failed) << run.result.failure;
  const double e0 = run.at(0, "energy");
  const std::size_t n = run.rows.size();
  double first = 0.0, last = 0.0, phi = 0.0;
  for (std::size_t r = 0; r < n; ++r) {
    const double e = std::abs(run.at(r, "energy") - e0) / e0;
    if (r < n / 4) first = std::max(first, e);
    if (r >= 3 * n / 4) last = std::max(last, e);
    phi = std::max(phi, run.at(r, "constraint_error"));
  }
  std::printf("free Cardan shaft, lgvi (joint) h = 2e-3 over 40 s: energy error %.3g (first quarter), %.3g (last), "
              "max |Phi| %.2g\n",
              first, last, phi);
  EXPECT_GT(first, 0.0);
  EXPECT_LT(first, 1e-4);
  EXPECT_LT(last, 1.5 * first);
  EXPECT_LT(phi, 3e-13);
}

TEST(ArticulatedLoops, LgviHoldsGearRowsOnVelocities) {
  // The built-in gear train (two gears on fixed axes, 2 (ω₁·r₁) + ω₂·r₂ = 0)
  // in joint coordinates: the gear row as a multiplier at the midpoint, the
  // ratio and the kinetic energy kept to rounding over 2 s.
  const Simulation sim(loadScene("gear-train"));
  EXPECT_EQ(sim.defaultFormulation("lgvi"), "joint");
  const scene_testing::Trajectory run = scene_testing::simulate(loadScene("gear-train"), "lgvi", 1e-3, 2.0, 1, "joint");
  const double e0 = run.at(0, "energy");
  double ratio = 0.0, energy = 0.0;
  for (std::size_t r = 0; r < run.rows.size(); ++r) {
    ratio = std::max(ratio, std::abs(2.0 * run.at(r, "pinion.wz") + run.at(r, "wheel.wz")));
    energy = std::max(energy, std::abs(run.at(r, "energy") - e0) / e0);
  }
  EXPECT_LT(ratio, 1e-12);
  EXPECT_LT(energy, 1e-12);
}

TEST(ArticulatedLoops, GenalphaClosesTheLoopWhenAskedForAndConvergesAtOrderTwo) {
  // genalpha in joint coordinates with the loop's rows as multipliers
  // (articulated_kkt_assembly.hpp: the stabilized index-2 method, exact
  // tangents by differences): positions at t = 1 s against joint rkmk4 at
  // h = 1e-4 at order 2, every row on Φ = 0, 1-2 Newton iterations per step;
  // index 3 at rho_inf = 0.9 too. Not the default (stepper_table_rows.hpp,
  // notDefault): the slider-crank stops at index 2 after seconds. Measured:
  // slope 2.0, 1.0-2.0 iterations per step.
  const Simulation sim(fourBar());
  EXPECT_EQ(sim.defaultFormulation("genalpha"), "maximal");
  std::string why;
  EXPECT_TRUE(sim.supports("genalpha", &why, "joint")) << why;
  const RunEnds reference = runEnds(sim, "joint", "rkmk4", 1e-4, 1.0);
  ASSERT_FALSE(reference.result.failed) << reference.result.failure;
  const std::size_t error_column =
      std::find(reference.columns.begin(), reference.columns.end(), "constraint_error") - reference.columns.begin();
  for (const double index : {2.0, 3.0}) {
    std::vector<double> h, error;
    for (double dt : {4e-3, 2e-3, 1e-3}) {
      SimulationOptions o = scene_testing::runOptions("genalpha", "joint", dt, 1.0);
      if (index == 3.0) o.integrator_options = {{"index", 3.0}, {"rho_inf", 0.9}};
      double worst_row = 0.0;
      const RunEnds run = runWatching(sim, o, error_column, &worst_row);
      ASSERT_FALSE(run.result.failed) << run.result.failure;
      h.push_back(dt);
      error.push_back(largestDifference(run, reference, {".x", ".y", ".z"}));
      std::printf("four-bar genalpha (joint, index %g) h = %g: position error %.3g m, max |Phi| %.2g, %.2f Newton "
                  "iterations per step\n",
                  index, dt, error.back(), worst_row, run.result.newton_iterations_mean);
      EXPECT_LE(worst_row, 1e-12) << "h = " << dt;
      EXPECT_LE(run.result.newton_iterations_mean, 2.5) << "h = " << dt;
    }
    EXPECT_NEAR(testing_support::logLogSlope(h, error), 2.0, 0.3) << "index " << index;
  }
}

TEST(ArticulatedLoops, RefusesWhatTheLoopsCannotCarry) {
  std::string why;
  // The integrators without multipliers.
  const Simulation cardan(loadScene("cardan-shaft"));
  EXPECT_TRUE(cardan.supports("rkmk45", &why, "joint")) << why;
  EXPECT_FALSE(cardan.supports("genalpha", &why, "joint"));
  EXPECT_NE(why.find("prescribed"), std::string::npos) << why;
  // lgvi takes the loop, not the prescribed input shaft (a time-dependent
  // constraint), nor a rack-and-pinion row between a floating rack and a
  // pinion on the ground (the row would move the rack's centre of mass).
  EXPECT_FALSE(cardan.supports("lgvi", &why, "joint"));
  EXPECT_NE(why.find("prescribed"), std::string::npos) << why;
  EXPECT_TRUE(Simulation(freeCardanShaft()).supports("lgvi", &why, "joint")) << why;
  EXPECT_FALSE(Simulation(loadScene("rack-pinion")).supports("lgvi", &why, "joint"));
  EXPECT_NE(why.find("floating tree"), std::string::npos) << why;
  EXPECT_TRUE(cardan.supports("cf4", &why, "joint")) << why;
  // A loop whose every joint carries a force element: the joint that closes
  // it would have no coordinate to carry its spring.
  SceneDescription driven = freeCardanShaft();
  for (JointDescription& j : driven.joints) j.coordinates[0].stiffness = 0.5;
  std::string reason;
  EXPECT_FALSE(articulatedCovers(driven, &reason));
  EXPECT_NE(reason.find("closes a loop whose every joint carries a force element"), std::string::npos) << reason;
}

}  // namespace
}  // namespace lieflow
