/// \file
/// The Cayley map (liegroup/cayley.hpp) and dexp⁻¹ (liegroup/dexp.hpp).
///
/// Cayley references: the matrix definition cay(ξ) = (I − ξ^/2)⁻¹(I + ξ^/2)
/// evaluated with a general matrix inverse; the rotation angle 2 atan(θ/2);
/// central finite differences and ceres::Jet for dcayRight / dcayLeft
/// (Kobilarov & Marsden 2011, §2.3).
/// dexp⁻¹ references: its defining property as the inverse of the left
/// Jacobian, the RKMK algebra ODE Θ' = dexp⁻¹_{−Θ}(ξ) measured by finite
/// differences, and the measured order of the truncation error of its
/// Bernoulli series (Iserles, Munthe-Kaas, Nørsett, Zanna 2000, §3.4).
#include <cmath>
#include <iomanip>
#include <sstream>
#include <vector>

#include <gtest/gtest.h>

#include "liegroup/cayley.hpp"
#include "liegroup/dexp.hpp"
#include "test_helpers.hpp"

namespace lieflow {
namespace test {
namespace {

/// Least-squares slope of log y against log x.
double logLogSlope(const std::vector<double>& x, const std::vector<double>& y) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = static_cast<double>(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double lx = std::log(x[i]), ly = std::log(y[i]);
    sx += lx;
    sy += ly;
    sxx += lx * lx;
    sxy += lx * ly;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

/// n log-spaced values from lo to hi.
std::vector<double> logSpace(double lo, double hi, int n) {
  std::vector<double> v;
  for (int i = 0; i < n; ++i) v.push_back(lo * std::pow(hi / lo, static_cast<double>(i) / (n - 1)));
  return v;
}

/// Rotation vectors with θ log-spaced over [1e-9, 1e3] (and 0), random axes.
std::vector<Eigen::Vector3d> cayleyArguments(Rng& rng) {
  std::vector<Eigen::Vector3d> ws{Eigen::Vector3d::Zero()};
  for (double theta : logSpace(1e-9, 1e3, 400)) ws.push_back(theta * randomUnit(rng));
  return ws;
}

// ---- Cayley, SO(3) -------------------------------------------------------------

// cay(w) is the rotation by 2 atan(θ/2) about w/θ, and equals the matrix
// definition (I − W/2)⁻¹(I + W/2).
TEST(CayleySO3, AngleAxisAndMatrixDefinition) {
  Rng rng(51);
  for (const Eigen::Vector3d& w : cayleyArguments(rng)) {
    const double theta = w.norm();
    const SO3d C = cay(w);
    const Eigen::Vector3d log_c = C.log();
    EXPECT_NEAR(log_c.norm(), 2.0 * std::atan(0.5 * theta), 1e-15 * std::max(1.0, theta)) << theta;
    if (theta > 0) {
      EXPECT_LE((log_c.normalized() - w / theta).norm(), 1e-14) << theta;
    }
    // The reference inverts I − W/2, whose condition number √(1 + θ²/4)
    // scales its own rounding error.
    const Eigen::Matrix3d W = SO3d::hat(w), I = Eigen::Matrix3d::Identity();
    const Eigen::Matrix3d ref = (I - 0.5 * W).inverse() * (I + 0.5 * W);
    EXPECT_LE((C.matrix() - ref).norm(), 1e-15 * (4 + theta)) << theta;
  }
}

// cay⁻¹(cay(w)) = w (relative), cay(cay⁻¹(R)) = R, cay(−w) = cay(w)⁻¹.
TEST(CayleySO3, InverseAndNegation) {
  Rng rng(52);
  for (const Eigen::Vector3d& w : cayleyArguments(rng)) {
    const SO3d C = cay(w);
    EXPECT_LE((cayInv(C) - w).norm(), 4e-16 * std::max(w.norm(), 1e-300) + 1e-300) << w.norm();
    EXPECT_LE((cay(Eigen::Vector3d(-w)).matrix() - C.inverse().matrix()).norm(), 1e-15) << w.norm();
  }
  for (int i = 0; i < 1000; ++i) {
    const SO3d R = SO3d::exp(std::uniform_real_distribution<double>(0, kPi - 1e-3)(rng) * randomUnit(rng));
    EXPECT_LE((cay(cayInv(R)).matrix() - R.matrix()).norm(), 1e-13);
  }
}

// cay(w) = exp(w) + O(‖w‖³): the rotation angle 2 atan(θ/2) = θ − θ³/12 + …,
// so ‖log(exp(w)⁻¹ cay(w))‖ / θ³ → 1/12 and the log-log slope is 3.
TEST(CayleySO3, ApproximatesExpToThirdOrder) {
  Rng rng(53);
  const Eigen::Vector3d u = randomUnit(rng);
  std::vector<double> s = logSpace(1e-3, 1e-1, 12), err;
  for (double t : s) err.push_back((SO3d::exp(t * u).inverse() * cay(Eigen::Vector3d(t * u))).log().norm());
  const double slope = logLogSlope(s, err);
  std::cout << "[ measured ] SO3 |cay(w) - exp(w)| log-log slope = " << slope << std::endl;
  EXPECT_NEAR(slope, 3.0, 0.02);
  EXPECT_NEAR(err[5] / std::pow(s[5], 3), 1.0 / 12.0, 1e-3);
}

// dcayRight / dcayLeft against central differences of
// cay(w+δ) ⊖ cay(w) = log(cay(w)⁻¹ cay(w+δ)) and log(cay(w+δ) cay(w)⁻¹),
// and against Jets through the matrix of cay; their ...Inv are inverses.
TEST(CayleySO3, TrivializedDerivatives) {
  Rng rng(54);
  MaxTracker fd_right, fd_left, jet_right, jet_left, inverse;
  for (const Eigen::Vector3d& w : cayleyArguments(rng)) {
    const SO3d C = cay(w);
    std::ostringstream at;
    at << "theta = " << w.norm();
    // cay varies on the scale max(1, θ): step 1e-6 of that scale.
    const double h = 1e-6 * std::max(1.0, w.norm());
    const Eigen::MatrixXd fdR = centralDifference(
        [&](const Eigen::VectorXd& d) -> Eigen::VectorXd {
          return (C.inverse() * cay(Eigen::Vector3d(w + d))).log();
        },
        3, h);
    const Eigen::MatrixXd fdL = centralDifference(
        [&](const Eigen::VectorXd& d) -> Eigen::VectorXd {
          return (cay(Eigen::Vector3d(w + d)) * C.inverse()).log();
        },
        3, h);
    fd_right.update(relativeError(dcayRight(w), fdR), at.str());
    fd_left.update(relativeError(dcayLeft(w), fdL), at.str());
#ifdef LIEFLOW_HAVE_CERES
    const SO3<Jet> CJ = cay(seed<3>(w));
    jet_right.update(relativeError(dcayRight(w), jetRightJacobianOfGroup(CJ)), at.str());
    jet_left.update(relativeError(dcayLeft(w), jetLeftJacobianOfGroup(CJ)), at.str());
#endif
    const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
    inverse.update((dcayRight(w) * dcayRightInv(w) - I).norm(), at.str());
    inverse.update((dcayRightInv(w) * dcayRight(w) - I).norm(), at.str());
    inverse.update((dcayLeft(w) * dcayLeftInv(w) - I).norm(), at.str());
    inverse.update((dcayLeftInv(w) * dcayLeft(w) - I).norm(), at.str());
  }
  std::cout << "[ measured ] dcayRight vs FD " << fd_right.value << ", vs Jet " << jet_right.value
            << "; dcayLeft vs FD " << fd_left.value << ", vs Jet " << jet_left.value
            << "; |dcay * dcayInv - I| " << inverse.value << std::endl;
  EXPECT_LE(fd_right.value, 1e-7) << fd_right.where;
  EXPECT_LE(fd_left.value, 1e-7) << fd_left.where;
  EXPECT_LE(jet_right.value, 1e-7) << jet_right.where;
  EXPECT_LE(jet_left.value, 1e-7) << jet_left.where;
  // dcayRightInv grows like θ²/4, so the products lose ~θ² ε.
  EXPECT_LE(inverse.value, 1e-9) << inverse.where;
}

// ---- Cayley, SE(3) --------------------------------------------------------------

// cay(ξ) equals the 4×4 matrix definition (I − ξ^/2)⁻¹(I + ξ^/2);
// cay⁻¹(cay(ξ)) = ξ; cay(−ξ) = cay(ξ)⁻¹; cay = exp + O(‖ξ‖³).
TEST(CayleySE3, MatrixDefinitionInverseAndOrder) {
  Rng rng(55);
  const Eigen::Matrix4d I = Eigen::Matrix4d::Identity();
  for (const Eigen::Vector3d& w : cayleyArguments(rng)) {
    Eigen::Matrix<double, 6, 1> xi;
    xi << randomInBall(rng), w;
    const SE3d C = cay(xi);
    const Eigen::Matrix4d A = SE3d::hat(xi);
    const Eigen::Matrix4d ref = (I - 0.5 * A).inverse() * (I + 0.5 * A);
    EXPECT_LE((C.matrix() - ref).norm(), 1e-15 * (4 + w.norm()) * ref.norm()) << w.norm();
    EXPECT_LE((cayInv(C) - xi).norm(), 1e-15 * std::max(1.0, xi.norm())) << w.norm();
    EXPECT_LE((cay(Eigen::Matrix<double, 6, 1>(-xi)).matrix() - C.inverse().matrix()).norm(), 1e-14);
  }
  Eigen::Matrix<double, 6, 1> dir;
  dir << randomInBall(rng), randomUnit(rng);
  dir.normalize();
  std::vector<double> s = logSpace(1e-3, 1e-1, 12), err;
  for (double t : s) {
    const Eigen::Matrix<double, 6, 1> xi = t * dir;
    err.push_back((SE3d::exp(xi).inverse() * cay(xi)).log().norm());
  }
  const double slope = logLogSlope(s, err);
  std::cout << "[ measured ] SE3 |cay(xi) - exp(xi)| log-log slope = " << slope << std::endl;
  EXPECT_NEAR(slope, 3.0, 0.02);
}

// ---- dexp⁻¹ --------------------------------------------------------------------------

template <typename G>
typename G::Tangent randomTangent(Rng& rng, double rotation_angle) {
  return sampleTangent<G>(AngleBand{"", rotation_angle}, rng);
}

// dexp⁻¹_Ω inverts the left Jacobian (dexp_Ω = Jl(Ω), checked against finite
// differences in jacobians_test.cpp), and the RKMK algebra ODE of dexp.hpp
// holds: X₀ exp(Θ + h Θ') = X₀ exp(Θ) exp(h ξ) + O(h²) for Θ' = dexp⁻¹_{−Θ}(ξ).
template <typename G>
void checkDexpInvDefinition() {
  Rng rng(61);
  for (int i = 0; i < 500; ++i) {
    const double angle = std::uniform_real_distribution<double>(0.0, 3.0)(rng);
    const auto Omega = randomTangent<G>(rng, angle);
    const auto u = randomTangent<G>(rng, 1.0);
    const typename G::Tangent v = G::Jl(Omega) * u;
    EXPECT_LE((dexpInv<G>(Omega, v) - u).norm(), 1e-14 * (1 + v.norm())) << Omega.transpose();
    // Θ' by central differences of Θ(h) = log(exp(Θ) exp(h ξ)).
    const double h = 1e-6;
    const typename G::Tangent theta_dot =
        ((G::exp(Omega) * G::exp(h * u)).log() - (G::exp(Omega) * G::exp(-h * u)).log()) / (2 * h);
    EXPECT_LE((dexpInv<G>(typename G::Tangent(-Omega), u) - theta_dot).norm(), 1e-8 * (1 + u.norm()))
        << Omega.transpose();
  }
}

TEST(DexpInvSO3, InvertsLeftJacobianAndGivesTheAlgebraOde) { checkDexpInvDefinition<SO3d>(); }
TEST(DexpInvSE3, InvertsLeftJacobianAndGivesTheAlgebraOde) { checkDexpInvDefinition<SE3d>(); }

/// The order of the error of the series truncated after ad^q: the index of
/// the first omitted nonzero Bernoulli coefficient (B_k = 0 for odd k ≥ 3).
int expectedTruncationOrder(int q) {
  int k = q + 1;
  while (k >= 3 && k % 2 == 1) ++k;
  return k;
}

// ‖dexpInvTruncated(Ω, v, q) − dexpInv(Ω, v)‖ = O(‖Ω‖^p) with p the first
// omitted nonzero Bernoulli term: slopes 1, 2, 4, 4, 6, 6, 8 for q = 0..6.
// Each order is fitted where that term dominates both the next one (≤ 3%)
// and rounding (error ≥ 1e-12).
template <typename G>
void checkTruncationOrders(const char* group) {
  Rng rng(62);
  auto Omega_dir = randomTangent<G>(rng, 1.0);
  Omega_dir.normalize();
  const auto v = randomTangent<G>(rng, 1.0);
  for (int q = 0; q <= 6; ++q) {
    const int p = expectedTruncationOrder(q);
    const double lo = p <= 2 ? 5e-3 : p == 4 ? 5e-2 : p == 6 ? 1e-1 : 2e-1;
    const double hi = p <= 2 ? 5e-2 : p == 4 ? 5e-1 : 1.0;
    std::vector<double> s = logSpace(lo, hi, 12), err;
    for (double t : s) {
      const typename G::Tangent Omega = t * Omega_dir;
      err.push_back((dexpInvTruncated<G>(Omega, v, q) - dexpInv<G>(Omega, v)).norm());
    }
    const double slope = logLogSlope(s, err);
    std::ostringstream key;
    key << group << " dexpInvTruncated q=" << q << " slope";
    std::cout << "[ measured ] " << key.str() << " = " << std::fixed << std::setprecision(3) << slope
              << " (expected " << p << ")" << std::defaultfloat << std::endl;
    ::testing::Test::RecordProperty(key.str(), std::to_string(slope));
    EXPECT_NEAR(slope, p, 0.15) << group << " q = " << q;
  }
  // Through ad^8 at ‖Ω‖ = 0.1 the omitted B_10 term is ~1e-18: the series
  // matches the closed form to rounding.
  const typename G::Tangent Omega = 0.1 * Omega_dir;
  EXPECT_LE((dexpInvTruncated<G>(Omega, v, 8) - dexpInv<G>(Omega, v)).norm(), 4e-16 * v.norm());
}

TEST(DexpInvSO3, TruncationErrorOrders) { checkTruncationOrders<SO3d>("SO3"); }
TEST(DexpInvSE3, TruncationErrorOrders) { checkTruncationOrders<SE3d>("SE3"); }

}  // namespace
}  // namespace test
}  // namespace lieflow
