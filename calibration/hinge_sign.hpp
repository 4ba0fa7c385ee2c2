/// \file
/// The relative sign of hinge axes fitted to gyroscopes alone, which the
/// constraint ‖ω₁×j₁‖ = ‖ω₂×j₂‖ cannot see (it is even in j₁ and in j₂), read
/// from how the perpendicular rates turn.
///
/// If R₁j₁ = R₂j₂ = j, the parts of ω perpendicular to the axis are one world
/// vector v⊥ (R₂ω₂ − R₁ω₁ = φ̇ j). In right-handed bases (eᵢ, fᵢ, jᵢ) of the two
/// bodies, zᵢ = eᵢ·ωᵢ + i fᵢ·ωᵢ are its coordinates; body 2's basis is body 1's
/// turned about j by ψ = φ + const, so z₁ z̄₂ = |v⊥|² e^{iψ} with
///     ψ' = φ̇ = ω₂·j₂ − ω₁·j₁.
/// So the phase ρ = arg(z₁ z̄₂) − ∫(ω₂·j₂ − ω₁·j₁)dt (trapezoid rule) is
/// constant up to noise. With j₂ → −j₂ (basis (e₂, −f₂, −j₂)) the same test
/// reads ρ' = arg(z₁ z₂) + ∫(ω₂·j₂ + ω₁·j₁)dt, which drifts at 2(α̇ + ω₁·j₁),
/// α the angle of z₁: the rate at which v⊥ turns about j in the world. The
/// measured phase is absolute (only the rates are integrated, so the noise
/// does not accumulate), and its spread is the circular variance
/// D = 1 − |Σ w e^{iρ}| / Σ w with weights w = min(|z₁|², |z₂|²) (the phase's
/// noise is σ/|z|), taken per window of kSignWindowSeconds so that a gyroscope
/// bias cannot build up. The hypothesis with the smaller D wins when it is
/// below kSignDecisionRatio times the other; otherwise (v⊥ does not turn about
/// j, e.g. a swing about one fixed world axis) the data cannot tell, and the
/// fitted signs are kept by convention.
#pragma once

#include <vector>

#include <Eigen/Core>

namespace lieflow {
namespace calibration {

/// The winner's circular variance must be below this fraction of the loser's.
constexpr double kSignDecisionRatio = 0.25;
/// Length of the windows over which the phase is compared (s).
constexpr double kSignWindowSeconds = 4.0;

struct HingeSignEvidence {
  int relative_sign = 1;          ///< multiply j₂ by this to get R₁j₁ = R₂j₂
  bool decided = false;           ///< false: the data cannot tell; relative_sign = +1 by convention
  double spread_same = 0.0;       ///< circular variance D of the phase with j₂
  double spread_flipped = 0.0;    ///< ... with −j₂
};

/// The decision from the two circular variances (of one recording, or the
/// sample-weighted mean of several recordings' own).
HingeSignEvidence hingeSignFromSpreads(double spread_same, double spread_flipped);

HingeSignEvidence hingeRelativeSign(const std::vector<double>& time, const std::vector<Eigen::Vector3d>& w1,
                                    const std::vector<Eigen::Vector3d>& w2, const Eigen::Vector3d& j1,
                                    const Eigen::Vector3d& j2);

}  // namespace calibration
}  // namespace lieflow
