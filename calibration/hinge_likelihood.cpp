#include "calibration/hinge_likelihood.hpp"

#include <cmath>
#include <complex>
#include <memory>
#include <stdexcept>
#include <vector>

#include <ceres/ceres.h>
#include <ceres/rotation.h>
#include <Eigen/Geometry>

#include "calibration/fit_progress.hpp"
#include "calibration/fit_types.hpp"
#include "calibration/solver_options.hpp"
#include "calibration/rate_derivative.hpp"
#include "calibration/unit_axis.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {
namespace calibration {
namespace {

/// Solver limits: far below any gyroscope's noise.
constexpr int kMaxLikelihoodIterations = 100;
constexpr double kTolerance = 1e-12;
/// Levenberg–Marquardt's first trust region (Ceres' default 1e4): the start
/// is the constraint fit's, close enough for Gauss–Newton steps.
constexpr double kInitialTrustRegion = 1e8;
/// Samples of the five-point difference on either side.
constexpr int kHalfStencil = 2;
/// Largest relative spread of the sampling interval (φ̇ by a fixed stencil).
constexpr double kUniformSampling = 1e-3;

/// (ω₁,k + B₁ b₁ − m₁,k) · w: B₁ = [E₁ | j₁] of the start (orthonormal), b₁
/// the main gyroscope's bias in it (held at 0 without fit_gyro_bias).
struct MainGyro {
  Eigen::Vector3d measured;
  Eigen::Matrix3d basis;
  double weight;
  template <typename T>
  bool operator()(const T* w1, const T* b1, T* r) const {
    for (int i = 0; i < 3; ++i)
      r[i] = weight * (w1[i] + basis(i, 0) * b1[0] + basis(i, 1) * b1[1] + basis(i, 2) * b1[2] - measured[i]);
    return true;
  }
};

/// (Cᵀ[exp(−φ j₁) ω₁ + φ̇ j₁] + E₂ b₂ − (m₂,k − ν ṁ₂,k)) · w, equation (1)
/// of the header, φ̇ the five-point difference of φ_{k−2} … φ_{k+2}; C as a
/// unit quaternion (w, x, y, z), Ceres' convention; E₂ b₂ the secondary
/// gyroscope's bias perpendicular to the start's j₂; ν the fraction of a
/// clock offset beyond its whole samples (m₂ at t_k + ν, moved back by the
/// rates' slope; held at 0 without one).
struct SecondaryGyro {
  Eigen::Vector3d measured;
  Eigen::Vector3d slope;  ///< the measured rates' slope, for the clock offset's fraction ν
  Eigen::Matrix<double, 3, 2> basis;
  double inverse_step;  ///< 1/h
  double weight;
  template <typename T>
  bool operator()(const T* w1, const T* pm2, const T* pm1, const T* p0, const T* pp1, const T* pp2, const T* j1,
                  const T* q, const T* b2, const T* nu, T* r) const {
    using std::cos;
    using std::sin;
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
      r[i] = weight * (out[i] + basis(i, 0) * b2[0] + basis(i, 1) * b2[1] - measured[i] + nu[0] * slope[i]);
    return true;
  }
};

/// The problem's parameters: ω₁,k, φ_k, j₁, C, and the biases: b₁ in B₁ =
/// [E₁ | j₁] (all three components), b₂ in the plane E₂ perpendicular to the
/// start's j₂. Along the axis only the difference of the two biases is
/// observable — the same rate about the axis on both gyroscopes is the whole
/// hinge turning, which ω₁,k absorbs; a different one drifts the joint angle
/// and so the phase of the perpendicular rates —, so b₂'s component along j₂
/// is held at 0 and b₁'s along j₁ is the difference.
struct Parameters {
  std::vector<Eigen::Vector3d> w1;
  std::vector<double> phi;
  double j1[3];
  double q[4];  ///< w, x, y, z
  double b1[3] = {0.0, 0.0, 0.0}, b2[2] = {0.0, 0.0};
  double nu = 0.0;  ///< the clock offset's fraction [s]
  Eigen::Matrix3d B1 = Eigen::Matrix3d::Zero();
  Eigen::Matrix<double, 3, 2> E2 = Eigen::Matrix<double, 3, 2>::Zero();
};

double uniformStep(const std::vector<double>& t, const std::string& source) {
  const double h = (t.back() - t.front()) / static_cast<double>(t.size() - 1);
  for (std::size_t k = 0; k + 1 < t.size(); ++k)
    if (std::abs(t[k + 1] - t[k] - h) > kUniformSampling * h)
      throw InvalidInput(source, "the likelihood hinge fit needs uniformly sampled times (t[" + std::to_string(k + 1) +
                                     "] - t[" + std::to_string(k) + "] differs from the mean interval)");
  return h;
}

/// Where each recording's samples begin in the concatenated lists (one
/// entry per recording and a last one, the total) and each one's sampling
/// interval: the joint angle's stencils stay within a recording (samples of
/// two recordings are not neighbours in time).
struct Runs {
  std::vector<int> begin;
  std::vector<double> step;
  int count() const { return static_cast<int>(step.size()); }
  int size(int r) const { return begin[r + 1] - begin[r]; }
  static Runs one(int n, double h) { return Runs{{0, n}, {h}}; }
};

/// The least-squares problem of the header on `p`, residuals times `weight`.
class LikelihoodProblem {
 public:
  /// With `biases`, b₁ and b₂ are unknowns, with `offset` ν (else held at
  /// their values); `slopes` the secondary's rate slopes (empty: zero).
  /// Several recordings share j₁, C and the biases; each has its own
  /// angles, of which only the first recording's φ₀ is held (the gauge).
  LikelihoodProblem(Parameters* p, const std::vector<Eigen::Vector3d>& m1, const std::vector<Eigen::Vector3d>& m2,
                    const Runs& runs, double weight, bool biases, bool offset = false,
                    const std::vector<Eigen::Vector3d>& slopes = {})
      : problem_(options()) {
    const int n = static_cast<int>(p->w1.size());
    // The secondary's rows need a full stencil of angles: fewer samples leave
    // the axis, the rotation and φ out of the problem (Ceres would end the
    // process setting their manifolds).
    for (int r = 0; r < runs.count(); ++r)
      if (runs.size(r) < 2 * kHalfStencil + 2)
        throw NotIdentifiable("the likelihood fit needs at least " + std::to_string(2 * kHalfStencil + 2) +
                              " samples per recording (one has " + std::to_string(runs.size(r)) + ")");
    for (int k = 0; k < n; ++k)
      problem_.AddResidualBlock(
          new ceres::AutoDiffCostFunction<MainGyro, 3, 3, 3>(new MainGyro{m1[k], p->B1, weight}), nullptr,
          p->w1[k].data(), p->b1);
    for (int r = 0; r < runs.count(); ++r)
      for (int k = runs.begin[r] + kHalfStencil; k + kHalfStencil < runs.begin[r + 1]; ++k) {
        problem_.AddResidualBlock(
            new ceres::AutoDiffCostFunction<SecondaryGyro, 3, 3, 1, 1, 1, 1, 1, 3, 4, 2, 1>(new SecondaryGyro{
                m2[k], slopes.empty() ? Eigen::Vector3d::Zero() : slopes[k], p->E2, 1.0 / runs.step[r], weight}),
            nullptr, p->w1[k].data(), &p->phi[k - 2], &p->phi[k - 1], &p->phi[k], &p->phi[k + 1], &p->phi[k + 2],
            p->j1, p->q, p->b2, &p->nu);
        residuals_ += 3;
      }
    problem_.SetManifold(p->j1, &sphere_);
    problem_.SetManifold(p->q, &quaternion_);
    problem_.SetParameterBlockConstant(&p->phi[0]);  // gauge: φ₀ against C's turn about j₁
    if (!biases) {
      problem_.SetParameterBlockConstant(p->b1);
      problem_.SetParameterBlockConstant(p->b2);
    }
    if (!offset) problem_.SetParameterBlockConstant(&p->nu);
    residuals_ += 3 * n;
    free_parameters_ = 3 * n + (n - 1) + 2 + 3 + (biases ? 5 : 0) + (offset ? 1 : 0);
  }

