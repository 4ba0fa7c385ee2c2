/// \file
/// The joint formulation's dynamics on any scalar (scalar_dynamics.hpp)
/// against the simulator's articulated-body algorithm (articulated_system.hpp)
/// on the same models: every joint kind it takes, on either side of its
/// joint, at random states — u̇ to 1e-11, the mass matrix against the
/// composite-rigid-body algorithm's to 1e-12 — and in ceres::Jet, whose value
/// is the double result and whose derivative is the finite difference's.
#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>
#include <ceres/jet.h>

#include "dynamics/joint_space/articulated_scene.hpp"
#include "dynamics/joint_space/scalar_dynamics.hpp"
#include "liegroup/invalid_input.hpp"
#include "liegroup/so3.hpp"
#include "model/scene.hpp"

namespace lieflow {
namespace articulated {
namespace {

/// Spherical joints with the parent main (top, ball) and secondary (socket:
/// its main body e is the child), a universal and a revolute joint whose
/// main bodies are the children, springs, dashpots and an applied moment.
const char* kBalls = R"({"name": "balls", "gravity": [0, 0, -9.81],
  "bodies": [
    {"name": "a", "mass": 1.2, "inertia": [0.02, 0.03, 0.025], "position": [0, 0, -0.3]},
    {"name": "b", "mass": 0.8, "inertia": [0.01, 0.012, 0.006], "position": [0, 0, -0.85]},
    {"name": "c", "mass": 0.5, "inertia": [0.002, 0.004, 0.005], "position": [0.35, 0, -0.95]},
    {"name": "d", "mass": 0.7, "inertia": [0.004, 0.003, 0.002], "position": [0.5, 0, -1.15]},
    {"name": "e", "mass": 0.4, "inertia": [0.003, 0.002, 0.004], "position": [0.5, 0.1, -1.6]}],
  "joints": [
    {"name": "top", "type": "spherical", "main": "ground", "secondary": "a",
     "anchor_main": [0, 0, 0], "anchor_secondary": [0, 0, 0.3]},
    {"name": "cross", "type": "universal", "main": "b", "secondary": "a",
     "anchor_main": [0, 0, 0.25], "anchor_secondary": [0, 0, -0.3],
     "axis1_main": [1, 0, 0], "axis2_secondary": [0, 1, 0],
     "spring1": {"stiffness": 2.0, "rest_angle": 0.3}, "damper2": {"damping": 0.05}},
    {"name": "hinge", "type": "revolute", "main": "c", "secondary": "b",
     "anchor_main": [-0.15, 0, 0], "anchor_secondary": [0.2, 0, -0.1], "axis_main": [0, 0.6, 0.8],
     "moment": {"type": "sine", "amplitude": 0.3, "frequency": 1.5}},
    {"name": "ball", "type": "spherical", "main": "c", "secondary": "d",
     "anchor_main": [0.15, 0, 0], "anchor_secondary": [0, 0, 0.2]},
    {"name": "socket", "type": "spherical", "main": "e", "secondary": "d",
     "anchor_main": [0, -0.1, 0.25], "anchor_secondary": [0, 0, -0.2]}]})";

/// Slides: a cart on a tilted sprung and damped rail, a pendulum hinged on
/// it, a bead on the pendulum whose slide names the bead (the child) main,
/// and a sine force on that slide.
const char* kSlides = R"({"name": "slides", "gravity": [0, 0, -9.81],
  "bodies": [
    {"name": "cart", "mass": 2.0, "inertia": [0.02, 0.03, 0.04]},
    {"name": "arm", "mass": 0.6, "inertia": [0.01, 0.012, 0.002], "position": [0, 0, -0.3]},
    {"name": "bead", "mass": 0.2, "inertia": [0.0004, 0.0004, 0.0002], "position": [0, 0, -0.4]}],
  "joints": [
    {"name": "rail", "type": "prismatic", "main": "ground", "secondary": "cart",
     "anchor_main": [0, 0, 0], "anchor_secondary": [0, 0, 0], "axis_main": [0.9805806756909202, 0, 0.19611613513818404],
     "spring": {"stiffness": 20.0, "rest_position": 0.05}, "damper": {"damping": 0.5}},
    {"name": "pivot", "type": "revolute", "main": "cart", "secondary": "arm",
     "anchor_main": [0, 0, 0], "anchor_secondary": [0, 0, 0.3], "axis_main": [0, 1, 0]},
    {"name": "slide", "type": "prismatic", "main": "bead", "secondary": "arm",
     "anchor_main": [0, 0, 0], "anchor_secondary": [0, 0, -0.1], "axis_main": [0.6, 0, 0.8],
     "spring": {"stiffness": 50.0, "rest_position": 0.02},
     "force": {"type": "sine", "amplitude": 0.5, "frequency": 2.0}}]})";

