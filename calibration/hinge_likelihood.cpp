#include "calibration/hinge_likelihood.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <stdexcept>
#include <vector>

#include <Eigen/Geometry>

#include "calibration/fit_types.hpp"
#include "calibration/hinge_likelihood_problem.hpp"
#include "calibration/hinge_likelihood_terms.hpp"
#include "calibration/rate_derivative.hpp"
#include "calibration/unit_axis.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {
namespace calibration {
namespace {

constexpr int kHalfStencil = kHingeStencilHalfWidth;
/// Largest relative spread of the sampling interval (φ̇ by a fixed stencil).
constexpr double kUniformSampling = 1e-3;

double uniformStep(const std::vector<double>& t, const std::string& source) {
  const double h = (t.back() - t.front()) / static_cast<double>(t.size() - 1);
  for (std::size_t k = 0; k + 1 < t.size(); ++k)
    if (std::abs(t[k + 1] - t[k] - h) > kUniformSampling * h)
      throw InvalidInput(source, "the likelihood hinge fit needs uniformly sampled times (t[" + std::to_string(k + 1) +
                                     "] - t[" + std::to_string(k) + "] differs from the mean interval)");
  return h;
}

/// The start from a constraint fit's axes: φ̇ = j₂·ω₂ − j₁·ω₁ integrated
/// (trapezoid), C = exp(γ j₁) C₀ with C₀ j₂ = j₁ and γ the weighted circular
/// mean of angle(ω₁⊥) − φ − angle(C₀ω₂⊥) about j₁; returns the coherence
/// |Σ w e^{iΔ}| / Σ w (1 for a perfect hinge), which picks j₂'s sign. Each
/// further recording's angles start where its own circular mean puts them
/// against the first recording's γ (its φ₀ is not known from the rates).
double startFrom(const Eigen::Vector3d& a1, const Eigen::Vector3d& a2, const std::vector<Eigen::Vector3d>& m1,
                 const std::vector<Eigen::Vector3d>& m2, const HingeRates& runs, HingeUnknowns* p) {
  const int n = static_cast<int>(m1.size());
  const Eigen::Vector3d j1 = a1.normalized(), j2 = a2.normalized();
  p->phi.assign(n, 0.0);
  for (int r = 0; r < runs.runs(); ++r) {
    const int first = runs.run_begin[r];
    double previous = j2.dot(m2[first]) - j1.dot(m1[first]);
    for (int k = first + 1; k < runs.run_begin[r + 1]; ++k) {
      const double rate = j2.dot(m2[k]) - j1.dot(m1[k]);
      p->phi[k] = p->phi[k - 1] + 0.5 * runs.run_step[r] * (previous + rate);
      previous = rate;
    }
  }
  const Eigen::Quaterniond c0 = Eigen::Quaterniond::FromTwoVectors(j2, j1);
  const Eigen::Vector3d e1 = orthogonalUnit(j1), e2 = j1.cross(e1);
  std::vector<std::complex<double>> sums(runs.runs(), std::complex<double>(0.0, 0.0));
  double total = 0.0;
  for (int r = 0; r < runs.runs(); ++r)
    for (int k = runs.run_begin[r]; k < runs.run_begin[r + 1]; ++k) {
      const Eigen::Vector3d u = m1[k], v = c0 * m2[k];
      const std::complex<double> zu(u.dot(e1), u.dot(e2)), zv(v.dot(e1), v.dot(e2));
      const double w = std::abs(zu) * std::abs(zv);
      if (w <= 0.0) continue;
      sums[r] += w * std::polar(1.0, std::arg(zu) - p->phi[k] - std::arg(zv));
      total += w;
    }
  const double gamma = std::arg(sums.front());
  double resultant = 0.0;
  for (int r = 0; r < runs.runs(); ++r) {
    resultant += std::abs(sums[r]);
    if (r == 0) continue;
    const double offset = std::arg(sums[r]) - gamma;
    for (int k = runs.run_begin[r]; k < runs.run_begin[r + 1]; ++k) p->phi[k] += offset;
  }
  p->axis_main = j1;
  p->mount = (Eigen::Quaterniond(Eigen::AngleAxisd(gamma, j1)) * c0).normalized();
  p->main_bias_basis << perpendicularBasis(j1), j1;
  p->secondary_bias_basis = perpendicularBasis(j2);
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
  // Each recording's own biases and clock offset, or one set shared by all.
  const std::vector<SensorNuisanceEstimate>& own = options_in.recording_starts;
  const bool per_recording = !own.empty();
  if (per_recording && (own.size() != recordings.size() || options_in.recording_shifts.size() != recordings.size()))
    throw std::invalid_argument("fitHingeLikelihood: a start and a shift per recording expected");
  if (offset && recordings.size() > 1 && !per_recording)
    throw InvalidInput(recordings[1]->source, "the likelihood hinge fit does not estimate one clock offset shared "
                                              "by several recordings: each recording's own needs recording_starts");
  const auto shiftOf = [&](std::size_t r) {
    return !offset ? 0 : per_recording ? options_in.recording_shifts[r] : options_in.offset_shift;
  };
  // The samples paired across the clock offset's whole samples: main k with
  // secondary k − shift, and the secondary's slope there (its window inside).
  // Consecutive samples of a uniform series stay uniform: one step h per
  // recording for the paired ones.
  HingeRates rates;
  rates.run_begin.push_back(0);
  for (std::size_t r = 0; r < recordings.size(); ++r) {
    const JointSamples* samples = recordings[r];
    rates.run_step.push_back(uniformStep(samples->time, samples->source));
    const int all = samples->size(), shift = shiftOf(r), edge = offset ? kRateWindow : 0;
    for (int k = 0; k < all; ++k) {
      const int k2 = k - shift;
      if (k2 < edge || k2 >= all - edge) continue;
      rates.main.push_back(samples->main.angular_velocity[k]);
      rates.secondary.push_back(samples->secondary.angular_velocity[k2]);
      if (offset)
        rates.secondary_slope.push_back(rateDerivative(samples->time, samples->secondary.angular_velocity, k2));
    }
    const int paired = rates.samples() - rates.run_begin.back();
    rates.run_begin.push_back(rates.samples());
    // The secondary's residuals need a full stencil of angles.
    if (paired < 2 * kHalfStencil + 2)
      throw NotIdentifiable(samples->source + " has " + std::to_string(paired) + " samples: the likelihood fit needs " +
                            "at least " + std::to_string(2 * kHalfStencil + 2) + " in each recording");
  }
  const int n = rates.samples();
  if (n < 2 * kHalfStencil + 8) throw NotIdentifiable("too few samples for the likelihood hinge fit");
  // With biases, the start's rates are the measured ones less the start's
  // biases: one set, or each recording's own.
  const int sets = per_recording && options_in.fit_gyro_bias ? rates.runs() : 1;
  const int offset_sets = per_recording && offset ? rates.runs() : 1;
  Eigen::Matrix3Xd main_start(3, sets), secondary_start(3, sets);
  for (int b = 0; b < sets; ++b) {
    main_start.col(b) = sets > 1 ? own[b].gyro_bias_main : options_in.gyro_bias_main_start;
    secondary_start.col(b) = sets > 1 ? own[b].gyro_bias_secondary : options_in.gyro_bias_secondary_start;
  }
  std::vector<Eigen::Vector3d> c1 = rates.main, c2 = rates.secondary;
  if (options_in.fit_gyro_bias)
    for (int r = 0; r < rates.runs(); ++r)
      for (int k = rates.run_begin[r]; k < rates.run_begin[r + 1]; ++k) {
        c1[k] -= main_start.col(std::min(r, sets - 1));
        c2[k] -= secondary_start.col(std::min(r, sets - 1));
      }
  // j₂'s sign: the start whose perpendicular rates turn into each other.
  HingeUnknowns p, turned;
  const double coherence = startFrom(axis_main, axis_secondary, c1, c2, rates, &p);
  if (startFrom(axis_main, -axis_secondary, c1, c2, rates, &turned) > coherence) p = turned;
  // ν = δ − shift h: each recording's own, or the one offset's.
  p.offset_fraction = Eigen::VectorXd::Zero(offset_sets);
  for (int o = 0; o < offset_sets && offset; ++o)
    p.offset_fraction[o] = offset_sets > 1 ? own[o].time_offset - shiftOf(o) * rates.run_step[o]
                                           : options_in.offset_fraction_start;
  if (options_in.fit_gyro_bias) {
    p.main_bias = p.main_bias_basis.transpose() * main_start;
    p.secondary_bias = p.secondary_bias_basis.transpose() * secondary_start;
  }

  const HingeFreedoms free{options_in.fit_gyro_bias, offset, sets, offset_sets};
  HingeSolveOptions solve;
  solve.progress = options_in.progress;
  solve.interrupt = options_in.interrupt;
  HingeSigmas sigmas;  // at scale 1: times σ̂ below
  const HingeSolveSummary summary = solveHingeLikelihood(rates, &p, free, solve, &sigmas);
  if (summary.stop == HingeSolveSummary::Stop::kSingular)
    throw FitFailed("the likelihood hinge fit failed: the least-squares system was singular: the data do not "
                    "determine the parameters");
  if (!std::isfinite(summary.final_cost))
    throw FitFailed("the likelihood hinge fit failed: the cost became infinite or not a number");

  HingeLikelihoodFit fit;
  fit.axis_main = p.axis_main;
  fit.axis_secondary = p.axisSecondary();
  fit.iterations = summary.iterations;
  fit.converged = summary.converged();
  fit.message = summary.message();
  const double s = std::sqrt(2.0 * summary.final_cost / hingeLikelihoodDegreesOfFreedom(rates, free));
  fit.noise_sigma = s;
  if (!summary.covariance) throw NotIdentifiable("the likelihood hinge fit's covariance is rank deficient");
  fit.sigma_main_deg = s * sigmas.axis_main * kRadToDeg;
  fit.sigma_secondary_deg = s * sigmas.axis_secondary * kRadToDeg;
  // Each recording's biases and offset (its set's), the first's at the top.
  for (int r = 0; r < (per_recording ? rates.runs() : 1); ++r) {
    SensorNuisanceEstimate e;
    const hinge_likelihood::RecordingSets set = hinge_likelihood::setsOf(p, r);
    if (options_in.fit_gyro_bias) {
      e.fitted_gyro_bias = true;
      e.gyro_bias_main = p.main_bias_basis * p.main_bias.col(set.bias);
      e.gyro_bias_secondary = p.secondary_bias_basis * p.secondary_bias.col(set.bias);
      e.gyro_bias_main_sigma = s * sigmas.main_bias[set.bias];
      e.gyro_bias_secondary_sigma = s * sigmas.secondary_bias[set.bias];
    }
    if (offset) {
      e.fitted_time_offset = true;
      e.time_offset = shiftOf(r) * rates.run_step[r] + p.offset_fraction[set.offset];
      e.time_offset_sigma = s * sigmas.offset_fraction[set.offset];
    }
    if (r == 0) static_cast<SensorNuisanceEstimate&>(fit) = e;
    if (per_recording) fit.recording_nuisance.push_back(e);
  }
  return fit;
}

HingeBound hingeCramerRao(const HingeTruthSamples& truth, double rate_sigma) {
  const int n = static_cast<int>(truth.time.size());
  const double h = uniformStep(truth.time, "the bound's samples");
  if (n < 2 * kHalfStencil + 2 || truth.main_rate.size() != truth.time.size() ||
      truth.angle.size() != truth.time.size())
    throw std::invalid_argument("hingeCramerRao: too few samples, or rates and angles of other lengths than the times");
  HingeUnknowns p;
  p.phi = truth.angle;
  p.axis_main = truth.axis_main.normalized();
  p.mount = truth.mount.quaternion();
  // Exact "measurements", the model's own values: the residuals vanish and
  // the eliminated rates are the true ones, so the information is the
  // truth's (it does not depend on the noise's draw).
  HingeRates rates;
  rates.main = truth.main_rate;
  rates.secondary.assign(n, Eigen::Vector3d::Zero());
  const Eigen::Matrix3d ct = truth.mount.matrix().transpose();
  for (int k = kHalfStencil; k + kHalfStencil < n; ++k) {
    const double rate = fivePointRate(p.phi, k, h);
    const Eigen::Vector3d turned = Eigen::AngleAxisd(-p.phi[k], p.axis_main) * truth.main_rate[k];
    rates.secondary[k] = ct * (turned + rate * p.axis_main);
  }
  rates.run_begin = {0, n};
  rates.run_step = {h};
  rates.weight = 1.0 / rate_sigma;
  HingeSigmas sigmas;
  if (!hingeLikelihoodSigmas(rates, p, HingeFreedoms{}, 1.0, &sigmas))
    throw NotIdentifiable("the recording's information is singular");
  HingeBound bound;
  bound.sigma_main_deg = sigmas.axis_main * kRadToDeg;
  bound.sigma_secondary_deg = sigmas.axis_secondary * kRadToDeg;
  return bound;
}

}  // namespace calibration
}  // namespace lieflow
