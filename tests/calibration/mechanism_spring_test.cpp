/// \file
/// The spring/dashpot fit of whole mechanisms (mechanism_spring_fit.hpp) and
/// the joint-coordinate dynamics on any scalar it integrates
/// (dynamics/joint_space/scalar_dynamics.hpp, through mechanism_flow.hpp),
/// checked against the simulator's articulated-body algorithm on the
/// mechanisms the fit takes (every joint kind: tests/dynamics/scalar_dynamics_test.cpp).
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include <ceres/jet.h>

#include "calibration/mechanism_flow.hpp"
#include "calibration/mechanism_spring_fit.hpp"
#include "calibration/mechanism_spring_start.hpp"
#include "calibration/recording.hpp"
#include "calibration_test_helpers.hpp"
#include "liegroup/invalid_input.hpp"
#include "dynamics/joint_space/articulated_scene.hpp"
#include "model/scene.hpp"

namespace lieflow {
namespace calibration {
namespace {

/// A double pendulum with springs and dashpots on both joints (the elbow's
/// joint names the child as main), and a three-body tree with a universal
/// joint and an applied moment.
const char* kSprungPendulum = R"({"name": "sprung", "gravity": [0, 0, -9.81],
  "bodies": [
    {"name": "upper", "mass": 1.0, "inertia": [0.0833, 0.0833, 0.001], "position": [0, 0, -0.5]},
    {"name": "lower", "mass": 0.7, "inertia": [0.05, 0.04, 0.02], "position": [0, 0, -1.5]}],
  "joints": [
    {"name": "shoulder", "type": "revolute", "main": "ground", "secondary": "upper",
     "anchor_main": [0, 0, 0], "anchor_secondary": [0, 0, 0.5], "axis_main": [0, 1, 0],
     "initial_angle": 0.4, "spring": {"stiffness": 8.0, "rest_angle": 0.1}, "damper": {"damping": 0.05}},
    {"name": "elbow", "type": "revolute", "main": "lower", "secondary": "upper",
     "anchor_main": [0, 0, 0.5], "anchor_secondary": [0, 0, -0.5], "axis_main": [0.28603877677367767, 0.9534625892455922, 0.09534625892455922],
     "initial_angle": -0.3, "spring": {"stiffness": 3.0, "rest_angle": -0.2}, "damper": {"damping": 0.02}}]})";

/// A ball joint from the ground carrying the upper link (turning about the
/// vertical and swinging: a spherical pendulum), a sprung and damped elbow
/// below it.
const char* kBallPendulum = R"({"name": "ball", "gravity": [0, 0, -9.81],
  "bodies": [
    {"name": "upper", "mass": 1.0, "inertia": [0.0833, 0.0833, 0.002], "position": [0, 0, -0.5],
     "angular_velocity": [0.8, -0.5, 1.5]},
    {"name": "lower", "mass": 0.7, "inertia": [0.05, 0.04, 0.02], "position": [0, 0, -1.5]}],
  "joints": [
    {"name": "ball", "type": "spherical", "main": "ground", "secondary": "upper",
     "anchor_main": [0, 0, 0], "anchor_secondary": [0, 0, 0.5]},
    {"name": "elbow", "type": "revolute", "main": "upper", "secondary": "lower",
     "anchor_main": [0, 0, -0.5], "anchor_secondary": [0, 0, 0.5], "axis_main": [0, 1, 0],
     "initial_angle": 0.5, "spring": {"stiffness": 6.0, "rest_angle": 0.1}, "damper": {"damping": 0.03}}]})";

