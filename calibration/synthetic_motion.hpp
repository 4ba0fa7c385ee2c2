/// \file
/// Analytic two-body joint motions and their noisy recordings, the ground
/// truth of the calibration tests and benchmarks.
///
/// The main body turns as R₁(t) = exp(θ(t)) with θ a sum of sines, so its body
/// rate is ω₁ = Jr(θ) θ̇ exactly (README "Conventions": Ṙ = R ω^, and
/// d/dt exp(θ) = exp(θ) (Jr(θ)θ̇)^). The secondary body follows the joint:
///   hinge:      R₂ = R₁ exp(φ j₁) C,            C j₂ = j₁,
///               ω₂ = Cᵀ exp(−φ j₁) ω₁ + φ̇ j₂;
///   universal:  R₂ = R₁ exp(φ₁ a₁) C exp(φ₂ a₂), C a₂ ⟂ a₁,
///               ω₂ = exp(−φ₂a₂) Cᵀ exp(−φ₁a₁) (ω₁ + φ̇₁ a₁) + φ̇₂ a₂.
/// (Differentiate R₂ and use exp(φa)ᵀ a = a.) Recordings add Gaussian noise:
/// ω + n with n ~ N(0, σ_ω² I), and R exp(η) with η ~ N(0, σ_R² I).
///
/// Accelerometers (SensorGeometry): the joint centre moves along p(t) in the
/// world, and body k's sensor sits at p − R_k o_k (o_k the centre from the
/// sensor, body axes). The sensor's acceleration is p̈ − R_k(ω̇_k × o_k +
/// ω_k × (ω_k × o_k)), so it reads the specific force
///   f_k = R_kᵀ(p̈ − g) − ω̇_k × o_k − ω_k × (ω_k × o_k),
/// ω̇_k from a five-point central difference of the exact ω_k at
/// kRateDerivativeStep (error O(h⁴) ≈ 1e-11 m/s² on these motions).
#pragma once

#include <random>
#include <vector>

#include <Eigen/Core>

#include "calibration/hinge_likelihood.hpp"
#include "calibration/joint_samples.hpp"
#include "liegroup/so3.hpp"

namespace lieflow {
namespace calibration {

/// x(t) = offset + Σₖ amplitudeₖ sin(2π frequencyₖ t + phaseₖ) and its derivative.
template <typename V>
struct SineSum {
  V offset;
  std::vector<V> amplitude;
  std::vector<double> frequency_hz;
  std::vector<double> phase;

  V value(double t) const;
  V derivative(double t) const;
  V secondDerivative(double t) const;
};

/// R(t) = exp(θ(t)).
struct SmoothRotation {
  SineSum<Eigen::Vector3d> angle;
  SO3d orientation(double t) const;
  Eigen::Vector3d bodyRate(double t) const;  ///< Jr(θ) θ̇
};

/// Both bodies' exact state at time t.
struct TwoBodyState {
  SO3d R1, R2;
  Eigen::Vector3d w1, w2;
};

/// Where the accelerometers sit (file comment): the joint centre's world
/// path p(t), the centre from each sensor o₁, o₂ (body axes), gravity g.
struct SensorGeometry {
  SineSum<Eigen::Vector3d> centre{Eigen::Vector3d::Zero(), {}, {}, {}};
  Eigen::Vector3d anchor_main = Eigen::Vector3d::Zero();
  Eigen::Vector3d anchor_secondary = Eigen::Vector3d::Zero();
  Eigen::Vector3d gravity = Eigen::Vector3d(0.0, 0.0, -9.81);
};

/// Step of the five-point difference that gives ω̇ for the accelerometers [s].
constexpr double kRateDerivativeStep = 1e-3;

class JointMotion {
 public:
  virtual ~JointMotion() = default;
  virtual TwoBodyState at(double t) const = 0;

  SensorGeometry sensors;
  /// Both sensors' specific forces f₁, f₂ at time t (file comment).
  void specificForces(double t, Eigen::Vector3d* f1, Eigen::Vector3d* f2) const;
};

struct HingeMotion final : JointMotion {
  SmoothRotation main;
  SineSum<double> angle;     ///< φ(t)
  Eigen::Vector3d axis_main; ///< j₁
  SO3d mount;                ///< C

