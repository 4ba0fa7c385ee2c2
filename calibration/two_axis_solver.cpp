#include "calibration/two_axis_solver.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <stdexcept>

#include <ceres/loss_function.h>
#include <ceres/solver.h>
#include <ceres/sphere_manifold.h>
#include <Eigen/Eigenvalues>

#include "calibration/axis_problem.hpp"
#include "calibration/unit_axis.hpp"
#include "calibration/solver_options.hpp"
#include "liegroup/number_text.hpp"

namespace lieflow {
namespace calibration {
namespace {

/// Median of the χ² distribution with d = 1, 2, 3 degrees of freedom.
double chiSquareMedian(int dof) {
  switch (dof) {
    case 1: return 0.45493642311957283;
    case 2: return 1.3862943611198906;  // 2 ln 2
    case 3: return 2.3659738843753377;
    default: throw std::logic_error("chiSquareMedian: 1 to 3 noise components per sample");
  }
}

double median(std::vector<double> v) {
  const std::size_t n = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + n, v.end());
  if (v.size() % 2) return v[n];
  const double upper = v[n];
  return 0.5 * (upper + *std::max_element(v.begin(), v.begin() + n));
}


/// σ̂ of kind k from its residuals at the current axes: the median form
/// (robust) or the RMS form with kind k's share of the 4 parameters.
double noiseScale(AxisProblem& p, std::size_t k, bool robust) {
  const std::vector<double> q = p.blockSquaredNorms(k);
  if (q.empty()) return kNoiseScaleFloor;
  const int d = p.kind(k).noiseDof();
  double variance;
  if (robust) {
    variance = median(q) / chiSquareMedian(d);
  } else {
    double sum = 0.0;
    for (double x : q) sum += x;
    const double mk = static_cast<double>(q.size()) * d;
    const double parameters = 4.0 + p.nuisanceCount();
    variance = sum / std::max(1.0, mk - parameters * mk / p.noiseComponents());
  }
  return std::max(std::sqrt(variance), kNoiseScaleFloor);
}

ceres::Solver::Options solverOptions(const AxisFitOptions& options) {
  ceres::Solver::Options o;
  o.linear_solver_type = ceres::DENSE_QR;
  o.max_num_iterations = options.max_iterations;
  o.function_tolerance = options.function_tolerance;
  o.gradient_tolerance = options.gradient_tolerance;
  o.parameter_tolerance = options.parameter_tolerance;
  o.logging_type = ceres::SILENT;
  o.minimizer_progress_to_stdout = false;
  o.num_threads = 1;
  return o;
}

/// Where one start's refinement ended, at the weights of the multi-start.
struct EndPoint {
  AxisPair axes;
  double cost;
  int start;
};

/// Smallest ratio of the information's eigenvalues (smallest over largest)
/// that the covariance takes as regular, as Ceres' covariance's default
/// (min_reciprocal_condition_number).
constexpr double kCovarianceConditioning = 1e-14;

int iterationsOf(const ceres::Solver::Summary& s) {
  return std::max(0, s.num_successful_steps) + std::max(0, s.num_unsuccessful_steps);
}

/// The solution's covariances and σ from a covariance of the axes' tangent
/// coordinates (SphereManifold's, the unit of `tangent`).
void setTangentCovariance(AxisProblem& p, const Eigen::Matrix4d& tangent, TwoAxisSolution* out) {
  const double to_angle = 1.0 / (kSphereTangentPerRadian * kSphereTangentPerRadian);
  out->covariance = to_angle * tangent;
  out->sigma1_rad = std::sqrt(out->covariance.topLeftCorner<2, 2>().trace());
  out->sigma2_rad = std::sqrt(out->covariance.bottomRightCorner<2, 2>().trace());
  Eigen::Matrix<double, 3, 2, Eigen::RowMajor> J1, J2;
  p.plusJacobian(p.axis1(), J1.data());
  p.plusJacobian(p.axis2(), J2.data());
  out->covariance1 = J1 * tangent.topLeftCorner<2, 2>() * J1.transpose();
  out->covariance2 = J2 * tangent.bottomRightCorner<2, 2>() * J2.transpose();
}

/// solveTwoAxes in its steps (the numbered comments), each a member
/// function run in order; what one step finds, the next reads.
struct TwoAxisSolver {
  TwoAxisSolver(const std::vector<const ResidualKind*>& kinds, const std::vector<NamedStart>& starts_,
                const AxisFitOptions& options_, const IdentifiabilityContext& context_,
                const NuisanceSelection& nuisance_, const LowPassNoise* low_pass_)
      : starts(starts_),
        options(options_),
        context(context_),
        nuisance(nuisance_),
        low_pass(low_pass_),
        p(kinds, options_, nuisance_),
        parameters(4 + p.nuisanceCount()),
        robust(options_.loss != RobustLoss::kNone),
        solver(solverOptions(options_)),
        progress(options_.progress, options_.interrupt) {}
  TwoAxisSolver(const TwoAxisSolver&) = delete;
  TwoAxisSolver& operator=(const TwoAxisSolver&) = delete;