const char* kUniversalTree = R"({"name": "tree", "gravity": [0, 0, -9.81],
  "bodies": [
    {"name": "a", "mass": 1.2, "inertia": [0.09, 0.08, 0.03], "position": [0, 0, -0.5]},
    {"name": "b", "mass": 0.8, "inertia": [0.03, 0.05, 0.04], "position": [0.1, 0.2, -1.4]},
    {"name": "c", "mass": 0.5, "inertia": [0.01, 0.02, 0.015], "position": [-0.3, 0, -0.7]}],
  "joints": [
    {"name": "hip", "type": "universal", "main": "ground", "secondary": "a", "anchor_main": [0, 0, 0],
     "anchor_secondary": [0, 0, 0.5], "axis1_main": [1, 0, 0], "axis2_secondary": [0, 1, 0],
     "spring1": {"stiffness": 5.0}, "damper1": {"damping": 0.03}, "spring2": {"stiffness": 4.0, "rest_angle": 0.2},
     "damper2": {"damping": 0.02}},
    {"name": "knee", "type": "revolute", "main": "a", "secondary": "b", "anchor_main": [0, 0, -0.5],
     "anchor_secondary": [-0.1, -0.2, 0.4], "axis_main": [0, 0.9805806756909202, 0.19611613513818404],
     "moment": {"type": "sine", "amplitude": 0.3, "frequency": 0.8}},
    {"name": "arm", "type": "universal", "main": "c", "secondary": "a", "anchor_main": [0.3, 0, 0.2],
     "anchor_secondary": [0, 0, 0], "axis1_main": [0, 0, 1], "axis2_secondary": [1, 0, 0],
     "spring1": {"stiffness": 2.0}, "spring2": {"stiffness": 1.0}}]})";

/// A rotation-only flywheel on a sprung and damped hub (its centre held by
/// the hub's support), carrying a bob on a sprung hinge at its rim whose axis
/// is skew to the hub's: the wheel's support takes the bob's pull.
const char* kFlywheel = R"({"name": "flywheel", "gravity": [0, 0, -9.81],
  "bodies": [
    {"name": "wheel", "mass": 2.0, "inertia": [0.1, 0.05, 0.05], "rotation_only": true, "position": [0, 0, 0],
     "angular_velocity": [1.0, 0, 0]},
    {"name": "bob", "mass": 0.6, "inertia": [0.02, 0.01, 0.015], "position": [0, 0.3, -0.5]}],
  "joints": [
    {"name": "hub", "type": "revolute", "main": "ground", "secondary": "wheel", "anchor_main": [0, 0, 0],
     "anchor_secondary": [0, 0, 0], "axis_main": [1, 0, 0], "initial_angle": 0.2,
     "spring": {"stiffness": 6.0, "rest_angle": 0.1}, "damper": {"damping": 0.04}},
    {"name": "hanger", "type": "revolute", "main": "wheel", "secondary": "bob", "anchor_main": [0, 0.3, 0],
     "anchor_secondary": [0, 0, 0.5], "axis_main": [0.6, 0.8, 0], "initial_angle": -0.3,
     "spring": {"stiffness": 2.5, "rest_angle": -0.2}, "damper": {"damping": 0.02}}]})";

/// q̈ of MechanismDynamics<double> and of the simulator's ABA at random
/// states agree to rounding; and in Jets the value part is the same.
void expectSameAccelerations(const std::string& json) {
  const SceneDescription scene = parseScene(json, "test.json");
  const std::unique_ptr<ArticulatedScene> tree = assembleArticulated(scene);
  const articulated::ArticulatedModel& model = tree->system->model();
  const MechanismDynamics<double> dynamics(model);
  MechanismForces<double> forces;
  for (int i = 0; i < model.bodyCount(); ++i)
    for (int k = 0; k < model.bodies[i].coordinates(); ++k) {
      const auto& d = model.drives[i][k];
      forces.stiffness.push_back(d.stiffness);
      forces.damping.push_back(d.damping);
      forces.rest_angle.push_back(d.rest_angle);
    }
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> angle(-1.5, 1.5), rate(-3.0, 3.0);
  for (int trial = 0; trial < 5; ++trial) {
    articulated::ArticulatedState y = tree->y0;
    for (int j = 0; j < y.q.size(); ++j) y.q[j] = angle(gen);
    for (int j = 0; j < y.u.size(); ++j) y.u[j] = rate(gen);
    const double t = 0.37 * trial;
    Eigen::VectorXd reference;
    tree->system->accelerations(t, y, &reference);
    const Eigen::VectorXd mine = dynamics.accelerations(t, y.q, y.u, forces);
    EXPECT_LT((mine - reference).norm(), 1e-11 * (1.0 + reference.norm())) << mine.transpose() << "\n vs "
                                                                           << reference.transpose();
  }
}

TEST(CalibMechanismDynamics, AgreesWithTheArticulatedBodyAlgorithm) {
  expectSameAccelerations(kSprungPendulum);
  expectSameAccelerations(kUniversalTree);
  expectSameAccelerations(kFlywheel);
}

}  // namespace
}  // namespace calibration
}  // namespace lieflow

