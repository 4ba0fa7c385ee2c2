/// \file
/// A start for the spring/dashpot fit from the recorded angle alone, so that
/// `calibrate spring` needs no guess from the user.
///
/// Near its equilibrium a damped joint coordinate obeys I φ̈ + c φ̇ + k_eff φ = 0
/// (k_eff = k + the gravity stiffness −∂Q_g/∂φ, I the generalized inertia from
/// the scene), whose samples at a spacing Δ = d·δt satisfy exactly the linear
/// recurrence (an AR(2) model with intercept; e.g. Ljung, "System
/// Identification", 2nd ed., §4.2)
///   φ_{j+2d} = a₁ φ_{j+d} + a₂ φ_j + b,    a₁ = 2 r cos θ,  a₂ = −r²,
/// with the continuous poles s = (ln r ± iθ)/Δ = −ζω ± iω√(1−ζ²). The lag d is
/// chosen from the zero crossings (with hysteresis) so that Δ ≈ T/8: at a lag
/// of one sample the recurrence would be dominated by noise. Then
///   k_eff = I |s|²,  c = −2 I Re s,  φ_eq = b / (1 − a₁ − a₂),
///   k = k_eff − k_g,  φ₀ = φ_eq − Q_g(φ_eq)/k.
/// The estimate is biased by the noise (errors in variables) and by the
/// nonlinearity of gravity; it is only the start of the nonlinear fit.
#pragma once

#include <string>

#include "calibration/spring_data.hpp"
#include "calibration/spring_joint.hpp"

namespace lieflow {
namespace calibration {

struct SpringStart {
  bool found = false;      ///< false: the angle does not oscillate (see `why`)
  double stiffness = 0.0;
  double damping = 0.0;
  double rest_angle = 0.0;
  double natural_frequency = 0.0;  ///< ω = √(k_eff / I), rad/s
  double period = 0.0;             ///< from the zero crossings, s
  int lag = 0;                     ///< d
  std::string why;
};

/// The start for coordinate `coordinate` of `joint` from `data`.
SpringStart estimateSpringStart(const SpringJoint& joint, const SpringData& data, int coordinate);

}  // namespace calibration
}  // namespace lieflow
