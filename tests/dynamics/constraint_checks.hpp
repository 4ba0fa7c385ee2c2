/// \file
/// The test harness of the kinematic constraint library (dynamics/constraints/),
/// shared by constraints_test.cpp and slider_weld_constraints_test.cpp:
/// random poses and motions, central finite differences and ceres::Jet
/// derivatives with respect to right perturbations (δp, δθ) of every body,
/// 4th-order time derivatives along smooth motions, and the two generic
/// checks every holonomic constraint passes (its Jacobians, and its velocity
/// form and convective term).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <iomanip>
#include <iostream>
#include <map>
#include <random>
#include <string>
#include <type_traits>
#include <utility>

#include <gtest/gtest.h>

#include "dynamics/constraints/constraints.hpp"

#ifdef LIEFLOW_HAVE_CERES
#include <ceres/jet.h>
#endif

namespace lieflow {
namespace constraints {
namespace checks {

using Vec3 = Eigen::Vector3d;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat3 = Eigen::Matrix3d;
using Pose = BodyPose<double>;
using Vel = BodyVelocity<double>;

constexpr double kJacobianTolerance = 1e-7;  ///< relative, Jacobians (FD and Jet)
constexpr double kTimeTolerance = 1e-7;      ///< relative, time derivatives by FD
constexpr double kFdStep = 1e-5;             ///< central differences in δ
constexpr double kTimeStep = 2e-3;           ///< 4th-order stencils in t
constexpr int kSamples = 40;

// ---- random data ----------------------------------------------------------------

inline Vec3 randomVector(std::mt19937& gen, double scale = 1.0) {
  std::normal_distribution<double> n;
  return scale * Vec3(n(gen), n(gen), n(gen));
}
inline Vec3 randomUnit(std::mt19937& gen) { return randomVector(gen).normalized(); }
inline Vec3 randomUnitNormalTo(std::mt19937& gen, const Vec3& a) {
  const Vec3 w = randomVector(gen);
  return (w - w.dot(a) * a).normalized();
}
inline Pose randomPose(std::mt19937& gen) { return Pose{SO3d::random(gen), randomVector(gen)}; }
inline Vel randomVelocity(std::mt19937& gen) { return Vel{randomVector(gen), randomVector(gen)}; }

// ---- discrepancy bookkeeping -------------------------------------------------------

/// Worst relative discrepancy per named check, printed at the end of a test.
class Worst {
 public:
  void add(const std::string& name, double value) {
    double& w = table_[name];
    w = std::max(w, value);
  }
  double operator[](const std::string& name) const { return table_.at(name); }
  void print(const std::string& title) const {
    std::cout << "[ measured ] " << title << " (worst relative discrepancy)\n";
    for (const auto& [name, value] : table_) {
      std::cout << "             " << std::left << std::setw(44) << name << std::scientific
                << std::setprecision(2) << value << "\n";
      ::testing::Test::RecordProperty(name, std::to_string(value));
    }
    std::cout << std::defaultfloat << std::flush;
  }
  void expectAllBelow(double tolerance) const {
    for (const auto& [name, value] : table_) EXPECT_LE(value, tolerance) << name;
  }

