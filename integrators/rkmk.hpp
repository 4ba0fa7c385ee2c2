/// \file
/// Runge–Kutta–Munthe-Kaas methods for any explicit Butcher tableau
/// (Munthe-Kaas 1998, "Runge–Kutta methods on Lie groups"; Iserles et al.
/// 2000, Acta Numerica §5.1), in lieflow's right trivialization ẏ = y·f(t, y):
///   Θ₁ = 0,  Θᵢ = h Σ_{j<i} a_ij K_j,
///   Kᵢ = dexp⁻¹_{−Θᵢ}(f(t + cᵢh, y ⊕ Θᵢ))  (= Jr⁻¹(Θᵢ) f, truncated),
///   y₁ = y ⊕ h Σᵢ bᵢ Kᵢ.
/// The dexp⁻¹ series is truncated after ad^{p−2} for a method of order p,
/// which keeps order p (Munthe-Kaas 1999, "High order Runge–Kutta methods on
/// manifolds", Thm. 1); Euler and Heun need no correction at all.
///
/// A State supplies `Tangent`, `rplus(Tangent)`, `zeroTangent()` and
/// `dexpInvRight(Θ, v, order)` (static or not); a System supplies
/// `velocity(t, y, Tangent*)`. The stages live in a workspace held by the
/// stepper (integrators/state_workspace.hpp), so that no step allocates on
/// the heap after the first, whatever the state's size; a stepper is
/// therefore used by one thread at a time, and step() returns a reference to
/// the workspace's result, valid until the next step.
#pragma once

#include <algorithm>
#include <array>
#include <type_traits>

#include "integrators/butcher_tableau.hpp"
#include "integrators/state_workspace.hpp"
#include "integrators/step_report.hpp"
#include "liegroup/scalar.hpp"

namespace lieflow {

template <typename State>
class RkmkStepper {
 public:
  using StateType = State;
  using Scalar = typename State::Scalar;
  using Tangent = typename State::Tangent;

  explicit RkmkStepper(ButcherTableau tableau)
      : tableau_(std::move(tableau)), dexp_order_(std::max(0, tableau_.order - 2)) {}

  const ButcherTableau& tableau() const { return tableau_; }
  int order() const { return tableau_.order; }

  /// One step of size h from (t, y). For a heap-backed state the result
  /// lives in the stepper until its next step (y may be that result).
  template <typename System>
  state_ops::StepResult<State> step(const System& system, const Scalar& t, const State& y, const Scalar& h,
                                    StepReport* /*report*/ = nullptr) const {
    if constexpr (state_ops::kHeapBacked<State>) {
      computeStages(system, t, y, h, &work_.K);
      Tangent& theta = work_.theta;
      state_ops::setZeroTangent(y, &theta);
      for (int i = 0; i < tableau_.stages; ++i)
        if (tableau_.b[i] != 0.0) theta.noalias() += (h * Scalar(tableau_.b[i])) * work_.K[i];
      state_ops::rplusInto(y, theta, &work_.result);
      return work_.result;
    } else {
      std::array<Tangent, ButcherTableau::kMaxStages> K;
      computeStages(system, t, y, h, &K);
      Tangent theta = y.zeroTangent();
      for (int i = 0; i < tableau_.stages; ++i)
        if (tableau_.b[i] != 0.0) theta += (h * Scalar(tableau_.b[i])) * K[i];
      return y.rplus(theta);
    }
  }

  using Stages = std::array<Tangent, ButcherTableau::kMaxStages>;

  /// One step plus the algebra-coordinate error estimate h Σ (bᵢ − b̂ᵢ) Kᵢ of
  /// an embedded pair (the difference of the two solutions' Θ, which is the
  /// difference of the two points to O(h·‖Θ‖·err)). With `stages`, the
  /// stage derivatives Kᵢ and the increment Θ₁ are kept for `denseIncrement`.
  template <typename System>
  State stepWithError(const System& system, const Scalar& t, const State& y, const Scalar& h,
                      Tangent* error, Stages* stages = nullptr, Tangent* increment = nullptr) const {
    LIEFLOW_ASSERT(tableau_.hasEmbedded(), "stepWithError needs an embedded pair");
    Stages local;
    Stages& K = stages ? *stages : local;
    computeStages(system, t, y, h, &K);
    Tangent theta = y.zeroTangent();
    *error = y.zeroTangent();
    for (int i = 0; i < tableau_.stages; ++i) {
      theta += (h * Scalar(tableau_.b[i])) * K[i];
      *error += (h * Scalar(tableau_.b[i] - tableau_.b_embedded[i])) * K[i];
    }
    if (increment) *increment = theta;
    return y.rplus(theta);
  }

