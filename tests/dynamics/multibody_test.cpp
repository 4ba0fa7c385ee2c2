// Constrained acceleration solve of dynamics/maximal/ against independent
// references: the compound pendulum (θ̈ = −m g ℓ sin θ / I_o), the planar
// double pendulum from Lagrange's equations, long spherical chains (linear
// fill of the factor) and redundant constraints.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <sstream>

#include "dynamics/maximal/chain_builder.hpp"
#include "dynamics/maximal/constrained_acceleration.hpp"

namespace {

using namespace lieflow;
using namespace lieflow::multibody;
using constraints::BodyPose;
using constraints::BodyVelocity;
using Eigen::Matrix3d;
using Eigen::Vector3d;

const Vector3d ez(0, 0, 1);

std::string sci(double x) {
  std::ostringstream s;
  s.precision(3);
  s << std::scientific << x;
  return s.str();
}

SO3d Rz(double t) { return SO3d::exp(t * ez); }

// A general SPD inertia with products of inertia (exercises ω × Jω and the
// coupling the constraints must absorb).
Matrix3d inertiaWithProducts(double a, double b, double c) {
  Matrix3d J;
  J << a, 0.1 * a, -0.05 * c, 0.1 * a, b, 0.07 * b, -0.05 * c, 0.07 * b, c;
  return J;
}

// ---------------------------------------------------------------------------
// Compound pendulum: body on a revolute (axis z) to ground at the origin, CoM at
// distance ℓ: p = ℓ (sin θ, −cos θ, 0), R = Rz(θ), anchor in the body (0, ℓ, 0).
struct Pendulum {
  MultibodyModel model;
  double m = 2.5, l = 0.7, g = 9.81;
  Matrix3d I = inertiaWithProducts(0.3, 0.2, 0.15);
  Pendulum() {
    model.gravity = Vector3d(0, -g, 0);
    model.addBody(RigidBody{"link", m, I, false});
    BodyPose<double> p0{SO3d::identity(), Vector3d(0, -l, 0)};
    Joint j{"hinge", kGround, 0,
            constraints::assembleRevoluteJoint<double>(constraints::groundPose<double>(), p0,
                                                       Vector3d::Zero(), Vector3d(0, l, 0), ez, ez)};
    model.addJoint(j);
  }
  MultibodyState state(double th, double thd) const {
    MultibodyState s;
    s.poses.push_back(BodyPose<double>{Rz(th), l * Vector3d(std::sin(th), -std::cos(th), 0)});
    s.velocities.push_back(
        BodyVelocity<double>{l * thd * Vector3d(std::cos(th), std::sin(th), 0), thd * ez});
    return s;
  }
};

TEST(MultibodyAcceleration, CompoundPendulumMatchesAnalytic) {
  Pendulum P;
  const double Io = P.I(2, 2) + P.m * P.l * P.l;  // parallel axis
  double worst = 0, worst_res = 0;
  for (double th : {0.0, 0.3, -1.1, 2.0, 3.0}) {
    for (double thd : {0.0, 1.7, -4.0}) {
      const auto s = solveConstrainedAccelerations(P.model, P.state(th, thd));
      ASSERT_TRUE(s.ok) << s.reason;
      const double thdd = -P.m * P.g * P.l / Io * std::sin(th);
      const Vector3d wd_ref = thdd * ez;
      // CoM: tangential ℓ θ̈ (cos, sin) plus centripetal ℓ θ̇² (−sin, cos).
      const Vector3d vd_ref = P.l * thdd * Vector3d(std::cos(th), std::sin(th), 0) +
                              P.l * thd * thd * Vector3d(-std::sin(th), std::cos(th), 0);
      EXPECT_NEAR((s.omegadot[0] - wd_ref).norm(), 0.0, 1e-12) << th << " " << thd;
      EXPECT_NEAR((s.vdot[0] - vd_ref).norm(), 0.0, 1e-12) << th << " " << thd;
      EXPECT_LE(s.constraint_residual, 1e-12);
      worst = std::max(worst, (s.omegadot[0] - wd_ref).norm());
      worst_res = std::max(worst_res, s.constraint_residual);
      // Reactions: m v̇ = m g + f_joint; ideal hinge: no moment about the axis.
      EXPECT_NEAR((P.m * s.vdot[0] - P.m * P.model.gravity - s.reactions[0].secondary.force).norm(),
                  0.0, 1e-11);
      ASSERT_TRUE(s.reactions[0].axial_moment.has_value());
      EXPECT_NEAR(*s.reactions[0].axial_moment, 0.0, 1e-11);
    }
  }
  RecordProperty("worst_omegadot_error", sci(worst));
  RecordProperty("worst_constraint_residual", sci(worst_res));
}

TEST(MultibodyAcceleration, HangingPendulumReactionIsWeight) {
  Pendulum P;
  const auto s = solveConstrainedAccelerations(P.model, P.state(0.0, 0.0));
  ASSERT_TRUE(s.ok);
  EXPECT_NEAR((s.reactions[0].secondary.force - Vector3d(0, P.m * P.g, 0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(s.reactions[0].secondary.moment_anchor.norm(), 0.0, 1e-12);
}

// ---------------------------------------------------------------------------
// Planar double pendulum of rigid bodies. Angles θ₁, θ₂ from the downward
// vertical; link 1 pivot-to-pivot length L₁, CoM distances c₁, c₂ from each
// link's own pivot, I₁, I₂ the z inertias about the CoMs. Lagrange:
//   T = ½(I₁ + m₁c₁² + m₂L₁²) θ̇₁² + ½(I₂ + m₂c₂²) θ̇₂² + m₂L₁c₂ cos(θ₁−θ₂) θ̇₁θ̇₂
//   V = −(m₁c₁ + m₂L₁) g cos θ₁ − m₂c₂ g cos θ₂
//   M₁₁θ̈₁ + M₁₂θ̈₂ + m₂L₁c₂ sin(θ₁−θ₂) θ̇₂² + (m₁c₁ + m₂L₁) g sin θ₁ = 0
//   M₁₂θ̈₁ + M₂₂θ̈₂ − m₂L₁c₂ sin(θ₁−θ₂) θ̇₁² + m₂c₂ g sin θ₂ = 0
// with M₁₁ = I₁ + m₁c₁² + m₂L₁², M₁₂ = m₂L₁c₂ cos(θ₁−θ₂), M₂₂ = I₂ + m₂c₂².
TEST(MultibodyAcceleration, DoublePendulumMatchesLagrange) {
  const double m1 = 1.3, m2 = 0.8, L1 = 1.1, c1 = 0.45, c2 = 0.6, g = 9.81;
  const Matrix3d I1 = inertiaWithProducts(0.2, 0.25, 0.12);
  const Matrix3d I2 = inertiaWithProducts(0.1, 0.09, 0.07);
  MultibodyModel model;
  model.gravity = Vector3d(0, -g, 0);
  model.addBody(RigidBody{"upper", m1, I1, false});
  model.addBody(RigidBody{"lower", m2, I2, false});
  const BodyPose<double> b10{SO3d::identity(), Vector3d(0, -c1, 0)};
  const BodyPose<double> b20{SO3d::identity(), Vector3d(0, -L1 - c2, 0)};
  model.addJoint(Joint{"shoulder", kGround, 0,
                       constraints::assembleRevoluteJoint<double>(
                           constraints::groundPose<double>(), b10, Vector3d::Zero(),
                           Vector3d(0, c1, 0), ez, ez)});
  model.addJoint(Joint{"elbow", 0, 1,
                       constraints::assembleRevoluteJoint<double>(
                           b10, b20, Vector3d(0, -(L1 - c1), 0), Vector3d(0, c2, 0), ez, ez)});
  double worst = 0;
  for (const auto& th : {Eigen::Vector4d(0.3, -0.5, 0.0, 0.0), Eigen::Vector4d(1.2, 2.5, 1.5, -2.0),
                         Eigen::Vector4d(-2.8, 0.4, -3.0, 5.0), Eigen::Vector4d(0.0, 3.1, 0.7, 0.2)}) {
    const double t1 = th[0], t2 = th[1], w1 = th[2], w2 = th[3];
    const Vector3d d1(std::sin(t1), -std::cos(t1), 0), d2(std::sin(t2), -std::cos(t2), 0);
    const Vector3d e1(std::cos(t1), std::sin(t1), 0), e2(std::cos(t2), std::sin(t2), 0);
    MultibodyState s;
    s.poses = {BodyPose<double>{Rz(t1), c1 * d1}, BodyPose<double>{Rz(t2), L1 * d1 + c2 * d2}};
    s.velocities = {BodyVelocity<double>{c1 * w1 * e1, w1 * ez},
                    BodyVelocity<double>{L1 * w1 * e1 + c2 * w2 * e2, w2 * ez}};
    const auto sol = solveConstrainedAccelerations(model, s);
    ASSERT_TRUE(sol.ok) << sol.reason;

    const double M11 = I1(2, 2) + m1 * c1 * c1 + m2 * L1 * L1, M22 = I2(2, 2) + m2 * c2 * c2;
    const double M12 = m2 * L1 * c2 * std::cos(t1 - t2), S = m2 * L1 * c2 * std::sin(t1 - t2);
    Eigen::Matrix2d M;
    M << M11, M12, M12, M22;
    const Eigen::Vector2d rhs(-S * w2 * w2 - (m1 * c1 + m2 * L1) * g * std::sin(t1),
                              S * w1 * w1 - m2 * c2 * g * std::sin(t2));
    const Eigen::Vector2d acc = M.inverse() * rhs;
    for (int b = 0; b < 2; ++b) {
      const double err = std::abs(sol.omegadot[b].z() - acc[b]) / std::max(1.0, std::abs(acc[b]));
      EXPECT_LE(err, 1e-10) << "body " << b << " got " << sol.omegadot[b].z() << " want " << acc[b];
      EXPECT_NEAR(sol.omegadot[b].head<2>().norm(), 0.0, 1e-10);
      worst = std::max(worst, err);
    }
    // CoM of the lower link from the closed-form angular accelerations.
    const Vector3d a2 = L1 * (acc[0] * e1 - w1 * w1 * d1) + c2 * (acc[1] * e2 - w2 * w2 * d2);
    EXPECT_NEAR((sol.vdot[1] - a2).norm() / std::max(1.0, a2.norm()), 0.0, 1e-10);
    EXPECT_LE(sol.constraint_residual, 1e-12);
    for (const auto& r : sol.reactions) EXPECT_NEAR(*r.axial_moment, 0.0, 1e-10);
  }
  RecordProperty("worst_relative_error", sci(worst));
}

// ---------------------------------------------------------------------------
// Chain of N rods (length L along body x, CoM at the middle) on spherical
// joints, the first hung from the ground at the origin. Random orientations and
// body angular velocities; the linear velocities satisfy the velocity
// constraints.
MultibodyModel sphericalChain(int N, MultibodyState* state, unsigned seed = 7) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double L = 0.5;
  const Vector3d half(L / 2, 0, 0);
  MultibodyModel model;
  model.gravity = Vector3d(0, 0, -9.81);
  state->poses.clear();
  state->velocities.clear();
  Vector3d tip = Vector3d::Zero(), tip_v = Vector3d::Zero();
  for (int i = 0; i < N; ++i) {
    model.addBody(RigidBody{"rod" + std::to_string(i), 0.5 + 0.2 * (u(gen) + 1.0),
                            inertiaWithProducts(0.002, 0.01, 0.01), false});
    const SO3d R = SO3d::exp(Vector3d(u(gen), u(gen), u(gen)));
    const Vector3d w(3 * u(gen), 3 * u(gen), 3 * u(gen));
    const Vector3d p = tip + R * half;
    const Vector3d v = tip_v + R * w.cross(half);
    state->poses.push_back(BodyPose<double>{R, p});
    state->velocities.push_back(BodyVelocity<double>{v, w});
    model.addJoint(Joint{"ball" + std::to_string(i), i - 1, i,
                         constraints::makeSphericalJoint<double>(i == 0 ? Vector3d::Zero() : half,
                                                                 -half)});
    tip = p + R * half;
    tip_v = v + R * w.cross(half);
  }
  return model;
}

TEST(MultibodyAcceleration, SphericalChainsSolve) {
  for (int N : {10, 200}) {
    MultibodyState s;
    const MultibodyModel model = sphericalChain(N, &s);
    const auto sol = solveConstrainedAccelerations(model, s);
    ASSERT_TRUE(sol.ok) << sol.reason;
    EXPECT_LE(sol.constraint_residual, 1e-9) << "N = " << N;
    RecordProperty("chain_residual_" + std::to_string(N), sci(sol.constraint_residual));
    // Each body: m v̇ = m g + Σ joint forces on it (independent check of the reactions).
    for (int i = 0; i < N; ++i) {
      Vector3d f = model.bodies[i].mass * model.gravity + sol.reactions[i].secondary.force;
      if (i + 1 < N) f += sol.reactions[i + 1].main.force;
      EXPECT_NEAR((model.bodies[i].mass * sol.vdot[i] - f).norm(), 0.0, 1e-9);
    }
  }
}

TEST(MultibodyAcceleration, FactorFillGrowsLinearly) {
  double ratio[2];
  int idx = 0;
  for (int N : {50, 400}) {
    MultibodyState s;
    const MultibodyModel model = sphericalChain(N, &s);
    const auto sol = solveConstrainedAccelerations(model, s);
    ASSERT_TRUE(sol.ok) << sol.reason;
    ratio[idx++] = static_cast<double>(sol.factor_nonzeros) / N;
  }
  RecordProperty("nnzL_per_body_50", std::to_string(ratio[0]));
  RecordProperty("nnzL_per_body_400", std::to_string(ratio[1]));
  EXPECT_NEAR(ratio[1] / ratio[0], 1.0, 0.05) << ratio[0] << " vs " << ratio[1];
  // Block-tridiagonal 3×3 blocks: at most ~3 + 9 strictly lower entries per body.
  EXPECT_LE(ratio[1], 15.0);
}

// ---------------------------------------------------------------------------
TEST(MultibodyAcceleration, RedundantRevoluteIsReported) {
  Pendulum P;
  P.model.addJoint(Joint{"hinge-again", kGround, 0, P.model.joints[0].constraint});
  const auto s = solveConstrainedAccelerations(P.model, P.state(0.4, 1.0));
  EXPECT_FALSE(s.ok);
  EXPECT_TRUE(s.failed_joint == 0 || s.failed_joint == 1);
  EXPECT_NE(s.reason.find("redundant"), std::string::npos) << s.reason;
  EXPECT_NE(s.reason.find("hinge"), std::string::npos) << s.reason;
  EXPECT_EQ(s.lambda.size(), 0);
  try {
    solveConstrainedAccelerationsOrThrow(P.model, P.state(0.4, 1.0));
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.field()).find("joints["), std::string::npos);
  }
}

// Symmetric data (identity inertia, hanging at rest) gives an exactly zero
// pivot, where Eigen's factorization itself stops: still named, not garbage.
TEST(MultibodyAcceleration, RedundantRevoluteExactZeroPivotIsReported) {
  MultibodyModel model;
  model.gravity = Vector3d(0, -9.81, 0);
  model.addBody(RigidBody{"link", 1.0, 0.1 * Matrix3d::Identity(), false});
  const BodyPose<double> p0{SO3d::identity(), Vector3d(0, -1, 0)};
  const auto hinge = constraints::assembleRevoluteJoint<double>(
      constraints::groundPose<double>(), p0, Vector3d::Zero(), Vector3d(0, 1, 0), ez, ez);
  model.addJoint(Joint{"hinge", kGround, 0, hinge});
  model.addJoint(Joint{"hinge-again", kGround, 0, hinge});
  MultibodyState s;
  s.poses = {p0};
  s.velocities = {BodyVelocity<double>{}};
  const auto sol = solveConstrainedAccelerations(model, s);
  EXPECT_FALSE(sol.ok);
  EXPECT_TRUE(sol.failed_joint == 0 || sol.failed_joint == 1);
  EXPECT_NE(sol.reason.find("redundant"), std::string::npos) << sol.reason;
  EXPECT_NE(sol.reason.find("hinge"), std::string::npos) << sol.reason;
}

TEST(MultibodyAcceleration, BadJointInputNamesField) {
  MultibodyModel model;
  model.addBody(RigidBody{"b", 1.0, Matrix3d::Identity(), false});
  try {
    model.addJoint(Joint{"self", 0, 0, constraints::SphericalJoint<double>{}});
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.field(), "joints[0].secondary");
  }
  try {
    model.addJoint(Joint{"unknown", kGround, 3, constraints::SphericalJoint<double>{}});
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.field(), "joints[0].secondary");
  }
  try {
    model.addBody(RigidBody{"bad", 0.0, Matrix3d::Identity(), false});
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.field(), "bodies[1].mass");
  }
}

