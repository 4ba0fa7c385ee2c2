#include "calibration/hinge_constraint_fit.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "calibration/axis_problem.hpp"
#include "calibration/data_selection.hpp"
#include "calibration/hinge_initial.hpp"
#include "calibration/hinge_residuals.hpp"
#include "calibration/hinge_search.hpp"
#include "calibration/hinge_sign.hpp"
#include "calibration/joint_centre.hpp"
#include "calibration/rate_derivative.hpp"
#include "calibration/two_axis_solver.hpp"
#include "calibration/unit_axis.hpp"
#include "liegroup/invalid_input.hpp"
#include "liegroup/number_text.hpp"

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
    throw InvalidInput(samples.source, std::string(options.fit_gyro_bias ? "`fit_gyro_bias`" : "`fit_time_offset`") +
                                           " needs the gyroscopes in the fit (`use` gyroscopes, both, "
                                           "gyroscopes+accelerometers or all)");
  if (options.fit_gyro_bias) n.active[0] = n.active[1] = n.active[2] = n.active[3] = true;
  if (options.fit_time_offset) {
    const std::vector<double>& t = samples.time;
    if (t.size() < kMinOffsetSamples)
      throw InvalidInput(samples.source, "`fit_time_offset` needs at least " + std::to_string(kMinOffsetSamples) +
                                             " samples (to shift one clock against the other); the recording has " +
                                             std::to_string(t.size()));
    const double h = (t.back() - t.front()) / (t.size() - 1);
    for (std::size_t k = 0; k + 1 < t.size(); ++k)
      if (std::abs(t[k + 1] - t[k] - h) > kUniformSampling * h)
        throw InvalidInput(samples.source, "`fit_time_offset` needs uniformly sampled times: t[" + std::to_string(k + 1) +
                                               "] - t[" + std::to_string(k) + "] differs from the mean interval " +
                                               "by more than " + formatNumber(kUniformSampling) + " of it");
    n.active[4] = true;
  }
  return n;
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

/// How well the hinge explains the data, per kind, as a fraction of the
/// signal it compares: RMS(‖ω₁×j₁‖ − ‖ω₂×j₂‖) over the RMS mean of the two
/// (gyroscopes), RMS(j₁·f_c,1 − j₂·f_c,2) over the RMS of ‖f_c‖ (accelerometers).
void modelMisfit(const Recordings& runs, const Shifts& shifts, const Eigen::Vector3d& j1, const Eigen::Vector3d& j2,
                 const std::vector<AxisPair>* centres, HingeFit* fit) {
  double gd2 = 0.0, gm2 = 0.0, ad2 = 0.0, am2 = 0.0;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    const JointSamples& samples = *runs[r];
    const int shift = shifts[r];
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
      throw InvalidInput(samples.source, std::string("`estimator` likelihood with `use` ") + dataUseName(options.use) +
                                             ": the likelihood fit models the two gyroscopes alone (use `use` "
                                             "gyroscopes or auto)");
    if (!samples.hasAngularVelocities())
      throw InvalidInput(samples.source, "`estimator` likelihood needs both bodies' gyroscopes");
  }
  DataSelection data = selectData(samples, options.estimator == HingeEstimator::kLikelihood
                                               ? DataUse::kAngularVelocities : options.use,
                                  "hinge", true);
  if (options.fit_time_offset && (data.orientations || data.accelerometers)) {
    // The clock offset pairs the gyroscopes' samples; the other kinds pair at the recorded times.
    if (options.use != DataUse::kAuto)
      throw InvalidInput(samples.source, std::string("`fit_time_offset` with `use` ") + dataUseName(options.use) +
                                             ": the offset is estimated from the gyroscopes alone (use `use` "
                                             "gyroscopes or auto)");
    data.orientations = data.accelerometers = false;
    if (!data.rates) throw InvalidInput(samples.source, "`fit_time_offset` needs both bodies' gyroscopes");
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
                                              "same columns of each (choose them with `use`)");
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
/// not observable) of nuisance block `block`, with their σ.
SensorNuisanceEstimate biasesOf(const NamedStart& first, const TwoAxisSolution& solution, int block) {
  const Eigen::Matrix<double, 3, 2> B1 = perpendicularBasis(first.axes.axis1);
  const Eigen::Matrix<double, 3, 2> B2 = perpendicularBasis(first.axes.axis2);
  const int at = kNuisanceSize * block;
  SensorNuisanceEstimate e;
  e.fitted_gyro_bias = true;
  e.gyro_bias_main = B1 * solution.nuisance.segment<2>(at);
  e.gyro_bias_secondary = B2 * solution.nuisance.segment<2>(at + 2);
  e.gyro_bias_main_sigma = std::sqrt(solution.nuisance_covariance.block<2, 2>(at, at).trace());
  e.gyro_bias_secondary_sigma = std::sqrt(solution.nuisance_covariance.block<2, 2>(at + 2, at + 2).trace());
  return e;
}

