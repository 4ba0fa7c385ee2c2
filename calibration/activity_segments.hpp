/// \file
/// A recording cut by activity (issue 31): at the middle of each of its
/// rests. A person who sits down, sits, stands up and walks away makes
/// three bouts of motion separated by stillness; a hinge fixed in the
/// sensors' frames may describe one and not another (a sensor moves on the
/// tissue when the thigh rests on a chair), which quarters by time can hide
/// when the activities alternate. model_check.hpp fits each part alone.
/// Each part keeps half of the rests beside it: still poses are what the
/// accelerometers tell a hinge from (a single flexion alone leaves one of
/// the four axis directions undetermined on the real knee).
///
/// The motion's level at sample k is the RMS over a window of
/// kActivityWindowSeconds of ‖ω₁‖² + ‖ω₂‖² (the gyroscopes; without them, the
/// rates between successive orientations, ‖log(R_kᵀR_{k+1})‖/Δt). A sample
/// rests where that level is below kRestFraction of its 90th percentile over
/// the recording; rests shorter than kMinRestSeconds do not cut (a gait's
/// own pauses, a slow turn of a flexion), nor do rests at either end. A
/// recording without a rest that cuts is one part.
#pragma once

#include <string>
#include <vector>

#include "calibration/joint_samples.hpp"

namespace lieflow {
namespace calibration {

/// The motion level's window [s] (a gait cycle is about 1 s).
constexpr double kActivityWindowSeconds = 0.5;
/// A rest: the level below this fraction of its 90th percentile (white
/// gyroscope noise alone on a moving recording sits far below it; the real
/// knee's sitting reads 0.01 of its walking).
constexpr double kRestFraction = 0.1;
/// The shortest rest that divides a recording [s].
constexpr double kMinRestSeconds = 1.0;

/// A part: samples [begin, end) of the recording.
struct SampleSpan {
  int begin = 0, end = 0;
};

/// The recording's parts by activity (file comment), in time order, together
/// all its samples; empty when it has neither gyroscopes nor orientations
/// for both bodies, fewer than two samples or times that do not advance.
std::vector<SampleSpan> activityParts(const JointSamples& samples);

}  // namespace calibration
}  // namespace lieflow