/// A gimbal hip (three hinges through one point) hanging from a pelvis on a
/// hinge, sprung and damped, with a foot welded to the thigh.
const char* kGimbal = R"({"name": "gimbal", "gravity": [0, 0, -9.81],
  "bodies": [
    {"name": "pelvis", "mass": 4.0, "inertia": [0.04, 0.05, 0.06], "position": [0, 0, -0.1]},
    {"name": "thigh", "mass": 1.5, "inertia": [0.02, 0.02, 0.004], "position": [0.05, 0, -0.5]},
    {"name": "foot", "mass": 0.5, "inertia": [0.001, 0.003, 0.003], "position": [0.1, 0, -0.8]}],
  "joints": [
    {"name": "waist", "type": "revolute", "main": "ground", "secondary": "pelvis",
     "anchor_main": [0, 0, 0], "anchor_secondary": [0, 0, 0.1], "axis_main": [0, 0, 1],
     "spring": {"stiffness": 4.0}},
    {"name": "hip", "type": "gimbal", "main": "pelvis", "secondary": "thigh",
     "anchor_main": [0, 0, -0.1], "anchor_secondary": [-0.05, 0, 0.2],
     "axis1_main": [1, 0, 0], "axis2_main": [0, 0, 1], "axis3_main": [0, 1, 0],
     "spring1": {"stiffness": 3.0, "rest_angle": 0.3}, "spring2": {"stiffness": 2.0, "rest_angle": -0.2},
     "damper3": {"damping": 0.05}},
    {"name": "ankle", "type": "fixed", "main": "thigh", "secondary": "foot",
     "anchor_main": [0.05, 0, -0.3], "anchor_secondary": [0, 0, 0]}]})";

/// A rotation-only flywheel on a sprung and damped hub, carrying a bob on a
/// hinge skew to the hub's.
const char* kFlywheel = R"({"name": "flywheel", "gravity": [0, 0, -9.81],
  "bodies": [
    {"name": "wheel", "mass": 2.0, "inertia": [0.1, 0.05, 0.05], "rotation_only": true, "position": [0, 0, 0]},
    {"name": "bob", "mass": 0.6, "inertia": [0.02, 0.01, 0.015], "position": [0, 0.3, -0.5]}],
  "joints": [
    {"name": "hub", "type": "revolute", "main": "ground", "secondary": "wheel", "anchor_main": [0, 0, 0],
     "anchor_secondary": [0, 0, 0], "axis_main": [1, 0, 0], "spring": {"stiffness": 6.0}, "damper": {"damping": 0.04}},
    {"name": "hanger", "type": "revolute", "main": "wheel", "secondary": "bob", "anchor_main": [0, 0.3, 0],
     "anchor_secondary": [0, 0, 0.5], "axis_main": [0.6, 0.8, 0]}]})";

/// The four trees above and what each holds: every check below runs on each.
struct TestTree {
  const char* json;
  const char* what;
};
const TestTree kTestTrees[] = {
    {kBalls, "spherical joints both ways, universal and revolute with the child main"},
    {kSlides, "slides both ways"},
    {kGimbal, "a gimbal and a weld"},
    {kFlywheel, "a rotation-only wheel carrying a bob"}};

struct Tree {
  SceneDescription scene;
  Tree() = default;
  Tree(SceneDescription s, std::unique_ptr<ArticulatedScene> a) : scene(std::move(s)), assembled(std::move(a)) {}
  std::unique_ptr<ArticulatedScene> assembled;
  const ArticulatedModel& model() const { return assembled->system->model(); }
};

Tree tree(const char* json) {
  Tree t(parseScene(json, "test.json"), nullptr);
  t.assembled = assembleArticulated(t.scene);
  return t;
}

