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
/// `velocity(t, y, Tangent*)`. Fixed-size states allocate nothing per step.
#pragma once

#include <algorithm>
#include <array>

#include "integrators/butcher_tableau.hpp"
#include "integrators/step_report.hpp"
#include "liegroup/scalar.hpp"

namespace lieflow {

template <typename State>
class RkmkStepper {
 public:
  using Scalar = typename State::Scalar;
  using Tangent = typename State::Tangent;

  explicit RkmkStepper(ButcherTableau tableau)
      : tableau_(std::move(tableau)), dexp_order_(std::max(0, tableau_.order - 2)) {}

  const ButcherTableau& tableau() const { return tableau_; }
  int order() const { return tableau_.order; }

  /// One step of size h from (t, y).
  template <typename System>
  State step(const System& system, const Scalar& t, const State& y, const Scalar& h,
             StepReport* /*report*/ = nullptr) const {
    std::array<Tangent, ButcherTableau::kMaxStages> K;
    computeStages(system, t, y, h, &K);
    Tangent theta = y.zeroTangent();
    for (int i = 0; i < tableau_.stages; ++i)
      if (tableau_.b[i] != 0.0) theta += (h * Scalar(tableau_.b[i])) * K[i];
    return y.rplus(theta);
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

  ButcherTableau tableau_;
  int dexp_order_;
};

}  // namespace lieflow