  void weighAtFirstStart() {
    // 1. Noise scales at the first start.
    p.setAxes(starts.front().axes);
    p.resetNuisance();
    for (std::size_t k = 0; k < p.kindCount(); ++k) p.setWeight(k, 1.0 / noiseScale(p, k, true));
  }

  void multiStart() {
    // 2. Every start; the lowest cost wins. Every end point is kept for the
    // ambiguity check (step 6).
    solver.callbacks.push_back(&progress);
    for (std::size_t s = 0; s < starts.size(); ++s) {
      p.setAxes(starts[s].axes);
      p.resetNuisance();
      ceres::Solver::Summary summary;
      ceres::Solve(solver, &p.problem(), &summary);
      ends.push_back({p.axes(), summary.final_cost, static_cast<int>(s)});
      end_nuisance.push_back(p.activeNuisance());
      if (best_start < 0 || summary.final_cost < best.final_cost) {
        best = summary;
        best_start = static_cast<int>(s);
      }
    }
    best_axes = ends[best_start].axes;
    best_cost = best.final_cost;
    start_weights.resize(p.kindCount());
    for (std::size_t k = 0; k < p.kindCount(); ++k) start_weights[k] = p.weight(k);
    p.setAxes(best_axes);
    p.setActiveNuisance(end_nuisance[best_start]);
    out.summary.starts = static_cast<int>(starts.size());
    out.summary.start = starts[best_start].origin;
    out.summary.iterations = iterationsOf(best);
  }

  void reweight() {
    // 3. Re-weighting.
    if (p.kindCount() > 1 || robust) {
      for (int round = 0; round < kMaxReweightings; ++round) {
        double change = 0.0;
        std::vector<double> scales(p.kindCount());
        for (std::size_t k = 0; k < p.kindCount(); ++k) {
          scales[k] = noiseScale(p, k, robust);
          change = std::max(change, std::abs(scales[k] * p.weight(k) - 1.0));
        }
        if (change <= kReweightTolerance) break;
        for (std::size_t k = 0; k < p.kindCount(); ++k) p.setWeight(k, 1.0 / scales[k]);
        ceres::Solve(solver, &p.problem(), &best);
        out.summary.iterations += iterationsOf(best);
        ++out.summary.reweightings;
      }
    }
    out.axes = p.axes();
    out.summary.converged = best.termination_type == ceres::CONVERGENCE;
    out.summary.message = solverStopMessage(best);
  }

