#include "calibration/clock_offset.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "calibration/data_selection.hpp"
#include "calibration/hinge_initial.hpp"
#include "calibration/hinge_search.hpp"
#include "liegroup/number_text.hpp"

namespace lieflow {
namespace calibration {
namespace {

/// Shifts searched: |m h| ≤ max_offset, and at most half the record.
int reachOf(const JointSamples& samples, double max_offset) {
  const int n = samples.size();
  if (n < 2) return 0;  // no interval: no shift
  const double h = samples.meanStep();
  // In double first: a recording's step can make the quotient exceed an int.
  return static_cast<int>(std::min(std::floor(max_offset / h), static_cast<double>(n / 2)));
}

}  // namespace

void pairedRates(const JointSamples& samples, int m, std::vector<Eigen::Vector3d>* a, std::vector<Eigen::Vector3d>* b) {
  const int n = samples.size();
  a->clear();
  b->clear();
  for (int k = std::max(0, m); k < n && k - m < n; ++k) {
    a->push_back(samples.main.angular_velocity[static_cast<std::size_t>(k)]);
    b->push_back(samples.secondary.angular_velocity[static_cast<std::size_t>(k - m)]);
  }
}

int wholeSampleOffset(const JointSamples& samples, double max_offset) {
  const int n = samples.size();
  const double h = samples.meanStep();
  const int reach = reachOf(samples, max_offset);
  std::vector<Eigen::Vector3d> a, b;
  const auto meanCost = [&](const AxisPair& axes) { return hingeRateCost(a, b, axes) / static_cast<double>(a.size()); };
  int best = 0;
  double best_cost = std::numeric_limits<double>::infinity();
  for (int m = -reach; m <= reach; ++m) {
    pairedRates(samples, m, &a, &b);
    const double cost = meanCost(hingeAxesFromRates(a, b));
    if (cost < best_cost) {
      best_cost = cost;
      best = m;
    }
  }
  std::vector<double> costs(static_cast<std::size_t>(2 * reach + 1));
  bool have_costs = false;
  for (int round = 0; round < kOffsetRounds; ++round) {
    pairedRates(samples, best, &a, &b);
    const std::vector<HingeMinimum> minima = hingeMinimaFromRates(a, b, hingeStartsFromRates(a, b));
    if (minima.empty()) break;
    const AxisPair axes = minima.front().axes;
    int next = -reach;
    for (int m = -reach; m <= reach; ++m) {
      pairedRates(samples, m, &a, &b);
      costs[static_cast<std::size_t>(m + reach)] = meanCost(axes);
      if (costs[static_cast<std::size_t>(m + reach)] < costs[static_cast<std::size_t>(next + reach)]) next = m;
    }
    have_costs = true;
    if (next == best) break;
    best = next;
  }
  // Another shift that fits about as well?
  const double noise = 0.5 * (std::pow(whiteNoiseFromDifferences(samples.main.angular_velocity), 2) +
                              std::pow(whiteNoiseFromDifferences(samples.secondary.angular_velocity), 2));
  if (noise > 0.0 && have_costs)
    for (int m = -reach; m <= reach; ++m) {
      if (std::abs(m - best) <= 1) continue;
      const double delta = (n - std::abs(best)) *
                           (costs[static_cast<std::size_t>(m + reach)] - costs[static_cast<std::size_t>(best + reach)]) / noise;
      if (delta < kOffsetAmbiguity)
        throw NotIdentifiable("clock offsets of " + formatNumber(best * h) + " s and " + formatNumber(m * h) +
                              " s fit the gyroscopes about as well (Δχ² = " + formatNumber(delta) +
                              "): a longer or more varied recording is needed to find the offset");
    }
  return best;
}

std::vector<double> shiftCosts(const JointSamples& samples, const AxisPair& axes, const Eigen::Vector3d& bias_main,
                               const Eigen::Vector3d& bias_secondary, double max_offset) {
  const int reach = reachOf(samples, max_offset);
  std::vector<Eigen::Vector3d> a, b;
  std::vector<double> costs;
  for (int m = -reach; m <= reach; ++m) {
    pairedRates(samples, m, &a, &b);
    for (Eigen::Vector3d& w : a) w -= bias_main;
    for (Eigen::Vector3d& w : b) w -= bias_secondary;
    costs.push_back(hingeRateCost(a, b, axes) / static_cast<double>(a.size()));
  }
  return costs;
}

}  // namespace calibration
}  // namespace lieflow
