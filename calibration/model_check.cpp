#include "calibration/model_check.hpp"

#include <algorithm>
#include <cmath>

#include "calibration/activity_segments.hpp"
#include "calibration/identifiability.hpp"
#include "calibration/unit_axis.hpp"
#include "liegroup/invalid_input.hpp"
#include "liegroup/number_text.hpp"

namespace lieflow {
namespace calibration {

namespace {

/// Both checks of one recording in one: the segments of each, disagreement
/// where either disagrees, each vector's spread and χ² the larger.
ModelCheck merged(ModelCheck by_time, const ModelCheck& by_activity) {
  ModelCheck out = std::move(by_time);
  out.note = "by time: " + out.note + "; by activity: " + by_activity.note;
  out.segments.insert(out.segments.end(), by_activity.segments.begin(), by_activity.segments.end());
  if (!by_activity.ran) return out;
  out.ran = true;
  out.chi_square = std::max(out.chi_square, by_activity.chi_square);
  out.disagree = out.disagree || by_activity.disagree;
  out.spread_main = std::max(out.spread_main, by_activity.spread_main);
  out.spread_secondary = std::max(out.spread_secondary, by_activity.spread_secondary);
  return out;
}

}  // namespace

double ModelCheck::widened(double sigma, int body) const {
  return disagree ? std::hypot(sigma, body == 0 ? spread_main : spread_secondary) : sigma;
}

double lineDistanceDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return angleBetweenLines(a, b) * kRadToDeg;
}

std::vector<JointSamples> timeSegments(const JointSamples& samples, std::string* why, int min_samples) {
  const int n = samples.size();
  if (n < kModelSegments * min_samples) {
    *why = std::to_string(n) + " samples, fewer than " + std::to_string(kModelSegments) + " segments of " +
           std::to_string(min_samples);
    return {};
  }
  std::vector<JointSamples> pieces;
  for (int k = 0; k < kModelSegments; ++k)
    pieces.push_back(samplesBetween(samples, k * n / kModelSegments, (k + 1) * n / kModelSegments));
  return pieces;
}

ModelCheck checkAcrossPieces(const std::vector<JointSamples>& pieces, const PieceFit& fit,
                             const PieceDistance& distance, const Eigen::Vector3d& whole_main,
                             const Eigen::Vector3d& whole_secondary, const std::string& model,
                             const std::string& what, const std::string& whole, const std::string& by) {
  ModelCheck check;
  double sum = 0.0, d2[2] = {0.0, 0.0}, s2[2] = {0.0, 0.0};
  int answered = 0;
  for (const JointSamples& piece : pieces) {
    SegmentFit seg;
    seg.t_start = piece.time.empty() ? 0.0 : piece.time.front();
    seg.t_end = piece.time.empty() ? 0.0 : piece.time.back();
    seg.by = by;
    if (by == "recording") seg.source = piece.source;
    try {
      const PieceAnswer f = fit(piece);
      seg.answered = true;
      seg.main = f.main;
      seg.secondary = f.secondary;
      seg.sigma_main = f.sigma_main;
      seg.sigma_secondary = f.sigma_secondary;
      seg.apart_main = distance(f.main, whole_main);
      seg.apart_secondary = distance(f.secondary, whole_secondary);
      const double d[2] = {seg.apart_main, seg.apart_secondary};
      const double s[2] = {seg.sigma_main, seg.sigma_secondary};
      for (int a = 0; a < 2; ++a) {
        sum += s[a] > 0.0 ? d[a] * d[a] / (s[a] * s[a]) : 0.0;
        d2[a] += d[a] * d[a];
        s2[a] += s[a] * s[a];
      }
      ++answered;
    } catch (const NotIdentifiable& e) {
      seg.why = e.what();  // "not identifiable: …"
    } catch (const InvalidInput& e) {
      seg.why = e.what();
    } catch (const FitFailed& e) {
      seg.why = e.what();
    }
    check.segments.push_back(seg);
  }
  if (answered < 2) {
    check.note = "not checked across " + what + ": " + std::to_string(answered) + " of " +
                 std::to_string(pieces.size()) + " " + what + " answered alone";
    return check;
  }
  check.ran = true;
  check.chi_square = sum / (2.0 * answered);
  check.disagree = check.chi_square > kSegmentChiSquare;
  if (check.disagree) {
    check.spread_main = std::sqrt(std::max(0.0, (d2[0] - s2[0]) / answered));
    check.spread_secondary = std::sqrt(std::max(0.0, (d2[1] - s2[1]) / answered));
    check.note = "the " + std::to_string(answered) + " " + what + " that answered alone disagree beyond their sigma " +
                 "(chi-square " + formatNumber(check.chi_square, 3) + " times its mean): one " + model + " does not describe " +
                 whole + "; sigma includes their spread";
  } else {
    check.note = "the " + std::to_string(answered) + " " + what + " that answered alone agree within their sigma " +
                 "(chi-square " + formatNumber(check.chi_square, 3) + " times its mean)";
  }
  return check;
}

ModelCheck checkAcrossRecording(const JointSamples& samples, const PieceFit& fit, const PieceDistance& distance,
                                const Eigen::Vector3d& whole_main, const Eigen::Vector3d& whole_secondary,
                                const std::string& model, int min_samples) {
  const std::string whole = "the whole recording";
  std::string why;
  const std::vector<JointSamples> quarters = timeSegments(samples, &why, min_samples);
  ModelCheck by_time;
  if (quarters.empty())
    by_time.note = "not checked across segments: " + why;
  else
    by_time = checkAcrossPieces(quarters, fit, distance, whole_main, whole_secondary, model, "segments", whole, "time");
  // By activity: the parts between the middles of rests, each long enough.
  const std::vector<SampleSpan> parts = activityParts(samples);
  std::vector<JointSamples> pieces;
  if (parts.size() >= 2)  // (one part: the whole recording, not copied)
    for (const SampleSpan& p : parts)
      if (p.end - p.begin >= min_samples) pieces.push_back(samplesBetween(samples, p.begin, p.end));
  ModelCheck by_activity;
  if (parts.size() < 2)
    by_activity.note = "not checked: no rest of " + formatNumber(kMinRestSeconds) + " s divides the recording";
  else if (pieces.size() < 2)
    by_activity.note = "not checked: " + std::to_string(pieces.size()) + " of " + std::to_string(parts.size()) +
                       " parts between rests have " + std::to_string(min_samples) + " samples";
  else
    by_activity = checkAcrossPieces(pieces, fit, distance, whole_main, whole_secondary, model, "parts between rests",
                                    whole, "activity");
  return merged(std::move(by_time), by_activity);
}

}  // namespace calibration
}  // namespace lieflow

