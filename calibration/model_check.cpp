#include "calibration/model_check.hpp"

#include <algorithm>
#include <cmath>

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
    pieces.push_back(segmentOf(samples, k * n / kModelSegments, (k + 1) * n / kModelSegments));
  return pieces;
}

ModelCheck checkAcrossPieces(const std::vector<JointSamples>& pieces, const PieceFit& fit,
                             const PieceDistance& distance, const Eigen::Vector3d& whole_main,
                             const Eigen::Vector3d& whole_secondary, const std::string& model,
                             const std::string& what, const std::string& whole, bool name_sources) {
  ModelCheck check;
  double sum = 0.0, d2[2] = {0.0, 0.0}, s2[2] = {0.0, 0.0};
  int answered = 0;
  for (const JointSamples& piece : pieces) {
    SegmentFit seg;
    seg.t_start = piece.time.empty() ? 0.0 : piece.time.front();
    seg.t_end = piece.time.empty() ? 0.0 : piece.time.back();
    if (name_sources) seg.source = piece.source;
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
      seg.why = std::string("not identifiable: ") + e.what();
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

}  // namespace calibration
}  // namespace lieflow
