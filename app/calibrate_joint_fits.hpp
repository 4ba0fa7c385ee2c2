/// \file
/// The joint fits of `lieflow calibrate` — hinge (one recording or several),
/// universal and spherical — run and turned into their JSON
/// (app/calibrate_joint_fits.cpp); the command (command_calibrate.cpp) reads
/// the recordings and the options and prints the outcome.
#pragma once

#include <exception>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "app/calibrate_outcome.hpp"
#include "calibration/fit_types.hpp"
#include "calibration/joint_samples.hpp"

namespace lieflow {
namespace app {

using Json = nlohmann::ordered_json;

/// [x, y, z].
Json vector3(const Eigen::Vector3d& v);

/// The outcome of a fit's JSON: kComputationFailed when the solver did not
/// converge (saying why) or when a figure is not finite (naming it).
CommandOutcome finish(const Json& j, bool converged, const std::string& message, const std::string& what);

/// A fit that could not answer: kComputationFailed with the reason.
CommandOutcome failed(const std::string& what, const std::exception& e);

/// `calibrate hinge` of one or several recordings of the joint.
CommandOutcome runHinge(const std::vector<calibration::JointSamples>& joints,
                        const calibration::AxisFitOptions& options, const std::string& what);

/// `calibrate universal`.
CommandOutcome runUniversal(const calibration::JointSamples& joint, const calibration::AxisFitOptions& options,
                            const std::string& what);

/// `calibrate spherical`: the centre of a ball joint.
CommandOutcome runSpherical(const calibration::JointSamples& recorded, const std::string& what,
                            const calibration::AxisFitOptions& options);

}  // namespace app
}  // namespace lieflow
