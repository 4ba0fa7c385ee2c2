/// \file
/// Starting points from a linear relaxation whose null vector can be
/// ambiguous.
///
/// The closed forms of hinge_initial.hpp and universal_initial.hpp take the
/// eigenvector of the smallest eigenvalue of a Gram matrix G = Σ rowᵀrow. When
/// the motion excites the relaxation weakly in some direction, the second (or
/// third) eigenvalue is close to the first and noise mixes the eigenvectors: the
/// true solution is then some unit combination of them, not the first alone
/// (seen: λ₂ = 1.2 λ₁ at σ = 0.1 rad/s, the first eigenvector 62° off, and a
/// refinement from it ending in a local minimum). So all eigenvectors with
/// λᵢ ≤ kNearNullRatio · λ₁ (at most three) span the candidates: a half circle
/// (two) or a hemisphere (three) of unit combinations, each turned into axes
/// and ranked by the fit's own cost; the best kMaxStarts mutually distinct
/// ones start the refinement. A well-separated null vector (or exact data)
/// gives the closed form alone.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include <Eigen/Eigenvalues>

#include "calibration/fit_types.hpp"
#include "calibration/unit_axis.hpp"
#include "liegroup/scalar.hpp"

namespace lieflow {
namespace calibration {

/// Eigenvalues within this factor of the smallest count as near-null.
constexpr double kNearNullRatio = 20.0;
/// Below this fraction of the largest eigenvalue, the smallest one is taken as 0.
constexpr double kNullFloor = 1e-12;
/// Candidates per half circle; the hemisphere uses kCircleSteps² / 4 of them.
constexpr int kCircleSteps = 24;
/// Starts handed to the refinement at most.
constexpr int kMaxStarts = 3;
/// Candidates whose axes both lie within this angle of a better one are dropped (deg).
constexpr double kDistinctStartDeg = 5.0;

/// The starts for the linear relaxation with Gram matrix G; `toAxes` turns a
/// unit null-vector candidate into axes, `cost` ranks axes (lower is better).
template <int N>
std::vector<AxisPair> nullspaceStarts(const Eigen::Matrix<double, N, N>& G,
                                      const std::function<AxisPair(const Eigen::Matrix<double, N, 1>&)>& toAxes,
                                      const std::function<double(const AxisPair&)>& cost) {
  using Vector = Eigen::Matrix<double, N, 1>;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> eig(G);
  const auto& lambda = eig.eigenvalues();
  const double floor = kNullFloor * std::max(lambda[N - 1], 0.0);
  const double limit = kNearNullRatio * std::max(lambda[0], floor);
  int near_null = 1;
  while (near_null < 3 && lambda[near_null] <= limit) ++near_null;
  if (near_null == 1) return {toAxes(eig.eigenvectors().col(0))};

  // Unit combinations: a half circle, or a Fibonacci hemisphere.
  std::vector<Vector> candidates;
  const double pi = kPi;
  if (near_null == 2) {
    for (int i = 0; i < kCircleSteps; ++i) {
      const double a = pi * i / kCircleSteps;
      candidates.push_back(std::cos(a) * eig.eigenvectors().col(0) + std::sin(a) * eig.eigenvectors().col(1));
    }
  } else {
    const int n = kCircleSteps * kCircleSteps / 4;
    const double golden = pi * (3.0 - std::sqrt(5.0));
    for (int i = 0; i < n; ++i) {
      const double z = 1.0 - (i + 0.5) / n;  // (0, 1]: the upper hemisphere (x and −x are one candidate)
      const double r = std::sqrt(1.0 - z * z), phi = golden * i;
      candidates.push_back(z * eig.eigenvectors().col(0) + r * std::cos(phi) * eig.eigenvectors().col(1) +
                           r * std::sin(phi) * eig.eigenvectors().col(2));
    }
  }
  using Ranked = std::pair<double, AxisPair>;
  std::vector<Ranked> ranked;
  for (const Vector& x : candidates) {
    const AxisPair axes = toAxes(x);
    ranked.emplace_back(cost(axes), axes);
  }
  std::sort(ranked.begin(), ranked.end(), [](const Ranked& a, const Ranked& b) { return a.first < b.first; });
  std::vector<AxisPair> starts;
  for (const auto& candidate : ranked) {
    const AxisPair& c = candidate.second;
    bool distinct = true;
    for (const AxisPair& s : starts)
      distinct = distinct && (angleBetweenLines(c.axis1, s.axis1) * kRadToDeg > kDistinctStartDeg ||
                              angleBetweenLines(c.axis2, s.axis2) * kRadToDeg > kDistinctStartDeg);
    if (distinct) starts.push_back(c);
    if (static_cast<int>(starts.size()) == kMaxStarts) break;
  }
  return starts;
}

}  // namespace calibration
}  // namespace lieflow
