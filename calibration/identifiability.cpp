#include "calibration/identifiability.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>

#include "calibration/unit_axis.hpp"

namespace lieflow {
namespace calibration {
namespace {

bool sigmaDetermined(const AxisInformation& info, int i, const AxisFitOptions& options) {
  const double lambda_max = info.eigenvalues[3];
  if (!(lambda_max > 0.0) || !(info.eigenvalues[i] > kInformationRankTolerance * lambda_max)) return false;
  return info.sigma_rad[i] * kRadToDeg <= options.max_sigma_deg;
}

int countSigmaDetermined(const AxisInformation& info, const AxisFitOptions& options) {
  int n = 0;
  for (int i = 0; i < 4; ++i) n += sigmaDetermined(info, i, options);
  return n;
}

int countMotionDetermined(const AxisInformation& info, const AxisFitOptions& options) {
  int n = 0;
  for (int i = 0; i < 4; ++i) n += info.motion_to_noise[i] >= options.min_motion_to_noise;
  return n;
}

/// Which axis a direction of the 4 axis angles mostly turns.
std::string whichAxis(const Eigen::Vector4d& v, const IdentifiabilityContext& context) {
  const double share1 = v.head<2>().squaredNorm() / v.squaredNorm();
  return share1 > 0.8 ? "mostly " + context.axis1 : share1 < 0.2 ? "mostly " + context.axis2 : "both axes together";
}

}  // namespace

int AxisInformation::determined(const AxisFitOptions& options) const {
  return std::min(countSigmaDetermined(*this, options), countMotionDetermined(*this, options));
}

AxisInformation analyseInformation(const Eigen::Matrix4d& information, const Eigen::Matrix4d& noise_information,
                                   double reduced_chi_square) {
  AxisInformation info;
  info.information = information;
  info.noise_information = noise_information;
  info.reduced_chi_square = reduced_chi_square;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eig(information);
  info.eigenvalues = eig.eigenvalues().cwiseMax(0.0);
  info.directions = eig.eigenvectors();
  const double s = std::sqrt(reduced_chi_square);
  for (int i = 0; i < 4; ++i)
    info.sigma_rad[i] = info.eigenvalues[i] > 0.0 ? s / std::sqrt(info.eigenvalues[i])
                                                  : std::numeric_limits<double>::infinity();
  // H_motion v = ρ H_noise v; H_noise is nudged to positive definite (exact
  // data have next to no noise information, and ρ is then huge).
  const double nudge = 1e-12 * std::max(information.trace(), std::numeric_limits<double>::min());
  const Eigen::Matrix4d noise = noise_information + nudge * Eigen::Matrix4d::Identity();
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix4d> gen(information - noise_information, noise);
  info.motion_to_noise = gen.eigenvalues();
  info.motion_directions = gen.eigenvectors();
  return info;
}

void requireEnoughSamples(int samples, const AxisFitOptions& options) {
  if (samples < options.min_samples)
    throw NotIdentifiable(std::to_string(samples) + " samples; at least " + std::to_string(options.min_samples) +
                          " are needed for 4 axis angles and the noise scale");
}

void requireIdentifiable(const AxisInformation& info, const AxisFitOptions& options,
                         const IdentifiabilityContext& context) {
  const int determined = info.determined(options);
  if (determined == 4) return;
  if (!(info.eigenvalues[3] > 0.0))
    throw NotIdentifiable("the residuals do not depend on the axes at all (no motion); " + context.hint);
  std::string reason = "the data determine only " + std::to_string(determined) +
                       " of the 4 axis directions (two per axis); the weakest (";
  int weakest = 0;
  while (weakest < 3 && sigmaDetermined(info, weakest, options)) ++weakest;
  if (!(info.eigenvalues[weakest] > kInformationRankTolerance * info.eigenvalues[3])) {
    reason += whichAxis(info.directions.col(weakest), context) + ") is not constrained at all; ";
  } else if (countMotionDetermined(info, options) < 4) {
    reason += whichAxis(info.motion_directions.col(0), context) + ") draws " +
              formatNumber(std::max(0.0, info.motion_to_noise[0]), 2) +
              " times as much information from the motion as from the noise (needs ≥ " +
              formatNumber(options.min_motion_to_noise) + "); ";
  } else {
    reason += whichAxis(info.directions.col(weakest), context) + ") has 1σ = " +
              formatNumber(info.sigma_rad[weakest] * kRadToDeg, 3) + "° (needs ≤ " +
              formatNumber(options.max_sigma_deg) + "°); ";
  }
  throw NotIdentifiable(reason + context.hint);
}

}  // namespace calibration
}  // namespace lieflow
