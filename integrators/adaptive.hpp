/// \file
/// Adaptive step-size control on the group for embedded RKMK pairs
/// (Hairer, Nørsett, Wanner I, §II.4, with the error measured in the algebra:
/// Engø 2003, "On the construction of geometric integrators in the RKMK
/// class"). The local error estimate e = h Σ (bᵢ − b̂ᵢ)Kᵢ is scaled per
/// component by atol + rtol·max(|y|, |y₁|) and the step follows
///   h_new = h · min(fac_max, max(fac_min, safety · err^{−1/(q̂+1)})),
/// q̂ the order of the embedded solution. Output times are hit exactly.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "integrators/integrate.hpp"
#include "integrators/rkmk.hpp"

namespace lieflow {

struct AdaptiveOptions {
  double rtol = 1e-8;
  double atol = 1e-10;
  double safety = 0.9;
  double fac_min = 0.2;
  double fac_max = 5.0;
  /// Steps below this are a failure (the problem is too stiff or singular).
  double h_min = 1e-14;
  long max_steps = 100000000;
};

/// Advances y from t0 to t_end, calling observer(k, t_k, y) at the output
/// times t_k = t0 + k·dt_out (and t_end), with as many accepted adaptive
/// steps in between as the tolerances need. The step never exceeds dt_out.
template <typename State, typename System, typename Observer>
RunSummary integrateAdaptive(const RkmkStepper<State>& stepper, const System& system, State y,
                             double t0, double t_end, double dt_out,
                             const AdaptiveOptions& options, Observer&& observer) {
  using Scalar = typename State::Scalar;
  using Tangent = typename State::Tangent;
  LIEFLOW_ASSERT(stepper.tableau().hasEmbedded(), "integrateAdaptive needs an embedded pair");
  const double exponent = -1.0 / (stepper.tableau().embedded_order + 1.0);
  RunSummary summary;
  summary.t_reached = t0;
  const long n_out = stepCount(t0, t_end, dt_out);
  if (!observer(0L, t0, y)) return summary;
  double t = t0;
  double h = dt_out;
  for (long k = 1; k <= n_out; ++k) {
    const double t_out = k == n_out ? t_end : t0 + static_cast<double>(k) * dt_out;
    while (t < t_out) {
      const bool last = h >= t_out - t;
      const double h_try = last ? t_out - t : h;
      Tangent error = y.zeroTangent();
      const State y1 = stepper.stepWithError(system, Scalar(t), y, Scalar(h_try), &error);
      const Tangent scale = (y.magnitude().cwiseMax(y1.magnitude()) * Scalar(options.rtol))
                                .array() + Scalar(options.atol);
      double err = 0.0;
      for (int i = 0; i < error.size(); ++i)
        err = std::max(err, std::abs(scalarValue(error[i] / scale[i])));
      if (!std::isfinite(err) || !isFinite(y1)) err = std::numeric_limits<double>::infinity();
      const double factor =
          err == 0.0 ? options.fac_max
                     : std::min(options.fac_max,
                                std::max(options.fac_min, options.safety * std::pow(err, exponent)));
      if (err <= 1.0) {
        y = y1;
        t = last ? t_out : t + h_try;
        ++summary.steps;
        if (!last) h = std::min(h_try * factor, dt_out);
      } else {
        ++summary.rejected_steps;
        h = h_try * factor;
      }
      if (h < options.h_min || summary.steps + summary.rejected_steps > options.max_steps) {
        std::ostringstream why;
        why << "adaptive step size collapsed to h = " << h << " at t = " << t
            << " (tolerances rtol = " << options.rtol << ", atol = " << options.atol
            << " cannot be met)";
        summary.failed = true;
        summary.failure = why.str();
        return summary;
      }
    }
    summary.t_reached = t_out;
    if (!observer(k, t_out, y)) return summary;
  }
  return summary;
}

}  // namespace lieflow
