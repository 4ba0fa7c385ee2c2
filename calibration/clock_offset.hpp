/// \file
/// The whole samples of the clock offset between two sensors (the hinge fit's
/// --fit-time-offset, hinge_fit.hpp): a search over shifts of the secondary
/// sensor's samples; the fit then refines the fraction of a sample.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "calibration/fit_types.hpp"
#include "calibration/joint_samples.hpp"

namespace lieflow {
namespace calibration {

/// Rounds of wholeSampleOffset's search, at most.
constexpr int kOffsetRounds = 3;
/// Δχ² by which the best whole-sample clock offset must beat every other one
/// more than a sample away, or the offset is not identifiable.
constexpr double kOffsetAmbiguity = 25.0;

/// ω₁,k and ω₂,k−m over the samples both exist.
void pairedRates(const JointSamples& samples, int m, std::vector<Eigen::Vector3d>* a, std::vector<Eigen::Vector3d>* b);

/// The whole samples m of the secondary sensor's clock offset (its sample
/// stamped t was taken at t + m h), |m h| ≤ max_offset: (1) the shift whose
/// closed-form gyroscope axes (hingeAxesFromRates) leave the least mean
/// Sampson residual; (2) the global search's best axes at that shift
/// (hinge_search.hpp); (3) the shift at which those axes leave the least mean
/// residual; (2)–(3) again until the shift stays (≤ kOffsetRounds). Fixed
/// axes make the cost sharp in m where the closed form alone, refitted at
/// every shift, is not (on 3 s recordings it missed by 2–6 samples). Another
/// shift more than one sample away that fits within Δχ² = kOffsetAmbiguity
/// (against the gyroscopes' noise from third differences) throws
/// NotIdentifiable.
int wholeSampleOffset(const JointSamples& samples, double max_offset);

/// The mean squared Sampson residual of the given axes, with the rates less
/// the given gyroscope biases, at every shift m = −R … R (|R h| ≤
/// max_offset): element m + R.
std::vector<double> shiftCosts(const JointSamples& samples, const AxisPair& axes, const Eigen::Vector3d& bias_main,
                               const Eigen::Vector3d& bias_secondary, double max_offset);

}  // namespace calibration
}  // namespace lieflow
