/// \file
/// The time grid of a shooting fit of a recorded motion, shared by the spring
/// fits of one joint (spring_fit.hpp) and of a mechanism
/// (mechanism_spring_fit.hpp): the model is integrated between the samples
/// in sub-steps, and the recording is cut into segments that multiple
/// shooting starts from their own states (Bock and Plitt 1984) before single
/// shooting runs the whole recording from the first.
#pragma once

#include <string>
#include <vector>

#include "liegroup/scalar.hpp"

namespace lieflow {
namespace calibration {

/// Samples per multiple-shooting segment, at least.
constexpr int kMinSegmentSamples = 4;

/// The largest interval between consecutive times (0 for fewer than two).
double largestInterval(const std::vector<double>& time);

/// Throws InvalidInput (field "SOURCE: t") when the largest sample interval
/// is longer than half a period π/ω of the fastest oscillation ω [rad/s]
/// that `what` gives: fewer than two samples per period cannot determine it
/// (aliasing); a time column in milliseconds shows up here first.
void requireResolved(const std::string& source, double max_interval, double omega, const std::string& what);

/// The number of multiple-shooting segments: `requested` when positive, else
/// one per quarter `period` of the `duration`; at least one, and each of at
/// least kMinSegmentSamples of the n samples.
int shootingSegments(int requested, double duration, double period, int n);

/// The segments' first samples, evenly spread over the n samples, and n − 1
/// last (segments + 1 indices).
std::vector<int> segmentBounds(int n, int segments);

/// The half width, in samples, of the local polynomial fits that start the
/// segments: a sixteenth of a period, at least 2.
int localFitHalfWidth(double period, double duration, int n);

}  // namespace calibration
}  // namespace lieflow
