/// \file
/// The inverse of the derivative of exp, dexp⁻¹, applied to a vector: exactly
/// and truncated after a given power of ad, as Runge–Kutta–Munthe-Kaas methods
/// use it (Munthe-Kaas 1998; Iserles, Munthe-Kaas, Nørsett, Zanna 2000, §3.4).
///
/// With the left-trivialized convention of the RKMK literature,
///   d/dt exp(Ω(t)) = dexp_Ω(Ω') exp(Ω),
///   dexp⁻¹_Ω(v) = Σ_{k≥0} B_k/k! ad_Ω^k v
///               = v − ½[Ω,v] + 1/12 [Ω,[Ω,v]] − 1/720 ad_Ω⁴ v + …,
/// and dexp⁻¹_Ω = Jl⁻¹(Ω) in lieflow's notation. For lieflow's body-frame
/// velocities (Ẋ = X ξ^, right trivialization) the algebra ODE of
/// X(t) = X₀ exp(Θ(t)) is Θ' = dexp⁻¹_{−Θ}(ξ) = Jr⁻¹(Θ) ξ.
#pragma once

#include "liegroup/se3.hpp"
#include "liegroup/so3.hpp"

namespace lieflow {

/// dexp⁻¹_Ω(v) = Jl⁻¹(Ω) v, exact (closed form of Group::JlInv). ‖rotation
/// part of Ω‖ < 2π.
template <typename Group>
typename Group::Tangent dexpInv(const typename Group::Tangent& Omega,
                                const typename Group::Tangent& v) {
  return Group::JlInv(Omega) * v;
}

/// Σ_{k=0}^{order} B_k/k! ad_Ω^k v: the series of dexp⁻¹ truncated after ad^order.
/// Its error is O(‖Ω‖^{order+1} ‖v‖) (O(‖Ω‖^{order+2}) when order+1 ≥ 3 is
/// odd, since B_k = 0 for odd k ≥ 3). An RKMK method of order p needs
/// order ≥ p − 2 (Munthe-Kaas 1999, Thm. 1). Supports order ≤ 8.
template <typename Group>
typename Group::Tangent dexpInvTruncated(const typename Group::Tangent& Omega,
                                         const typename Group::Tangent& v, int order) {
  // B_k / k! for k = 0..8 (B_1 = −1/2, B_odd≥3 = 0).
  static constexpr double kCoeff[9] = {1.0,           -0.5, 1.0 / 12.0, 0.0, -1.0 / 720.0, 0.0,
                                       1.0 / 30240.0, 0.0,  -1.0 / 1209600.0};
  LIEFLOW_ASSERT(order >= 0 && order <= 8, "dexpInvTruncated: order must be in [0, 8]");
  using T = typename Group::Scalar;
  const auto adOmega = Group::ad(Omega);
  typename Group::Tangent term = v;
  typename Group::Tangent sum = v;
  for (int k = 1; k <= order; ++k) {
    term = adOmega * term;
    if (kCoeff[k] != 0.0) sum += T(kCoeff[k]) * term;
  }
  return sum;
}

}  // namespace lieflow
