/// \file
/// The residuals of the mechanism spring fit (mechanism_spring_fit.hpp): one
/// shooting segment of the tree in joint coordinates (mechanism_flow.hpp),
/// advanced by RKMK with the RK4 tableau in the scalar Ceres asks for, so the
/// Jacobian is the exact derivative of the discrete flow.
///
/// Parameter blocks: θ = (k, c, φ₀) per fitted coordinate, then one unit axis
/// per fitted revolute axis (--fit-axis), the segment's initial state
/// s = (q (nq), u (n)), one unit quaternion (w, x, y, z) per spherical joint
/// and, unless it is the last segment, the next segment's state and
/// quaternions. Residuals: per sample, predicted − recorded joint angles
/// [rad] or body rates [rad/s]; then the continuity defects w (q_end − q_next),
/// w log(N_nextᵀ N_end) per spherical joint and w_rate (u_end − u_next).
#pragma once

#include <cmath>
#include <vector>

#include <Eigen/Core>

#include "liegroup/flatten.hpp"
#include "calibration/mechanism_flow.hpp"
#include "dynamics/joint_space/articulated_model.hpp"
#include "liegroup/scalar.hpp"

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
  int coordinates = 0;  ///< nq: the joint angles
  int rotations = 0;    ///< ns: the spherical joints
  int dofs = 0;         ///< n = nq + 3 ns: the rates

  int perSample() const { return gyroscopes ? 3 * static_cast<int>(rates.size()) : coordinates; }
  /// The size of a segment's state block s = (q, u).
  int stateSize() const { return coordinates + dofs; }
};

/// One shooting segment: (θ, s[, s_next]) ↦ residuals at samples first …
/// last (the last only in the final segment), then the continuity defects.
class MechanismSegmentCost {
 public:
  MechanismSegmentCost(const MechanismShared* p, int first, int last, bool final, double w_angle, double w_rate)
      : p_(p), first_(first), last_(last), final_(final), w_angle_(w_angle), w_rate_(w_rate) {}

  int residualCount() const {
    return (last_ - first_ + (final_ ? 1 : 0)) * p_->perSample() +
           (final_ ? 0 : p_->coordinates + 3 * p_->rotations + p_->dofs);
  }

  template <typename T>
  LIEFLOW_FLATTEN bool operator()(T const* const* parameters, T* r) const {
    const T* theta = parameters[0];
    const std::size_t axes = p_->axis_bodies.size();
    const int nq = p_->coordinates, ns = p_->rotations, n = p_->dofs;
    MechanismForces<T> forces;
    for (int j = 0; j < nq; ++j) {
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
    const std::size_t first_state = 1 + axes;
    MechanismState<T> y = stateFrom(parameters + first_state);
    const MechanismFlow<T> flow(&dynamics, forces);
    const RkmkStepper<MechanismState<T>> stepper = mechanismStepper<T>();
    int k = 0;
    for (int i = first_;; ++i) {
      if (i < last_ || final_) {
        if (p_->gyroscopes) {
          for (int s = 0; s < ns; ++s) dynamics.setRotation(s, y.N[static_cast<std::size_t>(s)].matrix());
          const std::vector<Eigen::Matrix<T, 3, 1>> w = dynamics.bodyRates(y.q, y.u);
          for (std::size_t b = 0; b < w.size(); ++b)
            for (int c = 0; c < 3; ++c) r[k++] = w[b][c] - T((*p_->rates[b])[static_cast<std::size_t>(i)][c]);
        } else {
          for (int j = 0; j < nq; ++j)
            r[k++] = y.q[j] - T((*p_->angles[static_cast<std::size_t>(j)])[static_cast<std::size_t>(i)]);
        }
      }
      if (i == last_) break;
      const double t0 = p_->time[static_cast<std::size_t>(i)];
      const double h = (p_->time[static_cast<std::size_t>(i) + 1] - t0) / p_->substeps;
      for (int m = 0; m < p_->substeps; ++m) y = stepper.step(flow, T(t0 + m * h), y, T(h));
      for (int j = 0; j < n; ++j)  // a blown-up trial step: Ceres rejects it
        if (!std::isfinite(scalarValue(y.u[j]))) return false;
      for (int j = 0; j < nq; ++j)
        if (!std::isfinite(scalarValue(y.q[j]))) return false;
    }
    if (!final_) {
      const MechanismState<T> next = stateFrom(parameters + first_state + 1 + static_cast<std::size_t>(ns));
      for (int j = 0; j < nq; ++j) r[k++] = T(w_angle_) * (y.q[j] - next.q[j]);
      for (int s = 0; s < ns; ++s) {
        const Eigen::Matrix<T, 3, 1> d =
            (next.N[static_cast<std::size_t>(s)].inverse() * y.N[static_cast<std::size_t>(s)]).log();
        for (int c = 0; c < 3; ++c) r[k++] = T(w_angle_) * d[c];
      }
      for (int j = 0; j < n; ++j) r[k++] = T(w_rate_) * (y.u[j] - next.u[j]);
    }
    return true;
  }

 private:
  /// A segment's state from its blocks: s = (q, u), then a quaternion
  /// (w, x, y, z) per spherical joint.
  template <typename T>
  MechanismState<T> stateFrom(T const* const* blocks) const {
    const int nq = p_->coordinates, n = p_->dofs;
    MechanismState<T> y;
    y.q.resize(nq);
    y.u.resize(n);
    for (int j = 0; j < nq; ++j) y.q[j] = blocks[0][j];
    for (int j = 0; j < n; ++j) y.u[j] = blocks[0][nq + j];
    for (int s = 0; s < p_->rotations; ++s) {
      const T* w = blocks[1 + s];
      y.N.push_back(SO3<T>(Eigen::Quaternion<T>(w[0], w[1], w[2], w[3])));
    }
    return y;
  }

  const MechanismShared* p_;
  int first_, last_;
  bool final_;
  double w_angle_, w_rate_;
};

}  // namespace calibration
}  // namespace lieflow