  void residualStatistics() {
    // Residual statistics, and the check against independently estimated noise.
    std::string misfit;
    for (std::size_t k = 0; k < p.kindCount(); ++k) {
      const std::vector<double> q = p.blockSquaredNorms(k);
      double sum = 0.0;
      for (double x : q) sum += x;
      ResidualStats stats;
      stats.kind = p.kind(k).name();
      stats.unit = p.kind(k).unit();
      stats.samples = static_cast<int>(q.size());
      stats.noise_dof = p.kind(k).noiseDof();
      stats.rms = q.empty() ? 0.0 : std::sqrt(sum / (static_cast<double>(q.size()) * stats.noise_dof));
      stats.noise_scale = 1.0 / p.weight(k);
      stats.independent_noise = p.kind(k).independentNoise();
      if (stats.independent_noise > 0.0 && !q.empty()) {
        stats.residual_to_noise = noiseScale(p, k, true) / stats.independent_noise;
        if (options.max_residual_to_noise > 0.0 && stats.residual_to_noise > options.max_residual_to_noise &&
            misfit.empty())
          misfit = "the " + stats.kind + " residual is " + formatNumber(stats.residual_to_noise, 3) +
                   " times the noise estimated independently from " + p.kind(k).independentNoiseSource() + " (" +
                   formatNumber(stats.independent_noise, 3) + " " + stats.unit + "; at most " +
                   formatNumber(options.max_residual_to_noise) +
                   " accepted): the fit ended in a local minimum that no start escaped, or the model does not "
                   "describe the data (a gyroscope bias, another kind of joint, low-pass-filtered or otherwise "
                   "correlated noise); the axes are not reliable";
      }
      out.summary.residuals.push_back(stats);
    }
    out.summary.rms_residual = out.summary.residuals.front().rms;
    if (!misfit.empty()) {
      out.summary.converged = false;
      out.summary.message = misfit + " (" + solverStopMessage(best) + ")";
    }
  }

  void identifiability() {
    // 4. Identifiability.
    double cost = 0.0;
    Eigen::Matrix4d H, H_noise;
    informationAtAxes(p, &H, &H_noise, &cost, &profile, &information);
    m = p.noiseComponents();
    const double reduced_chi_square = m > parameters ? 2.0 * cost / (m - parameters) : 0.0;
    out.summary.reduced_chi_square = reduced_chi_square;
    // Low-passed signals (LowPassNoise): the residuals' variance is the noise's
    // times the filter's power gain g, and they are correlated over ~f_s/2f_c
    // samples; for a motion within the band the axes' covariance is the white
    // noise's, σ²(JᵀJ)⁻¹ = (s²/g)(JᵀJ)⁻¹, and Δχ² counts in units of s²/g too.
    // The noise's share of the information is the unfiltered problem's times g
    // (second differences cannot tell filtered noise from motion).
    inflation = low_pass ? 1.0 / low_pass->power_gain : 1.0;
    s2 = reduced_chi_square * inflation;
    if (low_pass) {
      AxisProblem raw(low_pass->raw_kinds, options, nuisance);
      if (raw.kindCount() != p.kindCount()) throw std::logic_error("two-axis fit: raw kinds do not match the filtered ones");
      for (std::size_t k = 0; k < p.kindCount(); ++k) raw.setWeight(k, p.weight(k));
      raw.setAxes(p.axes());
      raw.setActiveNuisance(p.activeNuisance());
      Eigen::Matrix4d H_raw, H_noise_raw;
      Eigen::MatrixXd raw_profile;
      double raw_cost = 0.0;
      informationAtAxes(raw, &H_raw, &H_noise_raw, &raw_cost, &raw_profile);
      H_noise = low_pass->power_gain * H_noise_raw;
    }
    out.information = analyseInformation(H, H_noise, s2);
    requireIdentifiable(out.information, options, context);
  }