/// A random state of the tree: angles and slides, relative rotations, rates.
ArticulatedState randomState(const Tree& t, std::mt19937& gen) {
  std::uniform_real_distribution<double> angle(-1.2, 1.2), rate(-3.0, 3.0);
  ArticulatedState y = t.assembled->y0;
  for (int j = 0; j < y.q.size(); ++j) y.q[j] = 0.4 * angle(gen);
  for (SO3d& N : y.N) N = SO3d::exp(Eigen::Vector3d(angle(gen), angle(gen), angle(gen)));
  for (int j = 0; j < y.u.size(); ++j) y.u[j] = rate(gen);
  return y;
}

template <typename T>
std::vector<Eigen::Matrix<T, 3, 3>> rotationsOf(const ArticulatedState& y) {
  std::vector<Eigen::Matrix<T, 3, 3>> out;
  for (const SO3d& N : y.N) out.push_back(N.matrix().template cast<T>());
  return out;
}

void expectSameAccelerations(const char* json, const std::string& what) {
  SCOPED_TRACE(what);
  Tree t;
  try {
    t = tree(json);
  } catch (const std::exception& e) {
    FAIL() << e.what();
  }
  ScalarDynamics<double> dynamics(t.model());
  const CoordinateForces<double> forces = modelForces<double>(t.model());
  std::mt19937 gen(11);
  for (int trial = 0; trial < 6; ++trial) {
    const ArticulatedState y = randomState(t, gen);
    const double time = 0.37 * trial;
    Eigen::VectorXd reference;
    t.assembled->system->accelerations(time, y, &reference);
    dynamics.setRotations(rotationsOf<double>(y));
    const Eigen::VectorXd mine = dynamics.accelerations(time, y.q, y.u, forces);
    ASSERT_EQ(mine.size(), reference.size());
    EXPECT_LT((mine - reference).norm(), 1e-11 * (1.0 + reference.norm()))
        << "trial " << trial << "\n  " << mine.transpose() << "\n  vs " << reference.transpose();
  }
}

TEST(ScalarDynamics, AgreesWithTheArticulatedBodyAlgorithm) {
  for (const TestTree& t : kTestTrees) expectSameAccelerations(t.json, t.what);
}

/// The mass matrix from its columns (the recursive Newton–Euler passes for
/// u̇ = e_j without velocity terms) against the simulator's
/// composite-rigid-body algorithm (ArticulatedSystem::secondOrderTerms), at
/// random states of every tree above: to 1e-12 of |M|.
void expectSameMassMatrix(const char* json, const std::string& what) {
  SCOPED_TRACE(what);
  const Tree t = tree(json);
  ScalarDynamics<double> dynamics(t.model());
  std::mt19937 gen(19);
  for (int trial = 0; trial < 6; ++trial) {
    const ArticulatedState y = randomState(t, gen);
    dynamics.setRotations(rotationsOf<double>(y));
    const Eigen::MatrixXd M = dynamics.massMatrix(y.q);
    Eigen::MatrixXd crba, Ct, Kt;
    Eigen::VectorXd g;
    t.assembled->system->secondOrderTerms(0.29 * trial, y, &crba, &g, &Ct, &Kt);
    EXPECT_LT((M - crba).norm(), 1e-12 * crba.norm()) << "trial " << trial << "\n" << M << "\n vs\n" << crba;
  }
}

TEST(ScalarDynamics, MassMatrixIsTheCompositeRigidBodyAlgorithms) {
  for (const TestTree& t : kTestTrees) expectSameMassMatrix(t.json, t.what);
}

