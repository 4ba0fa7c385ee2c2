#include "calibration/spring_start.hpp"
#include "liegroup/input_number.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <complex>
#include <numeric>

#include <Eigen/QR>

namespace lieflow {
namespace calibration {
namespace {

/// Hysteresis of the zero-crossing count, in units of the noise estimate.
constexpr double kCrossingHysteresis = 4.0;
/// Samples of the lagged recurrence per period (Δ ≈ T / kLagsPerPeriod).
constexpr double kLagsPerPeriod = 8.0;

/// Noise of a smooth signal from its second differences: Var(Δ²ε) = 6σ².
double noiseFromSecondDifferences(const std::vector<double>& x) {
  if (x.size() < 5) return 0.0;
  std::vector<double> d2;
  for (std::size_t j = 1; j + 1 < x.size(); ++j) d2.push_back(std::abs(x[j + 1] - 2.0 * x[j] + x[j - 1]));
  std::nth_element(d2.begin(), d2.begin() + d2.size() / 2, d2.end());
  // median |N(0, 6σ²)| = 0.6745 √6 σ
  return d2[d2.size() / 2] / (0.6745 * std::sqrt(6.0));
}

}  // namespace

SpringStart estimateSpringStart(const SpringJoint& joint, const SpringData& data, int coordinate) {
  SpringStart s;
  const std::vector<double>& x = data.angle[coordinate];
  const int n = static_cast<int>(x.size());
  if (n < 8) {
    s.why = "fewer than 8 samples";
    return s;
  }
  // Zero crossings of φ − mean, with hysteresis of a few noise σ.
  const double mean = std::accumulate(x.begin(), x.end(), 0.0) / n;
  const double band = kCrossingHysteresis * noiseFromSecondDifferences(x);
  std::vector<double> crossings;
  int side = 0;
  for (int j = 0; j < n; ++j) {
    const double v = x[j] - mean;
    const int now = v > band ? 1 : (v < -band ? -1 : 0);
    if (now != 0 && side != 0 && now != side) crossings.push_back(data.time[j]);
    if (now != 0) side = now;
  }
  if (crossings.size() < 3) {
    s.why = "the recorded angle crosses its mean " + std::to_string(crossings.size()) +
            " times (no oscillation to read a frequency from)";
    return s;
  }
  s.period = 2.0 * (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
  const double dt = (data.time.back() - data.time.front()) / (n - 1);
  s.lag = std::max(1, clampedInt(std::round(s.period / (kLagsPerPeriod * dt)), 1, INT_MAX / 4));
  const int d = s.lag;
  const int rows = n - 2 * d;
  if (rows < 4) {
    s.why = "the record is shorter than a quarter period";
    return s;
  }
  Eigen::MatrixXd A(rows, 3);
  Eigen::VectorXd y(rows);
  for (int j = 0; j < rows; ++j) {
    A(j, 0) = x[j + d];
    A(j, 1) = x[j];
    A(j, 2) = 1.0;
    y[j] = x[j + 2 * d];
  }
  const Eigen::Vector3d p = A.colPivHouseholderQr().solve(y);
  const double a1 = p[0], a2 = p[1], b = p[2];
  // z² − a₁ z − a₂ = 0 must have complex roots r e^{±iθ}.
  const double disc = a1 * a1 + 4.0 * a2;
  if (!(disc < 0.0) || !(-a2 > 0.0)) {
    s.why = "the lagged recurrence has real poles (no damped oscillation)";
    return s;
  }
  const double r = std::sqrt(-a2);
  const double theta = std::atan2(std::sqrt(-disc), a1);
  const double delta = d * dt;
  const std::complex<double> pole(std::log(r) / delta, theta / delta);
  s.natural_frequency = std::abs(pole);

  const double phi_eq = std::abs(1.0 - a1 - a2) > 1e-12 ? b / (1.0 - a1 - a2) : mean;
  Eigen::Vector2d at = joint.initial_angle;
  at[coordinate] = phi_eq;
  const double I = joint.inertiaAbout(coordinate, at);
  const double k_gravity = joint.gravityStiffness(coordinate, at);
  const double k_eff = I * std::norm(pole);
  s.stiffness = std::max(k_eff - k_gravity, 0.05 * k_eff);
  s.damping = std::max(-2.0 * I * pole.real(), 0.0);
  s.rest_angle = phi_eq - joint.gravityMoment(coordinate, at) / s.stiffness;
  s.found = true;
  return s;
}

}  // namespace calibration
}  // namespace lieflow