  void covariances() {
    // 5. Covariance: (JᵀJ)⁻¹ of the information at the best axes (step 4's
    // Jacobian, the robust loss's weights applied), unit noise; refused
    // where the eigenvalues' ratio of the Jacobi-scaled information
    // D^-1/2 JᵀJ D^-1/2 (D its diagonal) is below kCovarianceConditioning.
    // Scaled, because the axes (per rad) and the nuisance (per rad/s, per s)
    // differ in units: exact orientations, weighted at the noise floor, put
    // the axes' information 1e20 above the biases', and the unscaled ratio
    // called a determined fit rank deficient.
    const Eigen::VectorXd diagonal = information.diagonal();
    if (!(diagonal.minCoeff() > 0.0))
      throw NotIdentifiable("the covariance of the axes is rank deficient; " + context.hint);
    const Eigen::VectorXd scale = diagonal.cwiseSqrt().cwiseInverse();
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(scale.asDiagonal() * information * scale.asDiagonal());
    const Eigen::VectorXd& lambda = eig.eigenvalues();
    if (eig.info() != Eigen::Success || !(lambda.minCoeff() > kCovarianceConditioning * lambda.maxCoeff()))
      throw NotIdentifiable("the covariance of the axes is rank deficient; " + context.hint);
    const Eigen::MatrixXd inverse = scale.asDiagonal() *
                                    (eig.eigenvectors() * lambda.cwiseInverse().asDiagonal() *
                                     eig.eigenvectors().transpose()) *
                                    scale.asDiagonal();
    const int n = static_cast<int>(inverse.rows());
    if (p.nuisanceCount() > 0) {
      // Zero for the coordinates held (the block's ambient covariance).
      const int size = kNuisanceSize * p.nuisanceBlocks();
      out.nuisance_covariance.setZero(size, size);
      for (int i = 0; i < n - 4; ++i)
        for (int j = 0; j < n - 4; ++j)
          out.nuisance_covariance(p.activeIndex(i), p.activeIndex(j)) = s2 * inverse(4 + i, 4 + j);
      out.nuisance = Eigen::Map<const Eigen::VectorXd>(p.nuisance(), size);
    }
    // Per rad² of axis rotation; SphereManifold's tangent units are
    // kSphereTangentPerRadian per rad.
    to_angle = 1.0 / (kSphereTangentPerRadian * kSphereTangentPerRadian);
    tangent = inverse.topLeftCorner<4, 4>() / to_angle;
    setTangentCovariance(p, s2 * Eigen::Matrix4d(tangent), &out);
  }

  /// An axis pair as the refusal reports it: "(x y z) in <axis1's body>,
  /// (x y z) in <axis2's>", unit vectors to 6 digits.
  std::string pairText(const AxisPair& pair) const {
    return "(" + formatNumbers(pair.axis1.normalized()) + ") " + context.axis1 + ", (" +
           formatNumbers(pair.axis2.normalized()) + ") " + context.axis2;
  }

