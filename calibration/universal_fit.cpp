#include "calibration/universal_fit.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <memory>
#include <limits>
#include <vector>

#include "calibration/data_selection.hpp"
#include "calibration/rate_derivative.hpp"
#include "calibration/residual_kind.hpp"
#include "calibration/two_axis_solver.hpp"
#include "calibration/unit_axis.hpp"
#include "calibration/universal_initial.hpp"
#include "calibration/universal_residuals.hpp"
#include "calibration/wobble_check.hpp"
#include "liegroup/invalid_input.hpp"
#include "liegroup/input_number.hpp"

namespace lieflow {
namespace calibration {

namespace {

/// The per-sample weights σ_ref/σₖ of RelativeRateUniversalResidual at the
/// axes `at` (the closed-form start: the weights need the axes only roughly).
/// To first order in the noise, with b = R₁₂a₂, N = a₁ × b, v = R₁₂ω₂ and u
/// the relative rate, r = u·N changes by
///   −n₁·N + (R₁₂n₂)·N                        gyroscope noise n₁, n₂,
///   −η₁·(v × N + b × (u × a₁)) = −η₁·g₁       orientation noise R₁ exp(η₁),
///   η₂·(ω₂ × R₁₂ᵀN + a₂ × R₁₂ᵀ(u × a₁)) = η₂·g₂   and R₂ exp(η₂),
/// so σₖ² = (σ_g1² + σ_g2²)|N|² + σ_η1²|g₁|² + σ_η2²|g₂|² (checked against a
/// Monte Carlo of synthetic recordings to a few %). All four σ come from the
/// recorded signals' own third differences (data_selection.hpp), not from
/// the fit: the closed-form start of a short recording can be 15° off, and
/// its residuals would overstate the orientation noise 30-fold.
/// σ_ref = (σ_g1² + σ_g2²)^½, the noise the residual would have with exact
/// orientations, keeps the residual in rad/s.
std::vector<double> relativeRateScales(const JointSamples& samples, const std::vector<Eigen::Matrix3d>& R12,
                                       const std::vector<Eigen::Vector3d>& u, const AxisPair& at) {
  const Eigen::Vector3d a1 = at.axis1.normalized(), a2 = at.axis2.normalized();
  const double gyro_variance = std::pow(whiteNoiseFromDifferences(samples.main.angular_velocity), 2) +
                               std::pow(whiteNoiseFromDifferences(samples.secondary.angular_velocity), 2);
  const double eta1 = std::pow(orientationNoiseFromDifferences(samples.main.orientation), 2);
  const double eta2 = std::pow(orientationNoiseFromDifferences(samples.secondary.orientation), 2);
  std::vector<double> variance(R12.size());
  double mean = 0.0;
  for (std::size_t k = 0; k < R12.size(); ++k) {
    const Eigen::Vector3d& w2 = samples.secondary.angular_velocity[k];
    const Eigen::Vector3d b = R12[k] * a2, N = a1.cross(b), v = R12[k] * w2, ua = u[k].cross(a1);
    const Eigen::Vector3d g1 = v.cross(N) + b.cross(ua);
    const Eigen::Vector3d g2 = w2.cross(R12[k].transpose() * N) + a2.cross(R12[k].transpose() * ua);
    variance[k] = gyro_variance * N.squaredNorm() + eta1 * g1.squaredNorm() + eta2 * g2.squaredNorm();
    mean += variance[k] / static_cast<double>(R12.size());
  }
  std::vector<double> scales(R12.size(), 1.0);
  if (!(mean > 0.0)) return scales;  // exact data: nothing to weight
  const double reference = gyro_variance > 0.0 ? gyro_variance : mean;
  for (std::size_t k = 0; k < R12.size(); ++k)
    scales[k] = std::sqrt(reference / std::max(variance[k], 1e-6 * mean));
  return scales;
}

/// Moves of the whole-sample shift after the search, at most.
constexpr int kUniversalOffsetRefits = 3;

/// The recording with the secondary's samples moved `m` back: sample k pairs
/// the main body's sample k with the secondary's k − m (the main's times),
/// over the samples both have; and, with `edge`, without the first and last
/// `edge` of those (the secondary's rate slope needs them).
JointSamples shifted(const JointSamples& s, int m, int edge) {
  JointSamples out;
  out.source = s.source;
  out.main.name = s.main.name;
  out.secondary.name = s.secondary.name;
  const int n = s.size();
  for (int k = std::max(0, m) + edge; k < n - edge && k - m < n - edge; ++k) {
    if (k - m < edge) continue;
    out.time.push_back(s.time[k]);
    if (s.main.hasOrientation()) out.main.orientation.push_back(s.main.orientation[k]);
    if (s.main.hasAngularVelocity()) out.main.angular_velocity.push_back(s.main.angular_velocity[k]);
    if (s.secondary.hasOrientation()) out.secondary.orientation.push_back(s.secondary.orientation[k - m]);
    if (s.secondary.hasAngularVelocity()) out.secondary.angular_velocity.push_back(s.secondary.angular_velocity[k - m]);
  }
  return out;
}

/// Mean of (a₁·R₁ᵀR₂a₂)² at the closed-form axes of the orientations paired at shift m.
double orientationCostAtShift(const JointSamples& s, int m) {
  const JointSamples paired = shifted(s, m, 0);
  const std::vector<Eigen::Matrix3d> R12 = relativeOrientations(paired);
  const AxisPair a = universalStartsFromOrientations(R12).front();
  double sum = 0.0;
  for (const Eigen::Matrix3d& R : R12) sum += std::pow(a.axis1.dot(R * a.axis2), 2);
  return sum / static_cast<double>(R12.size());
}

/// The fit with the secondary's samples `shift` whole samples back.
UniversalFit fitUniversalAtShift(const JointSamples& recorded, const AxisFitOptions& options, int shift,
                                 const DataSelection& data) {
  const bool offset = options.fit_time_offset;
  // With the offset: the pairs at the shift, and the same less kRateWindow at
  // each end (the secondary's rate slope needs them); without, the recording.
  const int edge = offset ? kRateWindow : 0;
  JointSamples whole_pairs, pairs;
  if (offset) {
    whole_pairs = shifted(recorded, shift, 0);
    pairs = shifted(recorded, shift, edge);
  }
  const JointSamples& whole = offset ? whole_pairs : recorded;
  const JointSamples& samples = offset ? pairs : recorded;
  requireEnoughSamples(samples.size(), options);

  const std::vector<Eigen::Matrix3d> R12 = relativeOrientations(samples);
  std::vector<std::unique_ptr<ResidualKind>> kinds;
  const std::string orientation_kind = "orientation constraint (R1 a1) . (R2 a2) = 0";
  if (offset) {
    std::vector<OrientationUniversalOffsetResidual> blocks(R12.size());
    for (std::size_t k = 0; k < R12.size(); ++k) {
      blocks[k].R12 = R12[k];
      blocks[k].w2 = samples.secondary.angular_velocity[k];
    }
    kinds.push_back(std::make_unique<SampleResidualKind<OrientationUniversalOffsetResidual, 1, true>>(
        orientation_kind + " with the clock offset", "rad", 1, std::move(blocks)));
  } else {
    std::vector<OrientationUniversalResidual> blocks;
    blocks.reserve(R12.size());
    for (const Eigen::Matrix3d& R : R12) blocks.emplace_back(R);
    kinds.push_back(
        std::make_unique<SampleResidualKind<OrientationUniversalResidual, 1>>(orientation_kind, "rad", 1, std::move(blocks)));
  }
  std::vector<NamedStart> starts;
  const std::vector<AxisPair> closed_form = universalStartsFromOrientations(R12);
  NuisanceSelection nuisance;
  Eigen::Matrix<double, 3, 2> B1 = Eigen::Matrix<double, 3, 2>::Zero(), B2 = B1;
  if (data.rates) {
    const std::vector<Eigen::Vector3d> u = relativeRates(samples, R12);
    const std::vector<double> scales = relativeRateScales(samples, R12, u, closed_form.front());
    const std::string kind = "relative angular velocity in span{R1 a1, R2 a2} (per-sample noise weights)";
    if (options.fit_gyro_bias || offset) {
      if (options.fit_gyro_bias) {
        B1 = perpendicularBasis(closed_form.front().axis1);
        B2 = perpendicularBasis(closed_form.front().axis2);
        for (int i = 0; i < 4; ++i) nuisance.active[i] = true;
      }
      if (offset) nuisance.active[4] = true;
      std::vector<RelativeRateUniversalNuisanceResidual> blocks(R12.size());
      for (std::size_t k = 0; k < R12.size(); ++k) {
        blocks[k].R12 = R12[k];
        blocks[k].w1 = samples.main.angular_velocity[k];
        blocks[k].w2 = samples.secondary.angular_velocity[k];
        if (offset) blocks[k].dw2 = rateDerivative(whole.time, whole.secondary.angular_velocity, k + edge);
        blocks[k].B1 = B1;
        blocks[k].B2 = B2;
        blocks[k].scale = scales[k];
      }
      kinds.push_back(std::make_unique<SampleResidualKind<RelativeRateUniversalNuisanceResidual, 1, true>>(
          kind + (options.fit_gyro_bias ? " with gyroscope biases" : "") + (offset ? " with the clock offset" : ""),
          "rad/s", 1, std::move(blocks)));
    } else {
      std::vector<RelativeRateUniversalResidual> blocks;
      blocks.reserve(R12.size());
      for (std::size_t k = 0; k < R12.size(); ++k) {
        blocks.emplace_back(R12[k], u[k]);
        blocks.back().scale = scales[k];
      }
      kinds.push_back(std::make_unique<SampleResidualKind<RelativeRateUniversalResidual, 1>>(kind, "rad/s", 1,
                                                                                            std::move(blocks)));
    }
  }
  for (std::size_t i = 0; i < closed_form.size(); ++i)
    starts.push_back({closed_form[i], i == 0 ? std::string("closed form (orientations)")
                                             : "closed form (orientations), near-null alternative " +
                                                   std::to_string(i)});
  for (std::size_t i = 0; i < options.extra_starts.size(); ++i)
    starts.push_back({options.extra_starts[i], "given start " + std::to_string(i + 1)});

  IdentifiabilityContext context;
  context.axis1 = "axis 1 in the main body '" + samples.main.name + "'";
  context.axis2 = "axis 2 in the secondary body '" + samples.secondary.name + "'";
  context.hint =
      "both joint angles must move (a universal joint turned about one of its axes only acts as a hinge and "
      "leaves the other axis undetermined)";

  std::vector<const ResidualKind*> kind_list;
  for (const auto& k : kinds) kind_list.push_back(k.get());
  const TwoAxisSolution solution = solveTwoAxes(kind_list, starts, options, context, nuisance);

  UniversalFit fit;
  fit.axis1_main = canonicalSign(solution.axes.axis1) * solution.axes.axis1;
  fit.axis2_secondary = canonicalSign(solution.axes.axis2) * solution.axes.axis2;
  fit.sigma1_deg = solution.sigma1_rad * kRadToDeg;
  fit.sigma2_deg = solution.sigma2_rad * kRadToDeg;
  fit.covariance = solution.covariance;
  if (options.fit_gyro_bias) {
    fit.fitted_gyro_bias = true;
    fit.gyro_bias_main = B1 * solution.nuisance.segment<2>(0);
    fit.gyro_bias_secondary = B2 * solution.nuisance.segment<2>(2);
    fit.gyro_bias_main_sigma = std::sqrt(solution.nuisance_covariance.block<2, 2>(0, 0).trace());
    fit.gyro_bias_secondary_sigma = std::sqrt(solution.nuisance_covariance.block<2, 2>(2, 2).trace());
  }
  if (offset) {
    const double h = recorded.meanStep();
    fit.fitted_time_offset = true;
    fit.time_offset = shift * h + solution.nuisance[4];
    fit.time_offset_sigma = std::sqrt(solution.nuisance_covariance(4, 4));
  }
  fit.information = solution.information;
  fit.summary = solution.summary;
  fit.summary.data = data.name();
  fit.summary.samples = samples.size();
  return fit;
}

UniversalFit fitUniversalAsked(const JointSamples& samples, const AxisFitOptions& options) {
  if (options.estimator == HingeEstimator::kLikelihood)
    throw InvalidInput(samples.source, "`estimator` likelihood is an option of the hinge fit");
  if (options.low_pass_hz > 0.0)
    throw InvalidInput(samples.source, "`low_pass` is an option of the hinge fit (the universal fit weighs its "
                                       "gyroscope residual by the rates' white noise, which a filter colours)");
  const DataSelection data = selectData(samples, options.use, "universal joint");
  if (!data.orientations)
    throw NotIdentifiable(
        "a universal joint's axes need both bodies' orientations (" + samples.main.name + ".qw.. and " +
        samples.secondary.name +
        ".qw..): from gyroscopes alone there is no per-sample constraint (two unmeasured joint angles and "
        "their rates against three measured relative rates)");
  if ((options.fit_gyro_bias || options.fit_time_offset) && !data.rates)
    throw InvalidInput(samples.source, std::string(options.fit_gyro_bias ? "`fit_gyro_bias`" : "`fit_time_offset`") +
                                           " needs both bodies' gyroscopes in the fit (`use` both or auto)");
  requireEnoughSamples(samples.size(), options);
  if (!options.fit_time_offset) return fitUniversalAtShift(samples, options, 0, data);

  // The clock offset: uniform times; the whole samples by the closed-form
  // orientation fit at every shift within ±max_time_offset (the orientations
  // make that cost sharp in the shift), then the full fit with the fraction ν.
  const std::vector<double>& t = samples.time;
  const double h = (t.back() - t.front()) / (t.size() - 1);
  for (std::size_t k = 0; k + 1 < t.size(); ++k)
    if (std::abs(t[k + 1] - t[k] - h) > 1e-3 * h)
      throw InvalidInput(samples.source, "`fit_time_offset` needs uniformly sampled times: t[" + std::to_string(k + 1) +
                                             "] - t[" + std::to_string(k) + "] differs from the mean interval");
  const int reach = clampedInt(std::floor(options.max_time_offset / h), 0, samples.size() / 4);
  int best = 0;
  double best_cost = std::numeric_limits<double>::infinity();
  for (int m = -reach; m <= reach; ++m) {
    const double c = orientationCostAtShift(samples, m);
    if (c < best_cost) {
      best_cost = c;
      best = m;
    }
  }
  // The fit at the search's shift, moved while its fraction says the offset
  // lies nearer another whole sample (|ν| > h/2). Choosing among the fits at
  // neighbouring shifts by their residual instead (as the hinge fit's profile
  // does) picked shifts one sample off, whose first-order rate shift fits
  // worse while the orientations fit as well: axes' mean (error/σ)² 1.6 / 2.2
  // with no offset at all, against 0.93 / 1.19 at the right shift.
  UniversalFit fit = fitUniversalAtShift(samples, options, best, data);
  for (int round = 0; round < kUniversalOffsetRefits; ++round) {
    const int step = clampedInt(std::round((fit.time_offset - best * h) / h), -samples.size(), samples.size());
    if (step == 0) break;
    best += step;
    if (std::abs(best) > reach) break;
    fit = fitUniversalAtShift(samples, options, best, data);
  }
  return fit;
}

/// The whole fit (fitUniversal times it).
UniversalFit fitUniversalWhole(const JointSamples& samples, const AxisFitOptions& options) {
  // A wobble on soft tissue (wobble_check.hpp): with --use auto the fit
  // leaves the gyroscopes out (their residual is weighted by white noise,
  // which a filter would colour) and reads the orientations alone.
  AxisFitOptions chosen = options;
  std::string reason = "no filter: the recording has no gyroscopes";
  if (!options.low_pass_auto) {
    reason = "no filter: asked for (`low_pass` none)";
  } else if (samples.hasAngularVelocities()) {
    const LowPassChoice wobble = chooseLowPass(samples);
    if (wobble.cutoff_hz > 0.0) {
      reason = "no filter although " + wobble.reason.substr(0, wobble.reason.find("; low-passed")) +
               ": the universal fit weighs its gyroscope residual by the rates' white noise, which a filter colours";
      if (options.use == DataUse::kAuto && samples.hasOrientations() && !options.fit_gyro_bias &&
          !options.fit_time_offset) {
        chosen.use = DataUse::kOrientations;
        reason += ", so it reads the orientations alone (`low_pass` none keeps the gyroscopes)";
      }
    } else {
      reason = wobble.reason;
    }
  }
  UniversalFit fit = fitUniversalAsked(samples, chosen);
  fit.low_pass_reason = reason;
  if (!options.check_segments) return fit;
  if (options.fit_time_offset) {
    fit.model_check.note = "not checked across segments: each segment would search its own clock offset";
    return fit;
  }
  AxisFitOptions piece = chosen;
  piece.check_segments = false;
  piece.low_pass_auto = false;
  piece.progress = nullptr;
  const PieceFit fitPiece = [piece](const JointSamples& s) {
    const UniversalFit f = fitUniversalAsked(s, piece);
    return PieceAnswer{f.axis1_main, f.axis2_secondary, f.sigma1_deg, f.sigma2_deg};
  };
  fit.model_check = checkAcrossRecording(samples, fitPiece, lineDistanceDeg, fit.axis1_main, fit.axis2_secondary,
                                         "universal joint");
  fit.sigma1_deg = fit.model_check.widened(fit.sigma1_deg, 0);
  fit.sigma2_deg = fit.model_check.widened(fit.sigma2_deg, 1);
  return fit;
}

}  // namespace

/// summary.seconds: the whole fit's (timedFit).
UniversalFit fitUniversal(const JointSamples& samples, const AxisFitOptions& options) {
  return timedFit([&] { return fitUniversalWhole(samples, options); });
}

}  // namespace calibration
}  // namespace lieflow
