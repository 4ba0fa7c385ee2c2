/// \file
/// What the sampling of a recording allows a spring fit, checked before the
/// model is integrated at all: the rates of the start's model against the
/// sample interval, and the integration substeps against their limit.
///
/// Near the mean angle a coordinate obeys I φ̈ + c φ̇ + k_eff φ = 0 (k_eff = k
/// plus the gravity stiffness). Its poles s have |s| = √(k_eff/I) when it
/// oscillates and at most c/I when it is overdamped, so
///   ω_k = √(|k_eff|/I)  (oscillation, or growth when k_eff < 0),
///   ω_c = c/I           (decay of the overdamped fast pole)
/// bound how fast the model moves. Samples Δt apart show a motion only if
/// ω Δt ≤ π (Nyquist: two samples per period; a decay by e^{−π} = 4 % per
/// interval). A start beyond that is not a start the data can correct: the
/// error names its source — the option (`--stiffness-start 1e100`), the
/// recording's time column (a start read from the recording, the scene's
/// gravity: "is t in seconds?") or the scene's spring. Substeps: h ω ≤
/// kStepTimesFrequency at √3 times the fastest rate (spring_fit.hpp), and no
/// more than `max_substeps` over the record (--max-substeps).
#pragma once

#include <array>
#include <string>

#include <Eigen/Core>

#include "calibration/spring_data.hpp"
#include "joints/grounded_joint_scene.hpp"

namespace lieflow {
namespace calibration {

/// h·ω bound of the automatic step (rkmk4's relative frequency error is then
/// (hω)⁴/120 ≈ 1e-6).
constexpr double kStepTimesFrequency = 0.1;
/// The largest ω Δt a recording can show (Nyquist).
constexpr double kNyquistRateTimesInterval = 3.141592653589793;
/// Margin of the automatic substeps on the start's fastest rate: the fit may
/// raise the frequency by √3 (k by 3) and keep hω ≤ kStepTimesFrequency.
constexpr double kSubstepRateMargin = 1.7320508075688772;

/// Where a start value came from; an error about it blames that source.
enum class StartOrigin { kGiven, kRecording, kScene };

/// The start (k, c, φ₀) of the fitted coordinate and where each came from.
struct SpringStartValues {
  std::array<double, 3> value{0.0, 0.0, 0.0};
  std::array<StartOrigin, 3> origin{StartOrigin::kScene, StartOrigin::kScene, StartOrigin::kScene};
  /// The recording's own frequency estimate (spring_start.hpp), 0 if none.
  double recorded_frequency = 0.0;
  double recorded_period = 0.0;  ///< s, 0 if none
};

struct SpringSampling {
  double max_interval = 0.0;   ///< largest sample interval, s
  double fastest_rate = 0.0;   ///< max of ω_k, ω_c over the coordinates at the start, 1/s
  int substeps = 1;            ///< integration steps per sample interval
  double total_substeps = 0.0; ///< over the record (one shooting pass)
};

/// ω = max(√(|k_eff|/I), c/I) of one coordinate (the bound on its poles' |s|).
double fastestRate(double inertia, double effective_stiffness, double damping);

/// Checks `start` for coordinate `coordinate` of `joint` against the sampling
/// of `data` at the recorded mean angles `mean_angle`, and chooses the
/// substeps (`substeps_option` > 0: given by --substeps). Throws InvalidInput
/// naming the start option, the recording's time column, the scene's spring
/// or dashpot, or --substeps, with the reason and the largest value the
/// recording allows; the substep limit names --max-substeps.
SpringSampling checkSpringSampling(const GroundedJointScene& joint, const SpringData& data, int coordinate,
                                   const SpringStartValues& start, const Eigen::Vector2d& mean_angle,
                                   int substeps_option, long max_substeps);

}  // namespace calibration
}  // namespace lieflow