  void rejectSecondMinimum() {
    // 6. A second minimum that fits as well: Δχ² = 2Δcost/s² at the weights of
    // the multi-start, for the end points whose axes lie more than
    // distinct_minimum_sigmas σ from the best's. s² is the best's reduced
    // chi-square there or, if larger, the noise variance estimated without the
    // fit (kinds that have one; the others count with the fit's): a short
    // recording lets the best fit absorb part of the noise (seen: residuals 0.7
    // times the noise), which would inflate Δχ².
    double s2_starts = m > parameters ? 2.0 * best_cost / (m - parameters) * inflation : 0.0;
    {
      double independent = 0.0;
      for (std::size_t k = 0; k < p.kindCount(); ++k) {
        const double share = static_cast<double>(p.kind(k).blockCount()) * p.kind(k).noiseDof() / m;
        const double sigma = p.kind(k).independentNoise() * start_weights[k];
        independent += share * (sigma > 0.0 ? sigma * sigma : s2_starts);
      }
      s2_starts = std::max(s2_starts, independent);
    }
    // (Not closer than kQuadraticCheckFloor: on exact data σ is at the
    // rounding level, and two end points of one minimum would look distinct.)
    const double far1 = std::max(options.distinct_minimum_sigmas * out.sigma1_rad, kQuadraticCheckFloor);
    const double far2 = std::max(options.distinct_minimum_sigmas * out.sigma2_rad, kQuadraticCheckFloor);
    const auto near = [&](const AxisPair& a, const AxisPair& b) {
      return angleBetweenLines(a.axis1, b.axis1) <= far1 && angleBetweenLines(a.axis2, b.axis2) <= far2;
    };
    const EndPoint* runner_up = nullptr;
    double runner_up_delta = 0.0;
    std::vector<AxisPair> distinct = {best_axes};
    for (const EndPoint& e : ends) {
      if (near(e.axes, best_axes)) continue;
      if (std::none_of(distinct.begin(), distinct.end(), [&](const AxisPair& d) { return near(e.axes, d); }))
        distinct.push_back(e.axes);
      const double delta = s2_starts > 0.0 ? 2.0 * (e.cost - best_cost) / s2_starts
                                           : std::numeric_limits<double>::infinity();
      if (!runner_up || delta < runner_up_delta) {
        runner_up = &e;
        runner_up_delta = delta;
      }
    }
    out.summary.minima = static_cast<int>(distinct.size());
    if (runner_up) out.summary.runner_up_delta_chi_square = runner_up_delta;
    if (runner_up && runner_up_delta < options.ambiguity_chi_square) {
      const double angle1 = angleBetweenLines(runner_up->axes.axis1, best_axes.axis1) * kRadToDeg;
      const double angle2 = angleBetweenLines(runner_up->axes.axis2, best_axes.axis2) * kRadToDeg;
      throw NotIdentifiable("two axis pairs " + formatNumber(angle1, 3) + "° (" + context.axis1 + ") and " +
                            formatNumber(angle2, 3) + "° (" + context.axis2 +
                            ") apart fit the data equally well (their costs differ by Δχ² = " +
                            formatNumber(std::max(0.0, runner_up_delta), 3) + ", below " +
                            formatNumber(options.ambiguity_chi_square) + ", while the best's 1σ are " +
                            formatNumber(out.sigma1_rad * kRadToDeg, 3) + "° and " +
                            formatNumber(out.sigma2_rad * kRadToDeg, 3) + "°; starts '" + starts[best_start].origin +
                            "' and '" + starts[runner_up->start].origin + "'); both pairs: " +
                            pairText(best_axes) + " (the lower cost) and " + pairText(runner_up->axes) +
                            "; a longer or more varied recording is needed; " + context.hint);
    }
  }

