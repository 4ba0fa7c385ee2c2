/// \file
/// The hinge fit's core (hinge_fit.hpp, for its own use): the constraint fit
/// of one or several recordings at a given whole-sample clock shift — the
/// residual kinds of the data it uses (gyroscopes in Sampson form,
/// orientations, the accelerometers at the joint centre; each recording its
/// own kinds and noise weight), their starts (closed forms and the global
/// search), the two-axis solve, the relative sign and the misfit. What the
/// fit chooses by itself around it (filter, estimator, clock-offset profile,
/// the likelihood refinement, the bias check, the model check) is in
/// hinge_fit.cpp.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "calibration/fit_types.hpp"
#include "calibration/hinge_fit.hpp"
#include "calibration/joint_samples.hpp"
#include "calibration/residual_kind.hpp"

namespace lieflow {
namespace calibration {

/// The recordings one fit reads: one, or several of the same joint (each
/// its own series in time: no stencil or filter reaches across two).
using Recordings = std::vector<const JointSamples*>;

/// How a residual kind of recording `r` is named: as it is for one
/// recording, with the recording's file after it for several.
std::string recordingLabel(const Recordings& runs, std::size_t r);

int totalSamples(const Recordings& runs);

/// A low-passed fit's unfiltered recordings (empty without a filter) and
/// the filter's noise power gain.
struct Unfiltered {
  Recordings samples;
  double power_gain = 1.0;
};

/// The name of the gyroscopes' plain residual kind (a recording's label after it).
extern const std::string kGyroKindName;

/// The gyroscopes' residual kind with the nuisance block (biases in the
/// planes perpendicular to j1, j2; a clock offset's fraction with `offset`);
/// `shift` whole samples of clock offset (0 without one); `label` after its name.
std::unique_ptr<ResidualKind> gyroNuisanceKind(const JointSamples& samples, const Eigen::Vector3d& j1,
                                               const Eigen::Vector3d& j2, int shift, bool offset,
                                               const std::string& label = "");

/// Each recording's whole samples of clock offset (0 without one).
using Shifts = std::vector<int>;
Shifts sameShift(const Recordings& runs, int shift);

/// The constraint fit of `runs` with each one's clock offset's whole samples
/// given. Several recordings add their residual kinds side by side, each
/// with its own noise (its own third differences, its own weight) and its
/// own biases and clock offset's fraction (its own nuisance block;
/// HingeFit::recording_nuisance): one axis pair.
/// With `unfiltered`, `runs` are low-passed and the statistics account for
/// the filter.
HingeFit fitHingeAtShift(const Recordings& runs, const AxisFitOptions& options, const Shifts& shifts,
                         const Unfiltered& unfiltered = Unfiltered());

}  // namespace calibration
}  // namespace lieflow