// A rotation-only body (CoM held fixed): free rigid-body Euler equations with
// a spherical joint to ground at its CoM are unchanged: J ω̇ = −ω × J ω.
TEST(MultibodyAcceleration, RotationOnlyBodyWithBallAtCoM) {
  MultibodyModel model;
  const Matrix3d I = inertiaWithProducts(0.4, 0.3, 0.2);
  model.addBody(RigidBody{"top", 1.0, I, true});
  model.addJoint(Joint{"ball", kGround, 0, constraints::SphericalJoint<double>{}});
  // The ball rows have zero δθ columns at s_b = 0 for a rotation-only body:
  // the system is singular (the joint is redundant with the support).
  MultibodyState s;
  s.poses = {BodyPose<double>{SO3d::exp(Vector3d(0.1, 0.2, 0.3)), Vector3d::Zero()}};
  s.velocities = {BodyVelocity<double>{Vector3d::Zero(), Vector3d(1.0, -2.0, 0.5)}};
  EXPECT_FALSE(solveConstrainedAccelerations(model, s).ok);
  model.joints.clear();
  const auto sol = solveConstrainedAccelerations(model, s);
  ASSERT_TRUE(sol.ok);
  const Vector3d w = s.velocities[0].omega;
  EXPECT_NEAR((I * sol.omegadot[0] + w.cross(I * w)).norm(), 0.0, 1e-12);
}