  void checkQuadratic() {
    // 7. σ describes the error where the cost is quadratic over the region it
    // claims. Δχ² at ±k σ along each principal direction of the covariance,
    // over its quadratic value k²:
    //  - above 1 + quadratic_tolerance the cost rises faster than its curvature
    //    at the minimum says: a curved valley (short recordings), along which
    //    the error can be many σ. Not identifiable.
    //  - below kSecantBand (the mean q̄ of both sides) the cost is flatter than
    //    the Gauss–Newton curvature JᵀJ (large noise: its noise-driven part,
    //    and the first-order noise model of the residuals, stretched): σ is
    //    taken from the cost's actual rise, λ/q̄ in that direction; below
    //    kFlatSecant the cost is too flat for that. Not identifiable.
    // (Below kQuadraticCheckFloor the cost is analytic, hence quadratic, and
    // its differences would be rounding errors: exact data are not checked.)
    const double k = options.quadratic_check_sigmas;
    if (options.quadratic_tolerance > 0.0 && s2 > 0.0 &&
        k * std::max(out.sigma1_rad, out.sigma2_rad) > kQuadraticCheckFloor) {
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eig(s2 * Eigen::Matrix4d(tangent));
      const AxisPair at = p.axes();
      const double base = p.costAt(at, Eigen::Vector4d::Zero(), Eigen::VectorXd::Zero(p.nuisanceCount()));
      Eigen::Matrix<double, 4, 2> ratio;
      for (int i = 0; i < 4; ++i)
        for (int side = 0; side < 2; ++side) {
          const Eigen::Vector4d step = (side ? 1.0 : -1.0) * k * std::sqrt(std::max(0.0, eig.eigenvalues()[i])) *
                                       eig.eigenvectors().col(i);
          ratio(i, side) = 2.0 * (p.costAt(at, step, profile * step) - base) / s2 / (k * k);
        }
      out.summary.quadratic_ratio_min = ratio.minCoeff();
      out.summary.quadratic_ratio_max = ratio.maxCoeff();
      const auto which = [&](int i) {
        const double share1 = eig.eigenvectors().col(i).head<2>().squaredNorm();
        return share1 > 0.8 ? "mostly " + context.axis1 : share1 < 0.2 ? "mostly " + context.axis2 : "both axes together";
      };
      const auto sigmas = [&] {
        return "the best fit's 1σ would be " + formatNumber(out.sigma1_rad * kRadToDeg, 3) + "° and " +
               formatNumber(out.sigma2_rad * kRadToDeg, 3) + "°";
      };
      Eigen::Index steep_row, steep_col;
      if (ratio.maxCoeff(&steep_row, &steep_col) > 1.0 + options.quadratic_tolerance)
        throw NotIdentifiable(
            "the cost is far from quadratic over the " + formatNumber(k) + "σ region of the axes: Δχ² at ±" +
            formatNumber(k) + "σ along its principal directions is " + formatNumber(ratio.minCoeff() * k * k, 3) +
            " … " + formatNumber(ratio.maxCoeff() * k * k, 3) + " instead of " + formatNumber(k * k) +
            " (the steepest turns " + which(static_cast<int>(steep_row)) +
            "): the data leave the axes in a curved valley of the cost, along which axes many σ apart fit about "
            "as well (" + sigmas() + "); a longer or more varied recording is needed; " + context.hint);
      Eigen::Vector4d lambda = eig.eigenvalues().cwiseMax(0.0);
      bool flatter = false;
      for (int i = 0; i < 4; ++i) {
        const double mean = 0.5 * (ratio(i, 0) + ratio(i, 1));
        if (mean >= kSecantBand) continue;
        if (mean < kFlatSecant)
          throw NotIdentifiable("the cost is far from quadratic over the " + formatNumber(k) +
                                "σ region of the axes: it rises by Δχ² = " + formatNumber(mean * k * k, 3) +
                                " instead of " + formatNumber(k * k) + " at ±" + formatNumber(k) + "σ in a direction "
                                "that turns " + which(i) + " (" + sigmas() + "); " + context.hint);
        lambda[i] /= mean;
        flatter = true;
      }
      if (flatter) {
        const Eigen::Matrix4d secant = eig.eigenvectors() * lambda.asDiagonal() * eig.eigenvectors().transpose();
        setTangentCovariance(p, secant, &out);
      }
    }
  }

  void checkNuisance() {
    // 7b. A short recording lets the biases turn its few rate directions to
    // fit the noise: the cost can fall into a narrow valley tenths of rad/s
    // wide of the truth, whose curvature claims a σ of hundredths. Per block
    // (a recording's biases and clock fraction), where the estimate ν̂ lies
    // more than kNuisanceCheckSigmas σ from zero: the rise Δχ² = 2Δcost/s²
    // from ν̂ to ν = 0 (the axes and the other blocks held) against its
    // quadratic value ν̂ᵀ H_BB ν̂ / s²; below kFlatSecant of it the cost
    // between them is far from the quadratic the σ assumes, and the
    // nuisance is not identified. Not under a robust loss, whose cost
    // flattens far from any estimate.
    const int active = p.nuisanceCount();
    if (active == 0 || robust || !(s2 > 0.0)) return;
    const Eigen::VectorXd estimate = p.activeNuisance();
    const double base = p.costAt(p.axes(), Eigen::Vector4d::Zero(), Eigen::VectorXd::Zero(active));
    for (int block = 0; block < p.nuisanceBlocks(); ++block) {
      Eigen::VectorXd delta = Eigen::VectorXd::Zero(active);
      for (int i = 0; i < active; ++i)
        if (p.activeIndex(i) / kNuisanceSize == block) delta[i] = -estimate[i];
      const double quadratic = delta.dot(information.bottomRightCorner(active, active) * delta) / s2;
      if (!(quadratic > kNuisanceCheckSigmas * kNuisanceCheckSigmas)) continue;
      const double rise = 2.0 * (p.costAt(p.axes(), Eigen::Vector4d::Zero(), delta) - base) / s2;
      if (rise >= kFlatSecant * quadratic) continue;
      throw NotIdentifiable(nuisanceName(block) + (nuisance.active[0] ? " are" : " is") +
                            " not identified: from the estimate to none the cost rises "
                            "by Δχ² = " + formatNumber(std::max(0.0, rise), 3) + ", where its curvature at the "
                            "estimate predicts " + formatNumber(quadratic, 3) + " (the estimate lies in a narrow "
                            "valley of the cost that fits the noise); a longer or more varied recording is needed, "
                            "or a fit without them");
    }
  }