  Eigen::Vector3d axisSecondary() const { return mount.inverse() * axis_main; }  ///< j₂ = Cᵀ j₁
  TwoBodyState at(double t) const override;
};

struct UniversalMotion final : JointMotion {
  SmoothRotation main;
  SineSum<double> angle1, angle2;  ///< φ₁(t), φ₂(t)
  Eigen::Vector3d axis1_main;      ///< a₁
  Eigen::Vector3d axis2_secondary; ///< a₂
  SO3d mount;                      ///< C, with C a₂ ⟂ a₁

  TwoBodyState at(double t) const override;
};

/// A varied motion: the main body turns about all axes (about 1 rad and
/// 1–2 rad/s), the joint angle swings by about ±1.5 rad at 0.2–0.7 Hz;
/// random axes and mount.
HingeMotion randomHingeMotion(std::mt19937& gen);
/// The same for a universal joint, both angles swinging.
UniversalMotion randomUniversalMotion(std::mt19937& gen);
/// Sensors 5–25 cm from the joint centre in random directions, the centre
/// swinging by about ±5 cm at 0.5–1.5 Hz (accelerations of 1–4 m/s²), gravity
/// (0, 0, −9.81).
SensorGeometry randomSensorGeometry(std::mt19937& gen);
/// A knee-like hinge: the main body swings about the hinge axis (±0.6 rad,
/// 0.4–1.2 Hz) with `wobble` rad of turning about the other two axes, the
/// joint angle ±0.6 rad; the axis horizontal in the world, the centre moving
/// in the plane perpendicular to it (sagittal), sensors as
/// randomSensorGeometry. With small wobble both bodies turn almost only about
/// the hinge axis: the gyroscopes' constraint ‖ω₁ × j₁‖ = ‖ω₂ × j₂‖ is nearly
/// blind (it rises only quadratically), the accelerometers are not.
HingeMotion kneeLikeHingeMotion(std::mt19937& gen, double wobble);

struct RecordingNoise {
  double rate_sigma = 0.0;         ///< rad/s, per gyroscope axis
  double orientation_sigma = 0.0;  ///< rad, per axis of η in R exp(η)
  bool orientations = true;        ///< record B.qw..B.qz
  bool rates = true;               ///< record B.wx..B.wz
  double acc_sigma = 0.0;          ///< m/s², per accelerometer axis
  bool accelerometers = false;     ///< record B.ax..B.az (motion.sensors)
  Eigen::Vector3d gyro_bias_main = Eigen::Vector3d::Zero();       ///< rad/s, added to ω₁
  Eigen::Vector3d gyro_bias_secondary = Eigen::Vector3d::Zero();  ///< rad/s, added to ω₂
  /// The secondary sensor's clock offset δ [s]: its sample stamped t_k
  /// records the secondary body at t_k + δ.
  double secondary_clock_offset = 0.0;
  /// A sensor wobbling on soft tissue [rad/s]: each gyroscope reads, on top
  /// of its body's rate, wobble_rate · sin(2π f t + p) about a unit axis u of
  /// the sensor, f uniform in [wobble_min_hz, wobble_max_hz], p and u random,
  /// one draw per body (no joint model describes it; `--low-pass` removes it).
  double wobble_rate = 0.0;
  double wobble_min_hz = 10.0;
  double wobble_max_hz = 20.0;
};

/// The true main-body rates and joint angles of n samples at `rate_hz` from
/// t = 0, with the axis and mount: what hingeCramerRao needs.
HingeTruthSamples hingeTruth(const HingeMotion& motion, int n, double rate_hz);

/// n samples at `rate_hz` from t = 0, bodies named "main" and "secondary".
JointSamples recordMotion(const JointMotion& motion, int n, double rate_hz, const RecordingNoise& noise,
                          std::mt19937& gen);

}  // namespace calibration
}  // namespace lieflow
