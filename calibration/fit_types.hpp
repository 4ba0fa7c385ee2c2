/// \file
/// Options and summaries shared by the joint-axis fits (hinge_fit.hpp,
/// universal_fit.hpp), in the style of ceres::Solver::Options / Summary: every
/// threshold is a named field, and a summary says which data were used, how
/// the solve went and why it stopped.
#pragma once

#include "calibration/fit_progress.hpp"

#include <chrono>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "liegroup/number_text.hpp"

namespace lieflow {
namespace calibration {

/// Robust loss on each sample's whitened residual (its norm in units of the
/// estimated noise σ̂ of its kind), ceres::HuberLoss / ceres::CauchyLoss.
enum class RobustLoss { kNone, kHuber, kCauchy };

/// Which recorded columns a fit uses. kAuto takes everything the joint's two
/// bodies have (orientations and/or angular velocities, and for a hinge the
/// accelerometers with the angular velocities); kGyroscopesAccelerometers
/// and kAll ask for the accelerometers explicitly (hinge fits only).
enum class DataUse { kAuto, kAngularVelocities, kOrientations, kBoth, kGyroscopesAccelerometers, kAll };

/// "none", "huber", "cauchy" and back; parseRobustLoss throws
/// lieflow::InvalidInput naming `field` for anything else.
const char* robustLossName(RobustLoss loss);
RobustLoss parseRobustLoss(const std::string& text, const std::string& field);
/// "auto", "gyroscopes", "orientations", "both", "gyroscopes+accelerometers",
/// "all" and back.
const char* dataUseName(DataUse use);
DataUse parseDataUse(const std::string& text, const std::string& field);

/// A pair of unit axes, axis 1 in the main body's frame and axis 2 in the
/// secondary body's frame.
struct AxisPair {
  Eigen::Vector3d axis1;
  Eigen::Vector3d axis2;
};

/// The hinge fit's estimator from gyroscopes: Seel's constraint (fast; the
/// lengths of the perpendicular rates) or maximum likelihood over the joint
/// angle (hinge_likelihood.hpp; their phase too, σ at the Cramér–Rao bound);
/// kAuto: the best the recording supports (hinge_estimator.hpp says which
/// and why).
enum class HingeEstimator { kAuto, kConstraint, kLikelihood };
/// "auto", "constraint", "likelihood" and back (InvalidInput naming `field`).
const char* hingeEstimatorName(HingeEstimator e);
HingeEstimator parseHingeEstimator(const std::string& text, const std::string& field);

/// The range of AxisFitOptions::loss_scale [units of the noise σ̂]: below,
/// every residual counts as an outlier and the axes are not determined;
/// above, the robust loss is the squared one over any data.
constexpr double kMinLossScale = 0.01;
constexpr double kMaxLossScale = 1e6;

struct AxisFitOptions {
  DataUse use = DataUse::kAuto;
  HingeEstimator estimator = HingeEstimator::kAuto;
  RobustLoss loss = RobustLoss::kNone;
  /// Threshold of the robust loss in units of the estimated noise σ̂.
  double loss_scale = 3.0;

  // ceres::Solver::Options of the refinement (Levenberg–Marquardt, dense QR).
  int max_iterations = 100;
  /// Called at every solver iteration (fit_progress.hpp); may be empty.
  FitProgress progress;
  /// Asked at every solver iteration; true stops the solve (may be empty).
  FitInterrupt interrupt;
  double function_tolerance = 1e-12;
  double gradient_tolerance = 1e-12;
  double parameter_tolerance = 1e-12;

  /// Hinge fits with gyroscopes: estimate each gyroscope's constant bias
  /// (perpendicular to the axis) and/or the secondary sensor's clock offset
  /// as nuisance parameters (hinge_fit.hpp; the axes' σ is marginal over them).
  bool fit_gyro_bias = false;
  bool fit_time_offset = false;
  /// Without fit_gyro_bias, refit with the biases and compare: a gyroscope
  /// residual lower by more than Δχ² = 30 marks the fit converged = false
  /// and says to rerun with biases (hinge fits without a robust loss;
  /// AxisFitSummary::bias_check_delta_chi_square).
  bool check_gyro_bias = true;
  /// The clock offsets searched in whole samples before the fit refines the
  /// fraction [s] (hinge_fit.cpp wholeSampleOffset).
  double max_time_offset = 0.5;

