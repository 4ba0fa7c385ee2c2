/// \file
/// Residuals of a hinge (revolute joint) with unit axis j₁ in the main body's
/// frame and j₂ in the secondary's. The kinematics: R₁ j₁ = R₂ j₂ (the axis is
/// one line in the world), and the relative angular velocity is along it,
/// R₂ω₂ − R₁ω₁ = φ̇ R₁j₁ (R body → world, ω body-frame, φ the joint angle).
/// With orientations and gyroscopes both residuals are used (hinge_fit.hpp).
///
/// All functors multiply their residuals by *weight (1/σ̂ of their kind) and
/// allocate nothing.
#pragma once

#include <cmath>

#include <Eigen/Core>

#include "calibration/gyro_nuisance.hpp"
#include "calibration/mixed_scalar.hpp"
#include "liegroup/scalar.hpp"

namespace lieflow {
namespace calibration {

/// Gyroscopes only. The components of ω perpendicular to the axis are the
/// same world vector seen from either body, so their lengths agree:
/// ‖ω₁ × j₁‖ = ‖ω₂ × j₂‖ (Seel, Schauer & Raisch 2012, eq. 7). Seel's
/// difference of norms has a kink where ω ∥ j and a bias there (E‖n⊥‖ > 0 for
/// noise n); we use the smooth squared form c = ‖ω₁×j₁‖² − ‖ω₂×j₂‖² (its
/// noise bias 2σ₁² − 2σ₂² cancels for equal gyroscopes) divided by the norm of
/// its gradient with respect to the measured ω, 2 (‖ω₁×j₁‖² + ‖ω₂×j₂‖²)^½
/// (Sampson's first-order geometric error): the residual is then in rad/s with
/// the variance σ² of one gyroscope axis, and ≈ (‖ω₁×j₁‖ − ‖ω₂×j₂‖)/√2 where
/// both are large. `floor_sq` keeps 0/0 away when both vanish.
struct GyroHingeResidual {
  Eigen::Vector3d w1;
  Eigen::Vector3d w2;
  double floor_sq = 0.0;
  const double* weight = nullptr;

  /// Relative size of floor_sq: (kFloor · |ω|)², far below any gyroscope's noise.
  static constexpr double kFloor = 1e-6;

  GyroHingeResidual(const Eigen::Vector3d& omega1, const Eigen::Vector3d& omega2)
      : w1(omega1), w2(omega2),
        floor_sq(kFloor * kFloor * (omega1.squaredNorm() + omega2.squaredNorm()) + 1e-300) {}

  template <typename T>
  bool operator()(const T* j1_data, const T* j2_data, T* r) const {
    const Eigen::Map<const Vector3<T>> j1(j1_data), j2(j2_data);
    const T p1 = mixed::cross(w1, Vector3<T>(j1)).squaredNorm();
    const T p2 = mixed::cross(w2, Vector3<T>(j2)).squaredNorm();
    r[0] = *weight * sampson(p1, p2, floor_sq);
    return true;
  }

  /// The residual and its closed-form derivatives (residual_kind.hpp): with
  /// p = ‖ω×j‖² = ‖ω‖²‖j‖² − (ω·j)² (the ambient function of j, as Ceres
  /// differentiates it before the manifold), ∂p/∂j = 2(‖ω‖² j − (ω·j) ω), and
  /// with S = p₁ + p₂ + floor, r = (p₁ − p₂)/2√S:
  /// ∂r/∂p₁ = 1/2√S − r/2S, ∂r/∂p₂ = −1/2√S − r/2S (times the weight).
  bool evaluate(const double* j1_data, const double* j2_data, double* r, double* d1, double* d2) const {
    const Eigen::Map<const Eigen::Vector3d> j1(j1_data), j2(j2_data);
    const double a1 = w1.dot(j1), a2 = w2.dot(j2);
    const double n1 = w1.squaredNorm(), n2 = w2.squaredNorm();
    const double p1 = n1 * j1.squaredNorm() - a1 * a1, p2 = n2 * j2.squaredNorm() - a2 * a2;
    const double root = std::sqrt(p1 + p2 + floor_sq);
    const double value = (p1 - p2) / (2.0 * root);
    r[0] = *weight * value;
    if (d1 || d2) {
      const double half = 0.5 / root, slope = value / (2.0 * root * root);
      if (d1) Eigen::Map<Eigen::Vector3d>{d1} = (*weight * (half - slope) * 2.0) * (n1 * j1 - a1 * w1);
      if (d2) Eigen::Map<Eigen::Vector3d>{d2} = (*weight * (-half - slope) * 2.0) * (n2 * j2 - a2 * w2);
    }
    return true;
  }

