/// \file
/// A second-order system on a vector space: the state (x, v) ∈ ℝᴺ × ℝᴺ and the
/// linear system M ẍ + C ẋ + K x = f(t) (a mass–spring–dashpot chain, the linear
/// oscillator ẍ + ω₀² x = 0 for N = 1). The reference problem for the stability
/// and accuracy analysis of second-order integrators (Hilber, Hughes & Taylor
/// 1977; Chung & Hulbert 1993, J. Appl. Mech. 60, §3): its flow is known in
/// closed form, its energy ½ vᵀMv + ½ xᵀKx is conserved when C = 0 and f = 0.
///
/// VectorState follows the state layout of lieflow (integrators/rkmk.hpp):
/// Tangent = [δx (N); δv (N)], rplus adds both parts (ℝᴺ is an abelian group,
/// exp is the identity and dexp⁻¹ = I), so every Lie-group stepper runs on it.
#pragma once

#include <functional>
#include <utility>

#include <Eigen/Core>
#include <Eigen/LU>

#include "liegroup/scalar.hpp"

namespace lieflow {

/// (x, v) ∈ ℝᴺ × ℝᴺ, N fixed at compile time.
template <typename T, int N>
struct VectorState {
  static_assert(N > 0, "VectorState: fixed dimension N > 0");
  using Scalar = T;
  static constexpr int kDof = N;
  static constexpr int kTangentDim = 2 * N;
  using Vector = Eigen::Matrix<T, N, 1>;
  using Tangent = Eigen::Matrix<T, 2 * N, 1>;

  Vector x = Vector::Zero();
  Vector v = Vector::Zero();

  Tangent zeroTangent() const { return Tangent::Zero(); }

  /// (x, v) ⊕ (δx, δv) = (x + δx, v + δv).
  VectorState rplus(const Tangent& d) const {
    return {x + d.template head<N>(), v + d.template tail<N>()};
  }

  /// ad = 0 on an abelian algebra: dexp⁻¹ is the identity.
  static Tangent dexpInvRight(const Tangent& /*theta*/, const Tangent& w, int /*order*/) {
    return w;
  }
};

/// M ẍ + C ẋ + K x = f(t) with constant M (symmetric positive definite), C, K.
/// As a first-order system ẏ = y · F(t, y) (here y + F):
/// F = (v, M⁻¹(f(t) − C v − K x)).
template <typename T, int N>
class LinearSecondOrderSystem {
 public:
  using Scalar = T;
  using State = VectorState<T, N>;
  using Tangent = typename State::Tangent;
  using Vector = typename State::Vector;
  using Matrix = Eigen::Matrix<T, N, N>;

  /// `load` may be empty (f = 0).
  LinearSecondOrderSystem(const Matrix& mass, const Matrix& damping, const Matrix& stiffness,
                          std::function<Vector(const T&)> load = {})
      : M_(mass), C_(damping), K_(stiffness), M_inv_(mass.inverse()), load_(std::move(load)) {}

  /// The undamped oscillator ẍ + ω₀² x = 0 in every coordinate (M = I, C = 0,
  /// K = ω₀² I).
  static LinearSecondOrderSystem oscillator(const T& omega0) {
    return LinearSecondOrderSystem(Matrix::Identity(), Matrix::Zero(),
                                   (omega0 * omega0) * Matrix::Identity());
  }

  const Matrix& mass() const { return M_; }
  const Matrix& damping() const { return C_; }
  const Matrix& stiffness() const { return K_; }
  /// f(t); zero without a load.
  Vector load(const T& t) const { return load_ ? load_(t) : Vector(Vector::Zero()); }

  void velocity(const T& t, const State& y, Tangent* F) const {
    F->template head<N>() = y.v;
    F->template tail<N>() = M_inv_ * (load(t) - C_ * y.v - K_ * y.x);
  }

  /// ½ vᵀ M v + ½ xᵀ K x (the conserved energy when C = 0, f = 0, K = Kᵀ).
  T energy(const T& /*t*/, const State& y) const {
    return T(0.5) * y.v.dot(M_ * y.v) + T(0.5) * y.x.dot(K_ * y.x);
  }

 private:
  Matrix M_, C_, K_, M_inv_;
  std::function<Vector(const T&)> load_;
};

}  // namespace lieflow
