/// \file
/// The residuals of the spring/dashpot fit (spring_fit.hpp): one shooting
/// segment of the joint's one-body tree (spring_joint.hpp) in the joint
/// formulation's dynamics on any scalar (the mechanism fit's,
/// dynamics/joint_space/scalar_dynamics.hpp), integrated by lieflow's RKMK
/// stepper in the scalar Ceres asks for (double or ceres::Jet), so the
/// Jacobian is the exact derivative of the discrete flow.
///
/// Parameter blocks: θ = (k, c, φ₀) of the fitted coordinate, the segment's
/// initial state s = (φ (N), φ̇ (N)) and, unless it is the last segment, the
/// next segment's initial state. Residuals, in this order: for every sample
/// j of the segment (the last sample only in the last segment) and every
/// recorded coordinate i, φ_i(t_j) − φ̃_i(t_j) in radians; then the
/// continuity defects w (φ(t_end) − φ_next) and (w/ω)(φ̇(t_end) − φ̇_next).
#pragma once

#include <array>
#include <cmath>
#include <optional>

#include "liegroup/flatten.hpp"
#include "calibration/spring_data.hpp"
#include "dynamics/joint_space/articulated_model.hpp"
#include "dynamics/joint_space/scalar_dynamics.hpp"
#include "integrators/butcher_tableau.hpp"
#include "integrators/rkmk.hpp"
#include "integrators/vector_state.hpp"
#include "liegroup/scalar.hpp"

namespace lieflow {
namespace calibration {

/// Spring, dashpot and rest angle of each coordinate, in the fit's scalar.
template <typename T, int N>
struct JointSprings {
  std::array<T, N> stiffness{}, damping{}, rest_angle{};
};

/// The one-body tree as a system on ℝᴺ × ℝᴺ (VectorState: x = φ, v = φ̇), so
/// that every RKMK tableau of integrators/ advances it (exp is the identity
/// there: RKMK is the Runge–Kutta method). A hinge (N = 1) takes the closed
/// form whose constants the caller computed once (ScalarDynamics<double>::
/// groundedHinge()); a universal joint the general recursive Newton–Euler.
template <typename T, int N>
class SpringJointFlow {
 public:
  using Scalar = T;
  using State = VectorState<T, N>;
  using Tangent = typename State::Tangent;
  using Vec = typename articulated::ScalarDynamics<T>::Vec;

  /// The model and the constants must outlive the flow. N = 1 (a revolute
  /// joint to the ground) takes the closed form, so `hinge` must be valid.
  SpringJointFlow(const articulated::ArticulatedModel& model, const articulated::GroundedHinge& hinge,
                  const JointSprings<T, N>& springs)
      : model_(model), hinge_(hinge), springs_(springs) {
    if constexpr (N == 2) {
      forces_.stiffness.assign(springs.stiffness.begin(), springs.stiffness.end());
      forces_.damping.assign(springs.damping.begin(), springs.damping.end());
      forces_.rest_angle.assign(springs.rest_angle.begin(), springs.rest_angle.end());
      dynamics_.emplace(model);
    }
  }

  /// f(t, y) = (φ̇, φ̈).
  void velocity(const T& t, const State& y, Tangent* f) const {
    f->template head<N>() = y.v;
    if constexpr (N == 1) {
      (*f)[1] = articulated::groundedHingeAcceleration(hinge_, y.x[0], y.v[0], springs_.stiffness[0],
                                                       springs_.damping[0], springs_.rest_angle[0],
                                                       model_.drives[0][0].appliedMoment(scalarValue(t)));
    } else {
      const Vec q = y.x, u = y.v;
      f->template tail<N>() = dynamics_->accelerations(scalarValue(t), q, u, forces_);
    }
  }