// ---------------------------------------------------------------------------
// Reusable solver (pattern analysed once, factorize per step).

// Chain of N rods on revolute joints (dynamics/maximal/chain_builder.hpp) with
// products of inertia; axes alternating z / y when `alternate`, else all z.
MultibodyModel revoluteChain(int N, bool alternate, unsigned seed, MultibodyState* state) {
  return randomRevoluteChain(N, alternate, inertiaWithProducts(0.002, 0.01, 0.01), seed, state);
}

double relDiff(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return (a - b).lpNorm<Eigen::Infinity>() / std::max(1.0, b.lpNorm<Eigen::Infinity>());
}

TEST(MultibodyAcceleration, CachedSolverMatchesFreeFunction) {
  for (bool alternate : {false, true}) {
    MultibodyState s0;
    const MultibodyModel model = revoluteChain(30, alternate, 7, &s0);
    ConstrainedAccelerationSolver solver(model);
    AccelerationSolution cached;
    for (unsigned seed = 1; seed <= 6; ++seed) {
      MultibodyState s;
      revoluteChain(30, alternate, seed, &s);  // same topology, new state
      std::vector<BodyLoad> loads;
      if (seed % 2) loads.assign(30, BodyLoad{Vector3d(0.1 * seed, 0, 0), Vector3d(0, 0, 0.01)});
      ASSERT_TRUE(solver.solve(model, s, loads, cached)) << cached.reason;
      const auto ref = solveConstrainedAccelerations(model, s, loads);
      ASSERT_TRUE(ref.ok) << ref.reason;
      EXPECT_LE(cached.constraint_residual, 1e-9);
      EXPECT_LE(relDiff(cached.lambda, ref.lambda), 1e-14) << seed;
      for (int i = 0; i < 30; ++i) {
        EXPECT_LE((cached.vdot[i] - ref.vdot[i]).norm(), 1e-14 * (1 + ref.vdot[i].norm()));
        EXPECT_LE((cached.omegadot[i] - ref.omegadot[i]).norm(),
                  1e-14 * (1 + ref.omegadot[i].norm()));
        ASSERT_TRUE(cached.reactions[i].axial_moment.has_value());
        EXPECT_LE(std::abs(*cached.reactions[i].axial_moment - *ref.reactions[i].axial_moment),
                  1e-14 * (1 + std::abs(*ref.reactions[i].axial_moment)));
      }
      EXPECT_EQ(cached.factor_nonzeros, ref.factor_nonzeros);
    }
    EXPECT_EQ(solver.analyzeCount(), 1);  // pattern analysed once for all states
  }
}