  /// (p₁ − p₂) / 2(p₁ + p₂ + floor)^½ for p = ‖ω × j‖².
  template <typename T>
  static T sampson(const T& p1, const T& p2, double floor_sq) {
    using std::sqrt;
    return (p1 - p2) / (2.0 * sqrt(p1 + p2 + floor_sq));
  }
};

/// GyroHingeResidual with the gyroscopes' nuisance parameters ν (residual_kind.hpp):
/// constant biases b₁ = B₁(ν₀, ν₁), b₂ = B₂(ν₂, ν₃) in the planes perpendicular
/// to the start axes (a bias along the axis itself does not change ‖ω × j‖:
/// a hinge cannot observe it), and the fractional part ν₄ of the secondary
/// sensor's clock offset δ = m h + ν₄ [s] (its sample stamped t was taken at
/// t + δ; the whole samples m are found before, hinge_fit.cpp): sample k
/// pairs ω₁,k with ω₂ at stamp t_k − δ, to first order
///   ω₂,k−m − ν₄ ω̇₂,k−m,
/// ω̇ the cubic slope of rate_derivative.hpp. (Interpolating the noisy rates
/// instead made the residual's slope in δ share noise with the residual and
/// biased δ, by 8.5 ms ± 0.26 ms on the hinge-pair scene at 0.02 rad/s; the
/// slope's weights are odd about the sample, so its noise is uncorrelated
/// with ω₂,k−m's.)
struct GyroHingeNuisanceResidual {
  Eigen::Vector3d w1;   ///< ω₁,k
  Eigen::Vector3d w2;   ///< ω₂,k−m
  Eigen::Vector3d dw2;  ///< ω̇₂,k−m (zero without a clock offset)
  Eigen::Matrix<double, 3, 2> B1, B2;
  double floor_sq = 0.0;
  const double* weight = nullptr;

  template <typename T>
  bool operator()(const T* j1_data, const T* j2_data, const T* nu, T* r) const {
    const Eigen::Map<const Vector3<T>> j1(j1_data), j2(j2_data);
    Vector3<T> v1, v2;
    correctedRates(w1, w2, dw2, B1, B2, nu, &v1, &v2);
    r[0] = *weight * GyroHingeResidual::sampson<T>(v1.cross(Vector3<T>(j1)).squaredNorm(),
                                                   v2.cross(Vector3<T>(j2)).squaredNorm(), floor_sq);
    return true;
  }
};

/// Accelerometers with gyroscopes. The joint centre's acceleration is one
/// world vector; each body sees it as its specific force moved from the
/// sensor to the centre, f_c,k (joint_centre.hpp), and the hinge turns body 2
/// relative to body 1 only about the axis, which keeps a vector's component
/// along it: j₁·f_c,1 = j₂·f_c,2 [m/s²] (Olsson, Kok, Seel & Halvorsen
/// 2020's accelerometer constraint, at the centre instead of at the
/// sensors). Linear in the axes: gravity and the centre's own acceleration
/// fix the axes even when both bodies turn almost only about the hinge, where
/// the gyroscopes' constraint rises only quadratically. Any point of the axis
/// serves as the centre: moving it by λ along the axis changes both sides by
/// −λ‖ω_k × j_k‖², equal by Seel's constraint. One noise component.
struct AccelerometerHingeResidual {
  Eigen::Vector3d c1;  ///< f_c,1, body 1's axes
  Eigen::Vector3d c2;  ///< f_c,2, body 2's axes
  const double* weight = nullptr;

  AccelerometerHingeResidual(const Eigen::Vector3d& centre_force1, const Eigen::Vector3d& centre_force2)
      : c1(centre_force1), c2(centre_force2) {}

  template <typename T>
  bool operator()(const T* j1_data, const T* j2_data, T* r) const {
    const Eigen::Map<const Vector3<T>> j1(j1_data), j2(j2_data);
    r[0] = *weight * (mixed::dot(c1, Vector3<T>(j1)) - mixed::dot(c2, Vector3<T>(j2)));
    return true;
  }

  /// Linear in the axes: ∂r/∂j₁ = w f_c,1, ∂r/∂j₂ = −w f_c,2 (residual_kind.hpp).
  bool evaluate(const double* j1, const double* j2, double* r, double* d1, double* d2) const {
    const Eigen::Map<const Eigen::Vector3d> a(j1), b(j2);
    r[0] = *weight * (c1.dot(a) - c2.dot(b));
    if (d1) Eigen::Map<Eigen::Vector3d>{d1} = *weight * c1;
    if (d2) Eigen::Map<Eigen::Vector3d>{d2} = -*weight * c2;
    return true;
  }
};

/// Orientations: j₁ − R₁ᵀR₂ j₂ = 0 (the axis as one world line, in body 1's
/// frame; its norm is ‖R₁j₁ − R₂j₂‖). Noise on R₁, R₂ moves it within the plane
/// ⟂ j₁ only: 2 noise components per sample. In rad (the angle between R₁j₁
/// and R₂j₂ for small residuals).
struct OrientationHingeResidual {
  Eigen::Matrix3d R12;  ///< R₁ᵀ R₂
  const double* weight = nullptr;

  explicit OrientationHingeResidual(const Eigen::Matrix3d& r12) : R12(r12) {}

  template <typename T>
  bool operator()(const T* j1_data, const T* j2_data, T* r) const {
    const Eigen::Map<const Vector3<T>> j1(j1_data), j2(j2_data);
    const Vector3<T> d = mixed::mul(R12, Vector3<T>(j2)) - j1;
    for (int i = 0; i < 3; ++i) r[i] = *weight * d[i];
    return true;
  }

  /// Linear in the axes: ∂r/∂j₁ = −w I, ∂r/∂j₂ = w R₁ᵀR₂ (row-major 3 × 3).
  bool evaluate(const double* j1, const double* j2, double* r, double* d1, double* d2) const {
    const Eigen::Map<const Eigen::Vector3d> a(j1), b(j2);
    Eigen::Map<Eigen::Vector3d>{r} = *weight * (R12 * b - a);
    if (d1) Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>{d1} = -*weight * Eigen::Matrix3d::Identity();
    if (d2) Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>{d2} = *weight * R12;
    return true;
  }
};

}  // namespace calibration
}  // namespace lieflow