namespace lieflow {
namespace calibration {
namespace {

/// `lieflow simulate` of `json` (written to a file named after the test) with
/// extra arguments, read back as a recording.
Recording simulated(const std::string& json, const std::string& args) {
  const std::string stem = testing::TempDir() + "lieflow_mech_" +
                           testing::UnitTest::GetInstance()->current_test_info()->name();
  {
    std::ofstream f(stem + ".json");
    f << json;
  }
  const std::string command = std::string(LIEFLOW_BINARY_DIR) + "/app/lieflow simulate " + stem + ".json " + args +
                              " --out " + stem + ".csv --quiet";
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
  Recording r = readRecording(stem + ".csv");
  std::remove((stem + ".csv").c_str());
  std::remove((stem + ".json").c_str());
  return r;
}

/// The scene with every spring's stiffness and dashpot's damping scaled (the
/// fit's start).
std::string perturbed(std::string json, double k_scale, double c_scale) {
  for (const char* key : {"\"stiffness\": ", "\"damping\": "}) {
    const double scale = std::string(key).find("stiff") != std::string::npos ? k_scale : c_scale;
    std::size_t at = 0;
    while ((at = json.find(key, at)) != std::string::npos) {
      at += std::string(key).size();
      std::size_t end = at;
      const double value = std::stod(json.substr(at), &end);
      json.replace(at, end, std::to_string(value * scale));
    }
  }
  return json;
}

struct Truth {
  std::string joint;
  int coordinate;
  double stiffness, damping;
};

/// Every fitted coordinate against the truth: |error| within `tolerance`
/// relative (stiffness) and absolute × 10 of the truth's scale (damping).
void expectRecovered(const MechanismSpringFit& f, const std::vector<Truth>& truth, double tolerance) {
  ASSERT_EQ(f.coordinates.size(), truth.size());
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const CoordinateSpring& c = f.coordinates[i];
    SCOPED_TRACE(c.joint + "." + std::to_string(c.coordinate));
    EXPECT_EQ(c.joint, truth[i].joint);
    EXPECT_EQ(c.coordinate, truth[i].coordinate);
    EXPECT_NEAR(c.stiffness, truth[i].stiffness, tolerance * truth[i].stiffness);
    EXPECT_NEAR(c.damping, truth[i].damping, tolerance * 10.0 * std::max(truth[i].damping, 0.01));
  }
}

const char* kSimulate = "--integrator rkmk4 --dt 0.001 --formulation joint --every 10 ";

/// Exact recordings of `json` (10 s, 100 Hz), the fit started 30 % off
/// (stiffness × 1.3, damping × 0.7): from the joint angles and from the
/// gyroscopes alone, every coordinate back to 1e-4 of the truth — the
/// difference of the simulator's and the fit's integrators (rkmk4 at 1 ms
/// against RK4 at 5 ms). (Under the sanitizers 2 s: the fits integrate in
/// Jets, ~20× slower there.)
void expectFittedFromAnglesAndGyroscopes(const char* json, const std::vector<Truth>& truth) {
  const Recording r = simulated(json, std::string(kSimulate) + (test::kSanitized ? "--t-end 2" : "--t-end 10"));
  const SceneDescription start = parseScene(perturbed(json, 1.3, 0.7), "start.json");
  for (MechanismData data : {MechanismData::kAngles, MechanismData::kGyroscopes}) {
    SCOPED_TRACE(mechanismDataName(data));
    MechanismSpringOptions o;
    o.data = data;
    const MechanismSpringFit f = fitMechanismSprings(start, r, o);
    EXPECT_TRUE(f.converged) << f.message;
    EXPECT_EQ(f.data, mechanismDataName(data));
    for (const CoordinateSpring& c : f.coordinates)
      std::printf("%s %s: k %.6f c %.6f\n", mechanismDataName(data), c.joint.c_str(), c.stiffness, c.damping);
    expectRecovered(f, truth, 1e-4);
  }
}

/// A spherical joint in the tree: its rotation is a state on SO(3) that the
/// fit integrates by RKMK and shoots by quaternion blocks, from the bodies'
/// gyroscopes (no angle records it: `data` angles is refused, naming it).
TEST(CalibMechanismSprings, BallJointPendulumFromTheGyroscopes) {
  const Recording r = simulated(kBallPendulum, std::string(kSimulate) + (test::kSanitized ? "--t-end 2" : "--t-end 6"));
  const SceneDescription start = parseScene(perturbed(kBallPendulum, 1.3, 0.7), "start.json");
  MechanismSpringOptions o;
  const MechanismSpringFit f = fitMechanismSprings(start, r, o);
  EXPECT_TRUE(f.converged) << f.message;
  EXPECT_EQ(f.data, "gyroscopes");
  std::printf("ball: k %.7f c %.7f (%d segments, %d substeps, %.2f s)\n", f.coordinates[0].stiffness,
              f.coordinates[0].damping, f.segments, f.substeps, f.seconds);
  expectRecovered(f, {{"elbow", 1, 6.0, 0.03}}, 1e-4);
  o.data = MechanismData::kAngles;
  try {
    fitMechanismSprings(start, r, o);
    ADD_FAILURE() << "angles accepted for a spherical joint";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("'upper' turns on a spherical joint"), std::string::npos) << e.what();
  }
}

/// The sprung double pendulum (a child-first elbow).
TEST(CalibMechanismSprings, DoublePendulumFromAnglesAndFromGyroscopes) {
  expectFittedFromAnglesAndGyroscopes(kSprungPendulum, {{"shoulder", 1, 8.0, 0.05}, {"elbow", 1, 3.0, 0.02}});
}

/// A rotation-only body in the mechanism: the flywheel's hub (measured
/// k 6.000001 and 2.500002, c 0.040000 and 0.020000 from both data).
TEST(CalibMechanismSprings, FlywheelWithARotationOnlyHub) {
  expectFittedFromAnglesAndGyroscopes(kFlywheel, {{"hub", 1, 6.0, 0.04}, {"hanger", 1, 2.5, 0.02}});
}

/// The inverse-dynamics start (mechanism_spring_start.hpp) from the angles
/// alone, rest angles estimated too, against the truth: exact angles (10 s at
/// 100 Hz; measured k 7.74 and 2.79 against 8 and 3: the local cubics over
/// ±0.11 s smooth q̈ by a few %) and angles with 0.002 rad of noise (k 7.81,
/// 2.90; the small dashpots only to a factor of a few there: 0.011 and 0.032
/// against 0.05 and 0.02).
TEST(CalibMechanismSprings, InverseDynamicsStartFromTheAngles) {
  const std::unique_ptr<ArticulatedScene> tree = assembleArticulated(parseScene(kSprungPendulum, "sprung.json"));
  const articulated::ArticulatedModel& model = tree->system->model();
  const std::vector<StartCoordinate> coordinates = {{0, true, true, true, 0.0}, {1, true, true, true, 0.0}};
  const double truth[2][3] = {{8.0, 0.05, 0.1}, {3.0, 0.02, -0.2}};
  for (const char* noise : {"", "--noise-angle 0.002 --seed 3 "}) {
    SCOPED_TRACE(noise);
    // 10 s also under the sanitizers (the start is one pass of inverse
    // dynamics, 0.1 s; over 3 s it is 12 % low on the elbow).
    const Recording r = simulated(kSprungPendulum, std::string(kSimulate) + noise + "--t-end 10");
    const std::vector<const std::vector<double>*> angles = {r.column("shoulder.phi"), r.column("elbow.phi")};
    const MechanismStart s = inverseDynamicsStart(model, r.time, angles, coordinates);
    for (int f = 0; f < 2; ++f) {
      SCOPED_TRACE(f ? "elbow" : "shoulder");
      EXPECT_TRUE(s.stiffness_usable[f]);
      EXPECT_TRUE(s.damping_usable[f]);
      EXPECT_NEAR(s.stiffness[f], truth[f][0], 0.1 * truth[f][0]);
      EXPECT_NEAR(s.rest_angle[f], truth[f][2], 0.02);
      if (*noise == '\0') {
        EXPECT_NEAR(s.damping[f], truth[f][1], 0.2 * truth[f][1]);
      }
    }
  }
}

/// The fit does not depend on the scene's guesses when the angles are
/// recorded: with the scene's springs 100× too stiff and its dashpots 100×
/// too weak it starts from the inverse dynamics (k 7.98, 2.97) and recovers
/// the truth as from any scene (measured 7 iterations, 1.6 s). Started at
/// the scene's values instead (--start scene) it converges too, but its
/// integration steps follow the start's frequency: 18 s at × 100, 5.6 s at
/// × 10, 2.0 s at × 0.01 (9 iterations each).
TEST(CalibMechanismSprings, StartsFromTheRecordedAnglesNotTheScene) {
  const Recording r = simulated(kSprungPendulum, std::string(kSimulate) + (test::kSanitized ? "--t-end 2" : "--t-end 10"));
  const SceneDescription start = parseScene(perturbed(kSprungPendulum, 100.0, 0.01), "start.json");
  const MechanismSpringFit f = fitMechanismSprings(start, r, MechanismSpringOptions());
  EXPECT_TRUE(f.converged) << f.message;
  EXPECT_NE(f.start.find("inverse dynamics"), std::string::npos) << f.start;
  EXPECT_TRUE(f.start_note.empty()) << f.start_note;
  EXPECT_NEAR(f.coordinates[0].start_stiffness, 8.0, 0.8);
  EXPECT_NEAR(f.coordinates[1].start_stiffness, 3.0, 0.3);
  expectRecovered(f, {{"shoulder", 1, 8.0, 0.05}, {"elbow", 1, 3.0, 0.02}}, test::kSanitized ? 1e-3 : 1e-4);
  // From gyroscopes alone the angles are integrated from the scene's initial
  // angles (anglesFromGyroscopes): the same start (measured k 7.976, 2.969
  // against 7.978, 2.967 from the recorded angles).
  MechanismSpringOptions o;
  o.data = MechanismData::kGyroscopes;
  Recording rates_only = r;
  rates_only.scalars.clear();
  const MechanismSpringFit g = fitMechanismSprings(start, rates_only, o);
  EXPECT_TRUE(g.converged) << g.message;
  EXPECT_NE(g.start.find("integrated from the gyroscopes"), std::string::npos) << g.start;
  EXPECT_NEAR(g.coordinates[0].start_stiffness, 8.0, 0.8);
  EXPECT_NEAR(g.coordinates[1].start_stiffness, 3.0, 0.3);
  expectRecovered(g, {{"shoulder", 1, 8.0, 0.05}, {"elbow", 1, 3.0, 0.02}}, test::kSanitized ? 1e-3 : 1e-4);
}

/// The angles integrated from two gyroscopes per joint (Heun between
/// samples; anglesFromGyroscopes) against the recorded ones: on the sprung
/// double pendulum and on the universal tree (whose rates need the current
/// angles), 10 s / 2 s at 100 Hz from exact rates.
TEST(CalibMechanismSprings, AnglesFromGyroscopes) {
  for (const auto& [json, t_end] : {std::pair<const char*, const char*>{kSprungPendulum, "--t-end 10"},
                                    {kUniversalTree, "--t-end 2"}}) {
    const SceneDescription scene = parseScene(json, "scene.json");
    const std::unique_ptr<ArticulatedScene> tree = assembleArticulated(scene);
    const articulated::ArticulatedModel& model = tree->system->model();
    const Recording r = simulated(json, std::string(kSimulate) + t_end);
    std::vector<const std::vector<Eigen::Vector3d>*> rates;
    for (const std::string& name : model.names) rates.push_back(&r.body(name)->angular_velocity);
    std::vector<std::vector<double>> angles;
    ASSERT_TRUE(anglesFromGyroscopes(model, tree->y0.q, r.time, rates, &angles));
    double worst = 0.0;
    for (const articulated::ArticulatedBody& b : model.bodies) {
      const std::string& joint = scene.joints[static_cast<std::size_t>(b.scene_joint)].name;
      for (int c = 0; c < b.coordinates(); ++c) {
        const std::string column = joint + (b.coordinates() == 1 ? ".phi" : c == 0 ? ".phi1" : ".phi2");
        const std::vector<double>& recorded = *r.column(column);
        for (std::size_t k = 0; k < recorded.size(); ++k)
          worst = std::max(worst, std::abs(angles[static_cast<std::size_t>(b.q_begin + c)][k] - recorded[k]));
      }
    }
    // Measured 9.8e-5 rad (pendulum, 10 s) and 2.0e-4 rad (universal tree).
    EXPECT_LT(worst, 5e-4);
  }
  // With gyroscope noise (0.01 rad/s: a random walk of ~3e-3 rad over 10 s)
  // the inverse-dynamics start from the integrated angles stays within 10 %
  // (measured 7.74 and 2.79 against 8 and 3; rest angles 0.093, -0.195
  // against 0.1, -0.2).
  const std::unique_ptr<ArticulatedScene> tree = assembleArticulated(parseScene(kSprungPendulum, "sprung.json"));
  const articulated::ArticulatedModel& model = tree->system->model();
  const Recording r = simulated(kSprungPendulum, std::string(kSimulate) + "--noise-gyro 0.01 --seed 5 --t-end 10");
  std::vector<const std::vector<Eigen::Vector3d>*> rates;
  for (const std::string& name : model.names) rates.push_back(&r.body(name)->angular_velocity);
  std::vector<std::vector<double>> angles;
  ASSERT_TRUE(anglesFromGyroscopes(model, tree->y0.q, r.time, rates, &angles));
  const MechanismStart s = inverseDynamicsStart(model, r.time, {&angles[0], &angles[1]},
                                                {{0, true, true, true, 0.0}, {1, true, true, true, 0.0}});
  EXPECT_NEAR(s.stiffness[0], 8.0, 0.8);
  EXPECT_NEAR(s.stiffness[1], 3.0, 0.3);
}

/// A three-body tree with two universal joints (one naming the child as
/// main), a revolute joint with an applied moment and no spring, rest angles
/// fitted: 4 sprung coordinates (the arm's without dashpots: their damping
/// held at 0). 2 s at 100 Hz (2.2 s of fitting in the optimized build; not
/// under the sanitizers).
TEST(CalibMechanismSprings, UniversalTreeWithRestAngles) {
  if (test::kSanitized) GTEST_SKIP() << "a 14 s fit in the optimized build";
  const Recording r = simulated(kUniversalTree, std::string(kSimulate) + "--t-end 2");
  const SceneDescription start = parseScene(perturbed(kUniversalTree, 1.2, 0.8), "start.json");
  MechanismSpringOptions o;
  o.fit_rest_angle = true;
  const MechanismSpringFit f = fitMechanismSprings(start, r, o);
  EXPECT_TRUE(f.converged) << f.message;
  expectRecovered(f, {{"hip", 1, 5.0, 0.03}, {"hip", 2, 4.0, 0.02}, {"arm", 1, 2.0, 0.0}, {"arm", 2, 1.0, 0.0}},
                  1e-4);
  EXPECT_FALSE(f.coordinates[2].damping_fitted);
  EXPECT_EQ(f.coordinates[2].damping, 0.0);
  EXPECT_EQ(f.coordinates[2].damping_sigma, 0.0);
  EXPECT_NEAR(f.coordinates[1].rest_angle, 0.2, 1e-4);
  EXPECT_NEAR(f.coordinates[0].rest_angle, 0.0, 1e-4);
}

/// σ is honest: 10 noisy recordings (angles 0.002 rad, 5 s), the four
/// parameters' errors pooled: within 3σ in ≥ 38 of 40, mean (error/σ)² in
/// [0.4, 1.8] (10 trials scatter it by about ±0.45; measured 40 of 40, 1.10).
TEST(CalibMechanismSprings, SigmaIsHonest) {
  if (test::kSanitized) GTEST_SKIP() << "10 fits of 2 s each: run in the optimized build";
  const SceneDescription start = parseScene(perturbed(kSprungPendulum, 1.3, 0.7), "start.json");
  const double truth[4] = {8.0, 0.05, 3.0, 0.02};
  int covered = 0, count = 0;
  double ratio = 0.0;
  for (int seed = 1; seed <= 10; ++seed) {
    const Recording r =
        simulated(kSprungPendulum, std::string(kSimulate) + "--t-end 5 --noise-angle 0.002 --seed " + std::to_string(seed));
    const MechanismSpringFit f = fitMechanismSprings(start, r, MechanismSpringOptions());
    for (int c = 0; c < 2; ++c) {
      const double value[2] = {f.coordinates[c].stiffness, f.coordinates[c].damping};
      const double sigma[2] = {f.coordinates[c].stiffness_sigma, f.coordinates[c].damping_sigma};
      for (int k = 0; k < 2; ++k) {
        const double e = (value[k] - truth[2 * c + k]) / sigma[k];
        covered += std::abs(e) <= 3.0;
        ratio += e * e;
        ++count;
      }
    }
  }
  ratio /= count;
  std::printf("mechanism springs: within 3 sigma %d of %d, mean (error/sigma)^2 %.2f\n", covered, count, ratio);
  EXPECT_GE(covered, count - 2);
  EXPECT_GT(ratio, 0.4);
  EXPECT_LT(ratio, 1.8);
}

/// The joint axis with the spring (--fit-axis) on `spring-hinge` (one bar on
/// a horizontal hinge; the fit started 3° off the axis, the spring 30 % off),
/// from the bar's gyroscope (0.01 rad/s): the gyroscope reads φ̇ times the
/// axis in the bar's frame, so that axis (axis_secondary) comes out within a
/// fraction of a degree and 3σ of the truth's (measured 0.0055°, σ 0.013°).
/// The world axis (axis_main) rests on the scene's zero-angle orientation,
/// which the tilted start scene gets wrong by 2.3°: the gravity stiffness
/// m g ℓ (1 − cos δ) it implies shifts k by ~1e-3 relative (measured 12.0015
/// ± 0.0005), so k is checked to 1e-3 and c to 3σ.
TEST(CalibMechanismSprings, AxisWithTheSpringFromAGyroscope) {
  std::ifstream file(std::string(LIEFLOW_SOURCE_DIR) + "/scenes/spring-hinge.json");
  std::string json((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  const Recording r = simulated(json, std::string(kSimulate) + (test::kSanitized ? "--t-end 2" : "--t-end 5") +
                                          " --noise-gyro 0.01 --seed 3");
  // The truth's axis in the bar's frame: the scene's axis seen from the bar at zero angle.
  const std::unique_ptr<ArticulatedScene> truth = assembleArticulated(parseScene(json, "truth.json"));
  const Eigen::Vector3d truth_secondary =
      truth->system->model().bodies[0].R_ref.transpose() * Eigen::Vector3d::UnitY();
  const std::string tilted = "\"axis_main\": [0, 0.9986295347545738, 0.05233595624294383]";  // 3° about x
  const std::size_t at = json.find("\"axis_main\": [0, 1, 0]");
  ASSERT_NE(at, std::string::npos);
  json.replace(at, std::string("\"axis_main\": [0, 1, 0]").size(), tilted);
  MechanismSpringOptions o;
  o.fit_axis = true;
  o.data = MechanismData::kGyroscopes;
  const MechanismSpringFit f = fitMechanismSprings(parseScene(perturbed(json, 1.3, 0.7), "start.json"), r, o);
  ASSERT_EQ(f.coordinates.size(), 1u);
  const CoordinateSpring& c = f.coordinates[0];
  ASSERT_TRUE(c.axis_fitted);
  const double error_deg =
      std::acos(std::min(1.0, std::abs(c.axis_secondary.dot(truth_secondary)))) * 57.29577951308232;
  std::printf("axis error %.4f deg (sigma %.4f), k %.4f ± %.4f, c %.5f ± %.5f\n", error_deg, c.axis_sigma_deg,
              c.stiffness, c.stiffness_sigma, c.damping, c.damping_sigma);
  EXPECT_LT(error_deg, 3.0 * c.axis_sigma_deg + 1e-6);
  EXPECT_LT(c.axis_sigma_deg, 0.5);
  EXPECT_LT(std::abs(c.stiffness - 12.0), 1e-3 * 12.0);
  EXPECT_LT(std::abs(c.damping - 0.1), 3.0 * c.damping_sigma + 1e-6);
}

TEST(CalibMechanismSprings, RefusedWhereItDoesNotApply) {
  const Recording r = simulated(kSprungPendulum, std::string(kSimulate) + "--t-end 1");
  MechanismSpringOptions o;
  // No spring or dashpot anywhere.
  std::string bare = kSprungPendulum;
  for (const char* cut : {", \"spring\": {\"stiffness\": 8.0, \"rest_angle\": 0.1}, \"damper\": {\"damping\": 0.05}",
                          ", \"spring\": {\"stiffness\": 3.0, \"rest_angle\": -0.2}, \"damper\": {\"damping\": 0.02}"}) {
    const std::size_t at = bare.find(cut);
    ASSERT_NE(at, std::string::npos) << cut;
    bare.erase(at, std::string(cut).size());
  }
  EXPECT_THROW(fitMechanismSprings(parseScene(bare, "bare.json"), r, o), InvalidInput);
  // Gyroscopes asked for, angles recorded only.
  Recording angles_only = r;
  angles_only.bodies.clear();
  o.data = MechanismData::kGyroscopes;
  EXPECT_THROW(fitMechanismSprings(parseScene(kSprungPendulum, "s.json"), angles_only, o), InvalidInput);
}

}  // namespace
}  // namespace calibration
}  // namespace lieflow
