/// \file
/// measureSpeed: std::chrono timing of each lieflow operation beside its Eigen
/// baseline (see speed_cases.hpp for exactly what is timed), and the table.
///
/// Method: inputs cycle through arrays of SpeedInputs::kSize random elements;
/// every result is added into a per-batch sink whose sum is written to a
/// volatile global, so no result can be optimized away (the additions are the
/// same for an operation and its baseline of the same result type, and a
/// floating-point sum cannot be reordered, so no loop is vectorized across
/// iterations). Each timed loop is its own non-inlined function. The
/// operation and its baseline are timed in many short interleaved pairs of
/// batches (kBatchSeconds each, alternating which goes first); the ratio is
/// the median of the paired ratios, the ns/op the medians of each side.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <iomanip>
#include <limits>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

#include "liegroup_measure/liegroup_measure.hpp"
#include "liegroup_measure/markdown_table.hpp"
#include "liegroup_measure/speed_cases.hpp"

#if defined(__GNUC__)
#define LIEFLOW_MEASURE_NOINLINE __attribute__((noinline))
#else
#define LIEFLOW_MEASURE_NOINLINE
#endif

namespace lieflow {
namespace measure {

namespace {

/// Length of one timed batch. Short, so that on a loaded machine most batches
/// run without being descheduled, and many, so that the median ignores those
/// that were: at 200 µs a batch spans a small part of a scheduler time slice.
constexpr double kBatchSeconds = 2e-4;

/// Bounds on the number of interleaved (operation, baseline) pairs.
constexpr int kMinRepetitions = 9;
constexpr int kMaxRepetitions = 2001;

/// Where every batch's sink ends up; volatile, so the sums must be computed.
volatile double g_sink = 0.0;

/// Accumulates every component of a result (Eigen matrices and vectors).
template <typename R>
struct Sink {
  R acc = R::Zero();
  void add(const R& r) { acc += r; }
  double total() const { return acc.sum(); }
};
template <>
struct Sink<Eigen::Quaterniond> {
  Eigen::Vector4d acc = Eigen::Vector4d::Zero();
  void add(const Eigen::Quaterniond& r) { acc += r.coeffs(); }
  double total() const { return acc.sum(); }
};
template <>
struct Sink<SO3d> {
  Eigen::Vector4d acc = Eigen::Vector4d::Zero();
  void add(const SO3d& r) { acc += r.quaternion().coeffs(); }
  double total() const { return acc.sum(); }
};
template <>
struct Sink<SE3d> {
  Eigen::Vector4d q = Eigen::Vector4d::Zero();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  void add(const SE3d& r) {
    q += r.quaternion().coeffs();
    t += r.translation();
  }
  double total() const { return q.sum() + t.sum(); }
};

/// ns per call of Case::run over `iterations` calls cycling through the inputs.
template <typename Case>
LIEFLOW_MEASURE_NOINLINE double timeBatch(const SpeedInputs& in, std::size_t iterations) {
  using Result = decltype(Case::run(in, 0));
  Sink<Result> sink;
  std::size_t i = 0;
  const auto start = std::chrono::steady_clock::now();
  for (std::size_t n = 0; n < iterations; ++n) {
    sink.add(Case::run(in, i));
    i = (i + 1) & SpeedInputs::kMask;
  }
  const auto stop = std::chrono::steady_clock::now();
  g_sink = g_sink + sink.total();
  return std::chrono::duration<double, std::nano>(stop - start).count() /
         static_cast<double>(iterations);
}

/// Iterations of Case so that one batch takes about `seconds` (at least one
/// pass over the inputs); also warms up caches, predictors and the clock rate.
template <typename Case>
std::size_t calibrate(const SpeedInputs& in, double seconds) {
  std::size_t iterations = SpeedInputs::kSize;
  double ns = timeBatch<Case>(in, iterations);
  for (int warm = 0; warm < 20 && ns * static_cast<double>(iterations) < seconds * 1e9; ++warm) {
    iterations *= 2;
    ns = timeBatch<Case>(in, iterations);
  }
  // Best of a few batches: the estimate of an undisturbed batch.
  for (int k = 0; k < 3; ++k) ns = std::min(ns, timeBatch<Case>(in, iterations));
  const double wanted = seconds * 1e9 / std::max(ns, 1e-3);
  return std::max<std::size_t>(SpeedInputs::kSize, static_cast<std::size_t>(wanted));
}

/// The q-quantile (0 ≤ q ≤ 1) of v, nearest rank.
double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  const std::size_t i = static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5);
  return v[std::min(i, v.size() - 1)];
}

double median(const std::vector<double>& v) { return quantile(v, 0.5); }

std::string formatFixed(double x, int digits) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << x;
  return s.str();
}

}  // namespace