 private:
  const articulated::ArticulatedModel& model_;
  const articulated::GroundedHinge& hinge_;
  JointSprings<T, N> springs_;
  articulated::CoordinateForces<T> forces_;  ///< N = 2: the springs for the general dynamics
  std::optional<articulated::ScalarDynamics<T>> dynamics_;
};

/// What every segment shares: the model, the data and the fixed forces.
template <int N>
struct SpringProblemData {
  const articulated::ArticulatedModel* model = nullptr;
  /// The closed form's constants when the model is a grounded hinge.
  articulated::GroundedHinge hinge;
  const SpringData* data = nullptr;
  /// The scene's spring and dashpot of every coordinate; the fitted
  /// coordinate's are replaced by θ.
  JointSprings<double, N> scene_forces;
  int coordinate = 0;
  ButcherTableau tableau;
  int substeps = 1;
};

template <int N>
class SpringSegmentCost {
 public:
  /// Samples first … last (indices into the data); `final`: the last
  /// segment (residual at `last` too, no continuity defect).
  SpringSegmentCost(const SpringProblemData<N>* problem, int first, int last, bool final, double w_angle,
                    double w_rate)
      : p_(problem), first_(first), last_(last), final_(final), w_angle_(w_angle), w_rate_(w_rate) {}

  int residualCount() const {
    const int samples = last_ - first_ + (final_ ? 1 : 0);
    return samples * p_->data->measured() + (final_ ? 0 : 2 * N);
  }

  /// The last segment: (θ, s) ↦ r.
  template <typename T>
  bool operator()(const T* theta, const T* s, T* r) const {
    return evaluate(theta, s, static_cast<const T*>(nullptr), r);
  }
  /// Any other segment: (θ, s, s_next) ↦ r.
  template <typename T>
  bool operator()(const T* theta, const T* s, const T* next, T* r) const {
    return evaluate(theta, s, next, r);
  }

 private:
  template <typename T>
  LIEFLOW_FLATTEN bool evaluate(const T* theta, const T* s, const T* next, T* r) const {
    const SpringData& data = *p_->data;
    JointSprings<T, N> forces;
    for (int i = 0; i < N; ++i) {
      forces.stiffness[i] = T(p_->scene_forces.stiffness[i]);
      forces.damping[i] = T(p_->scene_forces.damping[i]);
      forces.rest_angle[i] = T(p_->scene_forces.rest_angle[i]);
    }
    forces.stiffness[p_->coordinate] = theta[0];
    forces.damping[p_->coordinate] = theta[1];
    forces.rest_angle[p_->coordinate] = theta[2];
    const SpringJointFlow<T, N> system(*p_->model, p_->hinge, forces);
    const RkmkStepper<VectorState<T, N>> stepper(p_->tableau);
    VectorState<T, N> y;
    for (int i = 0; i < N; ++i) {
      y.x[i] = s[i];
      y.v[i] = s[N + i];
    }
    int k = 0;
    for (int j = first_;; ++j) {
      if (j < last_ || final_)
        for (int i = 0; i < N; ++i)
          if (data.has(i)) r[k++] = y.x[i] - T(data.angle[i][j]);
      if (j == last_) break;
      const double t0 = data.time[j];
      const double h = (data.time[j + 1] - t0) / p_->substeps;
      for (int m = 0; m < p_->substeps; ++m) y = stepper.step(system, T(t0 + m * h), y, T(h));
      for (int i = 0; i < N; ++i)  // a blown-up trial step: Ceres rejects it
        if (!std::isfinite(scalarValue(y.x[i])) || !std::isfinite(scalarValue(y.v[i]))) return false;
    }
    if (!final_)
      for (int i = 0; i < N; ++i) {
        r[k++] = T(w_angle_) * (y.x[i] - next[i]);
        r[k++] = T(w_rate_) * (y.v[i] - next[N + i]);
      }
    return true;
  }

  const SpringProblemData<N>* p_;
  int first_, last_;
  bool final_;
  double w_angle_, w_rate_;
};

}  // namespace calibration
}  // namespace lieflow
