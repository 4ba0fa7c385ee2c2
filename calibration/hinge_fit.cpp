// fitHinge: what the hinge fit chooses by itself around its constraint fit
// (hinge_constraint_fit.hpp): the filter, the estimator and the likelihood
// refinement, the clock-offset profile, the bias check and the model check;
// one recording or several.
#include "calibration/hinge_fit.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <stdexcept>
#include <vector>

#include "calibration/axis_problem.hpp"
#include "calibration/clock_offset.hpp"
#include "calibration/hinge_constraint_fit.hpp"
#include "calibration/hinge_estimator.hpp"
#include "calibration/hinge_likelihood.hpp"
#include "calibration/low_pass.hpp"
#include "calibration/residual_kind.hpp"
#include "calibration/unit_axis.hpp"
#include "calibration/wobble_check.hpp"
#include "liegroup/input_number.hpp"
#include "liegroup/invalid_input.hpp"
#include "liegroup/number_text.hpp"

namespace lieflow {
namespace calibration {
namespace {

/// Δχ² (4 parameters) by which fitting gyroscope biases must lower the
/// gyroscope residual for the plain fit to be called biased: χ²₄ exceeds it
/// with probability 5e-6 on unbiased data.
constexpr double kBiasChiSquare = 30.0;
/// The profile over whole-sample clock offsets: shifts either side of the
/// search's, and recentrings of that window, at most.
constexpr int kOffsetProfile = 4;
constexpr int kOffsetRefits = 3;

/// With --estimator likelihood: the constraint fit at `shifts` refined by
/// maximum likelihood over the joint angle (hinge_likelihood.hpp), with the
/// biases and the clock offsets where the constraint fit estimated them
/// (started from its values; several recordings: each one's own).
void refineByLikelihood(const Recordings& runs, const AxisFitOptions& options, const Shifts& shifts,
                        HingeFit* fit_out) {
  const JointSamples& samples = *runs.front();
  HingeFit& fit = *fit_out;
  HingeLikelihoodOptions ml_options;
  ml_options.progress = options.progress;
  ml_options.interrupt = options.interrupt;
  ml_options.fit_gyro_bias = fit.fitted_gyro_bias;
  ml_options.gyro_bias_main_start = fit.gyro_bias_main;
  ml_options.gyro_bias_secondary_start = fit.gyro_bias_secondary;
  ml_options.fit_time_offset = fit.fitted_time_offset;
  ml_options.offset_shift = shifts.front();
  if (fit.fitted_time_offset) ml_options.offset_fraction_start = fit.time_offset - shifts.front() * samples.meanStep();
  if (!fit.recording_nuisance.empty()) {  // several recordings: each one's own
    ml_options.recording_starts = fit.recording_nuisance;
    ml_options.recording_shifts = shifts;
  }
  const HingeLikelihoodFit ml = fitHingeLikelihood(runs, fit.axis_main, fit.axis_secondary, ml_options);
  fit.constraint_sigma_main_deg = fit.sigma_main_deg;
  fit.constraint_sigma_secondary_deg = fit.sigma_secondary_deg;
  const double flip = canonicalSign(ml.axis_main);
  fit.axis_main = flip * ml.axis_main;
  fit.axis_secondary = flip * ml.axis_secondary;
  fit.sigma_main_deg = ml.sigma_main_deg;
  fit.sigma_secondary_deg = ml.sigma_secondary_deg;
  if (ml.fitted_gyro_bias) {
    fit.gyro_bias_main = ml.gyro_bias_main;
    fit.gyro_bias_secondary = ml.gyro_bias_secondary;
    fit.gyro_bias_main_sigma = ml.gyro_bias_main_sigma;
    fit.gyro_bias_secondary_sigma = ml.gyro_bias_secondary_sigma;
  }
  if (ml.fitted_time_offset) {
    fit.time_offset = ml.time_offset;
    fit.time_offset_sigma = ml.time_offset_sigma;
  }
  if (!ml.recording_nuisance.empty()) fit.recording_nuisance = ml.recording_nuisance;
  fit.likelihood = ml;
  fit.sign = "R1 j1 = R2 j2 from the joint angle that turns the perpendicular rates (likelihood); overall sign: "
             "largest component of axis_main positive";
  if (!ml.converged) {
    fit.summary.converged = false;
    fit.summary.message = "the likelihood refinement did not converge: " + ml.message;
  }
}

}  // namespace

/// Without --fit-gyro-bias: would fitting the biases lower the gyroscope
/// residual significantly? The score test at the plain fit (gaussNewtonStep,
/// axis_problem.hpp): the gyroscope kind with the four bias coordinates in the
/// planes perpendicular to the fitted axes, evaluated at ν = 0, gives the Δχ²
/// = gᵀH⁻¹g/σ² a fit with biases would gain to first order, and the biases of
/// its Gauss–Newton step. (It replaced a refit with the biases, which doubled
/// the fit's time; the flags agree on the tests' recordings.) A residual
/// above max_residual_to_noise times the noise that the biases would leave
/// above it too is not flagged as a bias (a real knee: Δχ² 700–880, the
/// residual still 9 times the noise).
void checkForGyroscopeBias(const JointSamples& samples, const AxisFitOptions& options, HingeFit* fit,
                           const std::string& label = "") {
  // (Under a robust loss outliers would read as a bias: not checked.)
  if (options.fit_gyro_bias || !options.check_gyro_bias || options.loss != RobustLoss::kNone) return;
  const ResidualStats* plain = nullptr;
  for (const ResidualStats& r : fit->summary.residuals)
    if (r.kind == kGyroKindName + label) plain = &r;
  if (!plain || !(plain->independent_noise > 0.0)) return;
  const std::unique_ptr<ResidualKind> kind = gyroNuisanceKind(samples, fit->axis_main, fit->axis_secondary, 0, false);
  NuisanceSelection biases;
  for (int i = 0; i < 4; ++i) biases.active[i] = true;
  AxisFitOptions plain_options;
  AxisProblem problem({kind.get()}, plain_options, biases);
  problem.setAxes({fit->axis_main, fit->axis_secondary});
  GaussNewtonStep step;
  if (!gaussNewtonStep(problem, &step)) return;
  const double sigma2 = plain->independent_noise * plain->independent_noise;
  const double delta = 2.0 * step.decrease / sigma2;
  fit->summary.bias_check_delta_chi_square = std::max(fit->summary.bias_check_delta_chi_square, delta);
  if (delta <= kBiasChiSquare) return;
  // A residual far above the noise that the biases would not bring near it
  // is another misfit (the fit already says so); the bias is not its cause.
  const double biased_rms2 = plain->rms * plain->rms - 2.0 * step.decrease / std::max(1, plain->samples);
  const double bound = options.max_residual_to_noise > 0.0 ? options.max_residual_to_noise : 2.0;
  if (plain->rms * plain->rms > bound * bound * sigma2 && biased_rms2 > bound * bound * sigma2) return;
  const Eigen::Matrix<double, 3, 2> B1 = perpendicularBasis(fit->axis_main), B2 = perpendicularBasis(fit->axis_secondary);
  const double bias = std::max((B1 * step.step.segment<2>(4)).norm(), (B2 * step.step.segment<2>(6)).norm());
  fit->summary.converged = false;
  const std::string found = "lowers the gyroscope residual by delta chi-square " + formatNumber(delta) + " (above " +
                            formatNumber(kBiasChiSquare) + "; biases up to " + formatNumber(bias) +
                            " rad/s), and axes fitted without it can be many sigma off";
  fit->summary.message =
      label.empty()
          ? "the gyroscopes carry a constant bias: fitting one (`fit_gyro_bias`) " + found + "; rerun with `fit_gyro_bias`"
          : "the gyroscopes of " + samples.source + " carry a constant bias: fitting one " + found +
                "; rerun with `fit_gyro_bias` (each recording's biases its own)";
}

namespace {

HingeFit fitHingeOffsetsPerRecording(const Recordings& runs, const AxisFitOptions& options);

/// fitHinge with options.estimator chosen (not kAuto).
HingeFit fitHingeWithEstimator(const Recordings& runs, const AxisFitOptions& options) {
  const JointSamples& samples = *runs.front();
  const bool likelihood = options.estimator == HingeEstimator::kLikelihood;
  if (options.low_pass_hz > 0.0) {
    // The likelihood fit and the clock offset model white gyroscope noise
    // sample by sample; the filtered residuals are neither white nor of that size.
    if (likelihood || options.fit_time_offset)
      throw InvalidInput(samples.source, std::string("`low_pass` with ") +
                                             (likelihood ? "`estimator` likelihood" : "`fit_time_offset`") +
                                             ": it models the gyroscopes' white noise sample by sample, which a "
                                             "filter colours; fit without `low_pass`");
    // Each recording filtered alone (a filter's memory does not cross from one to the next).
    LowPassFilter filter;
    std::vector<JointSamples> filtered(runs.size()), trimmed(runs.size());
    Recordings filtered_runs;
    Unfiltered raw;
    for (std::size_t r = 0; r < runs.size(); ++r) {
      filtered[r] = lowPassed(*runs[r], options.low_pass_hz, "`low_pass`", &filter, &trimmed[r]);
      filtered_runs.push_back(&filtered[r]);
      raw.samples.push_back(&trimmed[r]);
    }
    raw.power_gain = filter.noisePowerGain();
    HingeFit fit = fitHingeAtShift(filtered_runs, options, sameShift(runs, 0), raw);
    fit.low_pass_hz = options.low_pass_hz;
    fit.low_pass_noise_gain = raw.power_gain;
    return fit;
  }
  if (!options.fit_time_offset) {
    HingeFit fit = fitHingeAtShift(runs, options, sameShift(runs, 0));
    for (std::size_t r = 0; r < runs.size(); ++r) checkForGyroscopeBias(*runs[r], options, &fit, recordingLabel(runs, r));
    if (likelihood) refineByLikelihood(runs, options, sameShift(runs, 0), &fit);
    return fit;
  }
  if (runs.size() > 1) return fitHingeOffsetsPerRecording(runs, options);
  // The profile over whole samples: the fit at every shift within
  // ±kOffsetProfile of the search's (wholeSampleOffset), recentred while the
  // best lies on the window's edge; the least residual wins, and every fit
  // that ends at an offset more than 1.5 samples away must fit worse by
  // Δχ² ≥ kOffsetAmbiguity
  // (on 3 s recordings with biases the search alone, or the fit from its
  // shift, stayed two samples off with σ a tenth of that).
  const double h = samples.meanStep();
  const int reach = clampedInt(std::floor(options.max_time_offset / h), 0, samples.size() / 2);
  std::map<int, HingeFit> fits;
  const auto meanSquare = [](const HingeFit& f) { return std::pow(f.summary.residuals.front().rms, 2); };
  int best = wholeSampleOffset(samples, options.max_time_offset);
  for (int round = 0; round < kOffsetRefits; ++round) {
    for (int m = std::max(-reach, best - kOffsetProfile); m <= std::min(reach, best + kOffsetProfile); ++m) {
      if (fits.count(m)) continue;
      try {
        fits.emplace(m, fitHingeAtShift(runs, options, sameShift(runs, m)));
      } catch (const NotIdentifiable&) {
      }
    }
    if (fits.empty()) break;
    const int previous = best;
    best = std::min_element(fits.begin(), fits.end(), [&](const auto& x, const auto& y) {
             return meanSquare(x.second) < meanSquare(y.second);
           })->first;
    if (std::abs(best - previous) < kOffsetProfile) break;
  }
  if (fits.empty()) return fitHingeAtShift(runs, options, sameShift(runs, best));  // throws why
  const HingeFit& fit = fits.at(best);
  const double noise = std::pow(fit.summary.residuals.front().independent_noise, 2);
  for (const auto& entry : fits) {
    // Fits from neighbouring shifts reach the same offset through their
    // fraction: a rival is an offset more than 1.5 samples away.
    const HingeFit& other = entry.second;
    if (std::abs(other.time_offset - fit.time_offset) <= 1.5 * h || noise <= 0.0) continue;
    const double delta = fit.summary.samples * (meanSquare(other) - meanSquare(fit)) / noise;
    if (delta < kOffsetAmbiguity)
      throw NotIdentifiable("clock offsets of " + formatNumber(fit.time_offset) + " s and " +
                            formatNumber(other.time_offset) + " s fit the gyroscopes about as well (Δχ² = " +
                            formatNumber(delta) + ", below " + formatNumber(kOffsetAmbiguity) +
                            "): a longer or more varied recording is needed to find the offset");
  }
  if (!likelihood) return fit;
  // The likelihood moves the secondary's rates by the fraction to first order,
  // so it is refined at the whole sample nearest the offset (the profile's
  // best shift can be a sample away from its own estimate), and moved while
  // its fraction says another whole sample is nearer (|ν| > h/2).
  int shift = clampedInt(std::round(fit.time_offset / h), -samples.size(), samples.size());
  HingeFit refined = fit;
  refineByLikelihood(runs, options, sameShift(runs, shift), &refined);
  for (int round = 0; round < kOffsetRefits; ++round) {
    const int step = clampedInt(std::round((refined.time_offset - shift * h) / h), -samples.size(), samples.size());
    if (step == 0 || std::abs(shift + step) > reach) break;
    shift += step;
    const double estimate = refined.time_offset;  // the fraction starts from the likelihood's estimate
    refined = fit;
    refined.time_offset = estimate;
    refineByLikelihood(runs, options, sameShift(runs, shift), &refined);
  }
  return refined;
}

/// Several recordings with fit_time_offset, each with its own clock. A
/// recording's whole samples come from its own profile (the one-recording
/// fit above, constraint estimator) or, where it does not answer alone, from
/// the search (wholeSampleOffset). Then one fit over all at those shifts,
/// each recording's fraction (and biases) its own, recentred while a
/// fraction says another whole sample is nearer (|ν| > h/2); then the
/// likelihood where chosen, recentred the same way.
HingeFit fitHingeOffsetsPerRecording(const Recordings& runs, const AxisFitOptions& options) {
  AxisFitOptions alone = options;
  alone.estimator = HingeEstimator::kConstraint;
  Shifts shifts;
  std::vector<int> reach;
  for (const JointSamples* run : runs) {
    const double h = run->meanStep();
    reach.push_back(clampedInt(std::floor(options.max_time_offset / h), 0, run->size() / 2));
    try {
      const double offset = fitHingeWithEstimator({run}, alone).time_offset;
      shifts.push_back(clampedInt(std::round(offset / h), -reach.back(), reach.back()));
    } catch (const NotIdentifiable&) {
      shifts.push_back(wholeSampleOffset(*run, options.max_time_offset));
    }
  }
  // Moves each shift whose recording's offset lies nearer another whole sample; false when none moved.
  const auto recentre = [&](const HingeFit& f) {
    bool moved = false;
    for (std::size_t r = 0; r < runs.size(); ++r) {
      const double h = runs[r]->meanStep();
      const int n = runs[r]->size();
      const int step = clampedInt(std::round((f.recording_nuisance[r].time_offset - shifts[r] * h) / h), -n, n);
      if (step == 0 || std::abs(shifts[r] + step) > reach[r]) continue;
      shifts[r] += step;
      moved = true;
    }
    return moved;
  };
  HingeFit fit = fitHingeAtShift(runs, options, shifts);
  for (int round = 0; round < kOffsetRefits && recentre(fit); ++round) fit = fitHingeAtShift(runs, options, shifts);
  if (options.estimator != HingeEstimator::kLikelihood) return fit;
  HingeFit refined = fit;
  refineByLikelihood(runs, options, shifts, &refined);
  for (int round = 0; round < kOffsetRefits && recentre(refined); ++round) {
    const std::vector<SensorNuisanceEstimate> estimates = refined.recording_nuisance;  // the fractions' starts
    refined = fit;
    refined.recording_nuisance = estimates;
    refineByLikelihood(runs, options, shifts, &refined);
  }
  return refined;
}

}  // namespace

namespace {

/// The filter of a fit without --low-pass HZ: none when asked for, else the
/// first recording whose gyroscopes wobble (wobble_check.hpp) sets it for all.
void chooseFilter(const Recordings& runs, const AxisFitOptions& options, AxisFitOptions* chosen, std::string* reason) {
  if (options.low_pass_hz > 0.0) {
    *reason = "asked for (`low_pass` " + formatNumber(options.low_pass_hz) + ")";
    return;
  }
  if (!options.low_pass_auto) {
    *reason = "no filter: asked for (`low_pass` none)";
    return;
  }
  LowPassChoice wobble = chooseLowPass(*runs.front());
  for (std::size_t r = 1; r < runs.size() && !(wobble.cutoff_hz > 0.0); ++r) {
    wobble = chooseLowPass(*runs[r]);
    if (wobble.cutoff_hz > 0.0) wobble.reason = runs[r]->source + ": " + wobble.reason;
  }
  const bool white = options.estimator == HingeEstimator::kLikelihood || options.fit_time_offset;
  if (wobble.cutoff_hz > 0.0 && white) {
    *reason = "no filter although " + wobble.reason.substr(0, wobble.reason.find("; low-passed")) + ": " +
              (options.fit_time_offset ? "`fit_time_offset`" : "`estimator` likelihood") +
              " models white gyroscope noise, which a filter colours";
  } else {
    chosen->low_pass_hz = wobble.cutoff_hz;
    *reason = wobble.reason;
  }
}

/// The filter, then the estimator, then the fit; the model check is the caller's.
HingeFit fitHingeChosen(const Recordings& runs, const AxisFitOptions& options, AxisFitOptions* chosen) {
  *chosen = options;
  std::string low_pass_reason;
  chooseFilter(runs, options, chosen, &low_pass_reason);
  const HingeEstimatorChoice choice = chooseHingeEstimator(*runs.front(), *chosen);
  chosen->estimator = choice.estimator;
  HingeFit fit = fitHingeWithEstimator(runs, *chosen);
  fit.estimator = choice.estimator;
  fit.estimator_reason = choice.reason;
  fit.low_pass_reason = low_pass_reason;
  return fit;
}

/// Whether two recordings hold the same samples (the same file twice, or a copy).
bool sameSamples(const JointSamples& a, const JointSamples& b) {
  const auto same = [](const BodySamples& x, const BodySamples& y) {
    if (x.orientation.size() != y.orientation.size()) return false;
    for (std::size_t k = 0; k < x.orientation.size(); ++k)
      if (x.orientation[k].quaternion().coeffs() != y.orientation[k].quaternion().coeffs()) return false;
    return x.angular_velocity == y.angular_velocity && x.specific_force == y.specific_force;
  };
  return a.time == b.time && same(a.main, b.main) && same(a.secondary, b.secondary);
}

/// σ of the recordings: the whole fit's and the spread one hinge leaves
/// across the segments (model_check.hpp), when they disagree.
void widenBySpread(HingeFit* fit) {
  fit->sigma_main_deg = fit->model_check.widened(fit->sigma_main_deg, 0);
  fit->sigma_secondary_deg = fit->model_check.widened(fit->sigma_secondary_deg, 1);
}

/// The whole fit of one recording (fitHinge times it).
HingeFit fitHingeWhole(const JointSamples& samples, const AxisFitOptions& options) {
  AxisFitOptions chosen;
  HingeFit fit = fitHingeChosen({&samples}, options, &chosen);
  if (!options.check_segments) return fit;
  if (options.fit_time_offset) {
    fit.model_check.note = "not checked across segments: each segment would profile its own clock offset";
    return fit;
  }
  fit.model_check = checkHingeAcrossSegments(samples, chosen, fit.axis_main, fit.axis_secondary);
  widenBySpread(&fit);
  return fit;
}

/// The whole fit of several recordings (fitHinge times it).
HingeFit fitHingeWhole(const std::vector<JointSamples>& recordings, const AxisFitOptions& options) {
  if (recordings.empty()) throw std::invalid_argument("fitHinge: no recording");
  if (recordings.size() == 1) return fitHingeWhole(recordings.front(), options);
  const JointSamples& first = recordings.front();
  for (const JointSamples& r : recordings) {
    if (r.main.name != first.main.name || r.secondary.name != first.secondary.name)
      throw InvalidInput(r.source, "joins bodies '" + r.main.name + "' and '" + r.secondary.name + "' where " +
                                       first.source + " joins '" + first.main.name + "' and '" +
                                       first.secondary.name + "': the recordings of one fit are of one joint "
                                       "(name the bodies with `main` and `secondary`)");
  }
  // A recording given twice would count its information twice (σ √2 too small).
  for (std::size_t a = 0; a < recordings.size(); ++a)
    for (std::size_t b = a + 1; b < recordings.size(); ++b)
      if (sameSamples(recordings[a], recordings[b]))
        throw InvalidInput(recordings[b].source, "holds the same samples as " + recordings[a].source +
                                                     ": a recording given twice would count its information twice "
                                                     "(sigma too small by the square root of 2)");
  Recordings runs;
  for (const JointSamples& r : recordings) runs.push_back(&r);
  AxisFitOptions chosen;
  HingeFit fit = fitHingeChosen(runs, options, &chosen);
  if (!options.check_segments) return fit;
  fit.model_check = checkHingeAcrossRecordings(recordings, chosen, fit.axis_main, fit.axis_secondary);
  widenBySpread(&fit);
  return fit;
}

}  // namespace

/// summary.seconds: the whole fit's (timedFit).
HingeFit fitHinge(const JointSamples& samples, const AxisFitOptions& options) {
  return timedFit([&] { return fitHingeWhole(samples, options); });
}

HingeFit fitHinge(const std::vector<JointSamples>& recordings, const AxisFitOptions& options) {
  return timedFit([&] { return fitHingeWhole(recordings, options); });
}

}  // namespace calibration
}  // namespace lieflow