  /// Dense output inside the last step: the increment u(θ) of the
  /// continuous extension (butcher_tableau.hpp), so that y(t + θh) ≈
  /// y ⊕ u(θ), θ ∈ [0, 1]. The RKMK stages are the derivatives of the
  /// algebra-coordinate ODE Θ' = dexp⁻¹_{−Θ} f(y ⊕ Θ), so the extension of
  /// that (vector-space) ODE carries over unchanged and keeps its order.
  Tangent denseIncrement(const Stages& K, const Tangent& increment, const Scalar& h, double theta) const {
    LIEFLOW_ASSERT(tableau_.hasDenseOutput() && tableau_.fsal, "denseIncrement needs an FSAL pair with dense output");
    const int last = tableau_.stages - 1;
    const Scalar th(theta), s(1.0 - theta);
    Tangent d = (h * Scalar(tableau_.dense_d[0])) * K[0];
    for (int i = 1; i < tableau_.stages; ++i)
      if (tableau_.dense_d[i] != 0.0) d += (h * Scalar(tableau_.dense_d[i])) * K[i];
    const Tangent hk1 = h * K[0];
    const Tangent r4 = Scalar(2.0) * increment - hk1 - h * K[last];
    return th * (increment + s * ((hk1 - increment) + th * (r4 + s * d)));
  }

 private:
  template <typename System>
  void computeStages(const System& system, const Scalar& t, const State& y, const Scalar& h,
                     std::array<Tangent, ButcherTableau::kMaxStages>* K) const {
    if constexpr (state_ops::kHeapBacked<State>) {
      Tangent& f = work_.f;
      Tangent& theta = work_.stage_theta;
      state_ops::setZeroTangent(y, &f);
      system.velocity(t, y, &f);
      (*K)[0] = f;
      for (int i = 1; i < tableau_.stages; ++i) {
        state_ops::setZeroTangent(y, &theta);
        for (int j = 0; j < i; ++j)
          if (tableau_.a[i][j] != 0.0) theta.noalias() += (h * Scalar(tableau_.a[i][j])) * (*K)[j];
        state_ops::rplusInto(y, theta, &work_.stage);
        system.velocity(t + Scalar(tableau_.c[i]) * h, work_.stage, &f);
        if (dexp_order_ == 0)
          (*K)[i] = f;
        else
          state_ops::dexpInvRightInto(y, theta, f, dexp_order_, &(*K)[i]);
      }
    } else {
      Tangent f = y.zeroTangent();
      system.velocity(t, y, &f);
      (*K)[0] = f;
      for (int i = 1; i < tableau_.stages; ++i) {
        Tangent theta = y.zeroTangent();
        for (int j = 0; j < i; ++j)
          if (tableau_.a[i][j] != 0.0) theta += (h * Scalar(tableau_.a[i][j])) * (*K)[j];
        system.velocity(t + Scalar(tableau_.c[i]) * h, y.rplus(theta), &f);
        (*K)[i] = dexp_order_ == 0 ? f : y.dexpInvRight(theta, f, dexp_order_);
      }
    }
  }

  /// Reused every step by a heap-backed state: stage derivatives,
  /// increments, the stage point and the result (empty otherwise).
  struct Workspace {
    std::array<Tangent, ButcherTableau::kMaxStages> K;
    Tangent f, theta, stage_theta;
    State stage, result;
  };

  ButcherTableau tableau_;
  int dexp_order_;
  struct NoWorkspace {};
  mutable std::conditional_t<state_ops::kHeapBacked<State>, Workspace, NoWorkspace> work_;
};

}  // namespace lieflow