/// The recursive Newton–Euler algorithm at the articulated-body algorithm's
/// accelerations gives back the applied generalized forces, τ(q, u, u̇) = Q
/// (to 1e-10 of |Q| + |M u̇|), at random states of every tree above: the two
/// algorithms on the tree passes (tree_passes.hpp) against each other.
void expectInverseDynamicsUndoesForward(const char* json, const std::string& what) {
  SCOPED_TRACE(what);
  const Tree t = tree(json);
  ScalarDynamics<double> dynamics(t.model());
  const CoordinateForces<double> forces = modelForces<double>(t.model());
  std::mt19937 gen(23);
  for (int trial = 0; trial < 6; ++trial) {
    const ArticulatedState y = randomState(t, gen);
    const double time = 0.29 * trial;
    dynamics.setRotations(rotationsOf<double>(y));
    Eigen::VectorXd udot;
    t.assembled->system->accelerations(time, y, &udot);
    const Eigen::VectorXd Q = dynamics.appliedForces(time, y.q, y.u, forces);
    const Eigen::VectorXd tau = dynamics.inverseDynamics(y.q, y.u, udot);
    const Eigen::MatrixXd M = dynamics.massMatrix(y.q);
    EXPECT_LT((tau - Q).norm(), 1e-10 * (Q.norm() + (M * udot).norm())) << "trial " << trial;
  }
}

TEST(ScalarDynamics, NewtonEulerUndoesTheArticulatedBodyAlgorithm) {
  for (const TestTree& t : kTestTrees) expectInverseDynamicsUndoesForward(t.json, t.what);
}

/// The two forward algorithms on the tree passes, the Newton–Euler columns
/// and the articulated-body algorithm (accelerations() takes the first up to
/// kNewtonEulerMaxDofs degrees of freedom), give the same u̇ and the same
/// derivatives in ceres::Jet, seeded along an angle and along a direction
/// that moves a rate and a stiffness together, on every tree above at random
/// states: to 1e-11. (Jet<double, 2>, the instance the other tests build
/// too: each instance of the passes costs the compiler about 45 s.)
void expectBothForwardAlgorithmsAgree(const char* json, const std::string& what) {
  SCOPED_TRACE(what);
  using Jet = ceres::Jet<double, 2>;
  using VecJ = Eigen::Matrix<Jet, Eigen::Dynamic, 1>;
  const Tree t = tree(json);
  ScalarDynamics<Jet> dynamics(t.model());
  std::mt19937 gen(29);
  for (int trial = 0; trial < 4; ++trial) {
    const ArticulatedState y = randomState(t, gen);
    dynamics.setRotations(rotationsOf<Jet>(y));
    VecJ q = y.q.cast<Jet>(), u = y.u.cast<Jet>();
    CoordinateForces<Jet> forces = modelForces<Jet>(t.model());
    q[trial % q.size()].v[0] = 1.0;
    u[(trial + 1) % u.size()].v[1] = 1.0;
    forces.stiffness[static_cast<std::size_t>(trial) % forces.stiffness.size()].v[1] = 1.0;
    const VecJ columns = dynamics.newtonEulerAccelerations(0.3 * trial, q, u, forces);
    const VecJ aba = dynamics.articulatedBodyAccelerations(0.3 * trial, q, u, forces);
    ASSERT_EQ(columns.size(), aba.size());
    for (int j = 0; j < aba.size(); ++j) {
      EXPECT_NEAR(columns[j].a, aba[j].a, 1e-11 * (1.0 + std::abs(aba[j].a))) << "trial " << trial << " u " << j;
      for (int k = 0; k < 2; ++k)
        EXPECT_NEAR(columns[j].v[k], aba[j].v[k], 1e-11 * (1.0 + std::abs(aba[j].v[k])))
            << "trial " << trial << " u " << j << " derivative " << k;
    }
  }
}

TEST(ScalarDynamics, BothForwardAlgorithmsAgreeInJets) {
  for (const TestTree& t : kTestTrees) expectBothForwardAlgorithmsAgree(t.json, t.what);
}