// Planar pendulum chains against an independent dense KKT solve.
TEST(MultibodyAcceleration, CachedSolverMatchesDenseKkt) {
  MultibodyState s;
  const MultibodyModel model = revoluteChain(8, true, 3, &s);
  ConstrainedAccelerationSolver solver;
  const auto sol = solver.solve(model, s);
  ASSERT_TRUE(sol.ok) << sol.reason;
  const int n = model.dofs(), m = model.constraintCount();
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n + m, n + m);
  Eigen::VectorXd r = Eigen::VectorXd::Zero(n + m);
  for (int i = 0; i < 8; ++i) {
    const auto& b = model.bodies[i];
    K.block<3, 3>(6 * i, 6 * i) = b.mass * Matrix3d::Identity();
    K.block<3, 3>(6 * i + 3, 6 * i + 3) = b.inertia;
    const Vector3d w = s.velocities[i].omega;
    r.segment<3>(6 * i) = b.mass * model.gravity;
    r.segment<3>(6 * i + 3) = -w.cross(b.inertia * w);
  }
  for (int k = 0, row = n; k < 8; ++k, row += 5) {
    const auto& jt = model.joints[k];
    const auto& con = std::get<constraints::RevoluteJoint<double>>(jt.constraint);
    const auto pa = jt.main == kGround ? constraints::groundPose<double>() : s.poses[jt.main];
    const auto va =
        jt.main == kGround ? constraints::groundVelocity<double>() : s.velocities[jt.main];
    const auto J = con.jacobians(pa, s.poses[k]);
    if (jt.main != kGround) K.block<5, 6>(row, 6 * jt.main) = J[0];
    K.block<5, 6>(row, 6 * k) = J[1];
    r.segment<5>(row) = -con.convective(pa, s.poses[k], va, s.velocities[k]);
  }
  K.topRightCorner(n, m) = K.bottomLeftCorner(m, n).transpose();
  const Eigen::VectorXd x = K.fullPivLu().solve(r);
  for (int i = 0; i < 8; ++i) {
    EXPECT_NEAR((sol.vdot[i] - x.segment<3>(6 * i)).norm(), 0.0, 1e-9);
    EXPECT_NEAR((sol.omegadot[i] - x.segment<3>(6 * i + 3)).norm(), 0.0, 1e-9);
  }
  EXPECT_LE(relDiff(sol.lambda, x.tail(m)), 1e-9);
}

