/// \file
/// The likelihood hinge fit's reduced problem (hinge_likelihood_problem.hpp:
/// the main rates eliminated in closed form, Kaufman's Jacobian, a banded
/// Levenberg–Marquardt) against the whole problem solved by Ceres over every
/// unknown, the form the fit had before: the same minimum, the same main
/// rates, the same marginal covariance (Ceres' sparse QR).
#include <gtest/gtest.h>

#include <array>

#include <cmath>
#include <random>
#include <vector>

#include <ceres/ceres.h>
#include <ceres/rotation.h>
#include <Eigen/Cholesky>

#include "calibration/banded_cholesky.hpp"
#include "calibration/hinge_likelihood_problem.hpp"
#include "calibration/synthetic_motion.hpp"
#include "calibration/unit_axis.hpp"
#include "calibration_test_helpers.hpp"

namespace lieflow {
namespace calibration {
namespace {

/// r₁ = ω₁,k + B₁ b₁ − m₁,k.
struct MainGyro {
  Eigen::Vector3d measured;
  Eigen::Matrix3d basis;
  template <typename T>
  bool operator()(const T* w1, const T* b1, T* r) const {
    for (int i = 0; i < 3; ++i)
      r[i] = w1[i] + basis(i, 0) * b1[0] + basis(i, 1) * b1[1] + basis(i, 2) * b1[2] - measured[i];
    return true;
  }
};

/// r₂ = Cᵀ[exp(−φ j₁) ω₁ + φ̇ j₁] + E₂ b₂ + ν ṁ₂ − m₂, φ̇ five-point.
struct SecondaryGyro {
  Eigen::Vector3d measured, slope;
  Eigen::Matrix<double, 3, 2> basis;
  double inverse_step;
  template <typename T>
  bool operator()(const T* w1, const T* pm2, const T* pm1, const T* p0, const T* pp1, const T* pp2, const T* j1,
                  const T* q, const T* b2, const T* nu, T* r) const {
    const T rate = (pm2[0] - 8.0 * pm1[0] + 8.0 * pp1[0] - pp2[0]) * (inverse_step / 12.0);
    const T c = cos(p0[0]), s = sin(p0[0]);
    const T jw = j1[0] * w1[0] + j1[1] * w1[1] + j1[2] * w1[2];
    const T cross[3] = {j1[1] * w1[2] - j1[2] * w1[1], j1[2] * w1[0] - j1[0] * w1[2], j1[0] * w1[1] - j1[1] * w1[0]};
    T v[3];
    for (int i = 0; i < 3; ++i) v[i] = w1[i] * c - s * cross[i] + (1.0 - c) * jw * j1[i] + rate * j1[i];
    const T conjugate[4] = {q[0], -q[1], -q[2], -q[3]};
    T out[3];
    ceres::QuaternionRotatePoint(conjugate, v, out);
    for (int i = 0; i < 3; ++i)
      r[i] = out[i] + basis(i, 0) * b2[0] + basis(i, 1) * b2[1] - measured[i] + nu[0] * slope[i];
    return true;
  }
};

struct Case {
  HingeRates rates;
  HingeUnknowns start;
  HingeFreedoms free;
};

/// A random recording (σ = 0.1 rad/s, biases and a clock offset present),
/// started near the truth: axes 2° off, angles and mount as recorded.
Case makeCase(unsigned seed, bool biases, bool offset, int samples) {
  std::mt19937 gen(seed);
  const HingeMotion m = randomHingeMotion(gen);
  RecordingNoise noise = test::gyroscopeNoise(0.1);
  if (biases) {
    noise.gyro_bias_main = Eigen::Vector3d(0.03, -0.02, 0.05);
    noise.gyro_bias_secondary = Eigen::Vector3d(-0.04, 0.01, 0.02);
  }
  if (offset) noise.secondary_clock_offset = 0.004;
  const JointSamples s = recordMotion(m, samples, 100.0, noise, gen);
  const HingeTruthSamples truth = hingeTruth(m, samples, 100.0);
  Case c;
  c.free = HingeFreedoms{biases, offset};
  c.rates.main = s.main.angular_velocity;
  c.rates.secondary = s.secondary.angular_velocity;
  if (offset) {
    c.rates.secondary_slope.assign(samples, Eigen::Vector3d::Zero());
    for (int k = 1; k + 1 < samples; ++k)
      c.rates.secondary_slope[k] = (s.secondary.angular_velocity[k + 1] - s.secondary.angular_velocity[k - 1]) / 0.02;
  }
  c.rates.run_begin = {0, samples};
  c.rates.run_step = {0.01};
  const Eigen::Vector3d tilt = orthogonalUnit(m.axis_main);
  c.start.axis_main = Eigen::AngleAxisd(2.0 * M_PI / 180.0, tilt) * m.axis_main.normalized();
  c.start.mount = m.mount.quaternion();
  c.start.phi = truth.angle;
  c.start.main_bias_basis << perpendicularBasis(c.start.axis_main), c.start.axis_main;
  c.start.secondary_bias_basis = perpendicularBasis(c.start.axisSecondary());
  return c;
}

/// The two recordings' true biases (main, secondary) and clock offsets.
const Eigen::Vector3d kRecordingBiases[2][2] = {{{0.03, -0.02, 0.05}, {-0.04, 0.01, 0.02}},
                                                {{-0.05, 0.04, 0.01}, {0.02, 0.03, -0.06}}};
constexpr double kRecordingClocks[2] = {0.004, -0.003};

/// Two recordings of one hinge (its own motion each, 100 and 50 Hz), each
/// with its own biases and, with `offsets`, its own clock offset (4 and
/// −3 ms), one after the other: each recording's biases and ν are their own
/// set (HingeFreedoms::bias_sets = offset_sets = 2), started at zero.
Case makeTwoRecordingCase(unsigned seed, int samples, bool offsets) {
  std::mt19937 gen(seed);
  const HingeMotion m = randomHingeMotion(gen);
  HingeMotion m2 = randomHingeMotion(gen);
  m2.axis_main = m.axis_main;
  m2.mount = m.mount;
  const double rate[2] = {100.0, 50.0};
  Case c;
  c.free = HingeFreedoms{true, offsets, 2, 2};
  c.rates.run_begin = {0};
  for (int r = 0; r < 2; ++r) {
    RecordingNoise noise = test::gyroscopeNoise(0.1);
    noise.gyro_bias_main = kRecordingBiases[r][0];
    noise.gyro_bias_secondary = kRecordingBiases[r][1];
    if (offsets) noise.secondary_clock_offset = kRecordingClocks[r];
    const HingeMotion& motion = r == 0 ? m : m2;
    const int n = r == 0 ? samples : samples / 2;
    const JointSamples s = recordMotion(motion, n, rate[r], noise, gen);
    const HingeTruthSamples truth = hingeTruth(motion, n, rate[r]);
    c.rates.main.insert(c.rates.main.end(), s.main.angular_velocity.begin(), s.main.angular_velocity.end());
    c.rates.secondary.insert(c.rates.secondary.end(), s.secondary.angular_velocity.begin(),
                             s.secondary.angular_velocity.end());
    // The secondary's slope by central differences (zero at the ends), for ν.
    for (int k = 0; k < n && offsets; ++k)
      c.rates.secondary_slope.push_back(k == 0 || k + 1 == n ? Eigen::Vector3d::Zero()
                                                             : Eigen::Vector3d((s.secondary.angular_velocity[k + 1] -
                                                                                s.secondary.angular_velocity[k - 1]) *
                                                                               (0.5 * rate[r])));
    c.rates.run_begin.push_back(c.rates.samples());
    c.rates.run_step.push_back(1.0 / rate[r]);
    c.start.phi.insert(c.start.phi.end(), truth.angle.begin(), truth.angle.end());
  }
  const Eigen::Vector3d tilt = orthogonalUnit(m.axis_main);
  c.start.axis_main = Eigen::AngleAxisd(2.0 * M_PI / 180.0, tilt) * m.axis_main.normalized();
  c.start.mount = m.mount.quaternion();
  c.start.main_bias_basis << perpendicularBasis(c.start.axis_main), c.start.axis_main;
  c.start.secondary_bias_basis = perpendicularBasis(c.start.axisSecondary());
  c.start.main_bias = Eigen::Matrix3Xd::Zero(3, 2);
  c.start.secondary_bias = Eigen::Matrix2Xd::Zero(2, 2);
  c.start.offset_fraction = Eigen::VectorXd::Zero(2);
  return c;
}

/// The whole problem by Ceres from the same start; returns its cost and
/// fills the solution, its main rates and the axes' σ (ambient covariance,
/// sparse QR, as the fit computed them before).
struct Whole {
  HingeUnknowns theta;
  std::vector<Eigen::Vector3d> main_rates;
  double cost = 0.0;
  double sigma_main = 0.0, sigma_secondary = 0.0;
  int degrees_of_freedom = 0;
};

Whole solveWhole(const Case& c) {
  const int n = c.rates.samples();
  Whole out;
  out.theta = c.start;
  // Each recording reads its set of biases (one shared, or its own).
  const int sets = static_cast<int>(c.start.main_bias.cols());
  const auto setOf = [&](int r) { return std::min(r, sets - 1); };
  std::vector<Eigen::Vector3d> w1 = c.rates.main;
  std::vector<std::array<double, 3>> b1(sets);
  std::vector<std::array<double, 2>> b2(sets);
  for (int b = 0; b < sets; ++b) {
    for (int i = 0; i < 3; ++i) b1[b][i] = c.start.main_bias(i, b);
    for (int i = 0; i < 2; ++i) b2[b][i] = c.start.secondary_bias(i, b);
  }
  // ... and its ν (one shared, or its own).
  const int offset_sets = static_cast<int>(c.start.offset_fraction.size());
  std::vector<double> nu(c.start.offset_fraction.data(), c.start.offset_fraction.data() + offset_sets);
  double j1[3], q[4];
  for (int i = 0; i < 3; ++i) j1[i] = c.start.axis_main[i];
  q[0] = c.start.mount.w();
  q[1] = c.start.mount.x();
  q[2] = c.start.mount.y();
  q[3] = c.start.mount.z();
  std::vector<double>& phi = out.theta.phi;
  ceres::Problem problem;
  int residuals = 0;
  for (int r = 0; r < c.rates.runs(); ++r) {
    const int begin = c.rates.run_begin[r], end = c.rates.run_begin[r + 1];
    for (int k = begin; k < end; ++k) {
      w1[k] -= c.start.main_bias_basis * c.start.main_bias.col(setOf(r));
      problem.AddResidualBlock(new ceres::AutoDiffCostFunction<MainGyro, 3, 3, 3>(
                                   new MainGyro{c.rates.main[k], c.start.main_bias_basis}),
                               nullptr, w1[k].data(), b1[setOf(r)].data());
      residuals += 3;
    }
    for (int k = begin + 2; k + 2 < end; ++k) {
      const Eigen::Vector3d slope =
          c.rates.secondary_slope.empty() ? Eigen::Vector3d::Zero() : c.rates.secondary_slope[k];
      problem.AddResidualBlock(
          new ceres::AutoDiffCostFunction<SecondaryGyro, 3, 3, 1, 1, 1, 1, 1, 3, 4, 2, 1>(new SecondaryGyro{
              c.rates.secondary[k], slope, c.start.secondary_bias_basis, 1.0 / c.rates.run_step[r]}),
          nullptr, w1[k].data(), &phi[k - 2], &phi[k - 1], &phi[k], &phi[k + 1], &phi[k + 2], j1, q,
          b2[setOf(r)].data(), &nu[std::min(r, offset_sets - 1)]);
      residuals += 3;
    }
  }
  problem.SetManifold(j1, new ceres::SphereManifold<3>);
  problem.SetManifold(q, new ceres::QuaternionManifold);
  problem.SetParameterBlockConstant(&phi[0]);
  if (!c.free.biases)
    for (int b = 0; b < sets; ++b) {
      problem.SetParameterBlockConstant(b1[b].data());
      problem.SetParameterBlockConstant(b2[b].data());
    }
  if (!c.free.offset)
    for (double& v : nu) problem.SetParameterBlockConstant(&v);
  out.degrees_of_freedom = residuals - (3 * n + (n - 1) + c.free.globals());
  ceres::Solver::Options o;
  o.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  o.max_num_iterations = 200;
  o.function_tolerance = o.gradient_tolerance = o.parameter_tolerance = 1e-15;
  ceres::Solver::Summary summary;
  ceres::Solve(o, &problem, &summary);
  out.cost = summary.final_cost;
  out.theta.axis_main = Eigen::Vector3d(j1[0], j1[1], j1[2]);
  out.theta.mount = Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
  for (int b = 0; b < sets; ++b) {
    out.theta.main_bias.col(b) = Eigen::Vector3d(b1[b][0], b1[b][1], b1[b][2]);
    out.theta.secondary_bias.col(b) = Eigen::Vector2d(b2[b][0], b2[b][1]);
  }
  for (int o = 0; o < offset_sets; ++o) out.theta.offset_fraction[o] = nu[o];
  out.main_rates = w1;

  ceres::Covariance::Options co;
  co.algorithm_type = ceres::SPARSE_QR;
  ceres::Covariance covariance(co);
  EXPECT_TRUE(covariance.Compute({{j1, j1}, {q, q}, {j1, q}}, &problem));
  Eigen::Matrix<double, 3, 3, Eigen::RowMajor> c11;
  Eigen::Matrix<double, 4, 4, Eigen::RowMajor> cqq;
  Eigen::Matrix<double, 3, 4, Eigen::RowMajor> c1q;
  covariance.GetCovarianceBlock(j1, j1, c11.data());
  covariance.GetCovarianceBlock(q, q, cqq.data());
  covariance.GetCovarianceBlock(j1, q, c1q.data());
  Eigen::Matrix<double, 7, 7> all;
  all << c11, c1q, c1q.transpose(), cqq;
  // j₂ = Cᵀ j₁ and its ambient Jacobian by Jets.
  using Jet = ceres::Jet<double, 7>;
  Jet jj[3], cc[4], j2[3];
  for (int i = 0; i < 3; ++i) jj[i] = Jet(j1[i], i);
  cc[0] = Jet(q[0], 3);
  for (int i = 1; i < 4; ++i) cc[i] = -Jet(q[i], 3 + i);
  ceres::QuaternionRotatePoint(cc, jj, j2);
  Eigen::Matrix<double, 3, 7> d;
  for (int i = 0; i < 3; ++i) d.row(i) = j2[i].v.transpose();
  out.sigma_main = std::sqrt(all.topLeftCorner<3, 3>().trace());
  out.sigma_secondary = std::sqrt((d * all * d.transpose()).trace());
  return out;
}

double angleBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

/// On three recordings (plain; biases free; biases and clock offset free):
/// the reduced solve reaches the whole problem's minimum (cost to 1e-10
/// relative; axes, biases and clock offset within 1e-5 of their σ, measured
/// 3e-11 to 1.2e-8 rad and rad/s; angles to 2e-6 rad: a turn of C about j₁
/// against the held φ₀ moves the cost by round-off only, measured 5e-7 rad
/// at costs 1.8e-14 apart), its main rates are Ceres' ω₁,k (1e-7 rad/s),
/// and its marginal σ of both axes is Ceres' sparse-QR covariance to 1e-6
/// relative; the degrees of freedom agree.
TEST(CalibHingeLikelihood, ReducedProblemIsTheWholeOne) {
  const int samples = test::kSanitized ? 200 : 500;
  struct Setting {
    unsigned seed;
    bool biases, offset;
  };
  for (const Setting& setting : {Setting{5, false, false}, Setting{6, true, false}, Setting{7, true, true}}) {
    Case c = makeCase(setting.seed, setting.biases, setting.offset, samples);
    const Whole whole = solveWhole(c);
    HingeUnknowns reduced = c.start;
    HingeSolveOptions o;
    o.function_tolerance = o.gradient_tolerance = o.parameter_tolerance = 1e-15;
    HingeSigmas at_solution;
    const HingeSolveSummary summary = solveHingeLikelihood(c.rates, &reduced, c.free, o, &at_solution);
    const std::string what = "seed " + std::to_string(setting.seed);
    EXPECT_NE(summary.stop, HingeSolveSummary::Stop::kIterationLimit) << what << ": " << summary.message();
    EXPECT_NEAR(summary.final_cost / whole.cost, 1.0, 1e-10) << what;
    EXPECT_EQ(hingeLikelihoodDegreesOfFreedom(c.rates, c.free), whole.degrees_of_freedom) << what;
    HingeSigmas sigmas;
    ASSERT_TRUE(hingeLikelihoodSigmas(c.rates, reduced, c.free, 1.0, &sigmas)) << what;
    EXPECT_NEAR(sigmas.axis_main / whole.sigma_main, 1.0, 1e-6) << what;
    EXPECT_NEAR(sigmas.axis_secondary / whole.sigma_secondary, 1.0, 1e-6) << what;
    // The solve's own σ, from its last linearization, are these.
    EXPECT_TRUE(summary.covariance) << what;
    EXPECT_NEAR(at_solution.axis_main / sigmas.axis_main, 1.0, 1e-12) << what;
    EXPECT_NEAR(at_solution.axis_secondary / sigmas.axis_secondary, 1.0, 1e-12) << what;
    // The estimates agree far inside their σ (σ̂² = 2 cost / degrees of freedom).
    const double noise = std::sqrt(2.0 * whole.cost / whole.degrees_of_freedom), share = 1e-5;
    EXPECT_LT(angleBetween(reduced.axis_main, whole.theta.axis_main), share * noise * sigmas.axis_main) << what;
    EXPECT_LT(angleBetween(reduced.axisSecondary(), whole.theta.axisSecondary()),
              share * noise * sigmas.axis_secondary)
        << what;
    double phi = 0.0, rate = 0.0;
    const std::vector<Eigen::Vector3d> x = hingeMainRates(c.rates, reduced);
    for (int k = 0; k < samples; ++k) {
      phi = std::max(phi, std::abs(reduced.phi[k] - whole.theta.phi[k]));
      rate = std::max(rate, (x[k] - whole.main_rates[k]).norm());
    }
    EXPECT_LT(phi, 2e-6) << what;
    EXPECT_LT(rate, 1e-7) << what;
    if (setting.biases) {
      EXPECT_LT((reduced.main_bias - whole.theta.main_bias).norm(), share * noise * sigmas.main_bias.at(0)) << what;
      EXPECT_LT((reduced.secondary_bias - whole.theta.secondary_bias).norm(),
                share * noise * sigmas.secondary_bias.at(0))
          << what;
    }
    if (setting.offset) {
      EXPECT_NEAR(reduced.offset_fraction[0], whole.theta.offset_fraction[0],
                  share * noise * sigmas.offset_fraction.at(0))
          << what;
    }
    std::printf("%s (biases %d, offset %d): reduced %d iterations; cost %.12g vs Ceres %.12g, axes apart %.1e / "
                "%.1e rad, sigma ratio %.9f / %.9f\n",
                what.c_str(), setting.biases, setting.offset, summary.iterations, summary.final_cost, whole.cost,
                angleBetween(reduced.axis_main, whole.theta.axis_main),
                angleBetween(reduced.axisSecondary(), whole.theta.axisSecondary()),
                sigmas.axis_main / whole.sigma_main, sigmas.axis_secondary / whole.sigma_secondary);
  }
}

/// Two recordings, each with its own biases (a set of five coordinates per
/// recording: the normal equations' border grows by five columns per
/// recording) and then also its own clock offset's ν: the reduced solve is
/// the whole problem by Ceres with a bias block and a ν per recording, as on
/// one recording (cost to 1e-10 relative, σ of the axes to 1e-6, the axes,
/// each recording's biases and ν within 1e-5 of their σ); each recording's
/// biases and ν lie within 3.5σ of its truth.
TEST(CalibHingeLikelihood, ReducedProblemWithEachRecordingsNuisanceIsTheWholeOne) {
  const int samples = test::kSanitized ? 200 : 500;
  const auto& truth = kRecordingBiases;
  for (const bool offsets : {false, true}) {
    const std::string what = offsets ? "biases and offsets" : "biases";
    Case c = makeTwoRecordingCase(15, samples, offsets);
    const Whole whole = solveWhole(c);
    HingeUnknowns reduced = c.start;
    HingeSolveOptions o;
    o.function_tolerance = o.gradient_tolerance = o.parameter_tolerance = 1e-15;
    HingeSigmas sigmas;
    const HingeSolveSummary summary = solveHingeLikelihood(c.rates, &reduced, c.free, o, &sigmas);
    EXPECT_NE(summary.stop, HingeSolveSummary::Stop::kIterationLimit) << what << ": " << summary.message();
    ASSERT_TRUE(summary.covariance) << what;
    EXPECT_NEAR(summary.final_cost / whole.cost, 1.0, 1e-10) << what;
    EXPECT_EQ(hingeLikelihoodDegreesOfFreedom(c.rates, c.free), whole.degrees_of_freedom) << what;
    EXPECT_NEAR(sigmas.axis_main / whole.sigma_main, 1.0, 1e-6) << what;
    EXPECT_NEAR(sigmas.axis_secondary / whole.sigma_secondary, 1.0, 1e-6) << what;
    const double noise = std::sqrt(2.0 * whole.cost / whole.degrees_of_freedom), share = 1e-5;
    EXPECT_LT(angleBetween(reduced.axis_main, whole.theta.axis_main), share * noise * sigmas.axis_main) << what;
    ASSERT_EQ(sigmas.main_bias.size(), 2u);
    ASSERT_EQ(sigmas.offset_fraction.size(), offsets ? 2u : 0u);
    const Eigen::Vector3d j1 = reduced.axis_main, j2 = reduced.axisSecondary();
    for (int r = 0; r < 2; ++r) {
      EXPECT_LT((reduced.main_bias.col(r) - whole.theta.main_bias.col(r)).norm(), share * noise * sigmas.main_bias[r])
          << what;
      EXPECT_LT((reduced.secondary_bias.col(r) - whole.theta.secondary_bias.col(r)).norm(),
                share * noise * sigmas.secondary_bias[r])
          << what;
      // The main bias holds the difference along the axis (hinge_likelihood.hpp).
      const Eigen::Vector3d main = reduced.main_bias_basis * reduced.main_bias.col(r);
      const Eigen::Vector3d main_truth =
          test::perpendicular(truth[r][0], j1) + (truth[r][0].dot(j1) - truth[r][1].dot(j2)) * j1;
      const Eigen::Vector3d secondary = reduced.secondary_bias_basis * reduced.secondary_bias.col(r);
      EXPECT_LT((main - main_truth).norm(), 3.5 * noise * sigmas.main_bias[r]) << what << r;
      EXPECT_LT((secondary - test::perpendicular(truth[r][1], j2)).norm(), 3.5 * noise * sigmas.secondary_bias[r])
          << what << r;
      if (!offsets) continue;
      EXPECT_NEAR(reduced.offset_fraction[r], whole.theta.offset_fraction[r],
                  share * noise * sigmas.offset_fraction[r])
          << what;
      EXPECT_NEAR(reduced.offset_fraction[r], kRecordingClocks[r], 3.5 * noise * sigmas.offset_fraction[r])
          << what << r;
    }
    std::printf("two recordings, own %s: reduced %d iterations; cost %.12g vs Ceres %.12g, sigma ratio %.9f\n",
                what.c_str(), summary.iterations, summary.final_cost, whole.cost, sigmas.axis_main / whole.sigma_main);
  }
}

/// Rates that determine nothing (both gyroscopes at rest, the joint still):
/// the start fits exactly (the solve stops at once, its gradient zero), and
/// the information is singular: no σ, neither from the solve nor alone.
TEST(CalibHingeLikelihood, ReducedProblemGivesNoSigmaAtRest) {
  Case c = makeCase(9, false, false, 100);
  for (auto* rates : {&c.rates.main, &c.rates.secondary})
    for (Eigen::Vector3d& w : *rates) w.setZero();
  for (double& p : c.start.phi) p = 0.0;
  HingeUnknowns t = c.start;
  HingeSigmas sigmas;
  const HingeSolveSummary summary = solveHingeLikelihood(c.rates, &t, c.free, {}, &sigmas);
  EXPECT_EQ(summary.stop, HingeSolveSummary::Stop::kGradientVanished) << summary.message();
  EXPECT_EQ(summary.final_cost, 0.0);
  EXPECT_FALSE(summary.covariance);
  EXPECT_FALSE(hingeLikelihoodSigmas(c.rates, t, c.free, 1.0, &sigmas));
}

/// The banded Cholesky (banded_cholesky.hpp) against Eigen's dense one on a
/// random positive definite matrix of half-bandwidth 4: the solves of three
/// right-hand sides agree to 1e-12 relative; a zero row is singular.
TEST(CalibHingeLikelihood, BandedCholeskyIsTheDenseOne) {
  constexpr int B = 4, n = 60;
  std::mt19937 gen(12);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n, n);
  for (int k = 0; k < n; ++k)
    for (int d = 1; d <= B && k - d >= 0; ++d) a(k, k - d) = a(k - d, k) = u(gen);
  for (int k = 0; k < n; ++k) a(k, k) = 2.0 * B + 1.0 + u(gen);  // diagonally dominant
  std::vector<double> band(static_cast<std::size_t>(n) * (B + 1), 0.0);
  for (int k = 0; k < n; ++k)
    for (int d = 0; d <= B && k - d >= 0; ++d) band[static_cast<std::size_t>(k) * (B + 1) + d] = a(k, k - d);
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> x(n, 3);
  for (int k = 0; k < n; ++k)
    for (int c = 0; c < 3; ++c) x(k, c) = u(gen);
  const Eigen::MatrixXd dense = a.llt().solve(Eigen::MatrixXd(x));
  std::vector<double> factor = band;
  ASSERT_TRUE(bandedCholesky<B>(&factor, n, 1e-14));
  bandedSolve<B>(factor, n, &x);
  EXPECT_LT((Eigen::MatrixXd(x) - dense).norm(), 1e-12 * dense.norm());
  for (int d = 0; d <= B; ++d) band[static_cast<std::size_t>(30) * (B + 1) + d] = 0.0;
  for (int d = 1; d <= B; ++d) band[static_cast<std::size_t>(30 + d) * (B + 1) + d] = 0.0;
  EXPECT_FALSE(bandedCholesky<B>(&band, n, 1e-14));
}

/// Sizes that disagree, or a recording shorter than one stencil, are refused.
TEST(CalibHingeLikelihood, ReducedProblemRefusesBadSizes) {
  Case c = makeCase(8, false, false, 50);
  HingeUnknowns t = c.start;
  t.phi.pop_back();
  EXPECT_THROW(solveHingeLikelihood(c.rates, &t, c.free), std::invalid_argument);
  c.rates.run_begin = {0, 3, 50};
  c.rates.run_step = {0.01, 0.01};
  EXPECT_THROW(solveHingeLikelihood(c.rates, &c.start, c.free), std::invalid_argument);
}

}  // namespace
}  // namespace calibration
}  // namespace lieflow