/// In ceres::Jet the value part is the double evaluation, and the derivative
/// along a joint coordinate and along a stiffness is the central difference's.
TEST(ScalarDynamics, JetsCarryTheDerivatives) {
  using Jet = ceres::Jet<double, 2>;
  const Tree t = tree(kSlides);
  std::mt19937 gen(3);
  const ArticulatedState y = randomState(t, gen);
  const ScalarDynamics<double> plain(t.model());
  const ScalarDynamics<Jet> jets(t.model());
  const CoordinateForces<double> forces = modelForces<double>(t.model());
  CoordinateForces<Jet> jet_forces = modelForces<Jet>(t.model());
  Eigen::Matrix<Jet, Eigen::Dynamic, 1> q = y.q.cast<Jet>(), u = y.u.cast<Jet>();
  q[1].v[0] = 1.0;                   // d/d(pivot angle)
  jet_forces.stiffness[0].v[1] = 1.0;  // d/d(rail stiffness)
  const Eigen::Matrix<Jet, Eigen::Dynamic, 1> a = jets.accelerations(0.2, q, u, jet_forces);
  const Eigen::VectorXd a0 = plain.accelerations(0.2, y.q, y.u, forces);
  constexpr double h = 1e-6;
  Eigen::VectorXd qp = y.q, qm = y.q;
  qp[1] += h;
  qm[1] -= h;
  const Eigen::VectorXd dq = (plain.accelerations(0.2, qp, y.u, forces) - plain.accelerations(0.2, qm, y.u, forces)) / (2 * h);
  CoordinateForces<double> kp = forces, km = forces;
  kp.stiffness[0] += h;
  km.stiffness[0] -= h;
  const Eigen::VectorXd dk = (plain.accelerations(0.2, y.q, y.u, kp) - plain.accelerations(0.2, y.q, y.u, km)) / (2 * h);
  for (int j = 0; j < a0.size(); ++j) {
    EXPECT_NEAR(a[j].a, a0[j], 1e-13 * (1.0 + std::abs(a0[j]))) << j;
    EXPECT_NEAR(a[j].v[0], dq[j], 1e-6 * (1.0 + std::abs(dq[j]))) << j;
    EXPECT_NEAR(a[j].v[1], dk[j], 1e-6 * (1.0 + std::abs(dk[j]))) << j;
  }
}

/// A grounded hinge takes GroundedHinge's closed form: the same q̈ as the
/// simulator's articulated-body algorithm and as the general passes (setAxis
/// with the model's own axis turns the closed form off) at random states,
/// with the body on either side of a skew axis through an offset anchor, a
/// full inertia, gravity off the axis, a spring, a dashpot and a moment.
TEST(ScalarDynamics, GroundedHingeClosedFormIsTheGeneralAlgorithm) {
  for (const bool body_main : {false, true}) {
    SCOPED_TRACE(body_main ? "the body main" : "the body secondary");
    const std::string body = R"({"name": "bar", "mass": 1.3, "inertia": [[0.05, 0.004, -0.01], [0.004, 0.06, 0.003],
      [-0.01, 0.003, 0.04]], "position": [0.1, -0.05, -0.3], "orientation": [0.9, 0.1, -0.3, 0.3]})";
    const std::string ends = body_main ? R"("main": "bar", "secondary": "ground", "anchor_main": [0.05, 0.02, 0.28],)"
                                         R"( "anchor_secondary": [0.2, -0.1, 0.0],)"
                                       : R"("main": "ground", "secondary": "bar", "anchor_main": [0.2, -0.1, 0.0],)"
                                         R"( "anchor_secondary": [0.05, 0.02, 0.28],)";
    const std::string json = R"({"name": "hinge", "gravity": [0.4, -0.3, -9.81], "bodies": [)" + body +
                             R"(], "joints": [{"name": "h", "type": "revolute", )" + ends +
                             R"( "axis_main": [0.3, 0.9, -0.2], "spring": {"stiffness": 3.0, "rest_angle": 0.2},)"
                             R"( "damper": {"damping": 0.07}, "moment": {"type": "sine", "amplitude": 0.4,)"
                             R"( "frequency": 1.1}}]})";
    const Tree t = tree(json.c_str());
    ScalarDynamics<double> closed(t.model()), general(t.model());
    ASSERT_TRUE(closed.closedForm());
    general.setAxis(0, t.model().bodies[0].axis1.normalized());
    ASSERT_FALSE(general.closedForm());
    const CoordinateForces<double> forces = modelForces<double>(t.model());
    std::mt19937 gen(5);
    std::uniform_real_distribution<double> angle(-3.1, 3.1), rate(-4.0, 4.0);
    for (int trial = 0; trial < 8; ++trial) {
      ArticulatedState y = t.assembled->y0;
      y.q[0] = angle(gen);
      y.u[0] = rate(gen);
      const double time = 0.29 * trial;
      Eigen::VectorXd reference;
      t.assembled->system->accelerations(time, y, &reference);
      const double a = closed.accelerations(time, y.q, y.u, forces)[0];
      EXPECT_NEAR(a, reference[0], 1e-11 * (1.0 + std::abs(reference[0]))) << trial;
      EXPECT_NEAR(a, general.accelerations(time, y.q, y.u, forces)[0], 1e-12 * (1.0 + std::abs(a))) << trial;
    }
    // In Jets: the derivative along the angle is the general passes'. (Two
    // components, the second unused: the instance the tests above build.)
    using Jet = ceres::Jet<double, 2>;
    ScalarDynamics<Jet> closed_jet(t.model()), general_jet(t.model());
    general_jet.setAxis(0, t.model().bodies[0].axis1.normalized().cast<Jet>());
    Eigen::Matrix<Jet, Eigen::Dynamic, 1> q(1), u(1);
    q[0] = Jet(0.7, 0);
    u[0] = Jet(-1.3);
    const CoordinateForces<Jet> jet_forces = modelForces<Jet>(t.model());
    const Jet a = closed_jet.accelerations(0.4, q, u, jet_forces)[0];
    const Jet b = general_jet.accelerations(0.4, q, u, jet_forces)[0];
    EXPECT_NEAR(a.a, b.a, 1e-12 * (1.0 + std::abs(b.a)));
    EXPECT_NEAR(a.v[0], b.v[0], 1e-11 * (1.0 + std::abs(b.v[0])));
  }
}

