// The JSON of the joint fits of `lieflow calibrate` (hinge, universal,
// spherical): their keys (../shared/DESIGN.md and its Additions), the
// summary every axis fit prints, the joint centre and the model check.
#include "app/calibrate_joint_fits.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "calibration/hinge_fit.hpp"
#include "calibration/joint_centre.hpp"
#include "calibration/low_pass.hpp"
#include "calibration/spherical_fit.hpp"
#include "calibration/unit_axis.hpp"
#include "calibration/universal_fit.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {
namespace app {
namespace {

using calibration::AxisFitOptions;
using calibration::AxisFitSummary;

/// A fit's check across segments (calibration/model_check.hpp): the keys
/// model_spread_UNIT (null when not checked), model_check and segments, whose
/// answers `main` and `secondary` name ("axis_main" with `unit` "deg",
/// "anchor_main" with "m").
void addModelCheck(Json& j, const calibration::ModelCheck& check, const std::string& main = "axis_main",
                   const std::string& secondary = "axis_secondary", const std::string& unit = "deg") {
  j["model_spread_" + unit] = check.ran ? Json(std::max(check.spread_main, check.spread_secondary)) : Json(nullptr);
  j["model_check"] = check.note;
  Json segments = Json::array();
  for (const calibration::SegmentFit& s : check.segments) {
    Json seg = {{"by", s.by}, {"t_start", s.t_start}, {"t_end", s.t_end}};
    if (!s.source.empty()) seg["recording"] = s.source;
    if (s.answered) {
      seg[main] = {s.main.x(), s.main.y(), s.main.z()};
      seg[secondary] = {s.secondary.x(), s.secondary.y(), s.secondary.z()};
      seg[main + "_sigma_" + unit] = s.sigma_main;
      seg[secondary + "_sigma_" + unit] = s.sigma_secondary;
      seg[main + "_apart_" + unit] = s.apart_main;
      seg[secondary + "_apart_" + unit] = s.apart_secondary;
    } else {
      seg["not_answered"] = s.why;
    }
    segments.push_back(seg);
  }
  j["segments"] = segments;
}

/// The joint centre's keys: anchor_main, anchor_secondary, their _sigma and
/// the frame they are in.
void putJointCentre(Json& j, const calibration::JointCentreFit& c, bool hinge) {
  j["anchor_main"] = vector3(c.anchor_main);
  j["anchor_secondary"] = vector3(c.anchor_secondary);
  j["anchor_main_sigma"] = c.sigma_main;
  j["anchor_secondary_sigma"] = c.sigma_secondary;
  j["anchor_frame"] = std::string("from each body's sensor point, body axes [m]") +
                      (hinge ? "; on the hinge axis, the point closest to the two sensors" : "");
}

/// With both bodies' gyroscopes and accelerometers, the joint centre
/// (calibration/joint_centre.hpp): anchor_main, anchor_secondary [m] from
/// each sensor point in its body's axes, with σ; `axes` are a hinge's (its
/// centre closest to the sensors) or null. Where the motion does not
/// determine it, anchor_note says why and the axes' result stands.
void addJointCentre(Json& j, const calibration::JointSamples& joint, const Eigen::Vector3d* axis_main,
                    const Eigen::Vector3d* axis_secondary, int correlation_samples = 0) {
  if (!joint.hasAngularVelocities() || !joint.main.hasSpecificForce() || !joint.secondary.hasSpecificForce())
    return;
  try {
    const calibration::JointCentreFit c =
        calibration::fitJointCentre(joint, axis_main, axis_secondary, correlation_samples);
    putJointCentre(j, c, axis_main != nullptr);
    j["anchor_rms_residual"] = c.rms_residual;
    j["anchor_converged"] = c.converged;
  } catch (const calibration::NotIdentifiable& e) {
    j["anchor_note"] = std::string("joint centre ") + e.what();
  }
}

/// The keys every axis fit prints after its own: the solve's summary.
void addSummary(Json& j, const AxisFitSummary& s, const calibration::JointSamples& joint) {
  j["rms_residual"] = s.rms_residual;
  j["iterations"] = s.iterations;
  j["converged"] = s.converged;
  j["message"] = s.message;
  j["main"] = joint.main.name;
  j["secondary"] = joint.secondary.name;
  j["data"] = s.data;
  j["samples"] = s.samples;
  j["rms_residual_unit"] = s.residuals.front().unit;
  Json residuals = Json::array();
  for (const calibration::ResidualStats& r : s.residuals) {
    Json entry = {{"kind", r.kind}, {"unit", r.unit}, {"samples", r.samples}, {"noise_components", r.noise_dof},
                  {"rms", r.rms}, {"noise_scale", r.noise_scale}};
    // How well the joint model explains the data: the residual's scale over
    // the sensor noise estimated without the model (1 for a perfect model).
    if (r.independent_noise > 0.0) {
      entry["independent_noise"] = r.independent_noise;
      entry["residual_to_noise"] = r.residual_to_noise;
    }
    residuals.push_back(entry);
  }
  j["residuals"] = residuals;
  j["reduced_chi_square"] = s.reduced_chi_square;
  j["starts"] = s.starts;
  j["start"] = s.start;
  j["reweightings"] = s.reweightings;
  j["sigma_method"] = s.sigma_method;
  if (s.bias_check_delta_chi_square >= 0.0) j["bias_check_delta_chi_square"] = s.bias_check_delta_chi_square;
  if (s.gauss_newton_sigma_rad > 0.0) j["gauss_newton_sigma_deg"] = s.gauss_newton_sigma_rad * calibration::kRadToDeg;
  j["seconds"] = s.seconds;
}

/// The first non-finite number in j ("stiffness_sigma", "axis_main[1]"), or "".
std::string nonFiniteKey(const Json& j, const std::string& path = "") {
  if (j.is_number_float() && !std::isfinite(j.get<double>())) return path.empty() ? "value" : path;
  if (j.is_object())
    for (auto it = j.begin(); it != j.end(); ++it) {
      const std::string found = nonFiniteKey(it.value(), path.empty() ? it.key() : path + "." + it.key());
      if (!found.empty()) return found;
    }
  if (j.is_array())
    for (std::size_t i = 0; i < j.size(); ++i) {
      const std::string found = nonFiniteKey(j[i], path + "[" + std::to_string(i) + "]");
      if (!found.empty()) return found;
    }
  return "";
}

}  // namespace

Json vector3(const Eigen::Vector3d& v) { return Json::array({v.x(), v.y(), v.z()}); }

/// The JSON; exit 1 with the solver's message when it did not converge.
CommandOutcome finish(const Json& j, bool converged, const std::string& message, const std::string& what) {
  // Never a NaN or inf in the output (nlohmann would print it as null, or
  // -nan where it is not JSON): the fit failed, and says which figure.
  const std::string bad = nonFiniteKey(j);
  if (!bad.empty())
    return {Json(), kComputationFailed, what + ": the fit failed: " + bad + " is not a finite number (" + message + ")"};
  if (!converged) return {j, kComputationFailed, what + ": the solver did not converge: " + message};
  return {j, kSuccess, ""};
}

CommandOutcome failed(const std::string& what, const std::exception& e) {
  return {Json(), kComputationFailed, what + ": " + e.what()};
}

/// `calibrate spherical`: the centre of a ball joint (calibration/spherical_fit.hpp).
CommandOutcome runSpherical(const calibration::JointSamples& recorded, const std::string& what,
                            const AxisFitOptions& options) {
  try {
    const calibration::SphericalFit fit = calibration::fitSpherical(recorded, options);
    const calibration::JointCentreFit& c = fit.centre;
    Json j;
    putJointCentre(j, c, false);
    j["low_pass_hz"] = fit.low_pass_hz > 0.0 ? Json(fit.low_pass_hz) : Json(nullptr);
    j["low_pass_reason"] = fit.low_pass_reason;
    if (fit.low_pass_hz > 0.0) j["low_pass_noise_gain"] = fit.low_pass_noise_gain;
    addModelCheck(j, fit.model_check, "anchor_main", "anchor_secondary", "m");
    j["rms_residual"] = c.rms_residual;
    j["rms_residual_unit"] = "m/s^2";
    j["iterations"] = c.iterations;
    j["converged"] = c.converged;
    j["message"] = c.message;
    j["main"] = recorded.main.name;
    j["secondary"] = recorded.secondary.name;
    j["samples"] = c.samples;
    return finish(j, c.converged, c.message, what);
  } catch (const calibration::NotIdentifiable& e) {
    return failed(what, e);
  } catch (const calibration::FitFailed& e) {
    return failed(what, e);
  }
}

namespace {

/// The biases and the clock offset a fit estimated, as fields of `j`.
void addNuisance(Json& j, const calibration::SensorNuisanceEstimate& e) {
  if (e.fitted_gyro_bias) {
    j["gyro_bias_main"] = vector3(e.gyro_bias_main);
    j["gyro_bias_secondary"] = vector3(e.gyro_bias_secondary);
    j["gyro_bias_main_sigma"] = e.gyro_bias_main_sigma;
    j["gyro_bias_secondary_sigma"] = e.gyro_bias_secondary_sigma;
  }
  if (e.fitted_time_offset) {
    j["time_offset"] = e.time_offset;
    j["time_offset_sigma"] = e.time_offset_sigma;
  }
}

}  // namespace

/// `calibrate hinge` of one or several recordings of the joint: its JSON.
CommandOutcome runHinge(const std::vector<calibration::JointSamples>& joints, const AxisFitOptions& options,
                        const std::string& what) {
  const calibration::JointSamples& joint = joints.front();
  Json j;
  const calibration::HingeFit fit = calibration::fitHinge(joints, options);
  if (joints.size() > 1) {
    // Each recording's biases and clock offset are its own: in its entry.
    Json recordings = Json::array();
    for (std::size_t r = 0; r < joints.size(); ++r) {
      Json entry = {{"file", joints[r].source}, {"samples", joints[r].size()}, {"t_start", joints[r].time.front()},
                    {"t_end", joints[r].time.back()}};
      if (r < fit.recording_nuisance.size()) addNuisance(entry, fit.recording_nuisance[r]);
      recordings.push_back(entry);
    }
    j["recordings"] = recordings;
  }
  j["axis_main"] = vector3(fit.axis_main);
  j["axis_secondary"] = vector3(fit.axis_secondary);
  j["axis_sigma_deg"] = fit.axisSigmaDeg();
  j["axis_main_sigma_deg"] = fit.sigma_main_deg;
  j["axis_secondary_sigma_deg"] = fit.sigma_secondary_deg;
  addSummary(j, fit.summary, joint);
  j["sign"] = fit.sign;
  if (fit.recording_nuisance.empty()) addNuisance(j, fit);
  if (!fit.recording_nuisance.empty() && fit.fitted_time_offset)
    j["time_offset_note"] = "each recording's own, in its entry of `recordings`";
  if (fit.fitted_gyro_bias) {
    j["gyro_bias_note"] =
        std::string(fit.recording_nuisance.empty() ? "" : "each recording's own, in its entry of `recordings`; ") +
        (fit.likelihood.fitted_gyro_bias
             ? "rad/s in each body's axes; along the axis the joint angle sees only the difference of the two "
               "biases: the secondary's is reported 0 there and the main one's is the difference (main - secondary)"
             : "rad/s in each body's axes, perpendicular to the axis (a hinge does not observe a bias along its "
               "axis: reported 0)");
  }
  j["estimator"] = calibration::hingeEstimatorName(fit.estimator);
  j["estimator_reason"] = fit.estimator_reason;
  if (fit.estimator == calibration::HingeEstimator::kLikelihood) {
    j["constraint_axis_main_sigma_deg"] = fit.constraint_sigma_main_deg;
    j["constraint_axis_secondary_sigma_deg"] = fit.constraint_sigma_secondary_deg;
    j["likelihood_noise_sigma"] = fit.likelihood.noise_sigma;
    j["likelihood_iterations"] = fit.likelihood.iterations;
  }
  if (fit.gyro_misfit >= 0.0) j["gyro_misfit"] = fit.gyro_misfit;
  if (fit.accelerometer_misfit >= 0.0) j["accelerometer_misfit"] = fit.accelerometer_misfit;
  j["low_pass_hz"] = fit.low_pass_hz > 0.0 ? Json(fit.low_pass_hz) : Json(nullptr);
  j["low_pass_reason"] = fit.low_pass_reason;
  addModelCheck(j, fit.model_check);
  if (fit.low_pass_hz > 0.0) {
    j["low_pass_noise_gain"] = fit.low_pass_noise_gain;
    calibration::LowPassFilter filter;
    const calibration::JointSamples filtered = calibration::lowPassed(joint, fit.low_pass_hz, "--low-pass", &filter);
    addJointCentre(j, filtered, &fit.axis_main, &fit.axis_secondary,
                   calibration::lowPassCorrelationSamples(filter));
  } else {
    addJointCentre(j, joint, &fit.axis_main, &fit.axis_secondary);
  }
  // The joint centre is the first recording's (its sensors' points, from its samples alone).
  if (joints.size() > 1 && (j.contains("anchor_main") || j.contains("anchor_note"))) j["anchor_recording"] = joint.source;
  return finish(j, fit.summary.converged, fit.summary.message, what);
}

/// `calibrate universal`: its JSON.
CommandOutcome runUniversal(const calibration::JointSamples& joint, const AxisFitOptions& options,
                            const std::string& what) {
  Json j;
  const calibration::UniversalFit fit = calibration::fitUniversal(joint, options);
  j["axis1_main"] = vector3(fit.axis1_main);
  j["axis2_secondary"] = vector3(fit.axis2_secondary);
  j["axis1_main_sigma_deg"] = fit.sigma1_deg;
  j["axis2_secondary_sigma_deg"] = fit.sigma2_deg;
  addSummary(j, fit.summary, joint);
  j["sign"] = "each axis: largest component positive (the joint does not fix the axes' signs)";
  if (fit.fitted_gyro_bias) {
    j["gyro_bias_main"] = vector3(fit.gyro_bias_main);
    j["gyro_bias_secondary"] = vector3(fit.gyro_bias_secondary);
    j["gyro_bias_main_sigma"] = fit.gyro_bias_main_sigma;
    j["gyro_bias_secondary_sigma"] = fit.gyro_bias_secondary_sigma;
    j["gyro_bias_note"] = "rad/s in each body's axes, perpendicular to that body's axis (the joint does not "
                          "observe a bias along its axes: reported 0)";
  }
  if (fit.fitted_time_offset) {
    j["time_offset"] = fit.time_offset;
    j["time_offset_sigma"] = fit.time_offset_sigma;
  }
  j["low_pass_hz"] = nullptr;
  j["low_pass_reason"] = fit.low_pass_reason;
  addModelCheck(j, fit.model_check, "axis1_main", "axis2_secondary");
  addJointCentre(j, joint, nullptr, nullptr);
  return finish(j, fit.summary.converged, fit.summary.message, what);
}

}  // namespace app
}  // namespace lieflow
