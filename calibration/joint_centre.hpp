/// \file
/// The joint centre in each body's sensor frame, from the gyroscopes and
/// accelerometers of the two bodies (Seel, Schauer & Raisch 2012, "IMU-based
/// joint angle measurement for gait analysis", Sensors 14, §3.2; Olsson, Kok,
/// Seel & Halvorsen 2020, "Accelerometer calibration and joint centre
/// estimation"). The centre is one point of both bodies, so its acceleration
/// is one world vector; seen from body k's sensor it is the measured specific
/// force moved from the sensor point to the centre,
///   f_c,k = f_k + ω̇_k × o_k + ω_k × (ω_k × o_k),
/// o_k the centre from the sensor point in body k's axes (what `anchor_main`,
/// `anchor_secondary` report: the scene's anchor minus the sensor offset).
/// Without orientations only the norms can be compared,
///   e(t) = ‖f_c,1(t)‖ − ‖f_c,2(t)‖ = 0     [m/s²],
/// one residual per sample, ω̇ the slope of a cubic fitted to the rates over
/// ±6 samples (joint_centre.cpp says why not a central difference).
/// Gravity keeps ‖f_c‖ ≈ g away from the norm's kink at zero.
///
/// Unknowns o₁, o₂ (6), started at the sensors (o = 0, Seel's start) and
/// solved by Ceres (Levenberg–Marquardt). On a hinge every point of the axis
/// is a centre (o_k + λ j_k fit equally): the reported one is the closest to
/// the two sensors, imposed as the gauge o₁·j₁ + o₂·j₂ = 0 (the minimizer of
/// ‖o₁‖² + ‖o₂‖² along the axis, j unit). The covariance is a sandwich
/// (Newey–West: the residuals' scatter and their correlation over the rates'
/// window, so that misfit and noise of any size count, without an assumed
/// noise level); σ is the RMS position error, √trace of a body's 3 × 3 block
/// [m].
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "calibration/joint_samples.hpp"

namespace lieflow {
namespace calibration {

struct JointCentreFit {
  Eigen::Vector3d anchor_main = Eigen::Vector3d::Zero();       ///< o₁ [m], main body's sensor axes
  Eigen::Vector3d anchor_secondary = Eigen::Vector3d::Zero();  ///< o₂ [m]
  double sigma_main = 0.0;                                     ///< √trace Σ₁ [m]
  double sigma_secondary = 0.0;
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();  ///< (o₁, o₂) [m²]
  double rms_residual = 0.0;  ///< RMS of e(t) at the solution [m/s²]
  int samples = 0;            ///< residuals (interior samples)
  int iterations = 0;
  bool converged = false;
  std::string message;  ///< why the solver stopped
};

/// Samples at either end without an ω̇ (the cubic's half window): the
/// accelerations at the centre start at sample kCentreWindow and end
/// kCentreWindow before the last.
constexpr int kCentreWindow = 6;

/// The specific force at the centre, f_c,k = f_k + ω̇_k × o_k + ω_k × (ω_k ×
/// o_k), of both bodies for samples kCentreWindow … n − 1 − kCentreWindow.
struct CentreForces {
  int first = kCentreWindow;             ///< sample index of main[0]
  std::vector<Eigen::Vector3d> main;     ///< body 1's axes [m/s²]
  std::vector<Eigen::Vector3d> secondary;
};
CentreForces centreSpecificForces(const JointSamples& samples, const Eigen::Vector3d& anchor_main,
                                  const Eigen::Vector3d& anchor_secondary);

/// The least-squares centre alone (no gauge, no covariance), for a hinge
/// fit that needs the accelerations at a point of the axis before it knows
/// the axis: on a hinge, where along the axis is whatever the solver reached
/// from the sensors (the norm residuals do not see it).
void solveJointCentre(const JointSamples& samples, Eigen::Vector3d* anchor_main, Eigen::Vector3d* anchor_secondary);

/// The joint centre; `axis_main`, `axis_secondary` (unit) are a hinge's axes
/// for the gauge, or null for a joint whose centre is a point (spherical,
/// universal). Throws lieflow::InvalidInput when the samples lack the
/// gyroscope or accelerometer groups of either body, NotIdentifiable when the
/// motion does not determine the centre (the covariance is rank deficient).
/// `correlation_samples`: how far apart residuals can still be correlated
/// beyond the rates' window (low-passed signals: low_pass.hpp,
/// lowPassCorrelationSamples); the sandwich's lag window reaches at least that far.
JointCentreFit fitJointCentre(const JointSamples& samples, const Eigen::Vector3d* axis_main,
                              const Eigen::Vector3d* axis_secondary, int correlation_samples = 0);

}  // namespace calibration
}  // namespace lieflow
