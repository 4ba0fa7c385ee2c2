/// \file
/// Precision and speed measurements of liegroup/ that the `lieflow` main job
/// and the bench/ programs print (bench/README.md shows a measured run).
///
/// Precision: the largest error over random samples in four angle bands
///   θ ∈ [1e-12, 1e-8], [1e-8, 1e-4] (log-uniform), θ ∈ (0, π) (uniform),
///   θ = π − δ with δ ∈ [1e-8, 1e-3] (log-uniform),
/// each with a uniformly random rotation axis, against the targets
///   SO(3): error ≤ 2e-15 · max(1, ‖w‖),   SE(3): error ≤ 1e-14.
/// Every error is the largest absolute component (max |·|) of a vector,
/// quaternion or matrix difference.
///
/// Speed: ns per operation of each lieflow operation beside an Eigen baseline
/// doing the equivalent work, timed in the same run with std::chrono (no Google
/// Benchmark), and their ratio against the target ratio.
///
/// This header needs neither Eigen nor liegroup/: callers that only print
/// tables stay light.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <limits>
#include <string>
#include <vector>

namespace lieflow {
namespace measure {

/// The target of a row that has none (an Eigen baseline, an information row).
constexpr double kNoTarget = std::numeric_limits<double>::quiet_NaN();

// ---------------------------------------------------------------------------
// Precision
// ---------------------------------------------------------------------------

/// One (operation, band) cell: the largest error over `samples` samples.
struct PrecisionRow {
  std::string operation;  ///< e.g. "SO3 log(exp(w)) - w"
  std::string band;       ///< e.g. "theta in [1e-12, 1e-8]"
  int samples = 0;
  double max_error = 0.0;
  /// The error allowed for one sample: `target`, times max(1, ‖w‖) when
  /// `target_scales_with_norm`. NaN when the row has no target (Eigen rows,
  /// informational rows).
  double target = 0.0;
  bool target_scales_with_norm = false;
  /// max over samples of error / (allowed error of that sample); ≤ 1 passes.
  /// NaN when the row has no target.
  double worst_target_fraction = 0.0;

  bool hasTarget() const;
  bool pass() const;  ///< true when there is no target
  std::string targetText() const;  ///< "2e-15*max(1,|w|)", "1e-14" or "-"
};

/// The four bands above, in that order, with their printed names.
std::vector<std::string> precisionBands();

/// Max error per band per operation over `samples_per_band` random samples
/// per band (deterministic given `seed`). Operations:
///   SO3 log(exp(w)) − w (absolute; relative to max(1, ‖w‖); relative to ‖w‖),
///   SO3 exp(w) − q_ref, q_ref = (cos(θ/2), sin(θ/2) w/θ) in long double,
///   SO3 Jr(w) Jr⁻¹(w) − I,
///   SE3 log(exp(ξ)) − ξ, ρ uniform in [−1, 1]³,
///   SE3 Jr(ξ) Jr⁻¹(ξ) − I,
///   and for comparison Eigen's AngleAxis round trip
///   AngleAxis(Quaternion(AngleAxis(θ, w/θ))) (angle·axis) − w and its
///   quaternion against q_ref.
std::vector<PrecisionRow> measurePrecision(int samples_per_band, std::uint64_t seed);

/// One line per operation, one column per band (max error), then the target
/// and PASS / MISS (markdown table).
void printPrecisionTable(std::ostream& out, const std::vector<PrecisionRow>& rows);

// ---------------------------------------------------------------------------
// Speed
// ---------------------------------------------------------------------------

/// A lieflow operation, the Eigen baseline it is timed against, the target
/// ratio (NaN: none) and the ratios other libraries were measured at.
struct SpeedTarget {
  const char* operation;  ///< e.g. "SO3 exp"
  const char* baseline;   ///< e.g. "Eigen AngleAxis->Quaternion"
  double max_ratio;       ///< lieflow time / baseline time must be ≤ this; NaN: none
  const char* others;     ///< Sophus / manif / smooth ratios, e.g. "1.36 / 1.32 / 0.97", or ""
};

/// Every (operation, baseline) pair that measureSpeed and bench_liegroup time,
/// in the order they print.
const std::vector<SpeedTarget>& speedTargets();

struct SpeedRow {
  std::string operation;
  std::string baseline;
  double ns_per_op = 0.0;           ///< median over repetitions
  double baseline_ns_per_op = 0.0;  ///< median over repetitions
  /// Median over repetitions of (lieflow time / baseline time), each pair of
  /// timings taken back to back (so slow drifts of the clock rate cancel).
  double ratio = 0.0;
  double ratio_q1 = 0.0;  ///< 25th and 75th percentiles of the paired ratios:
  double ratio_q3 = 0.0;  ///< the spread of the measurement (noise)
  int repetitions = 0;
  double max_ratio = 0.0;  ///< the target; NaN: none
  std::string others;      ///< other libraries' ratios, for context

  bool hasTarget() const;
  bool pass() const;  ///< ratio ≤ max_ratio; true when there is no target
};

/// Times every pair of speedTargets(): each operation and its baseline get
/// about `seconds_per_op` seconds each (at least 9 repetitions), split into
/// interleaved 200 µs batches (op, baseline, baseline, op, ...), so that the
/// medians shrug off the batches a loaded machine interrupts. Inputs cycle
/// through pre-generated arrays of random elements; every result is added
/// into a sink. Takes about 2 × 11 × seconds_per_op seconds.
std::vector<SpeedRow> measureSpeed(double seconds_per_op);

/// One line per pair: ns/op of both, ratio (median, interquartile range),
/// target, PASS / MISS (markdown table).
void printSpeedTable(std::ostream& out, const std::vector<SpeedRow>& rows);

/// "g++ 12.2.0, -O3 -DNDEBUG" style description of how lieflow_measure was
/// built (compiler and the flags CMake passed), for the table captions.
std::string buildDescription();

}  // namespace measure
}  // namespace lieflow