TEST(MultibodyAcceleration, CachedSolverReportsRedundantAndRecovers) {
  Pendulum P;
  ConstrainedAccelerationSolver solver(P.model);
  ASSERT_TRUE(solver.solve(P.model, P.state(0.4, 1.0)).ok);
  MultibodyModel bad = P.model;
  bad.addJoint(Joint{"hinge-again", kGround, 0, P.model.joints[0].constraint});
  AccelerationSolution sol;
  for (int rep = 0; rep < 2; ++rep) {  // reported on every step, not just the first
    EXPECT_FALSE(solver.solve(bad, P.state(0.4 + rep, 1.0), {}, sol));
    EXPECT_TRUE(sol.failed_joint == 0 || sol.failed_joint == 1);
    EXPECT_NE(sol.reason.find("redundant"), std::string::npos) << sol.reason;
    EXPECT_NE(sol.reason.find("hinge"), std::string::npos) << sol.reason;
    EXPECT_EQ(sol.lambda.size(), 0);
  }
  EXPECT_EQ(solver.analyzeCount(), 2);  // topology change re-analysed once
  // The exactly-zero-pivot case through the cached solver (factorize fails).
  MultibodyModel sym;
  sym.gravity = Vector3d(0, -9.81, 0);
  sym.addBody(RigidBody{"link", 1.0, 0.1 * Matrix3d::Identity(), false});
  const BodyPose<double> p0{SO3d::identity(), Vector3d(0, -1, 0)};
  const auto hinge = constraints::assembleRevoluteJoint<double>(
      constraints::groundPose<double>(), p0, Vector3d::Zero(), Vector3d(0, 1, 0), ez, ez);
  sym.addJoint(Joint{"hinge", kGround, 0, hinge});
  sym.addJoint(Joint{"hinge-again", kGround, 0, hinge});
  MultibodyState s;
  s.poses = {p0};
  s.velocities = {BodyVelocity<double>{}};
  EXPECT_FALSE(solver.solve(sym, s, {}, sol));
  EXPECT_NE(sol.reason.find("redundant"), std::string::npos) << sol.reason;
  // Back to the valid model: solves again and matches the free function.
  ASSERT_TRUE(solver.solve(P.model, P.state(0.4, 1.0), {}, sol)) << sol.reason;
  const auto ref = solveConstrainedAccelerations(P.model, P.state(0.4, 1.0));
  EXPECT_EQ(sol.lambda, ref.lambda);
}

// The cached solver skips re-checking unchanged bodies, but still rejects a
// body made invalid (or a bad state) between steps, like the free function.
TEST(MultibodyAcceleration, CachedSolverStillValidatesBetweenSteps) {
  Pendulum P;
  ConstrainedAccelerationSolver solver(P.model);
  ASSERT_TRUE(solver.solve(P.model, P.state(0.4, 1.0)).ok);
  MultibodyModel bad = P.model;
  bad.bodies[0].inertia(0, 1) = 5.0;  // not symmetric
  try {
    solver.solve(bad, P.state(0.4, 1.0));
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.field(), "bodies[0].inertia");
  }
  bad = P.model;
  bad.bodies[0].mass = -1.0;
  EXPECT_THROW(solver.solve(bad, P.state(0.4, 1.0)), InvalidInput);
  MultibodyState s = P.state(0.4, 1.0);
  s.velocities[0].omega.x() = std::nan("");
  EXPECT_THROW(solver.solve(P.model, s), InvalidInput);
  EXPECT_TRUE(solver.solve(P.model, P.state(0.4, 1.0)).ok);
  EXPECT_EQ(solver.analyzeCount(), 1);
}

}  // namespace
