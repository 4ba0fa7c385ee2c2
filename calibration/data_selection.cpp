#include "calibration/data_selection.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <Eigen/Geometry>
#include <Eigen/SVD>

#include "liegroup/invalid_input.hpp"

namespace lieflow {
namespace calibration {
namespace {

std::string has(const BodySamples& b) {
  if (b.hasOrientation() && b.hasAngularVelocity()) return "orientations and angular velocities";
  if (b.hasOrientation()) return "only orientations";
  if (b.hasAngularVelocity()) return "only angular velocities";
  return "neither orientations nor angular velocities";
}

bool bothHaveAccelerometers(const JointSamples& s) {
  return s.main.hasSpecificForce() && s.secondary.hasSpecificForce();
}

void requireAccelerometers(const JointSamples& s, const std::string& joint) {
  for (const BodySamples* b : {&s.main, &s.secondary})
    if (!b->hasSpecificForce()) {
      const std::string& n = b->name;
      throw InvalidInput(s.source, joint + " fit with accelerometers: body '" + n + "' has no columns " + n + ".ax," +
                                       n + ".ay," + n + ".az");
    }
}

void requireGroup(const JointSamples& s, bool orientation, const std::string& joint) {
  for (const BodySamples* b : {&s.main, &s.secondary}) {
    const bool present = orientation ? b->hasOrientation() : b->hasAngularVelocity();
    if (!present) {
      const std::string& n = b->name;
      throw InvalidInput(s.source, joint + " fit with " + (orientation ? "orientations" : "gyroscopes") +
                                       ": body '" + n + "' has no columns " +
                                       (orientation ? n + ".qw," + n + ".qx," + n + ".qy," + n + ".qz"
                                                    : n + ".wx," + n + ".wy," + n + ".wz"));
    }
  }
}

}  // namespace

std::string DataSelection::name() const {
  std::string n = orientations && rates ? "orientations+gyroscopes" : orientations ? "orientations" : "gyroscopes";
  return accelerometers ? n + "+accelerometers" : n;
}

DataSelection selectData(const JointSamples& samples, DataUse use, const std::string& joint,
                         bool accelerometers_used) {
  for (const BodySamples* b : {&samples.main, &samples.secondary})
    if ((b->hasOrientation() && b->orientation.size() != samples.time.size()) ||
        (b->hasAngularVelocity() && b->angular_velocity.size() != samples.time.size()) ||
        (b->hasSpecificForce() && b->specific_force.size() != samples.time.size()))
      throw InvalidInput(samples.source, "body '" + b->name + "' has a different number of samples than t");
  const bool asks_accelerometers = use == DataUse::kGyroscopesAccelerometers || use == DataUse::kAll;
  if (asks_accelerometers && !accelerometers_used)
    throw InvalidInput(samples.source, std::string("`use` ") + dataUseName(use) + ": the " + joint +
                                           " fit does not use accelerometers (the hinge fit does; the joint "
                                           "centre is reported from them whenever both bodies have them)");
  DataSelection d;
  switch (use) {
    case DataUse::kAuto:
      d.orientations = samples.hasOrientations();
      d.rates = samples.hasAngularVelocities();
      if (!d.orientations && !d.rates)
        throw InvalidInput(samples.source, "a " + joint +
                                               " fit needs both bodies' orientations (B.qw,B.qx,B.qy,B.qz) or "
                                               "both bodies' angular velocities (B.wx,B.wy,B.wz); '" +
                                               samples.main.name + "' has " + has(samples.main) + ", '" +
                                               samples.secondary.name + "' has " + has(samples.secondary));
      if (d.orientations && d.rates) checkOrientationsAgreeWithRates(samples);
      d.accelerometers = accelerometers_used && d.rates && bothHaveAccelerometers(samples);
      return d;
    case DataUse::kOrientations: d.orientations = true; break;
    case DataUse::kAngularVelocities: d.rates = true; break;
    case DataUse::kBoth: d.orientations = d.rates = true; break;
    case DataUse::kGyroscopesAccelerometers: d.rates = d.accelerometers = true; break;
    case DataUse::kAll: d.orientations = d.rates = d.accelerometers = true; break;
  }
  if (d.orientations) requireGroup(samples, true, joint);
  if (d.rates) requireGroup(samples, false, joint);
  if (d.accelerometers) requireAccelerometers(samples, joint);
  if (d.orientations && d.rates) checkOrientationsAgreeWithRates(samples);
  return d;
}

void checkOrientationsAgreeWithRates(const JointSamples& samples) {
  for (const BodySamples* b : {&samples.main, &samples.secondary}) {
    const std::size_t n = samples.time.size();
    if (n < 3) return;
    Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
    double g2 = 0.0, u2 = 0.0;
    for (std::size_t k = 0; k + 1 < n; ++k) {
      const double dt = samples.time[k + 1] - samples.time[k];
      const Eigen::Vector3d u = (b->orientation[k].inverse() * b->orientation[k + 1]).log() / dt;
      const Eigen::Vector3d g = 0.5 * (b->angular_velocity[k] + b->angular_velocity[k + 1]);
      M.noalias() += u * g.transpose();
      g2 += g.squaredNorm();
      u2 += u.squaredNorm();
    }
    if (std::sqrt(g2 / (n - 1)) < kMinConsistencyRate) continue;
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
    D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
    const Eigen::Matrix3d C = svd.matrixU() * D * svd.matrixV().transpose();
    const Eigen::AngleAxisd turn(C);
    const double deg = turn.angle() * 180.0 / kPi;
    // Σ|u − Cg|² and Σ|u − g|² (|Cg| = |g|): only a C that explains the rates
    // significantly better than the identity counts (a motion about one axis
    // leaves C free about the others; noise alone improves the fit by Δχ² ≈ 3).
    const double misfit_C = u2 + g2 - 2.0 * (C.transpose() * M).trace();
    const double misfit_I = u2 + g2 - 2.0 * M.trace();
    const double variance = std::max(misfit_C, 1e-300) / (n - 1);
    if (deg <= kFrameMismatchDeg || (misfit_I - misfit_C) / variance <= kFrameSignificance) continue;
    std::ostringstream why;
    why.precision(3);
    why << "body '" << b->name << "': its quaternions (" << b->name << ".qw..qz) do not turn as its gyroscopes ("
        << b->name << ".wx..wz) say: their rates agree only after a constant rotation of " << deg
        << " degrees about (" << turn.axis().x() << ", " << turn.axis().y() << ", " << turn.axis().z()
        << ") in the body frame, so the two are not in the same frame; fit one of them (`use` gyroscopes or "
           "`use` orientations) or bring the quaternions into the gyroscopes' frame";
    throw InvalidInput(samples.source, why.str());
  }
}

std::vector<Eigen::Matrix3d> relativeOrientations(const JointSamples& samples) {
  std::vector<Eigen::Matrix3d> R12(samples.main.orientation.size());
  for (std::size_t k = 0; k < R12.size(); ++k)
    R12[k] = (samples.main.orientation[k].inverse() * samples.secondary.orientation[k]).matrix();
  return R12;
}

std::vector<Eigen::Vector3d> relativeRates(const JointSamples& samples, const std::vector<Eigen::Matrix3d>& R12) {
  std::vector<Eigen::Vector3d> u(R12.size());
  for (std::size_t k = 0; k < u.size(); ++k)
    u[k] = R12[k] * samples.secondary.angular_velocity[k] - samples.main.angular_velocity[k];
  return u;
}

namespace {

/// 1.4826 · median |Δᵏx| / √var over all components of the order-k
/// differences of x (k = 2 or 3), var the variance that unit white noise of
/// the underlying signal gives them (20 for third differences of it).
double robustDifferenceScale(const std::vector<Eigen::Vector3d>& x, int order, double var) {
  if (x.size() < static_cast<std::size_t>(order) + 1) return 0.0;
  std::vector<double> d;
  d.reserve(3 * (x.size() - order));
  for (std::size_t k = 0; k + order < x.size(); ++k) {
    const Eigen::Vector3d diff = order == 3 ? Eigen::Vector3d(x[k + 3] - 3.0 * x[k + 2] + 3.0 * x[k + 1] - x[k])
                                            : Eigen::Vector3d(x[k + 2] - 2.0 * x[k + 1] + x[k]);
    for (int i = 0; i < 3; ++i) d.push_back(std::abs(diff[i]));
  }
  const std::size_t n = d.size() / 2;
  std::nth_element(d.begin(), d.begin() + n, d.end());
  return 1.482602218505602 * d[n] / std::sqrt(var);
}

}  // namespace

double orientationNoiseFromDifferences(const std::vector<SO3d>& R) {
  if (R.size() < 4) return 0.0;
  std::vector<Eigen::Vector3d> increments;
  increments.reserve(R.size() - 1);
  for (std::size_t k = 0; k + 1 < R.size(); ++k) increments.push_back((R[k].inverse() * R[k + 1]).log());
  return robustDifferenceScale(increments, 2, 20.0);
}

double whiteNoiseFromDifferences(const std::vector<Eigen::Vector3d>& x) {
  return robustDifferenceScale(x, 3, 20.0);
}

}  // namespace calibration
}  // namespace lieflow