/// The fitted biases and clock offsets (the whole-sample shift plus the
/// fitted fraction), with their σ: the first recording's, and with several
/// each one's in recording_nuisance (its own block).
void setNuisance(const Recordings& runs, const NuisanceSelection& nuisance, const NamedStart& first,
                 const Shifts& shifts, const TwoAxisSolution& solution, HingeFit* out) {
  HingeFit& fit = *out;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    SensorNuisanceEstimate e;
    if (nuisance.active[0]) e = biasesOf(first, solution, static_cast<int>(r));
    if (nuisance.active[4]) {
      const double h = runs[r]->meanStep();
      const int at = kNuisanceSize * static_cast<int>(r) + 4;
      e.fitted_time_offset = true;
      e.time_offset = shifts[r] * h + solution.nuisance[at];
      e.time_offset_sigma = std::sqrt(solution.nuisance_covariance(at, at));
    }
    if (r == 0) static_cast<SensorNuisanceEstimate&>(fit) = e;
    if (runs.size() > 1 && nuisance.count() > 0) fit.recording_nuisance.push_back(e);
  }
}

}  // namespace

const std::string kGyroKindName = "gyroscope hinge constraint |w1 x j1| = |w2 x j2| (Sampson)";

std::string recordingLabel(const Recordings& runs, std::size_t r) {
  return runs.size() > 1 ? " [" + runs[r]->source + "]" : std::string();
}

int totalSamples(const Recordings& runs) {
  int n = 0;
  for (const JointSamples* r : runs) n += r->size();
  return n;
}

/// The gyroscopes' residual kind with the nuisance block; `shift` whole
/// samples of clock offset (0 without one).
std::unique_ptr<ResidualKind> gyroNuisanceKind(const JointSamples& samples, const Eigen::Vector3d& j1,
                                               const Eigen::Vector3d& j2, int shift, bool offset,
                                               const std::string& label) {
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
      kGyroKindName + " with gyroscope biases/clock offset" + label, "rad/s", 1, std::move(blocks));
}

namespace {

/// Recording r's gyroscope kind: with the nuisance block when biases or a
/// clock offset (`offset`: its fraction) are estimated, its bias planes from
/// the first start's axes `at`, and its own block (its own biases).
std::unique_ptr<ResidualKind> recordingGyroKind(const Recordings& runs, std::size_t r, const AxisPair& at, int shift,
                                                const NuisanceSelection& nuisance, bool offset) {
  const std::string label = recordingLabel(runs, r);
  std::unique_ptr<ResidualKind> kind = nuisance.count() > 0
                                           ? gyroNuisanceKind(*runs[r], at.axis1, at.axis2, shift, offset, label)
                                           : gyroKind(*runs[r], shift, label);
  kind->setNuisanceBlock(static_cast<int>(r));
  return kind;
}

/// Each recording's own biases and clock need as many samples as one
/// recording alone (a recording of 11 samples beside a long one answered
/// biases of 0.8 rad/s, σ 0.03, whose truth was 0): NotIdentifiable naming it.
void requireOwnNuisanceSamples(const Recordings& runs, const NuisanceSelection& nuisance,
                               const AxisFitOptions& options) {
  if (runs.size() < 2 || nuisance.count() == 0) return;
  for (const JointSamples* run : runs)
    if (run->size() < options.min_samples)
      throw NotIdentifiable(run->source + ": " + std::to_string(run->size()) +
                            " samples, too few to estimate its own gyroscope biases or clock offset (at least " +
                            std::to_string(options.min_samples) + ", as for one recording alone)");
}

}  // namespace