/// The mass matrix is symmetric positive definite, and ½ uᵀ M u is the
/// bodies' kinetic energy: the energy is conserved by a fine RK4 run of the
/// gimbal tree with its dashpots taken off (its springs and gravity kept).
TEST(ScalarDynamics, MassMatrixIsSymmetricAndTheEnergyIsConserved) {
  const Tree t = tree(kGimbal);
  const ScalarDynamics<double> dynamics(t.model());
  CoordinateForces<double> forces = modelForces<double>(t.model());
  for (double& c : forces.damping) c = 0.0;
  std::mt19937 gen(8);
  const ArticulatedState y0 = randomState(t, gen);
  const Eigen::MatrixXd M = dynamics.massMatrix(y0.q);
  EXPECT_LT((M - M.transpose()).norm(), 1e-13 * M.norm());
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(M).eigenvalues().minCoeff(), 0.0);
  Eigen::VectorXd q = y0.q, u = y0.u;
  const double e0 = dynamics.energy(q, u, forces);
  const double h = 1e-4;
  for (int k = 0; k < 2000; ++k) {  // classical RK4 on (q, u)
    const Eigen::VectorXd a1 = dynamics.accelerations(0.0, q, u, forces);
    const Eigen::VectorXd a2 = dynamics.accelerations(0.0, q + 0.5 * h * u, u + 0.5 * h * a1, forces);
    const Eigen::VectorXd a3 = dynamics.accelerations(0.0, q + 0.5 * h * (u + 0.5 * h * a1), u + 0.5 * h * a2, forces);
    const Eigen::VectorXd a4 = dynamics.accelerations(0.0, q + h * (u + 0.5 * h * a2), u + h * a3, forces);
    q += h / 6.0 * (u + 2.0 * (u + 0.5 * h * a1) + 2.0 * (u + 0.5 * h * a2) + (u + h * a3));
    u += h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4);
  }
  EXPECT_LT(std::abs(dynamics.energy(q, u, forces) - e0), 1e-9 * (1.0 + std::abs(e0)));
}

/// What it does not take is refused, naming the body: a free root.
TEST(ScalarDynamics, RefusesFreeRoots) {
  const Tree t = tree(R"({"name": "free", "gravity": [0, 0, -9.81],
    "bodies": [{"name": "stone", "mass": 1, "inertia": [0.01, 0.02, 0.03]},
               {"name": "bob", "mass": 1, "inertia": [0.01, 0.01, 0.01], "position": [0, 0, -1]}],
    "joints": [{"name": "hinge", "type": "revolute", "main": "ground", "secondary": "bob",
                "anchor_main": [0, 0, 0], "anchor_secondary": [0, 0, 1], "axis_main": [0, 1, 0]}]})");
  try {
    ScalarDynamics<double> d(t.model(), "free.json");
    FAIL() << "a free root";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("'stone' is a free root"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace articulated
}  // namespace lieflow