  /// Hinge fits: low-pass the gyroscopes and accelerometers at this cutoff
  /// [Hz] before fitting (low_pass.hpp: zero-phase Butterworth; 0 = off), for
  /// sensors that wobble on soft tissue. The statistics then account for the
  /// filter (two_axis_solver.hpp, LowPassNoise), the residual-to-noise check
  /// is not made (third differences no longer measure the noise), and the
  /// misfit is reported relative to the signal (HingeFit::gyro_misfit).
  double low_pass_hz = 0.0;
  /// With low_pass_hz = 0, the hinge fit checks the gyroscopes for a wobble
  /// and low-passes by itself at a cutoff it chooses (wobble_check.hpp);
  /// false: unfiltered (`--low-pass none`).
  bool low_pass_auto = true;
  /// The hinge fit checks its model across segments of the recording
  /// (hinge_segments.hpp); off for the segments' own fits.
  bool check_segments = true;

  /// Starts tried besides the closed-form one (which is always tried); the
  /// solution of lowest cost wins.
  std::vector<AxisPair> extra_starts;

  // Identifiability (identifiability.hpp): fewer samples, a principal
  // direction of the 4 axis angles with a 1σ above max_sigma_deg, or one in
  // which the motion informs less than min_motion_to_noise times as much as
  // the noise, make the fit throw NotIdentifiable.
  int min_samples = 20;
  double max_sigma_deg = 5.0;
  double min_motion_to_noise = 1.0;

  /// A second local minimum (from another start) whose axes lie more than
  /// distinct_minimum_sigmas σ from the best's, and whose cost exceeds the
  /// best's by less than this Δχ² = 2Δcost/s² (s² the reduced chi-square of
  /// the best), makes the fit throw NotIdentifiable: the data fit two axis
  /// pairs equally well, and a σ from the curvature at one of them would be a
  /// confident wrong answer. χ²₄ at 99 % (4 axis angles).
  double ambiguity_chi_square = 13.28;
  double distinct_minimum_sigmas = 3.0;

  /// σ describes the error only where the cost is quadratic over the region
  /// it claims. Δχ² at ±quadratic_check_sigmas σ along each principal
  /// direction of the covariance is compared with its quadratic value (9 at
  /// 3σ): more than 1 + quadratic_tolerance times it (a curved valley; short
  /// recordings give 2–27 times, with errors of 10–30 σ) makes the fit throw
  /// NotIdentifiable; less (a cost flatter than the Gauss–Newton curvature,
  /// e.g. at large noise) widens σ in that direction to the cost's actual
  /// rise (two_axis_solver.hpp). 0 switches the check off.
  double quadratic_tolerance = 0.5;
  double quadratic_check_sigmas = 3.0;

