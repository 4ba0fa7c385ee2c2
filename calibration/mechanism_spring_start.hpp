/// \file
/// A start for the mechanism spring fit (mechanism_spring_fit.hpp) from the
/// recorded joint angles alone, not from the scene's springs and dashpots:
/// inverse dynamics, linear in the unknowns.
///
/// Along the recorded motion the joints transmit τ(q, q̇, q̈) (recursive
/// Newton–Euler of the scene's bodies and gravity, dynamics/joint_space/scalar_dynamics.hpp),
/// and the joints' springs, dashpots and applied moments M(t) supply it:
///   τ_j(t) − M_j(t) = −k_j (q_j − q₀ⱼ) − c_j q̇_j,
/// linear in (k_j, c_j, k_j q₀ⱼ): the inverse-dynamics identification of
/// parameters that enter linearly (Atkeson, An & Hollerbach, "Estimation of
/// inertial parameters of manipulator loads and links", IJRR 5 (1986)
/// 101–119), here one least-squares regression per fitted coordinate over the
/// samples, with regressors −q (or −(q − q₀) when the rest angle is the
/// scene's), −q̇ and 1 for the elements the coordinate has. q, q̇ and q̈ at
/// each sample come from the cubic fitted to the angles over ±w samples
/// (Savitzky–Golay, any spacing), w about 1/16 of the shortest period seen
/// in the recording (from the crossings of each angle's mean), at least 3.
///
/// The angles' noise enters q̈ amplified by about 1/(w Δt)² and, through the
/// regressors, biases k and c towards zero (errors in variables): a start,
/// not an estimate — the fit that follows is maximum likelihood. A parameter
/// whose estimate is not positive is left at the scene's value and named.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "calibration/mechanism_flow.hpp"
#include "dynamics/joint_space/articulated_model.hpp"

namespace lieflow {
namespace calibration {

/// The local cubics' smallest half width, and the fewest samples the start
/// takes (one window and four more).
constexpr int kInverseDynamicsMinHalfWidth = 3;
constexpr int kInverseDynamicsMinSamples = 2 * kInverseDynamicsMinHalfWidth + 5;

/// One fitted coordinate: which elements it has and, for the rest angle,
/// whether it is estimated or the scene's (`rest_angle`).
struct StartCoordinate {
  int coordinate = 0;  ///< index in the model's joint coordinates
  bool stiffness = true, damping = true, rest_angle_fitted = false;
  double rest_angle = 0.0;
};

struct MechanismStart {
  /// Per StartCoordinate: the estimates (0 for an element it does not have;
  /// the rest angle the scene's unless estimated with a usable stiffness).
  std::vector<double> stiffness, damping, rest_angle;
  /// Per StartCoordinate: whether the stiffness / damping estimate is usable
  /// (finite and positive); when not, the caller keeps the scene's.
  std::vector<bool> stiffness_usable, damping_usable;
  int half_width = 0;  ///< w of the local cubics
};

/// The inverse-dynamics start (file comment) from the angles of every joint
/// coordinate (`angles[j]`, sampled at `time`; w is reduced to fit a short
/// recording). Throws InvalidInput below kInverseDynamicsMinSamples samples.
MechanismStart inverseDynamicsStart(const articulated::ArticulatedModel& model, const std::vector<double>& time,
                                    const std::vector<const std::vector<double>*>& angles,
                                    const std::vector<StartCoordinate>& fitted);

/// The joint angles from the bodies' gyroscopes alone (by tree index, body
/// axes), integrated from the angles q0 at the first sample. A joint turns
/// its secondary body relative to its main one by M(φ) (articulated_model.hpp),
/// so the relative angular velocity in the main frame is
///   M ω_s − ω_m = a₁ φ̇₁ [+ exp(φ₁ a₁) R_ref a₂ φ̇₂]
/// (a revolute joint: φ̇ = (R_refᵀ a)·ω_s − a·ω_m, no angle needed; a
/// universal joint: the rates by least squares on the two columns at the
/// current angles), integrated by Heun's method between samples. The gyroscopes'
/// noise enters as a random walk (σ √(T Δt)) and a bias as a drift: good for a
/// start, which is what it is for (the fit that follows uses the rates
/// themselves). Covers revolute and universal joints; false (angles
/// untouched) if a body turns on a spherical joint or an angle is prescribed.
bool anglesFromGyroscopes(const articulated::ArticulatedModel& model, const Eigen::VectorXd& q0,
                          const std::vector<double>& time,
                          const std::vector<const std::vector<Eigen::Vector3d>*>& rates,
                          std::vector<std::vector<double>>* angles);

/// The largest natural frequency of the start model about the state y0 at
/// rest: the square root of the largest |eigenvalue| of ∂u̇/∂(q, θ) (central
/// differences of relative step kFrequencyProbe; a spherical joint's rotation
/// turned by N exp(±d e_c)). It sets the fit's steps and segments.
double fastestFrequency(const articulated::ArticulatedModel& model, const MechanismForces<double>& forces,
                        const MechanismState<double>& y0);
constexpr double kFrequencyProbe = 1e-6;

}  // namespace calibration
}  // namespace lieflow
