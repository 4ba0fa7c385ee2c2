#include "calibration/hinge_segments.hpp"

#include <algorithm>
#include <cmath>

#include "calibration/hinge_fit.hpp"
#include "calibration/identifiability.hpp"
#include "calibration/unit_axis.hpp"
#include "liegroup/invalid_input.hpp"
#include "liegroup/number_text.hpp"

namespace lieflow {
namespace calibration {

namespace {

template <class T>
std::vector<T> slice(const std::vector<T>& v, int begin, int end) {
  return v.empty() ? v : std::vector<T>(v.begin() + begin, v.begin() + end);
}

JointSamples segmentOf(const JointSamples& s, int begin, int end) {
  JointSamples out;
  out.source = s.source;
  out.time = slice(s.time, begin, end);
  for (int b = 0; b < 2; ++b) {
    const BodySamples& from = b == 0 ? s.main : s.secondary;
    BodySamples& to = b == 0 ? out.main : out.secondary;
    to.name = from.name;
    to.orientation = slice(from.orientation, begin, end);
    to.angular_velocity = slice(from.angular_velocity, begin, end);
    to.specific_force = slice(from.specific_force, begin, end);
  }
  return out;
}

}  // namespace

namespace {

/// Fits each piece alone with `options` (no filter choice of its own, no
/// check of its own) and compares its axes with the whole fit's (the χ² of
/// the file comment); `what` names the pieces in the notes ("segments").
ModelCheck checkPieces(const std::vector<JointSamples>& pieces, const AxisFitOptions& options,
                       const Eigen::Vector3d& axis_main, const Eigen::Vector3d& axis_secondary, const std::string& what,
                       bool name_sources) {
  ModelCheck check;
  AxisFitOptions piece_options = options;
  piece_options.check_segments = false;
  piece_options.low_pass_auto = false;  // the whole fit's filter (options.low_pass_hz) or none
  piece_options.progress = nullptr;
  double sum = 0.0, d2[2] = {0.0, 0.0}, s2[2] = {0.0, 0.0};
  int answered = 0;
  for (const JointSamples& piece : pieces) {
    SegmentFit seg;
    seg.t_start = piece.time.front();
    seg.t_end = piece.time.back();
    if (name_sources) seg.source = piece.source;
    try {
      const HingeFit f = fitHinge(piece, piece_options);
      seg.answered = true;
      seg.axis_main = f.axis_main;
      seg.axis_secondary = f.axis_secondary;
      seg.sigma_main_deg = f.sigma_main_deg;
      seg.sigma_secondary_deg = f.sigma_secondary_deg;
      seg.apart_main_deg = angleBetweenLines(f.axis_main, axis_main) * kRadToDeg;
      seg.apart_secondary_deg = angleBetweenLines(f.axis_secondary, axis_secondary) * kRadToDeg;
      const double d[2] = {seg.apart_main_deg, seg.apart_secondary_deg};
      const double s[2] = {seg.sigma_main_deg, seg.sigma_secondary_deg};
      for (int a = 0; a < 2; ++a) {
        sum += s[a] > 0.0 ? d[a] * d[a] / (s[a] * s[a]) : 0.0;
        d2[a] += d[a] * d[a];
        s2[a] += s[a] * s[a];
      }
      ++answered;
    } catch (const NotIdentifiable& e) {
      seg.why = std::string("not identifiable: ") + e.what();
    } catch (const InvalidInput& e) {
      seg.why = e.what();
    } catch (const FitFailed& e) {
      seg.why = e.what();
    }
    check.segments.push_back(seg);
  }
  const std::string count = std::to_string(answered) + " of " + std::to_string(pieces.size()) + " " + what;
  if (answered < 2) {
    check.note = "not checked across " + what + ": " + count + " answered alone";
    return check;
  }
  check.ran = true;
  check.chi_square = sum / (2.0 * answered);
  check.disagree = check.chi_square > kSegmentChiSquare;
  if (check.disagree) {
    check.spread_main_deg = std::sqrt(std::max(0.0, (d2[0] - s2[0]) / answered));
    check.spread_secondary_deg = std::sqrt(std::max(0.0, (d2[1] - s2[1]) / answered));
    check.note = "the " + std::to_string(answered) + " " + what + " that answered alone disagree beyond their sigma "
                 "(chi-square " + formatNumber(check.chi_square, 3) + " times its mean): one hinge does not describe " +
                 (name_sources ? "all the recordings" : "the whole recording") + "; sigma includes their spread";
  } else {
    check.note = "the " + std::to_string(answered) + " " + what + " that answered alone agree within their sigma "
                 "(chi-square " + formatNumber(check.chi_square, 3) + " times its mean)";
  }
  return check;
}

}  // namespace

ModelCheck checkHingeAcrossSegments(const JointSamples& samples, const AxisFitOptions& options,
                                    const Eigen::Vector3d& axis_main, const Eigen::Vector3d& axis_secondary) {
  const int n = samples.size();
  if (n < kModelSegments * kMinModelSegmentSamples) {
    ModelCheck check;
    check.note = "not checked across segments: " + std::to_string(n) + " samples, fewer than " +
                 std::to_string(kModelSegments) + " segments of " + std::to_string(kMinModelSegmentSamples);
    return check;
  }
  std::vector<JointSamples> pieces;
  for (int k = 0; k < kModelSegments; ++k) pieces.push_back(segmentOf(samples, k * n / kModelSegments, (k + 1) * n / kModelSegments));
  return checkPieces(pieces, options, axis_main, axis_secondary, "segments", false);
}

ModelCheck checkHingeAcrossRecordings(const std::vector<JointSamples>& recordings, const AxisFitOptions& options,
                                      const Eigen::Vector3d& axis_main, const Eigen::Vector3d& axis_secondary) {
  return checkPieces(recordings, options, axis_main, axis_secondary, "recordings", true);
}

}  // namespace calibration
}  // namespace lieflow
