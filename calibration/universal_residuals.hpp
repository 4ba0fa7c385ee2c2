/// \file
/// Residuals of a universal (Cardan) joint with unit axis a₁ fixed in the main
/// body and a₂ fixed in the secondary body. The kinematics: R₂ = R₁ exp(φ₁ a₁)
/// C exp(φ₂ a₂) with C a₂ ⟂ a₁, so the two axes stay perpendicular in the world,
/// (R₁a₁)·(R₂a₂) = 0, and the relative angular velocity R₂ω₂ − R₁ω₁ =
/// φ̇₁ R₁a₁ + φ̇₂ R₂a₂ lies in the plane they span.
///
/// Gyroscopes alone give no instantaneous constraint (the span's normal
/// depends on the unmeasured φ₁), so these residuals need orientations.
#pragma once

#include <ceres/rotation.h>
#include <Eigen/Core>

#include "calibration/gyro_nuisance.hpp"
#include "calibration/mixed_scalar.hpp"
#include "liegroup/scalar.hpp"

namespace lieflow {
namespace calibration {

/// Orientations: a₁ · (R₁ᵀR₂ a₂) = 0, in rad (the departure of the world axes
/// from perpendicular), 1 noise component per sample.
struct OrientationUniversalResidual {
  Eigen::Matrix3d R12;  ///< R₁ᵀ R₂
  const double* weight = nullptr;

  explicit OrientationUniversalResidual(const Eigen::Matrix3d& r12) : R12(r12) {}

  template <typename T>
  bool operator()(const T* a1_data, const T* a2_data, T* r) const {
    const Eigen::Map<const Vector3<T>> a1(a1_data), a2(a2_data);
    r[0] = *weight * a1.dot(mixed::mul(R12, Vector3<T>(a2)));
    return true;
  }

  /// ∂r/∂a₁ = w R₁₂a₂, ∂r/∂a₂ = w R₁₂ᵀa₁ (residual_kind.hpp).
  bool evaluate(const double* a1_data, const double* a2_data, double* r, double* d1, double* d2) const {
    const Eigen::Map<const Eigen::Vector3d> a1(a1_data), a2(a2_data);
    const Eigen::Vector3d b = R12 * a2;
    r[0] = *weight * a1.dot(b);
    if (d1) Eigen::Map<Eigen::Vector3d>{d1} = *weight * b;
    if (d2) Eigen::Map<Eigen::Vector3d>{d2} = *weight * (R12.transpose() * a1);
    return true;
  }
};

/// Orientations and gyroscopes: u · (a₁ × R₁ᵀR₂a₂) = 0 with u = R₁ᵀR₂ω₂ − ω₁ the
/// relative angular velocity in body 1's frame (in the span of a₁ and R₁ᵀR₂a₂),
/// in rad/s, 1 noise component per sample.
///
/// Its noise is not one σ for all samples: besides both gyroscopes' noise it
/// carries the orientation noise (through R₁ᵀR₂, in u and in the normal)
/// scaled by the rates, which dominates at 0.5° and a few rad/s.
/// `scale` = σ_ref/σₖ (universal_fit.cpp: relativeRateNoise) makes every sample's
/// noise σ_ref, so that one noise scale per kind whitens it.
struct RelativeRateUniversalResidual {
  Eigen::Matrix3d R12;  ///< R₁ᵀ R₂
  Eigen::Vector3d u;    ///< R₁ᵀR₂ω₂ − ω₁
  double scale = 1.0;   ///< per-sample weight σ_ref/σₖ
  const double* weight = nullptr;

  RelativeRateUniversalResidual(const Eigen::Matrix3d& r12, const Eigen::Vector3d& relative_rate)
      : R12(r12), u(relative_rate) {}

  template <typename T>
  bool operator()(const T* a1_data, const T* a2_data, T* r) const {
    const Eigen::Map<const Vector3<T>> a1(a1_data), a2(a2_data);
    const Vector3<T> normal = Vector3<T>(a1).cross(mixed::mul(R12, Vector3<T>(a2)));
    r[0] = *weight * scale * mixed::dot(u, normal);
    return true;
  }

