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

ModelCheck checkHingeAcrossSegments(const JointSamples& samples, const AxisFitOptions& options,
                                    const Eigen::Vector3d& axis_main, const Eigen::Vector3d& axis_secondary) {
  ModelCheck check;
  const int n = samples.size();
  if (n < kModelSegments * kMinModelSegmentSamples) {
    check.note = "not checked across segments: " + std::to_string(n) + " samples, fewer than " +
                 std::to_string(kModelSegments) + " segments of " + std::to_string(kMinModelSegmentSamples);
    return check;
  }
  AxisFitOptions segment_options = options;
  segment_options.check_segments = false;
  segment_options.low_pass_auto = false;  // the whole fit's filter (options.low_pass_hz) or none
  segment_options.progress = nullptr;
  double sum = 0.0, d2[2] = {0.0, 0.0}, s2[2] = {0.0, 0.0};
  int answered = 0;
  for (int k = 0; k < kModelSegments; ++k) {
    const int begin = k * n / kModelSegments, end = (k + 1) * n / kModelSegments;
    SegmentFit seg;
    seg.t_start = samples.time[begin];
    seg.t_end = samples.time[end - 1];
    try {
      const HingeFit f = fitHinge(segmentOf(samples, begin, end), segment_options);
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
  if (answered < 2) {
    check.note = "not checked across segments: " + std::to_string(answered) + " of " +
                 std::to_string(kModelSegments) + " segments answered alone";
    return check;
  }
  check.ran = true;
  check.chi_square = sum / (2.0 * answered);
  check.disagree = check.chi_square > kSegmentChiSquare;
  if (check.disagree) {
    check.spread_main_deg = std::sqrt(std::max(0.0, (d2[0] - s2[0]) / answered));
    check.spread_secondary_deg = std::sqrt(std::max(0.0, (d2[1] - s2[1]) / answered));
    check.note = "the " + std::to_string(answered) + " segments that answered alone disagree beyond their sigma "
                 "(chi-square " + formatNumber(check.chi_square, 3) + " times its mean): one hinge does not describe "
                 "the whole recording; sigma includes their spread";
  } else {
    check.note = "the " + std::to_string(answered) + " segments that answered alone agree within their sigma "
                 "(chi-square " + formatNumber(check.chi_square, 3) + " times its mean)";
  }
  return check;
}

}  // namespace calibration
}  // namespace lieflow