  /// "the gyroscope biases" (and clock offset) of nuisance block b, with its
  /// recording's label where the context names one.
  std::string nuisanceName(int block) const {
    std::string what = nuisance.active[0] ? "the gyroscope biases" : "";
    if (nuisance.active[4]) what += what.empty() ? "the clock offset" : " and clock offset";
    if (block < static_cast<int>(context.nuisance_blocks.size())) what += " of" + context.nuisance_blocks[block];
    return what;
  }

  void robustCovariance() {
    // 8. Under a robust loss or on low-passed signals: the sandwich.
    Eigen::Matrix4d sandwich;
    int batches = 0;
    if ((robust || low_pass) && sandwichCovariance(p, &sandwich, &batches)) {
      out.summary.gauss_newton_sigma_rad = std::max(out.sigma1_rad, out.sigma2_rad);
      out.summary.sigma_method = "Gauss-Newton (larger than the sandwich from " + std::to_string(batches) + " batches)";
    }
    if (batches > 0 && to_angle * sandwich.trace() > out.covariance.trace()) {
      setTangentCovariance(p, sandwich, &out);
      out.summary.sigma_method = "sandwich (batch means, " + std::to_string(batches) + " batches; larger than Gauss-Newton)";
    }
  }

  const std::vector<NamedStart>& starts;
  const AxisFitOptions& options;
  const IdentifiabilityContext& context;
  const NuisanceSelection& nuisance;
  const LowPassNoise* low_pass;
  AxisProblem p;
  const int parameters;
  const bool robust;
  ceres::Solver::Options solver;
  FitProgressCallback progress;
  TwoAxisSolution out;
  ceres::Solver::Summary best;              ///< the best start's (then the re-weighted) solve
  std::vector<EndPoint> ends;               ///< every start's end point
  int best_start = -1;
  std::vector<Eigen::VectorXd> end_nuisance;
  AxisPair best_axes;
  double best_cost = 0.0;
  std::vector<double> start_weights;        ///< the weights of the multi-start
  int m = 0;                                ///< noise components
  double inflation = 1.0, s2 = 0.0;         ///< low-pass inflation; the noise variance s²
  Eigen::MatrixXd profile;                  ///< the nuisance's response to the axes
  Eigen::MatrixXd information;              ///< JᵀJ at the best axes: axes (per rad) and nuisance
  Eigen::Matrix<double, 4, 4, Eigen::RowMajor> tangent;  ///< the axes' covariance at unit noise, tangent coordinates
  double to_angle = 1.0;
};

}  // namespace

TwoAxisSolution solveTwoAxes(const std::vector<const ResidualKind*>& kinds, const std::vector<NamedStart>& starts,
                             const AxisFitOptions& options, const IdentifiabilityContext& context,
                             const NuisanceSelection& nuisance, const LowPassNoise* low_pass) {
  if (kinds.empty() || starts.empty()) throw std::logic_error("solveTwoAxes: needs residuals and a start");
  TwoAxisSolver solve(kinds, starts, options, context, nuisance, low_pass);
  solve.weighAtFirstStart();    // 1
  solve.multiStart();           // 2
  solve.reweight();             // 3
  solve.residualStatistics();
  solve.identifiability();      // 4
  solve.covariances();          // 5
  solve.rejectSecondMinimum();  // 6
  solve.checkQuadratic();       // 7
  solve.checkNuisance();        // 7b
  solve.robustCovariance();     // 8
  return std::move(solve.out);
}

}  // namespace calibration
}  // namespace lieflow