 private:
  std::map<std::string, double> table_;
};

inline double relative(const Eigen::MatrixXd& approx, const Eigen::MatrixXd& exact) {
  return (approx - exact).norm() / std::max(exact.norm(), 1e-300);
}

/// The blocks of a constraint side by side (rows × 6N).
template <typename M, std::size_t N>
Eigen::MatrixXd stack(const std::array<M, N>& blocks) {
  Eigen::MatrixXd out(blocks[0].rows(), 6 * N);
  for (std::size_t k = 0; k < N; ++k) out.middleCols(6 * k, 6) = blocks[k].template cast<double>();
  return out;
}

// ---- finite differences and Jets with respect to the body coordinates ---------------

/// Central differences of f(X) (an Eigen vector) w.r.t. (δp_k, δθ_k) of every
/// body k, right perturbations: rows × 6N.
template <std::size_t N, typename F>
Eigen::MatrixXd fdJacobian(const F& f, const std::array<Pose, N>& X, double h = kFdStep) {
  const Eigen::VectorXd f0 = f(X);
  Eigen::MatrixXd J(f0.size(), 6 * N);
  for (std::size_t k = 0; k < N; ++k)
    for (int j = 0; j < 6; ++j) {
      std::array<Pose, N> Xp = X, Xm = X;
      Xp[k] = X[k].rplus(h * Vec6::Unit(j));
      Xm[k] = X[k].rplus(-h * Vec6::Unit(j));
      J.col(6 * k + j) = (f(Xp) - f(Xm)) / (2 * h);
    }
  return J;
}

#ifdef LIEFLOW_HAVE_CERES
/// ∂f/∂(δp_k, δθ_k) by forward-mode differentiation: each body's pose is
/// (R exp(δθ), p + δp) with Jet-seeded δ = 0. f is called with Jet poses.
template <std::size_t N, typename F>
Eigen::MatrixXd jetJacobian(const F& f, const std::array<Pose, N>& X) {
  using J = ceres::Jet<double, 6 * N>;
  std::array<BodyPose<J>, N> XJ;
  for (std::size_t k = 0; k < N; ++k) {
    Vector6<J> delta;
    for (int j = 0; j < 6; ++j) delta[j] = J(0.0, static_cast<int>(6 * k) + j);
    XJ[k] = BodyPose<J>{X[k].R.template cast<J>(), X[k].p.template cast<J>()}.rplus(delta);
  }
  const auto y = f(XJ);
  Eigen::MatrixXd out(y.size(), 6 * N);
  for (int r = 0; r < y.size(); ++r)
    for (int c = 0; c < static_cast<int>(6 * N); ++c) out(r, c) = y[r].v[c];
  return out;
}
#endif

// ---- smooth motions and time derivatives -----------------------------------------------

/// R(t) = R₀ exp(ω t + ½ α t²), p(t) = p₀ + v t + ½ a t²: at t = 0 the body
/// velocity is (v, ω) and the acceleration (a, α) (ω̇ = d/dt[Jr(ξ) ξ̇] = α at
/// ξ = 0 because ω × ω = 0).
struct Motion {
  Pose X0;
  Vel V0;
  Vec6 acc;  ///< (a, α)
  Pose at(double t) const {
    const Vec3 xi = V0.omega * t + 0.5 * acc.tail<3>() * t * t;
    return Pose{X0.R * SO3d::exp(xi), X0.p + V0.v * t + 0.5 * acc.head<3>() * t * t};
  }
  /// The body velocity at time t: (v + a t, Jr(ξ) ξ̇).
  Vel velocityAt(double t) const {
    const Vec3 xi = V0.omega * t + 0.5 * acc.tail<3>() * t * t;
    const Vec3 xi_dot = V0.omega + acc.tail<3>() * t;
    return Vel{V0.v + acc.head<3>() * t, SO3d::Jr(xi) * xi_dot};
  }
};

inline Motion randomMotion(std::mt19937& gen, const Pose& X0) {
  Motion m;
  m.X0 = X0;
  m.V0 = randomVelocity(gen);
  m.acc << randomVector(gen), randomVector(gen);
  return m;
}

/// 4th-order central first and second derivatives of g at t = 0.
template <typename G>
std::pair<Eigen::VectorXd, Eigen::VectorXd> timeDerivatives(const G& g, double h = kTimeStep) {
  const Eigen::VectorXd m2 = g(-2 * h), m1 = g(-h), z = g(0.0), p1 = g(h), p2 = g(2 * h);
  const Eigen::VectorXd d1 = (m2 - 8 * m1 + 8 * p1 - p2) / (12 * h);
  const Eigen::VectorXd d2 = (-m2 + 16 * m1 - 30 * z + 16 * p1 - p2) / (12 * h * h);
  return {d1, d2};
}

// ---- joint specifications (double data, built for any scalar) -------------------------

template <typename S>
Vector3<S> castV(const Vec3& v) {
  return v.cast<S>();
}

/// A pose near b (off the manifold by about `size`).
inline Pose nudge(std::mt19937& gen, const Pose& b, double size) {
  return Pose{b.R * SO3d::exp(randomVector(gen, size)), b.p + randomVector(gen, size)};
}

// ---- independent reference residuals (world-frame formulas, rotation matrices) -------------

template <typename S>
Eigen::Matrix<S, 3, 1> refSpherical(const Vec3& s_a, const Vec3& s_b,
                                    const std::array<BodyPose<S>, 2>& X) {
  return X[0].p + X[0].R.matrix() * s_a.cast<S>() - X[1].p - X[1].R.matrix() * s_b.cast<S>();
}

template <typename S>
S refDot(const Vec3& u_main, const Vec3& w_secondary, const std::array<BodyPose<S>, 2>& X) {
  return (X[0].R.matrix() * u_main.cast<S>()).dot(X[1].R.matrix() * w_secondary.cast<S>());
}

/// Checks jacobians() of `joint` against FD of `reference` and of the
/// library residual, and against Jets of the library residual, at X.
template <typename JointD, typename Ref, typename LibJet>
void checkJacobians(Worst& worst, const std::string& name, const JointD& joint,
                    const std::array<Pose, 2>& X, const Ref& reference, const LibJet& lib_jet) {
  const Eigen::MatrixXd J = stack(joint.jacobians(X[0], X[1]));
  const auto lib = [&](const std::array<Pose, 2>& Y) -> Eigen::VectorXd {
    return joint.residual(Y[0], Y[1]);
  };
  // The library residual equals the reference residual.
  worst.add(name + " residual vs reference",
            (lib(X) - reference(X)).norm() / std::max(1.0, reference(X).norm()));
  worst.add(name + " J vs FD(reference)", relative(fdJacobian(reference, X), J));
  worst.add(name + " J vs FD(residual)", relative(fdJacobian(lib, X), J));
#ifdef LIEFLOW_HAVE_CERES
  worst.add(name + " J vs Jet(residual)", relative(jetJacobian(lib_jet, X), J));
#else
  (void)lib_jet;
#endif
}

/// Along a random motion of both bodies: d/dt Φ = velocity(), and
/// d²/dt² Φ − J q̈ = convective().
template <typename JointD>
void checkTimeDerivatives(Worst& worst, const std::string& name, const JointD& joint,
                          const Motion& ma, const Motion& mb) {
  const auto phi = [&](double t) -> Eigen::VectorXd {
    return joint.residual(ma.at(t), mb.at(t));
  };
  const auto [d1, d2] = timeDerivatives(phi);
  const Pose a = ma.at(0.0), b = mb.at(0.0);
  const Eigen::VectorXd vel = joint.velocity(a, b, ma.V0, mb.V0);
  const auto J = joint.jacobians(a, b);
  const Eigen::VectorXd acc_part = J[0] * ma.acc + J[1] * mb.acc;
  const Eigen::VectorXd conv = joint.convective(a, b, ma.V0, mb.V0);
  worst.add(name + " velocity form vs d/dt Φ", (d1 - vel).norm() / std::max(vel.norm(), 1.0));
  worst.add(name + " convective vs d²Φ/dt² − J q̈",
            (d2 - acc_part - conv).norm() / std::max({conv.norm(), acc_part.norm(), 1.0}));
  // The velocity form is the Jacobian applied to the twists (the same blocks).
  worst.add(name + " velocity == J q̇",
            (vel - (J[0] * ma.V0.twist() + J[1] * mb.V0.twist())).norm() /
                std::max(vel.norm(), 1.0));
}

}  // namespace checks
}  // namespace constraints
}  // namespace lieflow
