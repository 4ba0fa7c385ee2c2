/// \file
/// Lie-group methods built from exponentials only, no commutators and no
/// dexp⁻¹: the Crouch–Grossman method of order 3 and the commutator-free
/// method of order 4 of Celledoni, Marthinsen and Owren (2003).
///
/// Both are written for lieflow's right trivialization ẏ = y·f(t, y): the
/// left-action formulas of the papers (ẏ = F(y) y, products of exponentials
/// applied on the left) become products applied on the right in mirrored
/// order, y exp(βₖ)…exp(β₁) ↦ y exp(β₁)…exp(βₖ).
///
/// For a heap-backed state the stage values live in a workspace held by the
/// stepper (as in rkmk.hpp): no step allocates on the heap after the first,
/// and step() returns a reference to the result, valid until the next step.
#pragma once

#include <type_traits>

#include "integrators/state_workspace.hpp"
#include "integrators/step_report.hpp"

namespace lieflow {

/// Crouch & Grossman 1993 (J. Nonlinear Sci. 3), order 3, three stages,
/// with the coefficients of Owren & Marthinsen 1999 (BIT 39), Table 1:
///   c = (0, 3/4, 17/24), a₂₁ = 3/4, a₃₁ = 119/216, a₃₂ = 17/108,
///   b = (13/51, −2/3, 24/17);
///   Yᵢ = y exp(h aᵢ₁ F₁) ⋯ exp(h a_{i,i−1} F_{i−1}),
///   y₁ = y exp(h b₁ F₁) exp(h b₂ F₂) exp(h b₃ F₃).
template <typename State>
class CrouchGrossman3Stepper {
 public:
  using StateType = State;
  using Scalar = typename State::Scalar;
  using Tangent = typename State::Tangent;
  static constexpr int kOrder = 3;

  template <typename System>
  state_ops::StepResult<State> step(const System& system, const Scalar& t, const State& y, const Scalar& h,
                                    StepReport* /*report*/ = nullptr) const {
    if constexpr (state_ops::kHeapBacked<State>) {
      Tangent &F1 = w_.F1, &F2 = w_.F2, &F3 = w_.F3, &d = w_.d;
      State &Y = w_.Y, &out = w_.result;
      state_ops::setZeroTangent(y, &F1);
      system.velocity(t, y, &F1);
      d = (h * Scalar(3.0 / 4.0)) * F1;
      state_ops::rplusInto(y, d, &Y);
      system.velocity(t + Scalar(3.0 / 4.0) * h, Y, &F2);
      d = (h * Scalar(119.0 / 216.0)) * F1;
      state_ops::rplusInto(y, d, &Y);
      d = (h * Scalar(17.0 / 108.0)) * F2;
      state_ops::rplusInPlace(Y, d);
      system.velocity(t + Scalar(17.0 / 24.0) * h, Y, &F3);
      d = (h * Scalar(13.0 / 51.0)) * F1;
      state_ops::rplusInto(y, d, &out);
      d = (h * Scalar(-2.0 / 3.0)) * F2;
      state_ops::rplusInPlace(out, d);
      d = (h * Scalar(24.0 / 17.0)) * F3;
      state_ops::rplusInPlace(out, d);
      return out;
    } else {
      Tangent F1 = y.zeroTangent(), F2 = y.zeroTangent(), F3 = y.zeroTangent();
      system.velocity(t, y, &F1);
      const State Y2 = y.rplus((h * Scalar(3.0 / 4.0)) * F1);
      system.velocity(t + Scalar(3.0 / 4.0) * h, Y2, &F2);
      const State Y3 = y.rplus((h * Scalar(119.0 / 216.0)) * F1).rplus((h * Scalar(17.0 / 108.0)) * F2);
      system.velocity(t + Scalar(17.0 / 24.0) * h, Y3, &F3);
      return y.rplus((h * Scalar(13.0 / 51.0)) * F1)
          .rplus((h * Scalar(-2.0 / 3.0)) * F2)
          .rplus((h * Scalar(24.0 / 17.0)) * F3);
    }
  }

