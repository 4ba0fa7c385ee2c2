#include "calibration/spherical_fit.hpp"

#include <vector>

#include "calibration/low_pass.hpp"
#include "calibration/wobble_check.hpp"
#include "liegroup/invalid_input.hpp"
#include "liegroup/number_text.hpp"

namespace lieflow {
namespace calibration {

namespace {

/// The centre of `samples`, low-passed first at `cutoff_hz` (> 0).
JointCentreFit centreOf(const JointSamples& samples, double cutoff_hz, double* noise_gain) {
  if (!(cutoff_hz > 0.0)) return fitJointCentre(samples, nullptr, nullptr);
  LowPassFilter filter;
  const JointSamples filtered = lowPassed(samples, cutoff_hz, "`low_pass`", &filter);
  if (noise_gain) *noise_gain = filter.noisePowerGain();
  return fitJointCentre(filtered, nullptr, nullptr, lowPassCorrelationSamples(filter));
}

double pointDistance(const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return (a - b).norm(); }

}  // namespace

SphericalFit fitSpherical(const JointSamples& samples, const AxisFitOptions& options) {
  for (const BodySamples* b : {&samples.main, &samples.secondary})
    if (!b->hasAngularVelocity() || !b->hasSpecificForce())
      throw InvalidInput(samples.source, "calibrate spherical needs both bodies' gyroscopes and accelerometers: body '" +
                                             b->name + "' has no " +
                                             (b->hasAngularVelocity() ? "B.ax, B.ay, B.az" : "B.wx, B.wy, B.wz") +
                                             " columns");
  SphericalFit fit;
  if (options.low_pass_hz > 0.0) {
    fit.low_pass_hz = options.low_pass_hz;
    fit.low_pass_reason = "asked for (`low_pass` " + formatNumber(options.low_pass_hz) + ")";
  } else if (!options.low_pass_auto) {
    fit.low_pass_reason = "no filter: asked for (`low_pass` none)";
  } else {
    const LowPassChoice wobble = chooseLowPass(samples);
    fit.low_pass_hz = wobble.cutoff_hz;
    fit.low_pass_reason = wobble.reason;
  }
  fit.centre = centreOf(samples, fit.low_pass_hz, &fit.low_pass_noise_gain);
  if (!options.check_segments) return fit;
  const double cutoff = fit.low_pass_hz;
  const PieceFit fitPiece = [cutoff](const JointSamples& piece) {
    const JointCentreFit c = centreOf(piece, cutoff, nullptr);
    return PieceAnswer{c.anchor_main, c.anchor_secondary, c.sigma_main, c.sigma_secondary};
  };
  fit.model_check = checkAcrossRecording(samples, fitPiece, pointDistance, fit.centre.anchor_main,
                                         fit.centre.anchor_secondary, "ball joint", kMinCentreSegmentSamples);
  fit.centre.sigma_main = fit.model_check.widened(fit.centre.sigma_main, 0);
  fit.centre.sigma_secondary = fit.model_check.widened(fit.centre.sigma_secondary, 1);
  return fit;
}

}  // namespace calibration
}  // namespace lieflow