  /// With b = R₁₂a₂, u·(a₁ × b) = a₁·(b × u) = b·(u × a₁): ∂r/∂a₁ = w s (b × u),
  /// ∂r/∂a₂ = w s R₁₂ᵀ(u × a₁) (residual_kind.hpp).
  bool evaluate(const double* a1_data, const double* a2_data, double* r, double* d1, double* d2) const {
    const Eigen::Map<const Eigen::Vector3d> a1(a1_data), a2(a2_data);
    const Eigen::Vector3d b = R12 * a2;
    const double ws = *weight * scale;
    r[0] = ws * u.dot(a1.cross(b));
    if (d1) Eigen::Map<Eigen::Vector3d>{d1} = ws * b.cross(u);
    if (d2) Eigen::Map<Eigen::Vector3d>{d2} = ws * (R12.transpose() * u.cross(a1));
    return true;
  }
};

/// R₂ exp(−ν ω₂) v for a recorded secondary orientation R₁ᵀR₂ = R12 taken ν
/// seconds late (the secondary's clock offset's fraction): the orientation at
/// the main's time, turned back by the body rate ω₂ (ceres::AngleAxisRotatePoint,
/// exact for any ν and safe in Jets at ν = 0), then into body 1's axes.
template <typename T>
Vector3<T> secondaryAtMainTime(const Eigen::Matrix3d& R12, const Eigen::Vector3d& w2, const T& nu, const Vector3<T>& v) {
  const T turn[3] = {-nu * w2.x(), -nu * w2.y(), -nu * w2.z()};
  Vector3<T> back;
  ceres::AngleAxisRotatePoint(turn, v.data(), back.data());
  return mixed::mul(R12, back);
}

/// OrientationUniversalResidual with the secondary sensor's clock offset
/// (`--fit-time-offset`, nuisance ν[4] [s] after whole samples):
/// a₁ · R₁ᵀR₂ exp(−ν ω₂) a₂.
struct OrientationUniversalOffsetResidual {
  Eigen::Matrix3d R12;  ///< R₁ᵀ R₂ as recorded (the secondary's sample k − m)
  Eigen::Vector3d w2;   ///< ω₂ of that sample
  const double* weight = nullptr;

  template <typename T>
  bool operator()(const T* a1_data, const T* a2_data, const T* nu, T* r) const {
    const Eigen::Map<const Vector3<T>> a1(a1_data), a2(a2_data);
    r[0] = *weight * a1.dot(secondaryAtMainTime(R12, w2, nu[4], Vector3<T>(a2)));
    return true;
  }
};

/// RelativeRateUniversalResidual with a constant bias per gyroscope and/or
/// the secondary sensor's clock offset (`--fit-gyro-bias`, `--fit-time-offset`).
/// The gyroscopes read ω + b, so u = R₁ᵀR₂(ω₂ − b₂) − (ω₁ − b₁); b₁ = B₁ν₁,
/// b₂ = B₂ν₂ with B unit bases of the planes perpendicular to the start's axes
/// (nuisance ν[0..1], ν[2..3]): a bias along a₁ or a₂ does not change the
/// residual (the normal a₁ × R₁ᵀR₂a₂ is perpendicular to both world axes), so
/// it is not observable and reported 0, as for a hinge. With the clock offset's
/// fraction ν[4] [s], the secondary's orientation and rate are moved back to
/// the main's time: R₂ exp(−ν ω₂) and ω₂ − ν ω̇₂ (ω̇₂ the cubic slope of its
/// recorded rates, rate_derivative.hpp).
struct RelativeRateUniversalNuisanceResidual {
  Eigen::Matrix3d R12;  ///< R₁ᵀ R₂ as recorded
  Eigen::Vector3d w1, w2;
  Eigen::Vector3d dw2 = Eigen::Vector3d::Zero();  ///< ω̇₂ (zero without a clock offset)
  Eigen::Matrix<double, 3, 2> B1 = Eigen::Matrix<double, 3, 2>::Zero(), B2 = Eigen::Matrix<double, 3, 2>::Zero();
  double scale = 1.0;   ///< per-sample weight σ_ref/σₖ
  const double* weight = nullptr;

  template <typename T>
  bool operator()(const T* a1_data, const T* a2_data, const T* nu, T* r) const {
    const Eigen::Map<const Vector3<T>> a1(a1_data), a2(a2_data);
    Vector3<T> v1, v2;
    correctedRates(w1, w2, dw2, B1, B2, nu, &v1, &v2);
    const Vector3<T> normal = Vector3<T>(a1).cross(secondaryAtMainTime(R12, w2, nu[4], Vector3<T>(a2)));
    const Vector3<T> u = secondaryAtMainTime(R12, w2, nu[4], v2) - v1;
    r[0] = *weight * scale * u.dot(normal);
    return true;
  }
};

}  // namespace calibration
}  // namespace lieflow
