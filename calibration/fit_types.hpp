/// \file
/// Options and summaries shared by the joint-axis fits (hinge_fit.hpp,
/// universal_fit.hpp), in the style of ceres::Solver::Options / Summary: every
/// threshold is a named field, and a summary says which data were used, how
/// the solve went and why it stopped.
#pragma once

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace lieflow {
namespace calibration {

/// Robust loss on each sample's whitened residual (its norm in units of the
/// estimated noise σ̂ of its kind), ceres::HuberLoss / ceres::CauchyLoss.
enum class RobustLoss { kNone, kHuber, kCauchy };

/// Which recorded columns a fit uses. kAuto takes everything the joint's two
/// bodies have (orientations and/or angular velocities).
enum class DataUse { kAuto, kAngularVelocities, kOrientations, kBoth };

/// "none", "huber", "cauchy" and back; parseRobustLoss throws
/// lieflow::InvalidInput naming `field` for anything else.
const char* robustLossName(RobustLoss loss);
RobustLoss parseRobustLoss(const std::string& text, const std::string& field);
/// "auto", "gyroscopes", "orientations", "both" and back.
const char* dataUseName(DataUse use);
DataUse parseDataUse(const std::string& text, const std::string& field);

/// A pair of unit axes, axis 1 in the main body's frame and axis 2 in the
/// secondary body's frame.
struct AxisPair {
  Eigen::Vector3d axis1;
  Eigen::Vector3d axis2;
};

struct AxisFitOptions {
  DataUse use = DataUse::kAuto;
  RobustLoss loss = RobustLoss::kNone;
  /// Threshold of the robust loss in units of the estimated noise σ̂.
  double loss_scale = 3.0;

  // ceres::Solver::Options of the refinement (Levenberg–Marquardt, dense QR).
  int max_iterations = 100;
  double function_tolerance = 1e-12;
  double gradient_tolerance = 1e-12;
  double parameter_tolerance = 1e-12;

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
};

/// Per kind of residual: what it is, how many samples, and its size.
struct ResidualStats {
  std::string kind;        ///< e.g. "gyroscope hinge constraint"
  std::string unit;        ///< "rad/s" or "rad"
  int samples = 0;         ///< residual blocks (one per sample)
  int noise_dof = 0;       ///< independent noise components per block
  double rms = 0.0;        ///< RMS of the residual per noise component, in `unit`
  double noise_scale = 0.0;  ///< σ̂ the fit weighted this kind by, in `unit`
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
  std::string message;      ///< Ceres' reason for stopping
  int starts = 0;           ///< starting points tried
  std::string start;        ///< the one the solution came from
  int reweightings = 0;     ///< re-solves after re-estimating the noise scales
  double seconds = 0.0;     ///< wall time of the whole fit
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

}  // namespace calibration
}  // namespace lieflow
