/// \file
/// Whether a recording's gyroscopes wobble on soft tissue, and the low-pass
/// cutoff the hinge fit then chooses by itself (AxisFitOptions::low_pass_auto;
/// the JSON's `low_pass_hz` and `low_pass_reason`).
///
/// A body-worn sensor turns on the tissue under it: on the real knee
/// recording of tests/data/qmt the thigh gyroscope's long axis carries 85 % of
/// its power at 7–50 Hz, where the knee's own motion has almost none
/// (README, "Low-passed sensors"). White noise is flat: above f_split it puts
/// σ²(1 − g) into each axis (g the low-pass' noise power gain), σ from third
/// differences, which see a 10–20 Hz wobble at a few % of its power. So an
/// axis wobbles when its power above f_split is kWobbleExcess times what its
/// white noise puts there and its excess RMS is at least kWobbleShare of the
/// axis' RMS. The cutoff is then kWobbleCutoffHz: Winter's range for gait is
/// 4–6 Hz, and on the real knee's 25 s walking windows the fit answers at 2–5
/// Hz and finds two valleys at 6 Hz. (A cutoff chosen from the spectrum did
/// not work there: the gait's harmonics and the wobble's tail fill 1–7 Hz
/// without a gap, 80–93 % of the power below 7 Hz lying below 4–5 Hz.)
#pragma once

#include <string>

#include "calibration/joint_samples.hpp"

namespace lieflow {
namespace calibration {

/// Where the motion's band ends and a wobble's begins [Hz].
constexpr double kWobbleSplitHz = 7.0;
/// Power above kWobbleSplitHz over white noise's there, for a wobble (white
/// noise alone: 1; the real knee's thigh 13–16, its broadband wobble inflating
/// the third differences too).
constexpr double kWobbleExcess = 4.0;
/// The excess' RMS over the axis' own RMS, for a wobble.
constexpr double kWobbleShare = 0.05;
/// The cutoff of a wobbling recording [Hz].
constexpr double kWobbleCutoffHz = 4.0;

struct LowPassChoice {
  double cutoff_hz = 0.0;  ///< 0: no filter
  std::string reason;
};

/// The choice for `samples` (both bodies' gyroscopes); no filter, saying why,
/// when no gyroscope wobbles, when there are no gyroscopes, or when the
/// sampling is not uniform, too slow for kWobbleSplitHz or too short to filter.
LowPassChoice chooseLowPass(const JointSamples& samples);

}  // namespace calibration
}  // namespace lieflow