 private:
  /// Reused every step by a heap-backed state (empty otherwise).
  struct Workspace {
    Tangent F1, F2, F3, d;
    State Y, result;
  };
  struct NoWorkspace {};
  mutable std::conditional_t<state_ops::kHeapBacked<State>, Workspace, NoWorkspace> w_;
};

/// The commutator-free method of order 4 (Celledoni, Marthinsen, Owren 2003,
/// Future Gener. Comput. Syst. 19, eq. (9)), with Fᵢ = h f(t + cᵢh, Yᵢ):
///   Y₁ = y,  Y₂ = y exp(½F₁),  Y₃ = y exp(½F₂),  Y₄ = Y₂ exp(F₃ − ½F₁),
///   y₁ = y exp((3F₁ + 2F₂ + 2F₃ − F₄)/12) exp((−F₁ + 2F₂ + 2F₃ + 3F₄)/12).
template <typename State>
class CommutatorFree4Stepper {
 public:
  using StateType = State;
  using Scalar = typename State::Scalar;
  using Tangent = typename State::Tangent;
  static constexpr int kOrder = 4;

  template <typename System>
  state_ops::StepResult<State> step(const System& system, const Scalar& t, const State& y, const Scalar& h,
                                    StepReport* /*report*/ = nullptr) const {
    const Scalar half_h = Scalar(0.5) * h;
    const Scalar twelfth(1.0 / 12.0);
    if constexpr (state_ops::kHeapBacked<State>) {
      Tangent &F1 = w_.F1, &F2 = w_.F2, &F3 = w_.F3, &F4 = w_.F4, &d = w_.d;
      State &Y2 = w_.Y2, &Y = w_.Y, &out = w_.result;
      state_ops::setZeroTangent(y, &F1);
      system.velocity(t, y, &F1);
      F1 *= h;
      d = Scalar(0.5) * F1;
      state_ops::rplusInto(y, d, &Y2);
      system.velocity(t + half_h, Y2, &F2);
      F2 *= h;
      d = Scalar(0.5) * F2;
      state_ops::rplusInto(y, d, &Y);
      system.velocity(t + half_h, Y, &F3);
      F3 *= h;
      d = F3 - Scalar(0.5) * F1;
      state_ops::rplusInto(Y2, d, &Y);
      system.velocity(t + h, Y, &F4);
      F4 *= h;
      d = twelfth * (Scalar(3) * F1 + Scalar(2) * (F2 + F3) - F4);
      state_ops::rplusInto(y, d, &out);
      d = twelfth * (Scalar(-1) * F1 + Scalar(2) * (F2 + F3) + Scalar(3) * F4);
      state_ops::rplusInPlace(out, d);
      return out;
    } else {
      Tangent F1 = y.zeroTangent(), F2 = y.zeroTangent(), F3 = y.zeroTangent(), F4 = y.zeroTangent();
      system.velocity(t, y, &F1);
      F1 *= h;
      const State Y2 = y.rplus(Scalar(0.5) * F1);
      system.velocity(t + half_h, Y2, &F2);
      F2 *= h;
      system.velocity(t + half_h, y.rplus(Scalar(0.5) * F2), &F3);
      F3 *= h;
      system.velocity(t + h, Y2.rplus(F3 - Scalar(0.5) * F1), &F4);
      F4 *= h;
      return y.rplus(twelfth * (Scalar(3) * F1 + Scalar(2) * (F2 + F3) - F4))
          .rplus(twelfth * (Scalar(-1) * F1 + Scalar(2) * (F2 + F3) + Scalar(3) * F4));
    }
  }

 private:
  /// Reused every step by a heap-backed state (empty otherwise).
  struct Workspace {
    Tangent F1, F2, F3, F4, d;
    State Y2, Y, result;
  };
  struct NoWorkspace {};
  mutable std::conditional_t<state_ops::kHeapBacked<State>, Workspace, NoWorkspace> w_;
};

}  // namespace lieflow
