/// \file
/// A fit checks its own model across the recording (issue 31): the
/// recording is split into segments (by time: kModelSegments quarters; by
/// activity: its parts between the middles of its rests, activity_segments.hpp; or,
/// for a fit over several recordings, one segment per recording), each is
/// fitted alone with the same options, and each segment's answer — two
/// vectors, one per body (a hinge's or a universal joint's axes, a ball
/// joint's anchors) — is compared with the whole fit's. If one model
/// describes the recording, the segments scatter about the whole by their
/// own σ, so
///   χ² = Σ_segments (d₁,ᵢ/σ₁,ᵢ)² + (d₂,ᵢ/σ₂,ᵢ)²
/// (d the distance of a segment's vector from the whole fit's — the angle
/// between lines for axes, the distance between points for anchors — and
/// σ the segment's RMS error of it: each term 1 on average) stays near 2K.
/// Above kSegmentChiSquare × 2K the segments disagree: the excess spread
///   s² = max(0, mean(d²) − mean(σ²)) per body
/// is what one model leaves unexplained across the recording, and the whole
/// fit's σ becomes √(σ² + s²) (`model_spread_deg`, or `model_spread_m` for
/// anchors, = the larger s). The segments' spans and answers are reported
/// either way (`segments`).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "calibration/joint_samples.hpp"

namespace lieflow {
namespace calibration {

/// Segments by time.
constexpr int kModelSegments = 4;
/// Fewest samples a segment by time must have for the check to run.
constexpr int kMinModelSegmentSamples = 250;
/// χ² over its mean (2 per segment that answered) above which the segments
/// disagree (χ² of 8 degrees of freedom: 3.3 times its mean is the 0.1 %
/// tail; the segments' σ are estimates, so the bound is kept wide).
constexpr double kSegmentChiSquare = 3.0;

/// One segment's answer: its two vectors (axes or anchors, in each body's
/// frame), their σ and their distance from the whole fit's, in the check's
/// unit (degrees for axes, metres for anchors).
struct SegmentFit {
  double t_start = 0.0, t_end = 0.0;
  std::string source;  ///< the recording (a fit over several recordings: one segment per recording)
  /// What cut it: "time" (a quarter), "activity" (a part between the middles
  /// of rests, activity_segments.hpp) or "recording" (one of several).
  std::string by = "time";
  bool answered = false;
  std::string why;  ///< why not, when it did not answer
  Eigen::Vector3d main = Eigen::Vector3d::Zero(), secondary = Eigen::Vector3d::Zero();
  double sigma_main = 0.0, sigma_secondary = 0.0;
  double apart_main = 0.0, apart_secondary = 0.0;
};

struct ModelCheck {
  bool ran = false;
  std::string note;  ///< why it did not run, or what it found
  std::vector<SegmentFit> segments;
  double chi_square = 0.0;  ///< over its mean
  bool disagree = false;
  double spread_main = 0.0, spread_secondary = 0.0;  ///< s of each vector (0 unless disagree)

  /// √(σ² + s²) for the vector of `body` (0 main, 1 secondary).
  double widened(double sigma, int body) const;
};

/// What a segment's own fit answers.
struct PieceAnswer {
  Eigen::Vector3d main, secondary;
  double sigma_main = 0.0, sigma_secondary = 0.0;
};

/// How far a segment's vector lies from the whole fit's, in the check's unit.
using PieceDistance = std::function<double(const Eigen::Vector3d& piece, const Eigen::Vector3d& whole)>;
/// The fit of one segment; throws NotIdentifiable, InvalidInput or FitFailed
/// when the segment does not answer (reported with the reason).
using PieceFit = std::function<PieceAnswer(const JointSamples& piece)>;

/// The recording's kModelSegments quarters by time, or none when a quarter
/// would have fewer than `min_samples` (then *why says so).
std::vector<JointSamples> timeSegments(const JointSamples& samples, std::string* why,
                                       int min_samples = kMinModelSegmentSamples);

/// The check of the file comment over `pieces` against the whole fit's
/// vectors. `model` names the joint in the note ("hinge"), `what` the pieces
/// ("segments", "recordings"), `whole` what one joint should describe ("the
/// whole recording"); `by` is each segment's SegmentFit::by (with
/// "recording" each keeps its recording's name).
ModelCheck checkAcrossPieces(const std::vector<JointSamples>& pieces, const PieceFit& fit,
                             const PieceDistance& distance, const Eigen::Vector3d& whole_main,
                             const Eigen::Vector3d& whole_secondary, const std::string& model,
                             const std::string& what, const std::string& whole, const std::string& by);

/// The check of one recording's fit, by time and by activity: its quarters
/// (timeSegments) and its parts by activity (activityParts, those of at
/// least `min_samples`, when a rest divides the recording), each set
/// checked as checkAcrossPieces does; the two are merged (both sets in
/// `segments`, `by` telling them apart; disagreement where either set
/// disagrees; each vector's spread the larger of the two). Quarters that
/// each mix two activities can agree while the activities do not.
ModelCheck checkAcrossRecording(const JointSamples& samples, const PieceFit& fit, const PieceDistance& distance,
                                const Eigen::Vector3d& whole_main, const Eigen::Vector3d& whole_secondary,
                                const std::string& model, int min_samples = kMinModelSegmentSamples);

/// The angle between two lines, in degrees (an axis and its opposite are one line).
double lineDistanceDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b);

}  // namespace calibration
}  // namespace lieflow
