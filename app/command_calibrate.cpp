/// \file
/// `lieflow calibrate hinge|universal|spring RECORDING.csv ...`: fits a
/// joint's axes, or a joint coordinate's spring and dashpot, to a recording
/// and prints one JSON object (../shared/DESIGN.md). Exit 1 when the data
/// cannot identify the parameters or the solver does not converge (the JSON
/// is still printed then), 2 on bad input.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <algorithm>
#include <iostream>
#include <memory>
#include <optional>
#include <vector>
#include <string>

#include <glog/logging.h>
#include <nlohmann/json.hpp>

#include "app/arguments.hpp"
#include "app/calibrate_joint_fits.hpp"
#include "app/calibrate_outcome.hpp"
#include "app/cli.hpp"
#include "app/commands.hpp"
#include "app/flag_spelling.hpp"
#include "app/progress.hpp"
#include "app/run_setup.hpp"
#include "calibration/hinge_fit.hpp"
#include "calibration/mechanism_spring_fit.hpp"
#include "calibration/recording.hpp"
#include "calibration/unit_axis.hpp"
#include "calibration/spring_fit.hpp"
#include "calibration/spring_joint.hpp"
#include "model/scene.hpp"

namespace lieflow {
namespace app {
namespace {

using calibration::AxisFitOptions;
using calibration::AxisFitSummary;
using Json = nlohmann::ordered_json;

constexpr const char* kCalibrateUsage =
    "usage: lieflow calibrate hinge|universal RECORDING.csv [--main A] [--secondary B] [options]\n"
    "       lieflow calibrate hinge A.csv B.csv ... [options]   (one axis pair from several recordings)\n"
    "       lieflow calibrate spherical RECORDING.csv [--main A] [--secondary B]\n"
    "       lieflow calibrate spring RECORDING.csv --scene SCENE [--joint J] [options]\n"
    "\n"
    "Fits a joint's axes, or a joint coordinate's spring and dashpot, to a recording (the\n"
    "trajectory CSV: t and, per body B, any of B.qw,B.qx,B.qy,B.qz and B.wx,B.wy,B.wz; per\n"
    "joint J, J.phi or J.phi1,J.phi2) and prints one JSON object.\n"
    "  hinge      the revolute axis in both bodies' frames: axis_main, axis_secondary,\n"
    "             axis_sigma_deg (from gyroscopes, orientations or both)\n"
    "  universal  both axes of a universal joint: axis1_main, axis2_secondary and their\n"
    "             _sigma_deg (needs orientations; gyroscopes are used too when present)\n"
    "  spherical  the centre of a ball joint from both bodies' gyroscopes and accelerometers:\n"
    "             anchor_main, anchor_secondary [m] from each sensor point and their _sigma\n"
    "  spring     stiffness, damping, rest_angle (and their _sigma) of a revolute or universal\n"
    "             joint coordinate from its recorded angle; the body, its inertia, gravity and\n"
    "             the joint's geometry come from the scene (one body on the joint to ground);\n"
    "             on a scene of several bodies (a tree of revolute/universal joints) every\n"
    "             sprung or damped coordinate at once: coordinates [{joint, coordinate,\n"
    "             stiffness, damping, rest_angle, _sigma}], from the joint angles or the\n"
    "             bodies' gyroscopes, started from the inverse dynamics of the recorded\n"
    "             angles, or of the angles integrated from the gyroscopes (or at the\n"
    "             scene's values: --start)\n"
    "Always: rms_residual, iterations, converged, message; axis sigmas are 1-sigma RMS angles.\n"
    "With both bodies' accelerometers (B.ax,B.ay,B.az) and gyroscopes, hinge and universal\n"
    "also give the joint centre from each body's sensor point, in its axes: anchor_main,\n"
    "anchor_secondary [m] with anchor_main_sigma, anchor_secondary_sigma (1-sigma RMS position\n"
    "error; on a hinge the point of the axis closest to the two sensors), or anchor_note.\n"
    "\n"
    "hinge and universal:\n"
    "  --main A, --secondary B   the joint's bodies; with exactly two bodies in the recording\n"
    "                            they may be omitted (main: the first in column order)\n"
    "  --use auto|gyroscopes|orientations|both|gyroscopes+accelerometers|all\n"
    "                            data to fit (default auto: all both bodies have; a hinge fit\n"
    "                            uses the accelerometers with the gyroscopes: j1.a1 = j2.a2 at\n"
    "                            the joint centre)\n"
    "  --loss none|huber|cauchy  robust loss per sample (default none); under a robust loss\n"
    "                            sigma is the larger of Gauss-Newton and a sandwich (sigma_method)\n"
    "  --estimator auto|constraint|likelihood\n"
    "                            hinge: maximum likelihood over the joint angle (sigma at the\n"
    "                            Cramer-Rao bound; constraint_axis_*_sigma_deg for comparison)\n"
    "                            or Seel's constraint (fast; also takes orientations,\n"
    "                            accelerometers and filtered rates). Default auto: likelihood on\n"
    "                            gyroscopes alone without --low-pass, else constraint; the JSON's\n"
    "                            estimator and estimator_reason say which and why\n"
    "  --fit-gyro-bias           hinge, universal: estimate each gyroscope's constant bias\n"
    "                            (gyro_bias_main, gyro_bias_secondary [rad/s] and _sigma; axis\n"
    "                            sigmas marginal)\n"
    "  --fit-time-offset         hinge (gyroscopes), universal: estimate the secondary sensor's\n"
    "                            clock offset (time_offset [s]: its sample stamped t was taken\n"
    "                            at t + offset). Several recordings: each one's biases and\n"
    "                            offset its own, in its entry of recordings\n"
    "  --low-pass auto|none|HZ   hinge, spherical: low-pass the gyroscopes and accelerometers at\n"
    "                            HZ before fitting (zero-phase Butterworth; sensors wobbling on\n"
    "                            soft tissue); sigma accounts for the filter, gyro_misfit says\n"
    "                            how well a hinge explains the filtered rates. Default auto\n"
    "                            (hinge, spherical): filtered when a gyroscope wobbles (power\n"
    "                            above 7 Hz far above its white noise's), at the cutoff that\n"
    "                            keeps the motion's band; low_pass_hz (null: unfiltered) and\n"
    "                            low_pass_reason say so. universal is never filtered: with a\n"
    "                            wobble (and --use auto) it reads the orientations alone\n"
    "  --loss-scale K            its threshold in units of the estimated noise (default 3)\n"
    "  --start-main X,Y,Z --start-secondary X,Y,Z\n"
    "                            an extra starting point (the closed-form one is always tried)\n"
    "  --max-iterations N        Levenberg-Marquardt iterations (default 100)\n"
    "  --max-sigma-deg S         largest 1-sigma of an axis direction accepted (default 5)\n"
    "  --min-samples N           fewest samples accepted (default 20)\n"
    "spring:\n"
    "  --scene SCENE             JSON file or built-in scene with the body and the joint\n"
    "  --joint J                 the joint (default: the one between --main and --secondary if\n"
    "                            given, else the scene's only revolute/universal joint)\n"
    "  --coordinate 1|2          which coordinate of a universal joint (default 1)\n"
    "  --fit-rest-angle          fit the rest angle too (default: held at the scene's)\n"
    "  --hold-damping            hold the damping at --damping-start or the scene's\n"
    "  --stiffness-start K --damping-start C --rest-angle-start A\n"
    "                            starts (default: from the recorded angle's oscillation)\n"
    "  --shooting multiple|single  multiple shooting, then single (default), or single only\n"
    "  --segments N              multiple-shooting segments (default: a quarter period each)\n"
    "  --integrator NAME         rkmk-euler, rkmk-heun, rkmk3 or rkmk4 (default rkmk4)\n"
    "  --substeps N              integration steps per sample (default: h*omega <= 0.1)\n"
    "  --max-iterations N, --min-samples N\n"
    "  --max-substeps N          most integration substeps of one pass over the record (default 1e7)\n"
    "  --fit-axis                fit the axis of every sprung revolute joint too (axis_main,\n"
    "                            axis_sigma_deg per coordinate; the mechanism fit, any scene)\n"
    "  --data auto|angles|gyroscopes  a mechanism's data (default: the angles J.phi.. if all\n"
    "                            are recorded, else every body's gyroscopes)\n"
    "  --start auto|scene|inverse-dynamics  a mechanism's start (default: the inverse dynamics\n"
    "                            of the recorded angles when all are, else of the angles\n"
    "                            integrated from every body's gyroscopes, else the scene's values)\n"
    "all:\n"
    "  --max-input-mb N, --max-rows N  largest recording read (default 1024 MiB, 1e7 rows)\n"
    "  --verbose                 show the solver's (Ceres') own log lines on stderr\n"
    "exit status: 0 success, 1 not identifiable, no convergence or a failed fit (the message says\n"
    "which and why), 2 bad input\n";

Eigen::Vector3d parseAxis(const Arguments& args, const std::string& flag) {
  const std::vector<std::string> items = args.list(flag);
  if (items.size() != 3) throw UsageError(flag + ": expected three numbers X,Y,Z");
  Eigen::Vector3d v;
  for (int i = 0; i < 3; ++i) v[i] = parseNumber(flag, items[i]);
  if (!(v.norm() > 0.0)) throw UsageError(flag + ": the zero vector is no axis");
  return v;
}

AxisFitOptions fitOptions(const Arguments& args) {
  AxisFitOptions o;
  o.use = calibration::parseDataUse(args.value("--use", "auto"), "--use");
  o.loss = calibration::parseRobustLoss(args.value("--loss", "none"), "--loss");
  o.loss_scale = args.positiveNumber("--loss-scale", o.loss_scale);
  if (!(o.loss_scale >= calibration::kMinLossScale && o.loss_scale <= calibration::kMaxLossScale))
    throw UsageError("--loss-scale: " + formatNumber(o.loss_scale) + " is outside " +
                     formatNumber(calibration::kMinLossScale) + " ... " + formatNumber(calibration::kMaxLossScale) +
                     " (the threshold in units of the noise: below, every residual is an outlier; above, the loss is "
                     "the squared one)");
  o.max_iterations = args.positiveInt("--max-iterations", o.max_iterations);
  o.max_sigma_deg = args.positiveNumber("--max-sigma-deg", o.max_sigma_deg);
  o.min_samples = args.positiveInt("--min-samples", o.min_samples);
  o.estimator = calibration::parseHingeEstimator(args.value("--estimator", "auto"), "--estimator");
  o.fit_gyro_bias = args.has("--fit-gyro-bias");
  o.fit_time_offset = args.has("--fit-time-offset");
  if (args.has("--low-pass")) {
    const std::string v = args.value("--low-pass", "");
    if (v == "none")
      o.low_pass_auto = false;
    else if (v != "auto")
      o.low_pass_hz = args.positiveNumber("--low-pass", 0.0);
  }
  if (args.has("--start-main") != args.has("--start-secondary"))
    throw UsageError("--start-main and --start-secondary go together");
  if (args.has("--start-main"))
    o.extra_starts.push_back({parseAxis(args, "--start-main"), parseAxis(args, "--start-secondary")});
  return o;
}

/// Recordings above this size get a line on stderr before they are read:
/// how many rows, how much memory, so that a long silent read is explained.
constexpr std::uintmax_t kAnnounceBytes = 64u << 20;
/// Memory of an axis fit per recording row, measured: 0.94 GB for 10⁶ rows of
/// two bodies' quaternions, rates and positions (recording plus Ceres problem).
constexpr double kFitBytesPerRow = 950.0;

/// For a large recording, says on stderr how many rows it holds (from the
/// mean length of 64 lines from its middle) and the memory the fit will need.
void announceLargeRecording(const std::string& path, const std::string& what) {
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec || size < kAnnounceBytes) return;
  std::ifstream in(path);
  std::string line_text;
  in.seekg(static_cast<std::streamoff>(size / 2));
  std::getline(in, line_text);  // the rest of a line cut by the seek
  std::size_t bytes = 0, lines = 0;
  for (; lines < 64 && std::getline(in, line_text); ++lines) bytes += line_text.size() + 1;
  if (lines == 0) return;
  const double rows = static_cast<double>(size) * static_cast<double>(lines) / static_cast<double>(bytes);
  char line[256];
  std::snprintf(line, sizeof line, "lieflow: %s: %.0f MB, about %.2g rows; the fit needs about %.2g GB of memory\n",
                what.c_str(), size / 1e6, rows, rows * kFitBytesPerRow / 1e9);
  std::cerr << line << std::flush;
}

/// Progress of a fit on stderr: silent for the first 2 s (most fits end
/// sooner), then a line at most every 5 s with the iteration and the cost.
calibration::FitProgress fitProgressOnStderr(const std::string& what) {
  auto lines = std::make_shared<LineThrottle>(ProgressReporter::kProgressDelay, ProgressReporter::kProgressInterval);
  return [what, lines](int iteration, double cost) {
    if (!lines->due()) return;
    std::cerr << "lieflow: " << what << ": solver iteration " << iteration << ", cost " << cost << ", "
              << static_cast<long>(lines->elapsed()) << " s" << std::endl;
  };
}

std::optional<double> optionalNumber(const Arguments& args, const std::string& flag) {
  if (!args.has(flag)) return std::nullopt;
  return parseNumber(flag, args.value(flag, ""));
}

/// The joint to fit: --joint, or the scene's revolute/universal joint between
/// --main and --secondary (either may be given alone), or "" (the scene's only
/// one, resolved by groundedJointScene).
std::string jointBetween(const SceneDescription& scene, const std::string& joint, const std::string& main,
                         const std::string& secondary) {
  if (!joint.empty() || (main.empty() && secondary.empty())) {
    if (!joint.empty())
      for (const JointDescription& j : scene.joints)
        if (j.name == joint && ((!main.empty() && j.main != main) || (!secondary.empty() && j.secondary != secondary)))
          throw UsageError("--joint " + joint + " joins '" + j.main + "' (main) and '" + j.secondary +
                           "' (secondary), not the bodies given by --main/--secondary");
    return joint;
  }
  std::vector<std::string> found;
  for (const JointDescription& j : scene.joints)
    if ((j.type == "revolute" || j.type == "universal") && (main.empty() || j.main == main) &&
        (secondary.empty() || j.secondary == secondary))
      found.push_back(j.name);
  if (found.size() != 1)
    throw UsageError(std::to_string(found.size()) + " revolute or universal joints of " + scene.source +
                     " have main '" + (main.empty() ? "*" : main) + "' and secondary '" +
                     (secondary.empty() ? "*" : secondary) + "': name the joint with --joint");
  return found.front();
}

/// `calibrate spring` on a scene of several bodies: every sprung or damped
/// joint coordinate at once (calibration/mechanism_spring_fit.hpp).
CommandOutcome runMechanismSprings(const Arguments& args, const SceneDescription& scene,
                                   const std::string& recording_path, const ResourceLimits& limits,
                                   const std::function<bool()>& interrupted) {
  for (const char* flag : {"--joint", "--coordinate", "--stiffness-start", "--damping-start", "--rest-angle-start",
                           "--hold-damping", "--shooting", "--integrator", "--main", "--secondary"})
    if (args.has(flag))
      throw UsageError(std::string(flag) + " is an option of the one-joint spring fit; on a mechanism (" +
                       std::to_string(scene.bodies.size()) +
                       " bodies, or --fit-axis) every sprung or damped coordinate is fitted, started from the "
                       "inverse dynamics of the recorded angles or at the scene's values (--start)");
  calibration::MechanismSpringOptions o;
  o.data = calibration::parseMechanismData(args.value("--data", "auto"), "--data");
  o.start = calibration::parseMechanismStart(args.value("--start", "auto"), "--start");
  o.fit_rest_angle = args.has("--fit-rest-angle");
  o.fit_axis = args.has("--fit-axis");
  o.segments = args.has("--segments") ? args.positiveInt("--segments", 1) : 0;
  o.substeps = args.has("--substeps") ? args.positiveInt("--substeps", 1) : 0;
  o.max_iterations = args.positiveInt("--max-iterations", o.max_iterations);
  o.min_samples = args.positiveInt("--min-samples", o.min_samples);
  o.max_substeps = limits.max_substeps;
  o.progress = fitProgressOnStderr("calibrate spring " + recording_path);
  o.interrupt = interrupted;
  const calibration::Recording recording = calibration::readRecording(recording_path, limits);
  const std::string what = "calibrate spring " + recording_path;
  try {
    const calibration::MechanismSpringFit fit = calibration::fitMechanismSprings(scene, recording, o);
    Json j;
    Json coordinates = Json::array();
    for (const calibration::CoordinateSpring& c : fit.coordinates) {
      Json e = {{"joint", c.joint},
                {"coordinate", c.coordinate},
                {"stiffness", c.stiffness},
                {"stiffness_sigma", c.stiffness_sigma},
                {"damping", c.damping},
                {"damping_sigma", c.damping_sigma},
                {"rest_angle", c.rest_angle},
                {"rest_angle_sigma", c.rest_angle_sigma},
                {"start_values", {{"stiffness", c.start_stiffness}, {"damping", c.start_damping}}}};
      Json held = Json::array();
      if (!c.stiffness_fitted) held.push_back("stiffness (no spring in the scene)");
      if (!c.damping_fitted) held.push_back("damping (no dashpot in the scene)");
      if (!held.empty()) e["held_at_zero"] = held;
      if (c.axis_fitted) {
        e["axis_main"] = vector3(c.axis);
        e["axis_secondary"] = vector3(c.axis_secondary);
        e["axis_sigma_deg"] = c.axis_sigma_deg;
      }
      coordinates.push_back(e);
    }
    j["coordinates"] = coordinates;
    j["data"] = fit.data;
    j["rms_residual"] = fit.rms_residual;
    j["rms_residual_unit"] = fit.residual_unit;
    j["iterations"] = fit.iterations;
    j["converged"] = fit.converged;
    j["message"] = fit.message;
    j["samples"] = fit.samples;
    j["held_fixed"] = fit.held_fixed;
    j["start"] = fit.start;
    if (!fit.start_note.empty()) j["start_note"] = fit.start_note;
    j["segments"] = fit.segments;
    j["integrator"] = "rk4 in joint coordinates";
    j["substeps"] = fit.substeps;
    j["seconds"] = fit.seconds;
    return finish(j, fit.converged, fit.message, what);
  } catch (const calibration::NotIdentifiable& e) {
    return failed(what, e);
  } catch (const calibration::FitFailed& e) {
    return failed(what, e);
  }
}

CommandOutcome runSpring(const Arguments& args, const std::string& recording_path,
                         const std::function<bool()>& interrupted) {
  if (!args.has("--scene"))
    throw UsageError("calibrate spring needs --scene SCENE (the body, its inertia and the joint's geometry)");
  for (const char* flag : {"--use", "--loss", "--loss-scale", "--start-main", "--start-secondary", "--max-sigma-deg", "--estimator",
                           "--fit-gyro-bias", "--fit-time-offset", "--low-pass"})
    if (args.has(flag)) throw UsageError(std::string(flag) + " is an option of calibrate hinge|universal, not spring");
  calibration::SpringFitOptions o;
  const int coordinate = args.positiveInt("--coordinate", 1);
  if (coordinate > 2) throw UsageError("--coordinate: 1 or 2");
  o.coordinate = coordinate - 1;
  o.fit_rest_angle = args.has("--fit-rest-angle");
  o.hold_damping = args.has("--hold-damping");
  o.stiffness_start = optionalNumber(args, "--stiffness-start");
  o.damping_start = optionalNumber(args, "--damping-start");
  o.rest_angle_start = optionalNumber(args, "--rest-angle-start");
  o.shooting = calibration::parseShooting(args.value("--shooting", "multiple"), "--shooting");
  o.segments = args.has("--segments") ? args.positiveInt("--segments", 1) : 0;
  o.integrator = args.value("--integrator", o.integrator);
  o.substeps = args.has("--substeps") ? args.positiveInt("--substeps", 1) : 0;
  o.max_iterations = args.positiveInt("--max-iterations", o.max_iterations);
  o.min_samples = args.positiveInt("--min-samples", o.min_samples);
  const ResourceLimits limits = resourceLimitsFrom(args);
  o.max_substeps = limits.max_substeps;
  o.progress = fitProgressOnStderr("calibrate spring " + recording_path);
  o.interrupt = interrupted;

  const SceneDescription scene = loadScene(args.value("--scene", ""), limits);
  if (scene.bodies.size() > 1 || args.has("--fit-axis"))
    return runMechanismSprings(args, scene, recording_path, limits, interrupted);
  for (const char* flag : {"--data", "--start"})
    if (args.has(flag))
      throw UsageError(std::string(flag) + " is an option of the mechanism spring fit (a scene of several bodies)");
  const calibration::SpringJoint joint = calibration::springJoint(
      scene, jointBetween(scene, args.value("--joint", ""), args.value("--main", ""), args.value("--secondary", "")));
  if (o.coordinate >= joint.coordinates)
    throw UsageError("--coordinate 2: joint '" + joint.joint_name + "' is revolute (one coordinate)");
  const calibration::Recording recording = calibration::readRecording(recording_path, limits);
  const calibration::SpringData data = calibration::selectSpringData(recording, joint, o.coordinate);
  const std::string what = "calibrate spring " + recording_path;
  try {
    const calibration::SpringFit fit = calibration::fitSpring(joint, data, o);
    Json j;
    j["stiffness"] = fit.stiffness;
    j["stiffness_sigma"] = fit.stiffness_sigma;
    j["damping"] = fit.damping;
    j["damping_sigma"] = fit.damping_sigma;
    j["rest_angle"] = fit.rest_angle;
    j["rest_angle_sigma"] = fit.rest_angle_sigma;
    j["rms_residual"] = fit.rms_residual;
    j["iterations"] = fit.iterations;
    j["converged"] = fit.converged;
    j["message"] = fit.message;
    j["joint"] = joint.joint_name;
    j["body"] = joint.body_name;
    j["coordinate"] = o.coordinate + 1;
    j["column"] = data.column[o.coordinate];
    j["samples"] = fit.samples;
    j["rms_residual_unit"] = "rad";
    Json fitted = Json::array({"stiffness"});
    if (!o.hold_damping) fitted.push_back("damping");
    if (o.fit_rest_angle) fitted.push_back("rest_angle");
    fitted.push_back("initial state");
    j["fitted"] = fitted;
    j["held_fixed"] = fit.held_fixed;
    j["inertia"] = fit.inertia;
    j["natural_frequency"] = fit.natural_frequency;
    j["damping_ratio"] = fit.damping_ratio;
    j["correlation_stiffness_damping"] = fit.correlation_stiffness_damping;
    j["initial_state"] = std::vector<double>(fit.initial_state.data(), fit.initial_state.data() + fit.initial_state.size());
    j["start"] = fit.start;
    j["start_values"] = {{"stiffness", fit.start_stiffness}, {"damping", fit.start_damping},
                         {"rest_angle", fit.start_rest_angle}};
    j["shooting"] = fit.shooting;
    j["segments"] = fit.segments;
    j["multiple_shooting_iterations"] = fit.multiple_shooting_iterations;
    j["single_shooting_iterations"] = fit.single_shooting_iterations;
    j["max_continuity_defect"] = fit.max_continuity_defect;
    j["integrator"] = fit.integrator;
    j["substeps"] = fit.substeps;
    j["seconds"] = fit.seconds;
    return finish(j, fit.converged, fit.message, what);
  } catch (const calibration::NotIdentifiable& e) {
    return failed(what, e);
  } catch (const calibration::FitFailed& e) {
    return failed(what, e);
  }
}

}  // namespace

const std::set<std::string>& calibrateValueFlags() {
  static const std::set<std::string> flags = {
      "--main",          "--secondary",     "--use",           "--loss",       "--loss-scale",  "--start-main",
      "--start-secondary", "--max-iterations", "--max-sigma-deg", "--min-samples", "--scene",      "--joint",
      "--coordinate",    "--stiffness-start", "--damping-start", "--rest-angle-start", "--shooting", "--segments",
      "--integrator",    "--substeps",      "--max-input-mb",  "--max-bodies", "--max-substeps", "--max-rows",
      "--estimator",     "--data",          "--start",      "--low-pass"};
  return flags;
}

const std::set<std::string>& calibrateSwitches() {
  static const std::set<std::string> switches = {"--fit-rest-angle", "--hold-damping", "--verbose", "--fit-gyro-bias",
                                                 "--fit-time-offset", "--fit-axis"};
  return switches;
}

int runCalibrate(int argc, char** argv) {
  const Arguments args(argc, argv, calibrateValueFlags(), calibrateSwitches());
  if (args.help()) {
    std::cout << kCalibrateUsage;
    return kSuccess;
  }
  const CommandOutcome outcome = calibrate(args);
  if (!outcome.json.is_null()) std::cout << jsonLine(outcome.json) << "\n";
  if (!outcome.error.empty()) std::cerr << "lieflow: " << spellFlags(outcome.error) << "\n";
  return outcome.status;
}

CommandOutcome calibrate(const Arguments& args, const std::function<bool()>& interrupted) {
  // Ceres logs through glog (WARNING: Logging before InitGoogleLogging, E...
  // trust_region_minimizer.cc ...): those lines are for --verbose; lieflow
  // says in its own words why a fit stopped. glog is initialized once per
  // process (the Python module calibrates many times).
  static const bool glog_initialized = [] {
    google::InitGoogleLogging("lieflow");
    FLAGS_logtostderr = true;
    return true;
  }();
  (void)glog_initialized;
  FLAGS_minloglevel = args.has("--verbose") ? google::GLOG_INFO : google::GLOG_FATAL;
  const std::vector<std::string>& pos = args.positional();
  if (pos.empty())
    throw UsageError(
        "calibrate needs hinge, universal, spherical or spring and a RECORDING.csv (see lieflow calibrate --help)");
  const std::string& kind = pos[0];
  if (kind != "hinge" && kind != "universal" && kind != "spherical" && kind != "spring")
    throw UsageError("unknown calibration '" + kind + "' (available: hinge, universal, spherical, spring)");
  if (pos.size() < 2 || (pos.size() > 2 && kind != "hinge"))
    throw UsageError("calibrate " + kind + " needs exactly one RECORDING.csv" +
                     (pos.size() > 2 ? " (several recordings of one joint: calibrate hinge A.csv B.csv ...)" : ""));
  if (kind == "spring") return runSpring(args, pos[1], interrupted);
  for (const char* flag : {"--scene", "--joint", "--coordinate", "--stiffness-start", "--damping-start",
                           "--rest-angle-start", "--shooting", "--segments", "--integrator", "--substeps",
                           "--fit-rest-angle", "--hold-damping", "--max-substeps", "--max-bodies", "--fit-axis", "--data",
                           "--start"})
    if (args.has(flag)) throw UsageError(std::string(flag) + " is an option of calibrate spring, not " + kind);
  AxisFitOptions options = fitOptions(args);
  std::string files = pos[1];
  for (std::size_t i = 2; i < pos.size(); ++i) files += " " + pos[i];
  const std::string what = "calibrate " + kind + " " + files;
  options.progress = fitProgressOnStderr(what);
  options.interrupt = interrupted;
  // Every recording read, its joint selected; the row and byte limits hold
  // for all of them together (each file is read with what the ones before it left).
  std::vector<calibration::JointSamples> joints;
  ResourceLimits left = resourceLimitsFrom(args);
  for (std::size_t i = 1; i < pos.size(); ++i) {
    announceLargeRecording(pos[i], "calibrate " + kind + " " + pos[i]);
    const calibration::Recording recording = calibration::readRecording(pos[i], left);
    left.max_rows -= static_cast<long>(recording.time.size());
    std::error_code size_error;
    const std::uintmax_t bytes = std::filesystem::file_size(pos[i], size_error);
    if (!size_error) left.max_input_bytes -= std::min<std::uint64_t>(left.max_input_bytes, bytes);
    joints.push_back(calibration::selectJoint(recording, args.value("--main", ""), args.value("--secondary", "")));
  }
  const calibration::JointSamples& joint = joints.front();
  if (kind == "spherical") {
    for (const char* flag : {"--use", "--loss", "--loss-scale", "--start-main", "--start-secondary", "--max-sigma-deg", "--estimator",
                           "--fit-gyro-bias", "--fit-time-offset"})
      if (args.has(flag)) throw UsageError(std::string(flag) + " is an option of the axis fits, not of spherical");
    return runSpherical(joint, what, options);
  }
  try {
    return kind == "hinge" ? runHinge(joints, options, what) : runUniversal(joint, options, what);
  } catch (const calibration::NotIdentifiable& e) {
    return failed(what, e);
  } catch (const calibration::FitFailed& e) {
    return failed(what, e);
  }
}

}  // namespace app
}  // namespace lieflow
