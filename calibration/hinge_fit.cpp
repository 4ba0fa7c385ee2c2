#include "calibration/hinge_fit.hpp"

#include "calibration/hinge_estimator.hpp"
#include "calibration/wobble_check.hpp"

#include <algorithm>
#include <chrono>
#include <map>
#include <climits>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <vector>

#include "calibration/axis_problem.hpp"
#include "calibration/data_selection.hpp"
#include "calibration/hinge_initial.hpp"
#include "calibration/hinge_likelihood.hpp"
#include "calibration/clock_offset.hpp"
#include "calibration/hinge_residuals.hpp"
#include "calibration/hinge_search.hpp"
#include "calibration/hinge_sign.hpp"
#include "calibration/joint_centre.hpp"
#include "calibration/low_pass.hpp"
#include "calibration/rate_derivative.hpp"
#include "calibration/residual_kind.hpp"
#include "calibration/two_axis_solver.hpp"
#include "calibration/unit_axis.hpp"
#include "liegroup/number_text.hpp"
#include "liegroup/invalid_input.hpp"
#include "liegroup/input_number.hpp"

namespace lieflow {
namespace calibration {
namespace {

constexpr const char* kRateHint =
    "from gyroscopes alone each body must turn about directions other than the hinge axis (a body at rest, "
    "or motion only about the hinge axis itself, leaves its axis undetermined)";
/// Minima of the global search that Ceres refines, at most: the best, and
/// those within kRefineChiSquare (Δχ² against the best's noise estimate) that
/// could rival it in the ambiguity check (two_axis_solver.hpp).
constexpr int kMaxRefinedMinima = 4;
constexpr double kRefineChiSquare = 30.0;
constexpr const char* kOrientationHint =
    "the joint must move: the relative orientation of the two bodies has to turn about the hinge";
constexpr const char* kAccelerometerHint =
    "with accelerometers the joint centre's acceleration (gravity included) must turn within each body's "
    "frame, or the bodies must turn about directions other than the hinge axis";
/// Δχ² between the accelerometer constraint's cost at (j₁, −j₂) and at
/// (j₁, j₂) above which the accelerometers fix the relative sign.
constexpr double kSignChiSquare = 25.0;

/// The accelerometer residual kind: the centre's acceleration in both bodies'
/// axes at a point of the axis (joint_centre.hpp), one block per interior sample.
/// The centre is solved from `samples` and returned in `centre`, or, when
/// `starts` is null (the unfiltered twin of a low-passed fit), taken from it.
std::unique_ptr<ResidualKind> accelerometerKind(const JointSamples& samples, std::vector<NamedStart>* starts,
                                                AxisPair* centre, const std::string& label = "") {
  if (starts) solveJointCentre(samples, &centre->axis1, &centre->axis2);
  const CentreForces c = centreSpecificForces(samples, centre->axis1, centre->axis2);
  std::vector<AccelerometerHingeResidual> blocks;
  blocks.reserve(c.main.size());
  for (std::size_t k = 0; k < c.main.size(); ++k) blocks.emplace_back(c.main[k], c.secondary[k]);
  if (starts)
    for (const AxisPair& a : hingeStartsFromCentreForces(c.main, c.secondary))
      starts->push_back({a, "closed form (accelerometers)"});
  return std::make_unique<SampleResidualKind<AccelerometerHingeResidual, 1>>(
      "accelerometer hinge constraint j1.a1 = j2.a2 at the joint centre" + label, "m/s^2", 1, std::move(blocks));
}

/// Δχ² (4 parameters) by which fitting gyroscope biases must lower the
/// gyroscope residual for the plain fit to be called biased: χ²₄ exceeds it
/// with probability 5e-6 on unbiased data.
constexpr double kBiasChiSquare = 30.0;
/// The profile over whole-sample clock offsets: shifts either side of the
/// search's, and recentrings of that window, at most.
constexpr int kOffsetProfile = 4;
constexpr int kOffsetRefits = 3;
const std::string kGyroKindName = "gyroscope hinge constraint |w1 x j1| = |w2 x j2| (Sampson)";
/// Largest relative spread of the sampling interval for --fit-time-offset
/// (the clock offset interpolates the secondary's rates on a uniform grid).
constexpr double kUniformSampling = 1e-3;
/// Fewest samples --fit-time-offset takes: a mean sampling interval needs
/// two, and a shift by one sample leaves a pair to compare only from three.
constexpr std::size_t kMinOffsetSamples = 3;

/// The nuisance coordinates `options` asks for; InvalidInput where the data
/// cannot carry them (no gyroscopes; a clock offset on non-uniform times).
NuisanceSelection nuisanceOf(const JointSamples& samples, const DataSelection& data, const AxisFitOptions& options) {
  NuisanceSelection n;
  if (!options.fit_gyro_bias && !options.fit_time_offset) return n;
  if (!data.rates)
    throw InvalidInput(samples.source, std::string(options.fit_gyro_bias ? "--fit-gyro-bias" : "--fit-time-offset") +
                                           " needs the gyroscopes in the fit (--use gyroscopes, both, "
                                           "gyroscopes+accelerometers or all)");
  if (options.fit_gyro_bias) n.active[0] = n.active[1] = n.active[2] = n.active[3] = true;
  if (options.fit_time_offset) {
    const std::vector<double>& t = samples.time;
    if (t.size() < kMinOffsetSamples)
      throw InvalidInput(samples.source, "--fit-time-offset needs at least " + std::to_string(kMinOffsetSamples) +
                                             " samples (to shift one clock against the other); the recording has " +
                                             std::to_string(t.size()));
    const double h = (t.back() - t.front()) / (t.size() - 1);
    for (std::size_t k = 0; k + 1 < t.size(); ++k)
      if (std::abs(t[k + 1] - t[k] - h) > kUniformSampling * h)
        throw InvalidInput(samples.source, "--fit-time-offset needs uniformly sampled times: t[" + std::to_string(k + 1) +
                                               "] - t[" + std::to_string(k) + "] differs from the mean interval " +
                                               "by more than " + formatNumber(kUniformSampling) + " of it");
    n.active[4] = true;
  }
  return n;
}

/// The gyroscopes' residual kind with the nuisance block; `shift` whole
/// samples of clock offset (0 without one).
std::unique_ptr<ResidualKind> gyroNuisanceKind(const JointSamples& samples, const Eigen::Vector3d& j1,
                                               const Eigen::Vector3d& j2, int shift, bool offset) {
  const std::vector<Eigen::Vector3d>& w1 = samples.main.angular_velocity;
  const std::vector<Eigen::Vector3d>& w2 = samples.secondary.angular_velocity;
  const int n = samples.size();
  const Eigen::Matrix<double, 3, 2> B1 = perpendicularBasis(j1), B2 = perpendicularBasis(j2);
  std::vector<GyroHingeNuisanceResidual> blocks;
  blocks.reserve(n);
  // With a clock offset, the secondary's samples need their slope (±kRateWindow).
  const int edge = offset ? kRateWindow : 0;
  for (int k = 0; k < n; ++k) {
    const int k2 = k - shift;
    if (k2 < edge || k2 >= n - edge) continue;
    GyroHingeNuisanceResidual r;
    r.w1 = w1[k];
    r.w2 = w2[k2];
    r.dw2 = offset ? rateDerivative(samples.time, w2, k2) : Eigen::Vector3d::Zero();
    r.B1 = B1;
    r.B2 = B2;
    r.floor_sq = GyroHingeResidual(w1[k], w2[k2]).floor_sq;
    blocks.push_back(r);
  }
  return std::make_unique<SampleResidualKind<GyroHingeNuisanceResidual, 1, true>>(
      kGyroKindName + " with gyroscope biases/clock offset", "rad/s", 1, std::move(blocks));
}

/// The orientations' kind: R₁ j₁ = R₂ j₂ per sample.
std::unique_ptr<ResidualKind> orientationKind(const std::vector<Eigen::Matrix3d>& R12, const std::string& label = "") {
  std::vector<OrientationHingeResidual> blocks;
  blocks.reserve(R12.size());
  for (const Eigen::Matrix3d& R : R12) blocks.emplace_back(R);
  return std::make_unique<SampleResidualKind<OrientationHingeResidual, 3>>(
      "orientation hinge constraint R1 j1 = R2 j2" + label, "rad", 2, std::move(blocks));
}

/// The gyroscopes' plain kind, the secondary's rates `shift` samples back.
std::unique_ptr<ResidualKind> gyroKind(const JointSamples& samples, int shift, const std::string& label = "") {
  std::vector<GyroHingeResidual> blocks;
  for (int k = std::max(0, shift); k < samples.size() && k - shift < samples.size(); ++k)
    blocks.emplace_back(samples.main.angular_velocity[k], samples.secondary.angular_velocity[k - shift]);
  return std::make_unique<SampleResidualKind<GyroHingeResidual, 1>>(kGyroKindName + label, "rad/s", 1,
                                                                    std::move(blocks));
}

/// The recordings one fit reads: one, or several of the same joint (each
/// its own series in time: no stencil or filter reaches across two).
using Recordings = std::vector<const JointSamples*>;

/// How a residual kind of recording `r` is named: as it is for one
/// recording, with the recording's file after it for several.
std::string recordingLabel(const Recordings& runs, std::size_t r) {
  return runs.size() > 1 ? " [" + runs[r]->source + "]" : std::string();
}

int totalSamples(const Recordings& runs) {
  int n = 0;
  for (const JointSamples* r : runs) n += r->size();
  return n;
}

/// A low-passed fit's unfiltered recordings (empty without a filter) and
/// the filter's noise power gain.
struct Unfiltered {
  Recordings samples;
  double power_gain = 1.0;
};

/// How well the hinge explains the data, per kind, as a fraction of the
/// signal it compares: RMS(‖ω₁×j₁‖ − ‖ω₂×j₂‖) over the RMS mean of the two
/// (gyroscopes), RMS(j₁·f_c,1 − j₂·f_c,2) over the RMS of ‖f_c‖ (accelerometers).
void modelMisfit(const Recordings& runs, int shift, const Eigen::Vector3d& j1, const Eigen::Vector3d& j2,
                 const std::vector<AxisPair>* centres, HingeFit* fit) {
  double gd2 = 0.0, gm2 = 0.0, ad2 = 0.0, am2 = 0.0;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    const JointSamples& samples = *runs[r];
    if (samples.hasAngularVelocities())
      for (int k = std::max(0, shift); k < samples.size() && k - shift < samples.size(); ++k) {
        const double a = samples.main.angular_velocity[k].cross(j1).norm();
        const double b = samples.secondary.angular_velocity[k - shift].cross(j2).norm();
        gd2 += (a - b) * (a - b);
        gm2 += 0.25 * (a + b) * (a + b);
      }
    if (centres) {
      const CentreForces c = centreSpecificForces(samples, (*centres)[r].axis1, (*centres)[r].axis2);
      for (std::size_t k = 0; k < c.main.size(); ++k) {
        const double d = j1.dot(c.main[k]) - j2.dot(c.secondary[k]);
        ad2 += d * d;
        am2 += 0.5 * (c.main[k].squaredNorm() + c.secondary[k].squaredNorm());
      }
    }
  }
  if (gm2 > 0.0) fit->gyro_misfit = std::sqrt(gd2 / gm2);
  if (am2 > 0.0) fit->accelerometer_misfit = std::sqrt(ad2 / am2);
}

/// The fit with the clock offset's whole samples given (0 without one).
/// The recorded data the hinge fit uses: the likelihood estimator's
/// gyroscopes alone, the clock offset's gyroscopes (the offset pairs their
/// samples), or what --use asks for; InvalidInput when the recording lacks it.
DataSelection hingeData(const JointSamples& samples, const AxisFitOptions& options) {
  if (options.estimator == HingeEstimator::kLikelihood) {
    if (options.use != DataUse::kAuto && options.use != DataUse::kAngularVelocities)
      throw InvalidInput(samples.source, std::string("--estimator likelihood with --use ") + dataUseName(options.use) +
                                             ": the likelihood fit models the two gyroscopes alone (use --use "
                                             "gyroscopes or auto)");
    if (!samples.hasAngularVelocities())
      throw InvalidInput(samples.source, "--estimator likelihood needs both bodies' gyroscopes");
  }
  DataSelection data = selectData(samples, options.estimator == HingeEstimator::kLikelihood
                                               ? DataUse::kAngularVelocities : options.use,
                                  "hinge", true);
  if (options.fit_time_offset && (data.orientations || data.accelerometers)) {
    // The clock offset pairs the gyroscopes' samples; the other kinds pair at the recorded times.
    if (options.use != DataUse::kAuto)
      throw InvalidInput(samples.source, std::string("--fit-time-offset with --use ") + dataUseName(options.use) +
                                             ": the offset is estimated from the gyroscopes alone (use --use "
                                             "gyroscopes or auto)");
    data.orientations = data.accelerometers = false;
    if (!data.rates) throw InvalidInput(samples.source, "--fit-time-offset needs both bodies' gyroscopes");
  }
  return data;
}

/// hingeData of every recording: they must give the same selection (the
/// fit's kinds are the same for each), else InvalidInput naming the one
/// that differs.
DataSelection hingeData(const Recordings& runs, const AxisFitOptions& options) {
  const DataSelection data = hingeData(*runs.front(), options);
  for (std::size_t r = 1; r < runs.size(); ++r) {
    const DataSelection other = hingeData(*runs[r], options);
    if (other.name() != data.name())
      throw InvalidInput(runs[r]->source, "gives the fit " + other.name() + " where " + runs.front()->source +
                                              " gives " + data.name() + ": a fit over several recordings uses the "
                                              "same columns of each (choose them with --use)");
  }
  return data;
}

/// The starts of a fit to the gyroscopes alone: the closed form and a grid
/// of starts, descended cheaply (hinge_search.hpp), of which Ceres refines
/// the best minimum and those that could rival it (with the accelerometers,
/// each also with the second axis turned: their cost is odd in it).
void rateStarts(const JointSamples& samples, const std::vector<Eigen::Vector3d>& w1,
                const std::vector<Eigen::Vector3d>& w2, bool accelerometers, std::vector<NamedStart>* out,
                int* search_starts) {
  std::vector<NamedStart>& starts = *out;
  // The closed form and a grid of starts, descended cheaply (hinge_search.hpp);
  // Ceres refines the best minimum and those that could rival it.
  const std::vector<AxisPair> closed_form = hingeStartsFromRates(w1, w2);
  const std::vector<HingeMinimum> minima = hingeMinimaFromRates(w1, w2, closed_form);
  *search_starts = static_cast<int>(closed_form.size()) + kGridStarts;
  const auto origin = [&](int start) {
    if (start < 0 || start >= static_cast<int>(closed_form.size()))
      return "grid start " + std::to_string(start - static_cast<int>(closed_form.size()) + 1) + " of " +
             std::to_string(kGridStarts);
    return start == 0 ? std::string("closed form (gyroscopes)")
                      : "closed form (gyroscopes), near-null alternative " + std::to_string(start);
  };
  const double s2 = minima.empty() ? 0.0 : minima.front().cost / std::max(1, samples.size() - 4);
  for (std::size_t i = 0; i < minima.size() && static_cast<int>(i) < kMaxRefinedMinima; ++i) {
    const bool rival = s2 > 0.0 && (minima[i].cost - minima.front().cost) / s2 <= kRefineChiSquare;
    if (i != 0 && !rival) continue;
    starts.push_back({minima[i].axes, origin(minima[i].start)});
    // The gyroscopes' cost is even in each axis; the accelerometers' is not.
    if (accelerometers)
      starts.push_back({{minima[i].axes.axis1, -minima[i].axes.axis2}, origin(minima[i].start) + ", turned"});
  }
  if (starts.empty()) starts.push_back({closed_form.front(), origin(0)});
}

/// The relative sign of the secondary axis (R1 j1 = R2 j2), from the
/// orientations, else the accelerometers when they decide it, else the phase
/// of the perpendicular angular velocities (each recording's phase spread,
/// weighted by its samples); flips *j2 and says how in *how.
void relativeAxisSign(const Recordings& runs, const DataSelection& data,
                      const std::vector<std::vector<Eigen::Matrix3d>>& R12,
                      const std::vector<const ResidualKind*>& accelerometers, const TwoAxisSolution& solution,
                      const Eigen::Vector3d& j1, Eigen::Vector3d* j2_out, std::string* how) {
  Eigen::Vector3d& j2 = *j2_out;
  // The accelerometers' constraint is odd in j₂: its cost at (j₁, −j₂) says
  // whether it fixes the relative sign.
  double sign_delta = 0.0;
  const std::vector<ResidualStats>& stats = solution.summary.residuals;
  for (std::size_t r = 0; r < accelerometers.size(); ++r) {
    // The accelerometer kinds are the last ones, one per recording.
    const double w = 1.0 / stats[stats.size() - accelerometers.size() + r].noise_scale;
    const Eigen::Vector3d turned = -j2;
    sign_delta += 2.0 * (accelerometers[r]->cost(j1.data(), turned.data(), nullptr, &w, nullptr) -
                         accelerometers[r]->cost(j1.data(), j2.data(), nullptr, &w, nullptr));
  }
  if (data.orientations) {
    double agreement = 0.0;
    for (const std::vector<Eigen::Matrix3d>& run : R12)
      for (const Eigen::Matrix3d& R : run) agreement += j1.dot(R * j2);
    if (agreement < 0.0) j2 = -j2;
    *how = "R1 j1 = R2 j2 from the orientations";
  } else if (std::abs(sign_delta) > kSignChiSquare) {
    if (sign_delta < 0.0) j2 = -j2;
    *how = "R1 j1 = R2 j2 from the accelerometers (the centre's acceleration along the axis)";
  } else {
    HingeSignEvidence evidence;
    if (runs.size() == 1) {
      const JointSamples& samples = *runs.front();
      evidence = hingeRelativeSign(samples.time, samples.main.angular_velocity, samples.secondary.angular_velocity,
                                   j1, j2);
    } else {
      double same = 0.0, flipped = 0.0;
      for (const JointSamples* samples : runs) {
        const HingeSignEvidence e = hingeRelativeSign(samples->time, samples->main.angular_velocity,
                                                      samples->secondary.angular_velocity, j1, j2);
        same += e.spread_same * samples->size();
        flipped += e.spread_flipped * samples->size();
      }
      evidence = hingeSignFromSpreads(same / totalSamples(runs), flipped / totalSamples(runs));
    }
    j2 *= evidence.relative_sign;
    *how = evidence.decided ? "R1 j1 = R2 j2 from the phase of the perpendicular angular velocities"
                                : "relative sign of axis_secondary not determined by these gyroscope data "
                                  "(the perpendicular angular velocity does not turn about the axis); "
                                  "reported by convention";
  }
}

/// The fitted gyroscope biases (b = B ν in each body's axes, B the plane
/// perpendicular to the first start's axis: the component along the axis is
/// not observable) and clock offset (the whole-sample shift plus the fitted
/// fraction), with their σ.
void setNuisance(const JointSamples& samples, const NuisanceSelection& nuisance, const NamedStart& first, int shift,
                 const TwoAxisSolution& solution, HingeFit* out) {
  HingeFit& fit = *out;
  if (nuisance.active[0]) {
    const Eigen::Matrix<double, 3, 2> B1 = perpendicularBasis(first.axes.axis1);
    const Eigen::Matrix<double, 3, 2> B2 = perpendicularBasis(first.axes.axis2);
    fit.gyro_bias_main = B1 * solution.nuisance.segment<2>(0);
    fit.gyro_bias_secondary = B2 * solution.nuisance.segment<2>(2);
    fit.gyro_bias_main_sigma = std::sqrt(solution.nuisance_covariance.block<2, 2>(0, 0).trace());
    fit.gyro_bias_secondary_sigma = std::sqrt(solution.nuisance_covariance.block<2, 2>(2, 2).trace());
    fit.fitted_gyro_bias = true;
  }
  if (nuisance.active[4]) {
    const double h = (samples.time.back() - samples.time.front()) / (samples.size() - 1);
    fit.time_offset = shift * h + solution.nuisance[4];
    fit.time_offset_sigma = std::sqrt(solution.nuisance_covariance(4, 4));
    fit.fitted_time_offset = true;
  }
}

/// The fit of `runs` with the clock offset's whole samples given (0 without
/// one; a clock offset and biases only on one recording). Several
/// recordings add their residual kinds side by side, each with its own
/// noise (its own third differences, its own weight): one axis pair.
HingeFit fitHingeAtShift(const Recordings& runs, const AxisFitOptions& options, int shift,
                         const Unfiltered& unfiltered = Unfiltered()) {
  const auto start_time = std::chrono::steady_clock::now();
  const JointSamples& samples = *runs.front();
  DataSelection data = hingeData(runs, options);
  requireEnoughSamples(totalSamples(runs), options);
  const NuisanceSelection nuisance = nuisanceOf(samples, data, options);
  const bool filtered = !unfiltered.samples.empty();

  std::vector<std::vector<Eigen::Matrix3d>> R12(runs.size());
  std::vector<Eigen::Matrix3d> all_R12;
  if (data.orientations)
    for (std::size_t r = 0; r < runs.size(); ++r) {
      R12[r] = relativeOrientations(*runs[r]);
      all_R12.insert(all_R12.end(), R12[r].begin(), R12[r].end());
    }
  std::vector<std::unique_ptr<ResidualKind>> kinds;
  std::vector<NamedStart> starts;
  int search_starts = 0;
  IdentifiabilityContext context;
  context.axis1 = "the axis in the main body '" + samples.main.name + "'";
  context.axis2 = "the axis in the secondary body '" + samples.secondary.name + "'";
  if (data.orientations) {
    for (std::size_t r = 0; r < runs.size(); ++r) kinds.push_back(orientationKind(R12[r], recordingLabel(runs, r)));
    starts.push_back({hingeAxesFromOrientations(all_R12), "closed form (orientations)"});
    context.hint = kOrientationHint;
  }
  if (data.rates) {
    // The rates paired as the whole-sample clock offset says (as recorded without one).
    std::vector<Eigen::Vector3d> w1, w2;
    for (const JointSamples* run : runs)
      for (int k = std::max(0, shift); k < run->size() && k - shift < run->size(); ++k) {
        w1.push_back(run->main.angular_velocity[k]);
        w2.push_back(run->secondary.angular_velocity[k - shift]);
      }
    if (!data.orientations) {
      rateStarts(samples, w1, w2, data.accelerometers, &starts, &search_starts);
      context.hint = kRateHint;
    }
    // The gyroscopes' kinds, with the nuisance block when biases or a clock
    // offset are estimated (its bias planes from the first start's axes).
    const AxisPair& at = starts.front().axes;
    for (std::size_t r = 0; r < runs.size(); ++r) {
      const JointSamples& run = *runs[r];
      kinds.push_back(nuisance.count() > 0 ? gyroNuisanceKind(run, at.axis1, at.axis2, shift, options.fit_time_offset)
                                           : gyroKind(run, shift, recordingLabel(runs, r)));
      // (After a low-pass filter third differences no longer measure the noise.)
      if (filtered) continue;
      std::vector<Eigen::Vector3d> v1, v2;
      for (int k = std::max(0, shift); k < run.size() && k - shift < run.size(); ++k) {
        v1.push_back(run.main.angular_velocity[k]);
        v2.push_back(run.secondary.angular_velocity[k - shift]);
      }
      kinds.back()->setIndependentNoise(
          std::sqrt(0.5 * (std::pow(whiteNoiseFromDifferences(v1), 2) + std::pow(whiteNoiseFromDifferences(v2), 2))),
          "the third differences of the recorded angular velocities");
    }
  }
  std::vector<const ResidualKind*> accelerometers;
  std::vector<AxisPair> centres(runs.size());
  if (data.accelerometers) {
    for (std::size_t r = 0; r < runs.size(); ++r) {
      kinds.push_back(accelerometerKind(*runs[r], &starts, &centres[r], recordingLabel(runs, r)));
      accelerometers.push_back(kinds.back().get());
    }
    context.hint = kAccelerometerHint;
  }
  for (std::size_t i = 0; i < options.extra_starts.size(); ++i)
    starts.push_back({options.extra_starts[i], "given start " + std::to_string(i + 1)});

  std::vector<const ResidualKind*> kind_list;
  for (const auto& k : kinds) kind_list.push_back(k.get());
  // A low-passed fit: the same kinds on the unfiltered signals (LowPassNoise).
  std::vector<std::unique_ptr<ResidualKind>> raw_kinds;
  LowPassNoise low_pass;
  if (filtered) {
    const Recordings& raw = unfiltered.samples;
    if (data.orientations)
      for (std::size_t r = 0; r < raw.size(); ++r) raw_kinds.push_back(orientationKind(R12[r]));
    if (data.rates) {
      const AxisPair& at = starts.front().axes;
      for (const JointSamples* run : raw)
        raw_kinds.push_back(nuisance.count() > 0 ? gyroNuisanceKind(*run, at.axis1, at.axis2, shift, false)
                                                 : gyroKind(*run, shift));
    }
    if (data.accelerometers)
      for (std::size_t r = 0; r < raw.size(); ++r) raw_kinds.push_back(accelerometerKind(*raw[r], nullptr, &centres[r]));
    low_pass.power_gain = unfiltered.power_gain;
    for (const auto& k : raw_kinds) low_pass.raw_kinds.push_back(k.get());
  }
  const TwoAxisSolution solution =
      solveTwoAxes(kind_list, starts, options, context, nuisance, filtered ? &low_pass : nullptr);

  HingeFit fit;
  Eigen::Vector3d j1 = solution.axes.axis1, j2 = solution.axes.axis2;
  relativeAxisSign(runs, data, R12, accelerometers, solution, j1, &j2, &fit.sign);
  const double overall = canonicalSign(j1);
  fit.sign += "; overall sign: largest component of axis_main positive";
  fit.axis_main = overall * j1;
  fit.axis_secondary = overall * j2;
  fit.sigma_main_deg = solution.sigma1_rad * kRadToDeg;
  fit.sigma_secondary_deg = solution.sigma2_rad * kRadToDeg;
  fit.covariance = solution.covariance;
  setNuisance(samples, nuisance, starts.front(), shift, solution, &fit);
  modelMisfit(runs, data.rates ? shift : 0, j1, j2, data.accelerometers ? &centres : nullptr, &fit);
  if (!data.rates) fit.gyro_misfit = -1.0;
  fit.information = solution.information;
  fit.summary = solution.summary;
  fit.summary.search_starts = search_starts;
  fit.summary.data = data.name();
  fit.summary.samples = totalSamples(runs);
  fit.summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count();
  return fit;
}

/// With --estimator likelihood: the constraint fit at `shift` refined by
/// maximum likelihood over the joint angle (hinge_likelihood.hpp), with the
/// biases and the clock offset where the constraint fit estimated them
/// (started from its values).
void refineByLikelihood(const Recordings& runs, const AxisFitOptions& options, int shift, HingeFit* fit_out) {
  const auto start_time = std::chrono::steady_clock::now();
  const JointSamples& samples = *runs.front();
  HingeFit& fit = *fit_out;
  HingeLikelihoodOptions ml_options;
  ml_options.progress = options.progress;
  ml_options.interrupt = options.interrupt;
  ml_options.fit_gyro_bias = fit.fitted_gyro_bias;
  ml_options.gyro_bias_main_start = fit.gyro_bias_main;
  ml_options.gyro_bias_secondary_start = fit.gyro_bias_secondary;
  ml_options.fit_time_offset = fit.fitted_time_offset;
  ml_options.offset_shift = shift;
  if (fit.fitted_time_offset) {
    const double h = (samples.time.back() - samples.time.front()) / (samples.size() - 1);
    ml_options.offset_fraction_start = fit.time_offset - shift * h;
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
  fit.likelihood = ml;
  fit.sign = "R1 j1 = R2 j2 from the joint angle that turns the perpendicular rates (likelihood); overall sign: "
             "largest component of axis_main positive";
  if (!ml.converged) {
    fit.summary.converged = false;
    fit.summary.message = "the likelihood refinement did not converge: " + ml.message;
  }
  fit.summary.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count();
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
          ? "the gyroscopes carry a constant bias: fitting one (--fit-gyro-bias) " + found + "; rerun with --fit-gyro-bias"
          : "the gyroscopes of " + samples.source + " carry a constant bias: fitting one " + found +
                "; a fit over several recordings does not estimate biases: fit that recording alone with "
                "--fit-gyro-bias";
}

namespace {

/// fitHinge with options.estimator chosen (not kAuto).
HingeFit fitHingeWithEstimator(const Recordings& runs, const AxisFitOptions& options) {
  const JointSamples& samples = *runs.front();
  const bool likelihood = options.estimator == HingeEstimator::kLikelihood;
  if (options.low_pass_hz > 0.0) {
    // The likelihood fit and the clock offset model white gyroscope noise
    // sample by sample; the filtered residuals are neither white nor of that size.
    if (likelihood || options.fit_time_offset)
      throw InvalidInput(samples.source, std::string("--low-pass with ") +
                                             (likelihood ? "--estimator likelihood" : "--fit-time-offset") +
                                             ": it models the gyroscopes' white noise sample by sample, which a "
                                             "filter colours; fit without --low-pass");
    // Each recording filtered alone (a filter's memory does not cross from one to the next).
    LowPassFilter filter;
    std::vector<JointSamples> filtered(runs.size()), trimmed(runs.size());
    Recordings filtered_runs;
    Unfiltered raw;
    for (std::size_t r = 0; r < runs.size(); ++r) {
      filtered[r] = lowPassed(*runs[r], options.low_pass_hz, "--low-pass", &filter, &trimmed[r]);
      filtered_runs.push_back(&filtered[r]);
      raw.samples.push_back(&trimmed[r]);
    }
    raw.power_gain = filter.noisePowerGain();
    HingeFit fit = fitHingeAtShift(filtered_runs, options, 0, raw);
    fit.low_pass_hz = options.low_pass_hz;
    fit.low_pass_noise_gain = raw.power_gain;
    return fit;
  }
  if (!options.fit_time_offset) {
    HingeFit fit = fitHingeAtShift(runs, options, 0);
    for (std::size_t r = 0; r < runs.size(); ++r) checkForGyroscopeBias(*runs[r], options, &fit, recordingLabel(runs, r));
    if (likelihood) refineByLikelihood(runs, options, 0, &fit);
    return fit;
  }
  // (A clock offset is fitted on one recording: fitHinge refuses it on several.)
  // The profile over whole samples: the fit at every shift within
  // ±kOffsetProfile of the search's (wholeSampleOffset), recentred while the
  // best lies on the window's edge; the least residual wins, and every fit
  // that ends at an offset more than 1.5 samples away must fit worse by
  // Δχ² ≥ kOffsetAmbiguity
  // (on 3 s recordings with biases the search alone, or the fit from its
  // shift, stayed two samples off with σ a tenth of that).
  const double h = (samples.time.back() - samples.time.front()) / (samples.size() - 1);
  const int reach = clampedInt(std::floor(options.max_time_offset / h), 0, samples.size() / 2);
  std::map<int, HingeFit> fits;
  const auto meanSquare = [](const HingeFit& f) { return std::pow(f.summary.residuals.front().rms, 2); };
  int best = wholeSampleOffset(samples, options.max_time_offset);
  for (int round = 0; round < kOffsetRefits; ++round) {
    for (int m = std::max(-reach, best - kOffsetProfile); m <= std::min(reach, best + kOffsetProfile); ++m) {
      if (fits.count(m)) continue;
      try {
        fits.emplace(m, fitHingeAtShift(runs, options, m));
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
  if (fits.empty()) return fitHingeAtShift(runs, options, best);  // throws why
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
  refineByLikelihood(runs, options, shift, &refined);
  for (int round = 0; round < kOffsetRefits; ++round) {
    const int step = clampedInt(std::round((refined.time_offset - shift * h) / h), -samples.size(), samples.size());
    if (step == 0 || std::abs(shift + step) > reach) break;
    shift += step;
    const double estimate = refined.time_offset;  // the fraction starts from the likelihood's estimate
    refined = fit;
    refined.time_offset = estimate;
    refineByLikelihood(runs, options, shift, &refined);
  }
  return refined;
}

}  // namespace

namespace {

/// The filter of a fit without --low-pass HZ: none when asked for, else the
/// first recording whose gyroscopes wobble (wobble_check.hpp) sets it for all.
void chooseFilter(const Recordings& runs, const AxisFitOptions& options, AxisFitOptions* chosen, std::string* reason) {
  if (options.low_pass_hz > 0.0) {
    *reason = "asked for (--low-pass " + formatNumber(options.low_pass_hz) + ")";
    return;
  }
  if (!options.low_pass_auto) {
    *reason = "no filter: asked for (--low-pass none)";
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
              (options.fit_time_offset ? "--fit-time-offset" : "--estimator likelihood") +
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

/// σ of the recordings: the whole fit's and the spread one hinge leaves
/// across the segments (model_check.hpp), when they disagree.
void widenBySpread(HingeFit* fit) {
  fit->sigma_main_deg = fit->model_check.widened(fit->sigma_main_deg, 0);
  fit->sigma_secondary_deg = fit->model_check.widened(fit->sigma_secondary_deg, 1);
}

}  // namespace

HingeFit fitHinge(const JointSamples& samples, const AxisFitOptions& options) {
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

HingeFit fitHinge(const std::vector<JointSamples>& recordings, const AxisFitOptions& options) {
  if (recordings.empty()) throw std::invalid_argument("fitHinge: no recording");
  if (recordings.size() == 1) return fitHinge(recordings.front(), options);
  const JointSamples& first = recordings.front();
  for (const JointSamples& r : recordings) {
    if (r.main.name != first.main.name || r.secondary.name != first.secondary.name)
      throw InvalidInput(r.source, "joins bodies '" + r.main.name + "' and '" + r.secondary.name + "' where " +
                                       first.source + " joins '" + first.main.name + "' and '" +
                                       first.secondary.name + "': the recordings of one fit are of one joint "
                                       "(name the bodies with --main and --secondary)");
    if (options.fit_gyro_bias || options.fit_time_offset)
      throw InvalidInput(r.source, std::string(options.fit_gyro_bias ? "--fit-gyro-bias" : "--fit-time-offset") +
                                       " with several recordings: each recording's " +
                                       (options.fit_gyro_bias ? "biases" : "clock offset") +
                                       " would be its own, and the fit over several recordings does not estimate "
                                       "them; fit each recording alone with it");
  }
  Recordings runs;
  for (const JointSamples& r : recordings) runs.push_back(&r);
  AxisFitOptions chosen;
  HingeFit fit = fitHingeChosen(runs, options, &chosen);
  if (!options.check_segments) return fit;
  fit.model_check = checkHingeAcrossRecordings(recordings, chosen, fit.axis_main, fit.axis_secondary);
  widenBySpread(&fit);
  return fit;
}

}  // namespace calibration
}  // namespace lieflow
