#include "calibration/hinge_sign.hpp"

#include <algorithm>
#include <cmath>
#include <complex>

#include "calibration/unit_axis.hpp"

namespace lieflow {
namespace calibration {
namespace {

using Complex = std::complex<double>;

/// Circular variance of the phase test for j₂ → sign · j₂.
double phaseSpread(const std::vector<double>& time, const std::vector<Eigen::Vector3d>& w1,
                   const std::vector<Eigen::Vector3d>& w2, const Eigen::Vector3d& j1, const Eigen::Vector3d& j2,
                   double sign) {
  const Eigen::Vector3d e1 = orthogonalUnit(j1), f1 = j1.cross(e1);
  const Eigen::Vector3d e2 = orthogonalUnit(j2), f2 = j2.cross(e2);
  double total_weight = 0.0, resultant = 0.0, integral = 0.0, previous_rate = 0.0;
  Complex window_sum = 0.0;
  double window_start = time.empty() ? 0.0 : time.front();
  for (std::size_t k = 0; k < time.size(); ++k) {
    const double rate = sign * w2[k].dot(j2) - w1[k].dot(j1);
    if (k > 0) integral += 0.5 * (rate + previous_rate) * (time[k] - time[k - 1]);
    previous_rate = rate;
    if (time[k] - window_start >= kSignWindowSeconds) {
      resultant += std::abs(window_sum);
      window_sum = 0.0;
      window_start = time[k];
    }
    const Complex z1(e1.dot(w1[k]), f1.dot(w1[k]));
    // Basis (e₂, sign·f₂, sign·j₂): the f-coordinate takes the sign.
    const Complex z2(e2.dot(w2[k]), sign * f2.dot(w2[k]));
    const double weight = std::min(std::norm(z1), std::norm(z2));
    if (!(weight > 0.0)) continue;
    const double phase = std::arg(z1 * std::conj(z2)) - integral;
    window_sum += weight * std::polar(1.0, phase);
    total_weight += weight;
  }
  resultant += std::abs(window_sum);
  return total_weight > 0.0 ? 1.0 - resultant / total_weight : 1.0;
}

}  // namespace

HingeSignEvidence hingeSignFromSpreads(double spread_same, double spread_flipped) {
  HingeSignEvidence e;
  e.spread_same = spread_same;
  e.spread_flipped = spread_flipped;
  const double low = std::min(e.spread_same, e.spread_flipped);
  const double high = std::max(e.spread_same, e.spread_flipped);
  e.decided = low < kSignDecisionRatio * high;
  e.relative_sign = e.decided && e.spread_flipped < e.spread_same ? -1 : 1;
  return e;
}

HingeSignEvidence hingeRelativeSign(const std::vector<double>& time, const std::vector<Eigen::Vector3d>& w1,
                                    const std::vector<Eigen::Vector3d>& w2, const Eigen::Vector3d& j1,
                                    const Eigen::Vector3d& j2) {
  return hingeSignFromSpreads(phaseSpread(time, w1, w2, j1, j2, 1.0), phaseSpread(time, w1, w2, j1, j2, -1.0));
}

}  // namespace calibration
}  // namespace lieflow
