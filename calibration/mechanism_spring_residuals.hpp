/// \file
/// The residuals of the mechanism spring fit (mechanism_spring_fit.hpp): one
/// shooting segment of the tree in joint coordinates (mechanism_flow.hpp),
/// advanced by classical RK4 in the scalar Ceres asks for, so the Jacobian is
/// the exact derivative of the discrete flow.
///
/// Parameter blocks: θ = (k, c, φ₀) per fitted coordinate, then one unit axis
/// per fitted revolute axis (--fit-axis), the segment's initial state
/// s = (q (n), q̇ (n)) and, unless it is the last segment, the next segment's.
/// Residuals: per sample, predicted − recorded joint angles [rad] or body
/// rates [rad/s]; then the continuity defects w (q_end − q_next) and
/// w_rate (q̇_end − q̇_next).
#pragma once

#include <cmath>
#include <vector>

#include <Eigen/Core>

#include "calibration/mechanism_flow.hpp"
#include "dynamics/joint_space/articulated_model.hpp"

namespace lieflow {
namespace calibration {

/// The recorded data and what every segment shares.
struct MechanismShared {
  const articulated::ArticulatedModel* model = nullptr;
  std::vector<double> time;
  bool gyroscopes = false;
  /// Angles mode: per coordinate, its recorded angles. Gyroscope mode: per
  /// body (tree order), its recorded rates.
  std::vector<const std::vector<double>*> angles;
  std::vector<const std::vector<Eigen::Vector3d>*> rates;
  std::vector<int> fitted;  ///< coordinate indices of the fitted springs
  std::vector<int> axis_bodies;  ///< bodies whose (revolute) joint axis is fitted
  MechanismForces<double> scene_forces;
  int substeps = 1;
  int dofs = 0;

  int perSample() const { return gyroscopes ? 3 * static_cast<int>(rates.size()) : dofs; }
};

/// One shooting segment: (θ, s[, s_next]) ↦ residuals at samples first …
/// last (the last only in the final segment), then the continuity defects.
class MechanismSegmentCost {
 public:
  MechanismSegmentCost(const MechanismShared* p, int first, int last, bool final, double w_angle, double w_rate)
      : p_(p), first_(first), last_(last), final_(final), w_angle_(w_angle), w_rate_(w_rate) {}

  int residualCount() const {
    return (last_ - first_ + (final_ ? 1 : 0)) * p_->perSample() + (final_ ? 0 : 2 * p_->dofs);
  }

  template <typename T>
  bool operator()(T const* const* parameters, T* r) const {
    using Vec = typename MechanismDynamics<T>::Vec;
    const T* theta = parameters[0];
    const std::size_t axes = p_->axis_bodies.size();
    const T* s = parameters[1 + axes];
    const int n = p_->dofs;
    MechanismForces<T> forces;
    for (int j = 0; j < n; ++j) {
      forces.stiffness.push_back(T(p_->scene_forces.stiffness[j]));
      forces.damping.push_back(T(p_->scene_forces.damping[j]));
      forces.rest_angle.push_back(T(p_->scene_forces.rest_angle[j]));
    }
    for (std::size_t f = 0; f < p_->fitted.size(); ++f) {
      const int j = p_->fitted[f];
      forces.stiffness[j] = theta[3 * f];
      forces.damping[j] = theta[3 * f + 1];
      forces.rest_angle[j] = theta[3 * f + 2];
    }
    MechanismDynamics<T> dynamics(*p_->model);
    for (std::size_t a = 0; a < axes; ++a)
      dynamics.setAxis(p_->axis_bodies[a], Eigen::Matrix<T, 3, 1>(parameters[1 + a][0], parameters[1 + a][1],
                                                                  parameters[1 + a][2]));
    Vec q(n), v(n);
    for (int j = 0; j < n; ++j) {
      q[j] = s[j];
      v[j] = s[n + j];
    }
    int k = 0;
    for (int i = first_;; ++i) {
      if (i < last_ || final_) {
        if (p_->gyroscopes) {
          const std::vector<Eigen::Matrix<T, 3, 1>> w = dynamics.bodyRates(q, v);
          for (std::size_t b = 0; b < w.size(); ++b)
            for (int c = 0; c < 3; ++c) r[k++] = w[b][c] - T((*p_->rates[b])[static_cast<std::size_t>(i)][c]);
        } else {
          for (int j = 0; j < n; ++j) r[k++] = q[j] - T((*p_->angles[static_cast<std::size_t>(j)])[static_cast<std::size_t>(i)]);
        }
      }
      if (i == last_) break;
      const double t0 = p_->time[static_cast<std::size_t>(i)];
      const double h = (p_->time[static_cast<std::size_t>(i) + 1] - t0) / p_->substeps;
      for (int m = 0; m < p_->substeps; ++m) rk4Step(dynamics, forces, t0 + m * h, h, &q, &v);
      for (int j = 0; j < n; ++j)  // a blown-up trial step: Ceres rejects it
        if (!std::isfinite(scalarValue(q[j])) || !std::isfinite(scalarValue(v[j]))) return false;
    }
    if (!final_) {
      const T* next = parameters[2 + axes];
      for (int j = 0; j < n; ++j) {
        r[k++] = T(w_angle_) * (q[j] - next[j]);
        r[k++] = T(w_rate_) * (v[j] - next[n + j]);
      }
    }
    return true;
  }

 private:
  static double scalarValue(double x) { return x; }
  template <typename J>
  static double scalarValue(const J& x) {
    return x.a;
  }

  const MechanismShared* p_;
  int first_, last_;
  bool final_;
  double w_angle_, w_rate_;
};

}  // namespace calibration
}  // namespace lieflow
