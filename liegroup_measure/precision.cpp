/// \file
/// measurePrecision: the largest error of lieflow's exp/log round trips, of
/// exp against a long-double reference and of Jr·Jr⁻¹ per angle band, beside
/// the same round trip done with Eigen's AngleAxis; and the table.
///
/// References are independent of lieflow's formulas: the round trips compare
/// with the input itself, Jr·Jr⁻¹ with I, and exp with
///   q_ref = (cos(θ/2), sin(θ/2)/θ · w),  θ = ‖w‖,
/// evaluated in long double (x87 extended, 64-bit mantissa: ~1e-19 relative)
/// from the double components of w.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <ostream>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "liegroup_measure/liegroup_measure.hpp"
#include "liegroup_measure/markdown_table.hpp"
#include "liegroup/se3.hpp"
#include "liegroup/so3.hpp"

namespace lieflow {
namespace measure {

namespace {

constexpr double kPi = 3.14159265358979323846;

/// Targets (bench/README.md): SO(3) error ≤ 2e-15·max(1, ‖w‖), SE(3) ≤ 1e-14.
constexpr double kSO3Target = 2e-15;
constexpr double kSE3Target = 1e-14;

/// The angle bands: names and samplers of θ.
enum Band { kTiny = 0, kSmall, kGeneric, kNearPi, kBandCount };

const char* bandName(int band) {
  switch (band) {
    case kTiny: return "θ ∈ [1e-12, 1e-8]";
    case kSmall: return "θ ∈ [1e-8, 1e-4]";
    case kGeneric: return "θ ∈ (0, π)";
    default: return "π − θ ∈ [1e-8, 1e-3]";
  }
}

/// θ = 10^u, u uniform in [lo, hi] (log-uniform in [10^lo, 10^hi]).
double logUniform(std::mt19937_64& gen, double lo, double hi) {
  return std::pow(10.0, std::uniform_real_distribution<double>(lo, hi)(gen));
}

double sampleAngle(int band, std::mt19937_64& gen) {
  switch (band) {
    case kTiny: return logUniform(gen, -12.0, -8.0);
    case kSmall: return logUniform(gen, -8.0, -4.0);
    case kGeneric: {
      std::uniform_real_distribution<double> unit(0.0, 1.0);
      double theta;
      do {
        theta = kPi * unit(gen);
      } while (theta <= 0.0);
      return theta;
    }
    default: return kPi - logUniform(gen, -8.0, -3.0);
  }
}

Eigen::Vector3d randomAxis(std::mt19937_64& gen) {
  std::normal_distribution<double> normal;
  Eigen::Vector3d axis;
  do {
    axis = Eigen::Vector3d(normal(gen), normal(gen), normal(gen));
  } while (axis.norm() < 1e-6);
  return axis.normalized();
}

/// One operation's running maximum over the samples of one band.
struct Tally {
  double max_error = 0.0;
  double worst_fraction = 0.0;
  bool nan = false;
  void add(double error, double allowed) {
    if (std::isnan(error)) {
      nan = true;
      return;
    }
    max_error = std::max(max_error, error);
    if (!std::isnan(allowed)) worst_fraction = std::max(worst_fraction, error / allowed);
  }
};

/// An operation of the table: its name, target, and its error on one sample.
struct Operation {
  const char* name;
  double target;  // NaN: none
  bool scales;    // target × max(1, ‖w‖)
};

enum Op {
  kSO3RoundTrip = 0,
  kSO3RoundTripRelMax1,
  kSO3RoundTripRelNorm,
  kSO3ExpRef,
  kSO3JrJrInv,
  kSE3RoundTrip,
  kSE3JrJrInv,
  kEigenRoundTrip,
  kEigenRoundTripRelMax1,
  kEigenRoundTripRelNorm,
  kEigenExpRef,
  kOpCount
};

const Operation kOperations[kOpCount] = {
    {"SO3 log(exp(w)) − w", kSO3Target, true},
    {"SO3 log(exp(w)) − w, ÷ max(1,‖w‖)", kSO3Target, false},
    {"SO3 log(exp(w)) − w, ÷ ‖w‖ (info)", kNoTarget, false},
    {"SO3 exp(w) − q_ref (long double)", kSO3Target, true},
    {"SO3 Jr(w)·JrInv(w) − I", kSO3Target, true},
    {"SE3 log(exp(ξ)) − ξ, ρ ∈ [−1,1]³", kSE3Target, false},
    {"SE3 Jr(ξ)·JrInv(ξ) − I, ρ ∈ [−1,1]³", kSE3Target, false},
    {"Eigen AngleAxis round trip − w", kNoTarget, false},
    {"Eigen AngleAxis round trip − w, ÷ max(1,‖w‖)", kNoTarget, false},
    {"Eigen AngleAxis round trip − w, ÷ ‖w‖", kNoTarget, false},
    {"Eigen Quaternion(AngleAxis) − q_ref", kNoTarget, false},
};

/// max |q − q_ref| over the four components, q_ref = (cos(θ/2), sin(θ/2)/θ · w)
/// in long double. q and q_ref both have w ≥ 0 for θ ≤ π.
double quaternionErrorToReference(const Eigen::Quaterniond& q, const Eigen::Vector3d& w) {
  const long double x = w.x(), y = w.y(), z = w.z();
  const long double theta = std::sqrt(x * x + y * y + z * z);
  const long double h = std::cos(theta / 2);
  const long double k = std::sin(theta / 2) / theta;
  const long double e[4] = {q.w() - h, q.x() - k * x, q.y() - k * y, q.z() - k * z};
  long double m = 0;
  for (long double c : e) m = std::max(m, std::fabs(c));
  return static_cast<double>(m);
}

double maxAbs(const Eigen::MatrixXd& m) { return m.cwiseAbs().maxCoeff(); }

std::string scientific(double x) {
  if (std::isnan(x)) return "NaN";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1e", x);
  return buf;
}

}  // namespace

bool PrecisionRow::hasTarget() const { return !std::isnan(target); }

bool PrecisionRow::pass() const {
  return !hasTarget() || (!std::isnan(max_error) && worst_target_fraction <= 1.0);
}

std::string PrecisionRow::targetText() const {
  if (!hasTarget()) return "-";
  return scientific(target) + (target_scales_with_norm ? "·max(1,‖w‖)" : "");
}

std::vector<std::string> precisionBands() {
  std::vector<std::string> names;
  for (int b = 0; b < kBandCount; ++b) names.push_back(bandName(b));
  return names;
}

std::vector<PrecisionRow> measurePrecision(int samples_per_band, std::uint64_t seed) {
  using Vector6d = Eigen::Matrix<double, 6, 1>;
  using Matrix6d = Eigen::Matrix<double, 6, 6>;
  std::vector<PrecisionRow> rows;
  for (int band = 0; band < kBandCount; ++band) {
    // One generator per band, so a band's samples do not depend on the others.
    std::mt19937_64 gen(seed + 0x9E3779B97F4A7C15ULL * static_cast<std::uint64_t>(band + 1));
    std::uniform_real_distribution<double> cube(-1.0, 1.0);
    Tally tally[kOpCount];
    for (int s = 0; s < samples_per_band; ++s) {
      const double theta_sample = sampleAngle(band, gen);
      const Eigen::Vector3d w = theta_sample * randomAxis(gen);
      const Eigen::Vector3d rho(cube(gen), cube(gen), cube(gen));
      const double theta = w.norm();
      const double scale = std::max(1.0, theta);
      auto add = [&](Op op, double error) {
        const Operation& o = kOperations[op];
        tally[op].add(error, o.scales ? o.target * scale : o.target);
      };

      // SO(3) round trip, exp against the reference, Jr·Jr⁻¹.
      const SO3d R = SO3d::exp(w);
      const double so3_round = (R.log() - w).cwiseAbs().maxCoeff();
      add(kSO3RoundTrip, so3_round);
      add(kSO3RoundTripRelMax1, so3_round / scale);
      add(kSO3RoundTripRelNorm, so3_round / theta);
      add(kSO3ExpRef, quaternionErrorToReference(R.quaternion(), w));
      add(kSO3JrJrInv, maxAbs(SO3d::Jr(w) * SO3d::JrInv(w) - Eigen::Matrix3d::Identity()));

      // SE(3) with a unit-scale translation.
      Vector6d xi;
      xi << rho, w;
      add(kSE3RoundTrip, (SE3d::exp(xi).log() - xi).cwiseAbs().maxCoeff());
      add(kSE3JrJrInv, maxAbs(SE3d::Jr(xi) * SE3d::JrInv(xi) - Matrix6d::Identity()));

      // Eigen: Quaternion(AngleAxis(θ, w/θ)), then AngleAxis(q) as angle·axis.
      const Eigen::Quaterniond q(Eigen::AngleAxisd(theta, w / theta));
      const Eigen::AngleAxisd aa(q);
      const double eigen_round = (aa.angle() * aa.axis() - w).cwiseAbs().maxCoeff();
      add(kEigenRoundTrip, eigen_round);
      add(kEigenRoundTripRelMax1, eigen_round / scale);
      add(kEigenRoundTripRelNorm, eigen_round / theta);
      add(kEigenExpRef, quaternionErrorToReference(q, w));
    }
    for (int op = 0; op < kOpCount; ++op) {
      PrecisionRow row;
      row.operation = kOperations[op].name;
      row.band = bandName(band);
      row.samples = samples_per_band;
      row.max_error = tally[op].nan ? kNoTarget : tally[op].max_error;
      row.target = kOperations[op].target;
      row.target_scales_with_norm = kOperations[op].scales;
      row.worst_target_fraction = row.hasTarget() ? (tally[op].nan ? kNoTarget : tally[op].worst_fraction)
                                                  : kNoTarget;
      rows.push_back(row);
    }
  }
  return rows;
}

void printPrecisionTable(std::ostream& out, const std::vector<PrecisionRow>& rows) {
  // Pivot: one line per operation (in first-seen order), one column per band.
  std::vector<std::string> bands, operations;
  for (const PrecisionRow& r : rows) {
    if (std::find(bands.begin(), bands.end(), r.band) == bands.end()) bands.push_back(r.band);
    if (std::find(operations.begin(), operations.end(), r.operation) == operations.end())
      operations.push_back(r.operation);
  }
  std::vector<std::string> header = {"operation (max abs error)"};
  header.insert(header.end(), bands.begin(), bands.end());
  header.push_back("target");
  header.push_back("result");
  std::vector<std::vector<std::string>> lines;
  int samples = 0;
  for (const std::string& op : operations) {
    std::vector<std::string> line = {op};
    std::string target = "-";
    bool has_target = false, pass = true;
    for (const std::string& band : bands) {
      const auto it = std::find_if(rows.begin(), rows.end(), [&](const PrecisionRow& r) {
        return r.operation == op && r.band == band;
      });
      if (it == rows.end()) {
        line.push_back("");
        continue;
      }
      samples = std::max(samples, it->samples);
      std::string cell = scientific(it->max_error);
      if (it->hasTarget()) {
        has_target = true;
        target = it->targetText();
        if (!it->pass()) {
          pass = false;
          cell += " MISS";
        }
      }
      line.push_back(cell);
    }
    line.push_back(target);
    line.push_back(has_target ? (pass ? "PASS" : "MISS") : "-");
    lines.push_back(line);
  }
  std::vector<std::size_t> right;
  for (std::size_t c = 1; c <= bands.size(); ++c) right.push_back(c);
  detail::printMarkdownTable(out, header, lines, right);
  out << "\nmax over " << samples
      << " samples per band of the largest |component| of the error; random axis; θ log-uniform"
         " in the first two bands and in π − θ in the last. q_ref = (cos(θ/2), sin(θ/2)/θ · w)"
         " in long double. Eigen: θ = ‖w‖, Quaterniond(AngleAxisd(θ, w/θ)), then"
         " AngleAxisd(q) as angle·axis. "
      << buildDescription() << ".\n";
}

}  // namespace measure
}  // namespace lieflow
