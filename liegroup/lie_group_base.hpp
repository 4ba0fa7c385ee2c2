/// \file
/// CRTP base shared by SO3<T> and SE3<T>: the operations that follow from a
/// group's exp, log, inverse, compose and adjoint alone (Sola, Deray, Atchuthan
/// 2018, "A micro Lie theory for state estimation in robotics", §IV–V).
///
/// Perturbations are on the right (lieflow convention):
///   X ⊕ δ = X exp(δ),   Y ⊖ X = log(X⁻¹ Y),
/// and every Jacobian J of a map f is the right Jacobian
///   f(X ⊕ δ) ≈ f(X) ⊕ J δ.
#pragma once

#include <Eigen/Core>

namespace lieflow {

/// Specialized by each group: Scalar, DoF, Tangent, Jacobian (DoF × DoF).
template <typename Group>
struct LieGroupTraits;

template <typename Derived>
class LieGroupBase {
 public:
  using Traits = LieGroupTraits<Derived>;
  using Scalar = typename Traits::Scalar;
  using Tangent = typename Traits::Tangent;
  using Jacobian = typename Traits::Jacobian;
  static constexpr int DoF = Traits::DoF;

  const Derived& derived() const { return static_cast<const Derived&>(*this); }

  /// X ⊕ δ = X exp(δ).
  Derived rplus(const Tangent& delta) const { return derived() * Derived::exp(delta); }

  /// Y ⊖ X = log(X⁻¹ Y), called as Y.rminus(X).
  Tangent rminus(const Derived& X) const { return (X.inverse() * derived()).log(); }

  /// The geodesic X exp(t log(X⁻¹ Y)) from X (t = 0) to Y (t = 1), called as
  /// X.interpolate(Y, t). It is the constant-speed shortest path when the
  /// rotation from X to Y is below π.
  Derived interpolate(const Derived& Y, const Scalar& t) const {
    return rplus(t * Y.rminus(derived()));
  }

  // ---- Right Jacobians of the elementary operations ----------------------

  /// d(X⁻¹)/dX = −Adj(X).
  Jacobian inverseJacobian() const { return -derived().Adj(); }

  /// d(X Y)/dX = Adj(Y⁻¹), called as X.composeJacobianLhs(Y).
  Jacobian composeJacobianLhs(const Derived& Y) const { return Y.inverse().Adj(); }

  /// d(X Y)/dY = I.
  static Jacobian composeJacobianRhs() { return Jacobian::Identity(); }

  /// d log(X)/dX = Jr⁻¹(log X).
  Jacobian logJacobian() const { return Derived::JrInv(derived().log()); }

  /// d exp(δ)/dδ = Jr(δ).
  static Jacobian expJacobian(const Tangent& delta) { return Derived::Jr(delta); }

  /// d(X ⊕ δ)/dX = Adj(exp(δ))⁻¹ = Adj(exp(−δ)).
  static Jacobian rplusJacobianLhs(const Tangent& delta) { return Derived::exp(-delta).Adj(); }

  /// d(X ⊕ δ)/dδ = Jr(δ).
  static Jacobian rplusJacobianRhs(const Tangent& delta) { return Derived::Jr(delta); }

  /// d(Y ⊖ X)/dY = Jr⁻¹(Y ⊖ X), called as Y.rminusJacobianLhs(X).
  Jacobian rminusJacobianLhs(const Derived& X) const { return Derived::JrInv(rminus(X)); }

  /// d(Y ⊖ X)/dX = −Jl⁻¹(Y ⊖ X), called as Y.rminusJacobianRhs(X).
  Jacobian rminusJacobianRhs(const Derived& X) const { return -Derived::JlInv(rminus(X)); }

 protected:
  LieGroupBase() = default;
};

}  // namespace lieflow