  /// When the noise of a residual kind can be estimated independently of the
  /// fit (the gyroscopes' white noise, from third differences of the recorded
  /// rates: data_selection.hpp), a fitted residual scale (median form) above
  /// this multiple of it marks the fit as not converged (converged = false,
  /// the message says why): the fit stopped in a local minimum, or the model
  /// does not describe the data (a gyroscope bias, another kind of joint,
  /// low-pass-filtered or otherwise correlated noise). 0 switches the check off.
  double max_residual_to_noise = 2.0;
};

/// Per kind of residual: what it is, how many samples, and its size.
struct ResidualStats {
  std::string kind;        ///< e.g. "gyroscope hinge constraint"
  std::string unit;        ///< "rad/s" or "rad"
  int samples = 0;         ///< residual blocks (one per sample)
  int noise_dof = 0;       ///< independent noise components per block
  double rms = 0.0;        ///< RMS of the residual per noise component, in `unit`
  double noise_scale = 0.0;  ///< σ̂ the fit weighted this kind by, in `unit`
  /// The noise the residual should have, estimated without the fit (from the
  /// recorded signals' third differences), in `unit`; 0 when not available.
  double independent_noise = 0.0;
  /// The residual's scale at the solution (median form, robust) over
  /// independent_noise; 0 when not available. ≈ 1 when the model fits.
  double residual_to_noise = 0.0;
};

/// How a fit went.
struct AxisFitSummary {
  std::string data;        ///< "gyroscopes", "orientations" or "orientations+gyroscopes"
  int samples = 0;
  std::vector<ResidualStats> residuals;
  double rms_residual = 0.0;  ///< residuals.front().rms (the primary kind)
  double reduced_chi_square = 0.0;  ///< whitened cost per degree of freedom (≈ 1)
  int iterations = 0;       ///< Levenberg–Marquardt iterations of the accepted solution
  bool converged = false;   ///< ceres::CONVERGENCE (a tolerance was met)
  std::string message;      ///< why the solve stopped (solverStopMessage)
  int starts = 0;           ///< starting points refined by Ceres
  std::string start;        ///< the one the solution came from
  int search_starts = 0;    ///< starts of the global search before the refinement (0: none)
  int minima = 0;           ///< distinct local minima the refinement ended in
  /// Δχ² = 2Δcost/s² of the best other distinct minimum (−1: none found).
  double runner_up_delta_chi_square = -1.0;
  /// Δχ² at ±quadratic_check_sigmas σ along the principal directions of the
  /// covariance over its quadratic prediction, least and largest (1 and 1
  /// for a quadratic cost; 0 when not checked).
  double quadratic_ratio_min = 0.0;
  double quadratic_ratio_max = 0.0;
  int reweightings = 0;     ///< re-solves after re-estimating the noise scales
  /// Hinge fits without biases: Δχ² by which fitting gyroscope biases
  /// lowers the gyroscope residual (−1: not checked).
  double bias_check_delta_chi_square = -1.0;
  /// How σ was computed: "Gauss-Newton" (JᵀJ scaled by the reduced
  /// chi-square, widened where the cost is flatter) or, under a robust loss,
  /// the larger of it and the sandwich from B batch means (two_axis_solver.hpp
  /// step 8), named so.
  std::string sigma_method = "Gauss-Newton";
  /// Under a robust loss, the Gauss–Newton σ the sandwich replaced (the
  /// larger axis', rad); 0 otherwise.
  double gauss_newton_sigma_rad = 0.0;
  double seconds = 0.0;     ///< wall time of the whole fit (timedFit, at the public entry points)
};

/// What a fit estimated of the sensors besides the joint (AxisFitOptions::
/// fit_gyro_bias, fit_time_offset): each gyroscope's constant bias [rad/s, its
/// body's axes] with its RMS σ, and the secondary sensor's clock offset δ [s]
/// (its sample stamped t was taken at t + δ) with its σ. Which components of
/// a bias a joint observes is the fit's to say (hinge_fit.hpp, universal_fit.hpp).
struct SensorNuisanceEstimate {
  bool fitted_gyro_bias = false;
  Eigen::Vector3d gyro_bias_main = Eigen::Vector3d::Zero();
  Eigen::Vector3d gyro_bias_secondary = Eigen::Vector3d::Zero();
  double gyro_bias_main_sigma = 0.0;
  double gyro_bias_secondary_sigma = 0.0;
  bool fitted_time_offset = false;
  double time_offset = 0.0;
  double time_offset_sigma = 0.0;
};


/// A fit that could not be carried out (the model could not be evaluated
/// from the start, the solver stopped on a failure): exit status 1, and
/// what() says which stage failed and why, in lieflow's words.
class FitFailed : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Thrown when the data cannot determine the axes; what() is
/// "not identifiable: <reason>".
class NotIdentifiable : public std::runtime_error {
 public:
  explicit NotIdentifiable(const std::string& reason)
      : std::runtime_error("not identifiable: " + reason), reason_(reason) {}
  const std::string& reason() const { return reason_; }

 private:
  std::string reason_;
};

/// fit() with its summary.seconds set to the wall time of the whole call:
/// the public entry points of the axis fits time themselves here, so that
/// the estimator's and the filter's choice, the clock-offset profiles and
/// the model check's segment fits are counted, and nothing inside them
/// keeps a clock of its own.
template <typename Fit>
auto timedFit(Fit&& fit) {
  const auto start = std::chrono::steady_clock::now();
  auto out = fit();
  out.summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace calibration
}  // namespace lieflow