const std::vector<SpeedTarget>& speedTargets() {
  static const std::vector<SpeedTarget> targets = {
      {"SO3 exp", "Eigen AngleAxis->Quaternion", 1.0, "1.36 / 1.32 / 0.97"},
      {"SO3 log", "Eigen Quaternion->AngleAxis", 1.0, "0.94 / 1.01 / 0.94"},
      {"SO3 compose", "Eigen quaternion product", 1.5, "2.9 / 8.0 / 5.5"},
      {"SO3 act", "Eigen quaternion*vector", 1.05, "1.03 / 4.2 / 1.2"},
      {"SO3 inverse", "Eigen quaternion conjugate", kNoTarget, ""},
      {"SO3 Jr", "Eigen AngleAxis->matrix", kNoTarget, ""},
      {"SO3 JrInv", "Eigen AngleAxis->matrix", kNoTarget, ""},
      {"SE3 exp", "Eigen AngleAxis->Quaternion", 2.5, "4.2 / 5.6 / 8.0"},
      {"SE3 log", "Eigen Quaternion->AngleAxis", 2.5, "3.5 / 4.8 / 5.4"},
      {"SE3 compose", "Eigen quaternion product", 3.0, "5.4 / 24 / 11"},
      {"SE3 act", "Eigen quaternion*vector", kNoTarget, ""},
  };
  return targets;
}

bool SpeedRow::hasTarget() const { return !std::isnan(max_ratio); }
bool SpeedRow::pass() const { return !hasTarget() || ratio <= max_ratio; }

std::vector<SpeedRow> measureSpeed(double seconds_per_op) {
  const SpeedInputs in(SpeedInputs::kDefaultSeed);
  const double wanted = std::max(seconds_per_op, 0.0) / kBatchSeconds;
  int repetitions = static_cast<int>(std::min<double>(wanted, kMaxRepetitions));
  repetitions = std::max(repetitions, kMinRepetitions) | 1;  // odd: the median is a sample
  std::vector<SpeedRow> rows;
  forEachSpeedPair([&](auto op, auto base, const SpeedTarget& target) {
    using Op = decltype(op);
    using Base = decltype(base);
    const std::size_t n_op = calibrate<Op>(in, kBatchSeconds);
    const std::size_t n_base = calibrate<Base>(in, kBatchSeconds);
    std::vector<double> t_op, t_base, ratios;
    for (int r = 0; r < repetitions; ++r) {
      double a, b;
      if (r % 2 == 0) {
        a = timeBatch<Op>(in, n_op);
        b = timeBatch<Base>(in, n_base);
      } else {
        b = timeBatch<Base>(in, n_base);
        a = timeBatch<Op>(in, n_op);
      }
      t_op.push_back(a);
      t_base.push_back(b);
      ratios.push_back(a / b);
    }
    SpeedRow row;
    row.operation = target.operation;
    row.baseline = target.baseline;
    row.ns_per_op = median(t_op);
    row.baseline_ns_per_op = median(t_base);
    row.ratio = median(ratios);
    row.ratio_q1 = quantile(ratios, 0.25);
    row.ratio_q3 = quantile(ratios, 0.75);
    row.repetitions = repetitions;
    row.max_ratio = target.max_ratio;
    row.others = target.others;
    rows.push_back(row);
  });
  return rows;
}

void printSpeedTable(std::ostream& out, const std::vector<SpeedRow>& rows) {
  const std::vector<std::string> header = {
      "operation", "ns/op", "Eigen baseline", "ns/op", "ratio", "ratio IQR",
      "target", "result", "Sophus / manif / smooth"};
  std::vector<std::vector<std::string>> cells;
  for (const SpeedRow& r : rows) {
    cells.push_back({r.operation, formatFixed(r.ns_per_op, 2), r.baseline,
                     formatFixed(r.baseline_ns_per_op, 2), formatFixed(r.ratio, 2),
                     formatFixed(r.ratio_q1, 2) + "-" + formatFixed(r.ratio_q3, 2),
                     r.hasTarget() ? "<= " + formatFixed(r.max_ratio, 2) : "-",
                     r.hasTarget() ? (r.pass() ? "PASS" : "MISS") : "-",
                     r.others.empty() ? "-" : r.others});
  }
  detail::printMarkdownTable(out, header, cells, {1, 3, 4, 5});
  if (!rows.empty()) {
    out << "\nratio = lieflow time / Eigen time, median over " << rows.front().repetitions
        << " back-to-back pairs of batches in this run (IQR: 25th-75th percentile of the"
           " pairs); ns/op = median per side; Sophus / manif / smooth: their ratios to the"
           " same baselines, measured elsewhere (context). "
        << buildDescription() << ".\n";
  }
}

std::string buildDescription() {
  std::ostringstream s;
#if defined(__clang__)
  s << "clang " << __clang_major__ << "." << __clang_minor__ << "." << __clang_patchlevel__;
#elif defined(__GNUC__)
  s << "g++ " << __GNUC__ << "." << __GNUC_MINOR__ << "." << __GNUC_PATCHLEVEL__;
#else
  s << "unknown compiler";
#endif
#ifdef LIEFLOW_MEASURE_CXX_FLAGS
  s << ", flags \"" << LIEFLOW_MEASURE_CXX_FLAGS << "\"";
#endif
#ifdef NDEBUG
  s << ", NDEBUG";
#else
  s << ", assertions on (not a Release build: timings are not representative)";
#endif
  return s.str();
}

}  // namespace measure
}  // namespace lieflow