/// The fit of `runs` with the clock offset's whole samples given (0 without
/// one; a clock offset and biases only on one recording). Several
/// recordings add their residual kinds side by side, each with its own
/// noise (its own third differences, its own weight): one axis pair.
Shifts sameShift(const Recordings& runs, int shift) { return Shifts(runs.size(), shift); }

HingeFit fitHingeAtShift(const Recordings& runs, const AxisFitOptions& options, const Shifts& shifts,
                         const Unfiltered& unfiltered) {
  const JointSamples& samples = *runs.front();
  if (shifts.size() != runs.size()) throw std::invalid_argument("fitHingeAtShift: a shift per recording expected");
  DataSelection data = hingeData(runs, options);
  requireEnoughSamples(totalSamples(runs), options);
  NuisanceSelection nuisance;
  for (const JointSamples* run : runs) nuisance = nuisanceOf(*run, data, options);
  requireOwnNuisanceSamples(runs, nuisance, options);
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
  if (runs.size() > 1)
    for (std::size_t r = 0; r < runs.size(); ++r) context.nuisance_blocks.push_back(recordingLabel(runs, r));
  if (data.orientations) {
    for (std::size_t r = 0; r < runs.size(); ++r) kinds.push_back(orientationKind(R12[r], recordingLabel(runs, r)));
    starts.push_back({hingeAxesFromOrientations(all_R12), "closed form (orientations)"});
    context.hint = kOrientationHint;
  }
  if (data.rates) {
    // The rates paired as the whole-sample clock offset says (as recorded
    // without one): all of them for the starts, each recording's for its
    // noise (after a low-pass filter third differences no longer measure it).
    std::vector<Eigen::Vector3d> w1, w2;
    std::vector<double> run_noise;
    for (std::size_t r = 0; r < runs.size(); ++r) {
      const JointSamples* run = runs[r];
      const int shift = shifts[r];
      std::vector<Eigen::Vector3d> v1, v2;
      for (int k = std::max(0, shift); k < run->size() && k - shift < run->size(); ++k) {
        v1.push_back(run->main.angular_velocity[k]);
        v2.push_back(run->secondary.angular_velocity[k - shift]);
      }
      if (!filtered)
        run_noise.push_back(
            std::sqrt(0.5 * (std::pow(whiteNoiseFromDifferences(v1), 2) + std::pow(whiteNoiseFromDifferences(v2), 2))));
      w1.insert(w1.end(), v1.begin(), v1.end());
      w2.insert(w2.end(), v2.begin(), v2.end());
    }
    if (!data.orientations) {
      rateStarts(samples, w1, w2, data.accelerometers, &starts, &search_starts);
      context.hint = kRateHint;
    }
    for (std::size_t r = 0; r < runs.size(); ++r) {
      kinds.push_back(recordingGyroKind(runs, r, starts.front().axes, shifts[r], nuisance, options.fit_time_offset));
      if (!filtered)
        kinds.back()->setIndependentNoise(run_noise[r], "the third differences of the recorded angular velocities");
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
    if (data.rates)
      for (std::size_t r = 0; r < raw.size(); ++r)
        raw_kinds.push_back(recordingGyroKind(raw, r, starts.front().axes, shifts[r], nuisance, false));
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
  setNuisance(runs, nuisance, starts.front(), shifts, solution, &fit);
  modelMisfit(runs, data.rates ? shifts : sameShift(runs, 0), j1, j2, data.accelerometers ? &centres : nullptr, &fit);
  if (!data.rates) fit.gyro_misfit = -1.0;
  fit.information = solution.information;
  fit.summary = solution.summary;
  fit.summary.search_starts = search_starts;
  fit.summary.data = data.name();
  fit.summary.samples = totalSamples(runs);
  return fit;
}

}  // namespace calibration
}  // namespace lieflow
