/// \file
/// Adaptive step-size control on the group for embedded RKMK pairs
/// (Hairer, Nørsett, Wanner I, §II.4, with the error measured in the algebra:
/// Engø 2003, "On the construction of geometric integrators in the RKMK
/// class"). The local error estimate e = h Σ (bᵢ − b̂ᵢ)Kᵢ is scaled per
/// component by atol + rtol·max(|y|, |y₁|) and the step follows
///   h_new = h · min(fac_max, max(fac_min, safety · err^{−1/(q̂+1)})),
/// q̂ the order of the embedded solution. The step size comes from the error
/// estimate alone: output times are not stepped to but interpolated on the
/// group, y(t + θh) = y ⊕ u(θ), with the pair's continuous extension
/// (RkmkStepper::denseIncrement; HNW I §II.6), so a fine output grid costs
/// no extra steps.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <sstream>
#include <string>

#include "integrators/integrate.hpp"
#include "integrators/rkmk.hpp"

namespace lieflow {

struct AdaptiveOptions {
  double rtol = 1e-8;
  double atol = 1e-10;
  double safety = 0.9;
  double fac_min = 0.2;
  double fac_max = 5.0;
  /// Relative to the time scale max(|t|, t_end − t0): a step below h_min
  /// times it is a failure (the problem is too stiff or singular there).
  double h_min = 1e-14;
  /// Most steps, accepted plus rejected; beyond it the run stops with
  /// `RunSummary::step_limit_reached`.
  long max_steps = 100000000;
  /// Called every `heartbeat_steps` attempted steps with (t, steps) (long
  /// runs report progress through it); may be empty.
  std::function<void(double, long)> heartbeat;
  long heartbeat_steps = 65536;
};

/// The starting step of Hairer, Nørsett & Wanner I, §II.4 ("Starting step
/// size"), in the algebra: with the error scale sᵢ = atol + rtol·|yᵢ| and the
/// max norm, d₀ = ‖y₀/s‖, d₁ = ‖f₀/s‖, h₀ = 0.01·d₀/d₁ (10⁻⁶ when either is
/// below 10⁻⁵), one Lie–Euler step y₀ ⊕ h₀f₀ gives d₂ = ‖(f₁ − f₀)/s‖/h₀, and
/// h = min(100·h₀, (0.01/max(d₁, d₂))^{1/(p+1)}), p the method's order. It
/// depends on the problem alone, never on the output grid.
template <typename State, typename System>
double startingStep(const System& system, double t0, const State& y0, int order, const AdaptiveOptions& options) {
  using Scalar = typename State::Scalar;
  using Tangent = typename State::Tangent;
  const Tangent scale = (y0.magnitude() * Scalar(options.rtol)).array() + Scalar(options.atol);
  auto norm = [&](const Tangent& v) {
    double n = 0.0;
    for (int i = 0; i < v.size(); ++i) n = std::max(n, std::abs(scalarValue(v[i] / scale[i])));
    return n;
  };
  Tangent f0 = y0.zeroTangent(), f1 = y0.zeroTangent();
  system.velocity(Scalar(t0), y0, &f0);
  const double d0 = norm(y0.magnitude()), d1 = norm(f0);
  const double h0 = d0 < 1e-5 || d1 < 1e-5 ? 1e-6 : 0.01 * d0 / d1;
  system.velocity(Scalar(t0 + h0), y0.rplus(Scalar(h0) * f0), &f1);
  const double d2 = norm(f1 - f0) / h0;
  const double d = std::max(d1, d2);
  const double h1 = d <= 1e-15 ? std::max(1e-6, 1e-3 * h0) : std::pow(0.01 / d, 1.0 / (order + 1.0));
  const double h = std::min(100.0 * h0, h1);
  return std::isfinite(h) && h > 0.0 ? h : 1e-6;
}

/// A run whose pace projects it beyond this many times its step limit stops
/// early (the step size of an adaptive run can grow again, so a projection
/// just above the limit is not yet a reason).
constexpr double kProjectionMargin = 100.0;

/// No projection: integrateAdaptive's states are the pair's.
struct NoProjection {
  template <typename State>
  bool operator()(double, State*, std::string*) const {
    return true;
  }
};

/// Advances y from t0 to t_end, calling observer(k, t_k, y(t_k)) at the
/// output times t_k = t0 + k·dt_out (and t_end): y(t_k) is the dense output
/// of the step that covers t_k (the step's end point itself when t_k falls on
/// it, so the last output is the state at t_end).
///
/// With a projection project(t, State* y, std::string* why) (false: it
/// failed, and why) — for constrained systems stepped in index-1 form, the
/// mass-orthogonal projection onto Φ = 0 and J u = b of
/// integrators/projected_stepper.hpp — every accepted step's end state is
/// projected before the next step starts from it, and every output state
/// before the observer sees it (a copy: the integration goes on from the
/// step's end). The error estimate is the pair's, taken before the
/// projection, which moves the state by the size of the local error and
/// keeps the order (Hairer & Wanner, "Solving ODEs II", §VII.2, projection
/// methods with step size control). A failed projection ends the run
/// (RunSummary::failed, the failure says where and why).
template <typename State, typename System, typename Observer, typename Projection = NoProjection>
RunSummary integrateAdaptive(const RkmkStepper<State>& stepper, const System& system, State y,
                             double t0, double t_end, double dt_out,
                             const AdaptiveOptions& options, Observer&& observer, Projection project = {}) {
  using Scalar = typename State::Scalar;
  using Tangent = typename State::Tangent;
  LIEFLOW_ASSERT(stepper.tableau().hasEmbedded(), "integrateAdaptive needs an embedded pair");
  LIEFLOW_ASSERT(stepper.tableau().hasDenseOutput(), "integrateAdaptive needs a pair with dense output");
  const double exponent = -1.0 / (stepper.tableau().embedded_order + 1.0);
  RunSummary summary;
  summary.t_reached = t0;
  const long n_out = stepCount(t0, t_end, dt_out);
  const auto output_time = [&](long k) { return k == n_out ? t_end : t0 + static_cast<double>(k) * dt_out; };
  if (!observer(0L, t0, y)) return summary;
  const double h_floor = options.h_min * std::max(std::abs(t0), t_end - t0);
  typename RkmkStepper<State>::Stages K;
  Tangent increment = y.zeroTangent();
  std::string why_not_projected;
  double t = t0;
  double h = std::min(startingStep(system, t0, y, stepper.order(), options), t_end - t0);
  long k_out = 1;
  while (k_out <= n_out) {
    const bool last = h >= t_end - t;
    const double h_try = last ? t_end - t : h;
    Tangent error = y.zeroTangent();
    State y1 = stepper.stepWithError(system, Scalar(t), y, Scalar(h_try), &error, &K, &increment);
    const Tangent scale = (y.magnitude().cwiseMax(y1.magnitude()) * Scalar(options.rtol))
                              .array() + Scalar(options.atol);
    double err = 0.0;
    for (int i = 0; i < error.size(); ++i)
      err = std::max(err, std::abs(scalarValue(error[i] / scale[i])));
    if (!std::isfinite(err) || !isFinite(y1)) err = std::numeric_limits<double>::infinity();
    const double factor =
        err == 0.0 ? options.fac_max
                   : std::min(options.fac_max, std::max(options.fac_min, options.safety * std::pow(err, exponent)));
    if (err <= 1.0) {
      const double t_new = last ? t_end : t + h_try;
      auto projectOrFail = [&](double t_p, State* s) {
        if (project(t_p, s, &why_not_projected)) return true;
        std::ostringstream why;
        why << "constraint projection failed at t = " << t_p << ": " << why_not_projected;
        summary.failed = true;
        summary.failure = why.str();
        return false;
      };
      if (!projectOrFail(t_new, &y1)) return summary;
      // Every output time this step covers, from its continuous extension.
      for (; k_out <= n_out && output_time(k_out) <= t_new; ++k_out) {
        const double t_k = output_time(k_out);
        const bool at_end = k_out == n_out || t_k == t_new;
        State y_k = at_end ? y1 : y.rplus(stepper.denseIncrement(K, increment, Scalar(h_try), (t_k - t) / h_try));
        if (!at_end && !projectOrFail(t_k, &y_k)) return summary;
        summary.t_reached = t_k;
        if (!observer(k_out, t_k, y_k)) {
          ++summary.steps;
          return summary;
        }
      }
      y = y1;
      t = t_new;
      ++summary.steps;
      h = h_try * factor;
    } else {
      ++summary.rejected_steps;
      h = h_try * factor;
    }
    const long attempted = summary.steps + summary.rejected_steps;
    if (attempted % options.heartbeat_steps == 0) {
      if (options.heartbeat) options.heartbeat(t, attempted);
      // At the pace so far, the whole run would need `projected` steps: far
      // beyond the limit, stop now rather than after hours.
      const double projected = static_cast<double>(attempted) * (t_end - t0) / std::max(t - t0, 1e-300);
      if (projected > kProjectionMargin * static_cast<double>(options.max_steps)) {
        std::ostringstream why;
        why << "stopped after " << attempted << " adaptive steps at t = " << t << " of " << t_end
            << ": at this pace (h = " << h << ") the run would need about " << projected
            << " steps, far above the step limit of " << options.max_steps << " (the tolerances rtol = "
            << options.rtol << ", atol = " << options.atol << " need that small a step: fast or stiff motion)";
        summary.failed = true;
        summary.step_limit_reached = true;
        summary.failure = why.str();
        return summary;
      }
    }
    if (k_out > n_out) break;
    if (h < h_floor) {
      std::ostringstream why;
      why << "adaptive step size collapsed to h = " << h << " at t = " << t << ": the local error cannot be brought "
          << "below the tolerances rtol = " << options.rtol << ", atol = " << options.atol
          << " (the motion is singular or too fast there)";
      summary.failed = true;
      summary.failure = why.str();
      return summary;
    }
    if (attempted >= options.max_steps) {
      std::ostringstream why;
      why << "stopped after " << attempted << " adaptive steps (" << summary.rejected_steps
          << " rejected), the step limit, at t = " << t << " of " << t_end << " with h = " << h
          << " (the tolerances rtol = " << options.rtol << ", atol = " << options.atol << " need that small a step)";
      summary.failed = true;
      summary.step_limit_reached = true;
      summary.failure = why.str();
      return summary;
    }
  }
  return summary;
}

}  // namespace lieflow
