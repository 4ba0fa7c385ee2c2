// The inverse-dynamics start of the mechanism spring fit and the start
// model's fastest frequency (mechanism_spring_start.hpp states the methods).
#include "calibration/mechanism_spring_start.hpp"

#include <algorithm>
#include <climits>
#include <cmath>

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>

#include "calibration/mechanism_flow.hpp"
#include "liegroup/invalid_input.hpp"
#include "liegroup/input_number.hpp"

namespace lieflow {
namespace calibration {

namespace {

/// Largest half width w of the local cubics (the smallest is
/// kInverseDynamicsMinHalfWidth).
constexpr int kMaxHalfWidth = 40;
/// w Δt ≈ (shortest period seen) / kSamplesPerPeriodWindow.
constexpr double kSamplesPerPeriodWindow = 16.0;
/// Crossings count when an angle passes its mean ± this many standard
/// deviations (hysteresis: the noise about the mean does not count).
constexpr double kCrossingBand = 0.25;

/// The shortest period the angles show: twice the duration over the number
/// of crossings of each angle's mean (with hysteresis, kCrossingBand; 0 when
/// none crosses twice).
double shortestPeriod(const std::vector<double>& time, const std::vector<const std::vector<double>*>& angles,
                      const std::vector<StartCoordinate>& fitted) {
  const double duration = time.back() - time.front();
  double shortest = 0.0;
  for (const StartCoordinate& c : fitted) {
    const std::vector<double>& x = *angles[static_cast<std::size_t>(c.coordinate)];
    double mean = 0.0, square = 0.0;
    for (double v : x) mean += v;
    mean /= static_cast<double>(x.size());
    for (double v : x) square += (v - mean) * (v - mean);
    const double band = kCrossingBand * std::sqrt(square / static_cast<double>(x.size()));
    int crossings = 0, side = 0;  // side: +1 above mean + band, −1 below mean − band
    for (double v : x) {
      const int now = v > mean + band ? 1 : v < mean - band ? -1 : 0;
      if (now != 0 && side != 0 && now != side) ++crossings;
      if (now != 0) side = now;
    }
    if (crossings >= 2) {
      const double period = 2.0 * duration / crossings;
      shortest = shortest > 0.0 ? std::min(shortest, period) : period;
    }
  }
  return shortest;
}

}  // namespace

MechanismStart inverseDynamicsStart(const articulated::ArticulatedModel& model, const std::vector<double>& time,
                                    const std::vector<const std::vector<double>*>& angles,
                                    const std::vector<StartCoordinate>& fitted) {
  const int n = static_cast<int>(time.size());
  const int dofs = model.scalar_coordinates;
  MechanismStart out;
  const double dt = (time.back() - time.front()) / std::max(1, n - 1);
  const double period = shortestPeriod(time, angles, fitted);
  out.half_width = period > 0.0 ? clampedInt(std::round(period / (kSamplesPerPeriodWindow * dt)), 0, INT_MAX / 4) : 10;
  // At least 4 samples beyond one window (a regression of up to 3 unknowns).
  out.half_width = std::clamp(std::min(out.half_width, (n - 4) / 2), kInverseDynamicsMinHalfWidth, kMaxHalfWidth);
  const int w = out.half_width;
  if (n < kInverseDynamicsMinSamples)
    throw InvalidInput("t", "the inverse-dynamics start needs at least " + std::to_string(kInverseDynamicsMinSamples) +
                                " samples, got " + std::to_string(n));

  // Per fitted coordinate: the normal equations of y = A x over the samples,
  // x = (k, c, k q₀) for the elements it has.
  const std::size_t m = fitted.size();
  std::vector<Eigen::Matrix3d> AtA(m, Eigen::Matrix3d::Zero());
  std::vector<Eigen::Vector3d> Aty(m, Eigen::Vector3d::Zero());
  const MechanismDynamics<double> dynamics(model);
  Eigen::VectorXd q(dofs), qd(dofs), qdd(dofs);
  for (int k = w; k + w < n; ++k) {
    // The local cubic x(t_k + s) ≈ a₀ + a₁ s + a₂ s² + a₃ s³ of every angle.
    Eigen::Matrix4d G = Eigen::Matrix4d::Zero();
    Eigen::MatrixXd B = Eigen::MatrixXd::Zero(4, dofs);
    for (int i = k - w; i <= k + w; ++i) {
      const double s = time[static_cast<std::size_t>(i)] - time[static_cast<std::size_t>(k)];
      const Eigen::Vector4d p(1.0, s, s * s, s * s * s);
      G.noalias() += p * p.transpose();
      for (int j = 0; j < dofs; ++j) B.col(j) += (*angles[static_cast<std::size_t>(j)])[static_cast<std::size_t>(i)] * p;
    }
    const Eigen::MatrixXd a = G.ldlt().solve(B);
    for (int j = 0; j < dofs; ++j) {
      q[j] = a(0, j);
      qd[j] = a(1, j);
      qdd[j] = 2.0 * a(2, j);
    }
    const Eigen::VectorXd tau = dynamics.inverseDynamics(q, qd, qdd);
    for (std::size_t f = 0; f < m; ++f) {
      const StartCoordinate& c = fitted[f];
      const int j = c.coordinate;
      double y = tau[j];
      // Applied moments M(t) supply part of τ.
      for (int b = 0; b < model.bodyCount(); ++b) {
        const articulated::ArticulatedBody& body = model.bodies[static_cast<std::size_t>(b)];
        if (j < body.q_begin || j >= body.q_begin + body.coordinates()) continue;
        const auto& drive = model.drives[static_cast<std::size_t>(b)][static_cast<std::size_t>(j - body.q_begin)];
        y -= drive.appliedMoment(time[static_cast<std::size_t>(k)]);
      }
      const Eigen::Vector3d row(c.stiffness ? -(c.rest_angle_fitted ? q[j] : q[j] - c.rest_angle) : 0.0,
                                c.damping ? -qd[j] : 0.0, c.stiffness && c.rest_angle_fitted ? 1.0 : 0.0);
      AtA[f].noalias() += row * row.transpose();
      Aty[f] += row * y;
    }
  }
  for (std::size_t f = 0; f < m; ++f) {
    const StartCoordinate& c = fitted[f];
    // Unknowns the coordinate does not have get a unit diagonal (x = 0).
    for (int u = 0; u < 3; ++u)
      if (AtA[f](u, u) == 0.0) AtA[f](u, u) = 1.0;
    const Eigen::Vector3d x = AtA[f].ldlt().solve(Aty[f]);
    const bool k_ok = c.stiffness && std::isfinite(x[0]) && x[0] > 0.0;
    const bool c_ok = c.damping && std::isfinite(x[1]) && x[1] > 0.0;
    out.stiffness.push_back(c.stiffness ? x[0] : 0.0);
    out.damping.push_back(c.damping ? x[1] : 0.0);
    out.rest_angle.push_back(k_ok && c.rest_angle_fitted ? x[2] / x[0] : c.rest_angle);
    out.stiffness_usable.push_back(k_ok);
    out.damping_usable.push_back(c_ok);
  }
  return out;
}

bool anglesFromGyroscopes(const articulated::ArticulatedModel& model, const Eigen::VectorXd& q0,
                          const std::vector<double>& time,
                          const std::vector<const std::vector<Eigen::Vector3d>*>& rates,
                          std::vector<std::vector<double>>* angles) {
  for (int i = 0; i < model.bodyCount(); ++i) {
    const articulated::ArticulatedBody& b = model.bodies[static_cast<std::size_t>(i)];
    if (b.kind == articulated::JointKind::kSpherical || b.prescribed(0) || b.prescribed(1)) return false;
  }
  const int n = static_cast<int>(time.size());
  angles->assign(static_cast<std::size_t>(q0.size()), std::vector<double>(static_cast<std::size_t>(n)));
  for (int i = 0; i < model.bodyCount(); ++i) {
    const articulated::ArticulatedBody& b = model.bodies[static_cast<std::size_t>(i)];
    const int parent = b.parent;
    // ω of the joint's main and secondary bodies at sample k (ground: 0).
    auto omega = [&](int body, int k) {
      return body == articulated::kGround ? Eigen::Vector3d::Zero()
                                          : Eigen::Vector3d((*rates[static_cast<std::size_t>(body)])[k]);
    };
    const int main = b.parent_is_main ? parent : i, secondary = b.parent_is_main ? i : parent;
    // The angles' rates at sample k and angles φ.
    auto rate = [&](int k, const Eigen::Vector2d& phi) -> Eigen::Vector2d {
      const Eigen::Vector3d wm = omega(main, k), ws = omega(secondary, k);
      if (b.kind == articulated::JointKind::kRevolute)
        return Eigen::Vector2d((b.R_ref.transpose() * b.axis1).dot(ws) - b.axis1.dot(wm), 0.0);
      const Eigen::Matrix3d E1 = Eigen::AngleAxisd(phi[0], b.axis1).toRotationMatrix();
      const Eigen::Matrix3d M = E1 * b.R_ref * Eigen::AngleAxisd(phi[1], b.axis2).toRotationMatrix();
      Eigen::Matrix<double, 3, 2> A;
      A << b.axis1, E1 * b.R_ref * b.axis2;
      return (A.transpose() * A).ldlt().solve(A.transpose() * (M * ws - wm));
    };
    const int nc = b.coordinates();
    Eigen::Vector2d phi(q0[b.q_begin], nc == 2 ? q0[b.q_begin + 1] : 0.0);
    for (int k = 0; k < n; ++k) {
      for (int c = 0; c < nc; ++c) (*angles)[static_cast<std::size_t>(b.q_begin + c)][static_cast<std::size_t>(k)] = phi[c];
      if (k + 1 == n) break;
      const double h = time[k + 1] - time[k];
      const Eigen::Vector2d r0 = rate(k, phi);
      const Eigen::Vector2d predicted = phi + h * r0;
      phi += 0.5 * h * (r0 + rate(k + 1, predicted));
    }
  }
  return true;
}

double fastestFrequency(const articulated::ArticulatedModel& model, const MechanismForces<double>& forces,
                        const MechanismState<double>& y0) {
  MechanismDynamics<double> dynamics(model);
  const int nq = static_cast<int>(y0.q.size()), n = static_cast<int>(y0.u.size());
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
  auto accelerations = [&](const MechanismState<double>& y) {
    for (std::size_t k = 0; k < y.N.size(); ++k) dynamics.setRotation(static_cast<int>(k), y.N[k].matrix());
    return dynamics.accelerations(0.0, y.q, zero, forces);
  };
  Eigen::MatrixXd A(n, n);
  for (int j = 0; j < n; ++j) {
    const double d = kFrequencyProbe * (j < nq ? std::max(1.0, std::abs(y0.q[j])) : 1.0);
    Eigen::VectorXd step = Eigen::VectorXd::Zero(2 * n);
    step[j] = d;  // (δq, δθ) lead the tangent
    A.col(j) = (accelerations(y0.rplus(step)) - accelerations(y0.rplus(-step))) / (2.0 * d);
  }
  const Eigen::EigenSolver<Eigen::MatrixXd> eig(A);
  double largest = 0.0;
  for (int j = 0; j < n; ++j) largest = std::max(largest, std::abs(eig.eigenvalues()[j]));
  return std::sqrt(largest);
}

}  // namespace calibration
}  // namespace lieflow