  ceres::Problem& problem() { return problem_; }
  int degreesOfFreedom() const { return residuals_ - free_parameters_; }

 private:
  static ceres::Problem::Options options() {
    ceres::Problem::Options o;
    o.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    return o;
  }
  ceres::SphereManifold<3> sphere_;
  ceres::QuaternionManifold quaternion_;
  ceres::Problem problem_;
  int residuals_ = 0;
  int free_parameters_ = 0;
};

/// j₂ = Cᵀ j₁ and its Jacobian with respect to (j₁, q) (3 × 7, ambient).
Eigen::Vector3d secondaryAxis(const double* j1, const double* q, Eigen::Matrix<double, 3, 7>* jacobian) {
  using Jet = ceres::Jet<double, 7>;
  Jet j[3], c[4], out[3];
  for (int i = 0; i < 3; ++i) j[i] = Jet(j1[i], i);
  c[0] = Jet(q[0], 3);
  for (int i = 1; i < 4; ++i) c[i] = -Jet(q[i], 3 + i);
  ceres::QuaternionRotatePoint(c, j, out);
  Eigen::Vector3d a;
  for (int i = 0; i < 3; ++i) {
    a[i] = out[i].a;
    if (jacobian) jacobian->row(i) = out[i].v.transpose();
  }
  return a;
}

/// The axes' RMS angles (rad) from the covariance of (j₁, q) (ambient; times
/// `scale`), with `bias_sigmas` the biases' RMS [rad/s] (√trace of each b's
/// covariance: the bases are orthonormal), with `offset_sigma` ν's σ [s];
/// false when Ceres finds the covariance rank deficient.
bool axisSigmas(LikelihoodProblem& lp, Parameters& p, double scale, double* sigma1, double* sigma2,
                double* bias_sigmas = nullptr, double* offset_sigma = nullptr) {
  ceres::Covariance::Options options;
  options.algorithm_type = ceres::SPARSE_QR;
  options.num_threads = 1;
  ceres::Covariance covariance(options);
  std::vector<std::pair<const double*, const double*>> blocks = {{p.j1, p.j1}, {p.q, p.q}, {p.j1, p.q}};
  if (bias_sigmas) {
    blocks.emplace_back(p.b1, p.b1);
    blocks.emplace_back(p.b2, p.b2);
  }
  if (offset_sigma) blocks.emplace_back(&p.nu, &p.nu);
  if (!covariance.Compute(blocks, &lp.problem())) return false;
  if (offset_sigma) {
    double c = 0.0;
    covariance.GetCovarianceBlock(&p.nu, &p.nu, &c);
    *offset_sigma = std::sqrt(scale * c);
  }
  if (bias_sigmas) {
    Eigen::Matrix<double, 3, 3, Eigen::RowMajor> c1;
    Eigen::Matrix<double, 2, 2, Eigen::RowMajor> c2;
    covariance.GetCovarianceBlock(p.b1, p.b1, c1.data());
    covariance.GetCovarianceBlock(p.b2, p.b2, c2.data());
    bias_sigmas[0] = std::sqrt(scale * c1.trace());
    bias_sigmas[1] = std::sqrt(scale * c2.trace());
  }
  Eigen::Matrix<double, 3, 3, Eigen::RowMajor> c11;
  Eigen::Matrix<double, 4, 4, Eigen::RowMajor> cqq;
  Eigen::Matrix<double, 3, 4, Eigen::RowMajor> c1q;
  covariance.GetCovarianceBlock(p.j1, p.j1, c11.data());
  covariance.GetCovarianceBlock(p.q, p.q, cqq.data());
  covariance.GetCovarianceBlock(p.j1, p.q, c1q.data());
  Eigen::Matrix<double, 7, 7> all;
  all << c11, c1q, c1q.transpose(), cqq;
  all *= scale;
  Eigen::Matrix<double, 3, 7> J;
  secondaryAxis(p.j1, p.q, &J);
  *sigma1 = std::sqrt(all.topLeftCorner<3, 3>().trace());
  *sigma2 = std::sqrt((J * all * J.transpose()).trace());
  return std::isfinite(*sigma1) && std::isfinite(*sigma2);
}

/// The start from a constraint fit's axes: φ̇ = j₂·ω₂ − j₁·ω₁ integrated
/// (trapezoid), C = exp(γ j₁) C₀ with C₀ j₂ = j₁ and γ the weighted circular
/// mean of angle(ω₁⊥) − φ − angle(C₀ω₂⊥) about j₁; returns the coherence
/// |Σ w e^{iΔ}| / Σ w (1 for a perfect hinge), which picks j₂'s sign. Each
/// further recording's angles start where its own circular mean puts them
/// against the first recording's γ (its φ₀ is not known from the rates).
double startFrom(const Eigen::Vector3d& a1, const Eigen::Vector3d& a2, const std::vector<Eigen::Vector3d>& m1,
                 const std::vector<Eigen::Vector3d>& m2, const Runs& runs, Parameters* p) {
  const int n = static_cast<int>(m1.size());
  const Eigen::Vector3d j1 = a1.normalized(), j2 = a2.normalized();
  p->w1 = m1;
  p->phi.assign(n, 0.0);
  for (int r = 0; r < runs.count(); ++r) {
    const int first = runs.begin[r];
    double previous = j2.dot(m2[first]) - j1.dot(m1[first]);
    for (int k = first + 1; k < runs.begin[r + 1]; ++k) {
      const double rate = j2.dot(m2[k]) - j1.dot(m1[k]);
      p->phi[k] = p->phi[k - 1] + 0.5 * runs.step[r] * (previous + rate);
      previous = rate;
    }
  }
  const Eigen::Quaterniond c0 = Eigen::Quaterniond::FromTwoVectors(j2, j1);
  const Eigen::Vector3d e1 = orthogonalUnit(j1), e2 = j1.cross(e1);
  std::vector<std::complex<double>> sums(runs.count(), std::complex<double>(0.0, 0.0));
  double total = 0.0;
  for (int r = 0; r < runs.count(); ++r)
    for (int k = runs.begin[r]; k < runs.begin[r + 1]; ++k) {
      const Eigen::Vector3d u = m1[k], v = c0 * m2[k];
      const std::complex<double> zu(u.dot(e1), u.dot(e2)), zv(v.dot(e1), v.dot(e2));
      const double w = std::abs(zu) * std::abs(zv);
      if (w <= 0.0) continue;
      sums[r] += w * std::polar(1.0, std::arg(zu) - p->phi[k] - std::arg(zv));
      total += w;
    }
  const double gamma = std::arg(sums.front());
  double resultant = 0.0;
  for (int r = 0; r < runs.count(); ++r) {
    resultant += std::abs(sums[r]);
    if (r == 0) continue;
    const double offset = std::arg(sums[r]) - gamma;
    for (int k = runs.begin[r]; k < runs.begin[r + 1]; ++k) p->phi[k] += offset;
  }
  const Eigen::Quaterniond c = Eigen::Quaterniond(Eigen::AngleAxisd(gamma, j1)) * c0;
  for (int i = 0; i < 3; ++i) p->j1[i] = j1[i];
  p->B1 << perpendicularBasis(j1), j1;
  p->E2 = perpendicularBasis(j2);
  p->q[0] = c.w();
  p->q[1] = c.x();
  p->q[2] = c.y();
  p->q[3] = c.z();
  return total > 0.0 ? resultant / total : 0.0;
}

}  // namespace

HingeLikelihoodFit fitHingeLikelihood(const JointSamples& samples, const Eigen::Vector3d& axis_main,
                                      const Eigen::Vector3d& axis_secondary, const HingeLikelihoodOptions& options_in) {
  return fitHingeLikelihood(std::vector<const JointSamples*>{&samples}, axis_main, axis_secondary, options_in);
}

HingeLikelihoodFit fitHingeLikelihood(const std::vector<const JointSamples*>& recordings,
                                      const Eigen::Vector3d& axis_main, const Eigen::Vector3d& axis_secondary,
                                      const HingeLikelihoodOptions& options_in) {
  if (recordings.empty()) throw std::invalid_argument("fitHingeLikelihood: no recording");
  for (const JointSamples* samples : recordings)
    if (!samples->hasAngularVelocities())
      throw InvalidInput(samples->source, "the likelihood hinge fit needs both bodies' gyroscopes");
  const bool offset = options_in.fit_time_offset;
  if (offset && recordings.size() > 1)
    throw InvalidInput(recordings[1]->source, "the likelihood hinge fit estimates a clock offset on one recording "
                                              "only (fit each recording alone for its clock offset)");
  // The samples paired across the clock offset's whole samples: main k with
  // secondary k − shift, and the secondary's slope there (its window inside).
  // Consecutive samples of a uniform series stay uniform: one step h per
  // recording for the paired ones.
  std::vector<Eigen::Vector3d> m1, m2, slopes;
  Runs runs;
  runs.begin.push_back(0);
  for (const JointSamples* samples : recordings) {
    runs.step.push_back(uniformStep(samples->time, samples->source));
    const int all = samples->size(), shift = offset ? options_in.offset_shift : 0, edge = offset ? kRateWindow : 0;
    for (int k = 0; k < all; ++k) {
      const int k2 = k - shift;
      if (k2 < edge || k2 >= all - edge) continue;
      m1.push_back(samples->main.angular_velocity[k]);
      m2.push_back(samples->secondary.angular_velocity[k2]);
      if (offset) slopes.push_back(rateDerivative(samples->time, samples->secondary.angular_velocity, k2));
    }
    runs.begin.push_back(static_cast<int>(m1.size()));
    const int paired = runs.size(runs.count() - 1);
    if (recordings.size() > 1 && paired < 2 * kHalfStencil + 2)
      throw NotIdentifiable(samples->source + " has " + std::to_string(paired) + " samples: the likelihood fit needs " +
                            "at least " + std::to_string(2 * kHalfStencil + 2) + " in each recording");
  }
  const double h = runs.step.front();
  const int shift = offset ? options_in.offset_shift : 0;
  const int n = static_cast<int>(m1.size());
  if (n < 2 * kHalfStencil + 8) throw NotIdentifiable("too few samples for the likelihood hinge fit");
  // With biases, the start's rates are the measured ones less the start's
  // biases.
  std::vector<Eigen::Vector3d> c1 = m1, c2 = m2;
  if (options_in.fit_gyro_bias)
    for (int k = 0; k < n; ++k) {
      c1[k] -= options_in.gyro_bias_main_start;
      c2[k] -= options_in.gyro_bias_secondary_start;
    }
  // j₂'s sign: the start whose perpendicular rates turn into each other.
  Parameters p, turned;
  const double coherence = startFrom(axis_main, axis_secondary, c1, c2, runs, &p);
  if (startFrom(axis_main, -axis_secondary, c1, c2, runs, &turned) > coherence) p = turned;
  p.nu = offset ? options_in.offset_fraction_start : 0.0;
  if (options_in.fit_gyro_bias) {
    const Eigen::Vector3d b1 = p.B1.transpose() * options_in.gyro_bias_main_start;
    const Eigen::Vector2d b2 = p.E2.transpose() * options_in.gyro_bias_secondary_start;
    for (int i = 0; i < 3; ++i) p.b1[i] = b1[i];
    for (int i = 0; i < 2; ++i) p.b2[i] = b2[i];
  }

  LikelihoodProblem lp(&p, m1, m2, runs, 1.0, options_in.fit_gyro_bias, offset, slopes);
  ceres::Solver::Options options;
  // Sparse Cholesky of the whole normal equations (banded: each sample's
  // unknowns meet its stencil's angles only) costs less per iteration than
  // the Schur complement over the ω₁,k, whose reduced system is as banded;
  // a wide first trust region lets Levenberg–Marquardt take Gauss–Newton
  // steps from the constraint fit's start at once. Measured on 1000 samples
  // (the command, whole fit): 11 iterations in 61–64 ms, against 19 in
  // 121–126 ms with the Schur complement and Ceres' first radius.
  options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  options.initial_trust_region_radius = kInitialTrustRegion;
  options.max_num_iterations = kMaxLikelihoodIterations;
  options.function_tolerance = kTolerance;
  options.gradient_tolerance = kTolerance;
  options.parameter_tolerance = kTolerance;
  options.logging_type = ceres::SILENT;
  options.num_threads = 1;
  FitProgressCallback progress(options_in.progress, options_in.interrupt);
  options.callbacks.push_back(&progress);
  ceres::Solver::Summary summary;
  ceres::Solve(options, &lp.problem(), &summary);
  if (!summary.IsSolutionUsable()) throw FitFailed("the likelihood hinge fit failed: " + solverFailureReason(summary));

  HingeLikelihoodFit fit;
  fit.axis_main = Eigen::Vector3d(p.j1[0], p.j1[1], p.j1[2]);
  fit.axis_secondary = secondaryAxis(p.j1, p.q, nullptr);
  fit.iterations = static_cast<int>(summary.iterations.size()) - 1;
  fit.converged = summary.termination_type == ceres::CONVERGENCE;
  fit.message = solverStopMessage(summary);
  const double s2 = 2.0 * summary.final_cost / lp.degreesOfFreedom();
  fit.noise_sigma = std::sqrt(s2);
  double sigma1 = 0.0, sigma2 = 0.0, bias_sigmas[2] = {0.0, 0.0}, offset_sigma = 0.0;
  if (!axisSigmas(lp, p, s2, &sigma1, &sigma2, options_in.fit_gyro_bias ? bias_sigmas : nullptr,
                  offset ? &offset_sigma : nullptr))
    throw NotIdentifiable("the likelihood hinge fit's covariance is rank deficient");
  fit.sigma_main_deg = sigma1 * kRadToDeg;
  fit.sigma_secondary_deg = sigma2 * kRadToDeg;
  if (options_in.fit_gyro_bias) {
    fit.fitted_gyro_bias = true;
    fit.gyro_bias_main = p.B1 * Eigen::Vector3d(p.b1[0], p.b1[1], p.b1[2]);
    fit.gyro_bias_secondary = p.E2 * Eigen::Vector2d(p.b2[0], p.b2[1]);
    fit.gyro_bias_main_sigma = bias_sigmas[0];
    fit.gyro_bias_secondary_sigma = bias_sigmas[1];
  }
  if (offset) {
    fit.fitted_time_offset = true;
    fit.time_offset = shift * h + p.nu;
    fit.time_offset_sigma = offset_sigma;
  }
  return fit;
}

HingeBound hingeCramerRao(const HingeTruthSamples& truth, double rate_sigma) {
  const int n = static_cast<int>(truth.time.size());
  const double h = uniformStep(truth.time, "the bound's samples");
  Parameters p;
  p.w1 = truth.main_rate;
  p.phi = truth.angle;
  for (int i = 0; i < 3; ++i) p.j1[i] = truth.axis_main.normalized()[i];
  p.B1 << perpendicularBasis(truth.axis_main.normalized()), truth.axis_main.normalized();
  p.E2 = perpendicularBasis(truth.mount.inverse() * truth.axis_main.normalized());
  const Eigen::Quaterniond c = truth.mount.quaternion();
  p.q[0] = c.w();
  p.q[1] = c.x();
  p.q[2] = c.y();
  p.q[3] = c.z();
  // Exact "measurements": the model's own values, so the Jacobian is the truth's.
  std::vector<Eigen::Vector3d> m2(n, Eigen::Vector3d::Zero());
  LikelihoodProblem lp(&p, truth.main_rate, m2, Runs::one(n, h), 1.0 / rate_sigma, false);
  HingeBound bound;
  double sigma1 = 0.0, sigma2 = 0.0;
  if (!axisSigmas(lp, p, 1.0, &sigma1, &sigma2)) throw NotIdentifiable("the recording's information is singular");
  bound.sigma_main_deg = sigma1 * kRadToDeg;
  bound.sigma_secondary_deg = sigma2 * kRadToDeg;
  return bound;
}

}  // namespace calibration
}  // namespace lieflow
