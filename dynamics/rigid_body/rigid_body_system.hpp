/// \file
/// The equations of motion of one rigid body, as systems that the steppers
/// advance (Boost.odeint's separation: a system knows its vector field, a
/// stepper knows how to advance any system on a Lie group).
///
/// Euler's equations in the body frame and Newton's in the world frame:
///   Ṙ = R ω^,   J ω̇ = (J ω) × ω + τ,        (RotorSystem, on SO(3) × ℝ³)
///   ṗ = v,      m v̇ = m g + f,               (FreeBodySystem adds these)
/// where J is the inertia about the centre of mass, or, for a body turning
/// about a fixed pivot, about the pivot (parallel-axis theorem
/// J_o = J_c + m (‖c‖² I − c cᵀ), c the centre of mass from the pivot, body
/// frame); then gravity and a force at the centre of mass add the torque
/// τ = c × Rᵀ (m g + f).
///
/// Every system provides the right-trivialized vector field `velocity`
/// (ẏ = y · f(t, y)), `energy` and `spatialAngularMomentum` (about the world
/// origin), and the structure that variational and implicit steppers need:
/// `inertia()`, `externalTorque(t, R)` (body frame), `torqueJacobian(t, R)`
/// (∂τ/∂δθ for right perturbations R exp(δθ)).
#pragma once

#include <functional>
#include <utility>

#include <Eigen/Cholesky>

#include "integrators/rigid_body_state.hpp"
#include "integrators/second_order_traits.hpp"

namespace lieflow {

/// Physical parameters of one rigid body, shared by both systems.
template <typename T>
struct RigidBodyParameters {
  T mass = T(1);
  /// Inertia about the centre of mass, body axes (symmetric positive definite).
  Matrix3<T> inertia = Matrix3<T>::Identity();
  /// Gravitational acceleration, world frame.
  Vector3<T> gravity = Vector3<T>::Zero();
  /// Rotation about a fixed pivot (the heavy top): the pivot in the world and
  /// the centre of mass relative to it in body axes. RotorSystem only.
  bool has_pivot = false;
  Vector3<T> pivot_world = Vector3<T>::Zero();
  Vector3<T> com_from_pivot = Vector3<T>::Zero();
  /// Isotropic torsional spring to ground (RotorSystem only): the potential
  /// U = ½ k ‖log(R_rest⁻¹ R)‖² pulls the body back to R_rest with the body
  /// torque τ = −k log(R_rest⁻¹ R) (since Jr⁻ᵀ(w) w = w). k = 0: none.
  T spring_stiffness = T(0);
  SO3<T> spring_rest;
  /// Optional applied torque (body frame) and force at the centre of mass
  /// (world frame) as functions of time. Empty: none.
  std::function<Vector3<T>(const T&)> torque_body;
  std::function<Vector3<T>(const T&)> force_world;
};

/// A rotation-only rigid body (free rotor, or heavy top about a fixed pivot).
template <typename T>
class RotorSystem {
 public:
  using Scalar = T;
  using State = RotorState<T>;
  using Tangent = typename State::Tangent;

  explicit RotorSystem(RigidBodyParameters<T> params) : params_(std::move(params)) {
    J_ = params_.inertia;
    if (params_.has_pivot) {
      const Vector3<T>& c = params_.com_from_pivot;
      J_ += params_.mass * (c.squaredNorm() * Matrix3<T>::Identity() - c * c.transpose());
    }
    J_inv_ = J_.inverse();
  }

  const RigidBodyParameters<T>& parameters() const { return params_; }
  /// Inertia about the point the body turns about (centre of mass or pivot).
  const Matrix3<T>& inertia() const { return J_; }
  const Matrix3<T>& inertiaInverse() const { return J_inv_; }
  bool hasExternalTorque() const {
    return params_.has_pivot || static_cast<bool>(params_.torque_body) || hasSpring();
  }
  bool hasSpring() const { return params_.spring_stiffness != T(0); }

  /// τ(t, R), body frame: applied torque, spring torque −k log(R_rest⁻¹R)
  /// and, about a pivot, c × Rᵀ(m g + f).
  Vector3<T> externalTorque(const T& t, const SO3<T>& R) const {
    Vector3<T> tau = params_.torque_body ? params_.torque_body(t) : Vector3<T>(Vector3<T>::Zero());
    if (hasSpring()) tau -= params_.spring_stiffness * (params_.spring_rest.inverse() * R).log();
    if (params_.has_pivot) {
      Vector3<T> f = params_.mass * params_.gravity;
      if (params_.force_world) f += params_.force_world(t);
      tau += params_.com_from_pivot.cross(R.inverse() * f);
    }
    return tau;
  }

  /// ∂τ/∂δθ for R exp(δθ): with b = Rᵀ f, (R exp(δθ))ᵀ f ≈ b + b × δθ, so
  /// τ(R exp(δθ)) ≈ τ + c × (b × δθ) = τ + c^ b^ δθ; the spring adds
  /// −k Jr⁻¹(w), w = log(R_rest⁻¹R) (d log(X exp δ)/dδ = Jr⁻¹).
  Matrix3<T> torqueJacobian(const T& t, const SO3<T>& R) const {
    Matrix3<T> K = Matrix3<T>::Zero();
    if (hasSpring()) K -= params_.spring_stiffness * SO3<T>::JrInv((params_.spring_rest.inverse() * R).log());
    if (!params_.has_pivot) return K;
    Vector3<T> f = params_.mass * params_.gravity;
    if (params_.force_world) f += params_.force_world(t);
    const Vector3<T> b = R.inverse() * f;
    return K + SO3<T>::hat(params_.com_from_pivot) * SO3<T>::hat(b);
  }

  /// ω̇ = J⁻¹((J ω) × ω + τ).
  Vector3<T> angularAcceleration(const T& t, const SO3<T>& R, const Vector3<T>& omega) const {
    return J_inv_ * ((J_ * omega).cross(omega) + externalTorque(t, R));
  }

  /// Whether f does not depend on t (no applied torque or force of time).
  bool autonomous() const { return !params_.torque_body && !params_.force_world; }

  /// f(t, y) = (ω, ω̇) with ẏ = y · f.
  void velocity(const T& t, const State& y, Tangent* f) const {
    f->template head<3>() = y.omega;
    f->template tail<3>() = angularAcceleration(t, y.R, y.omega);
  }

  /// ½ ωᵀ J ω + ½ k ‖log(R_rest⁻¹R)‖², minus m gᵀ(R c) about a pivot
  /// (potential zero at the pivot).
  T energy(const T& /*t*/, const State& y) const {
    T e = T(0.5) * y.omega.dot(J_ * y.omega);
    if (hasSpring())
      e += T(0.5) * params_.spring_stiffness * (params_.spring_rest.inverse() * y.R).log().squaredNorm();
    if (params_.has_pivot)
      e -= params_.mass * params_.gravity.dot(y.R * params_.com_from_pivot);
    return e;
  }

  /// Angular momentum about the world origin, world frame: R J ω about the
  /// turning point, plus o × m v_c for a pivot o away from the origin.
  Vector3<T> spatialAngularMomentum(const State& y) const {
    Vector3<T> L = y.R * (J_ * y.omega);
    if (params_.has_pivot) {
      const Vector3<T> v_com = y.R * y.omega.cross(params_.com_from_pivot);
      L += params_.pivot_world.cross(params_.mass * v_com);
    }
    return L;
  }

  /// Spatial angular momentum is conserved when no torque acts.
  bool conservesAngularMomentum() const { return !hasExternalTorque(); }

 private:
  RigidBodyParameters<T> params_;
  Matrix3<T> J_;
  Matrix3<T> J_inv_;
};

/// A rigid body with rotation and centre-of-mass translation.
template <typename T>
class FreeBodySystem {
 public:
  using Scalar = T;
  using State = FreeBodyState<T>;
  using Tangent = typename State::Tangent;

  explicit FreeBodySystem(RigidBodyParameters<T> params)
      : params_(std::move(params)), J_(params_.inertia), J_inv_(params_.inertia.inverse()) {
    LIEFLOW_ASSERT(!params_.has_pivot, "FreeBodySystem: a pivoted body is a RotorSystem");
  }

  const RigidBodyParameters<T>& parameters() const { return params_; }
  const Matrix3<T>& inertia() const { return J_; }
  const Matrix3<T>& inertiaInverse() const { return J_inv_; }
  T mass() const { return params_.mass; }
  bool hasExternalTorque() const { return static_cast<bool>(params_.torque_body); }

  Vector3<T> externalTorque(const T& t, const SO3<T>&) const {
    return params_.torque_body ? params_.torque_body(t) : Vector3<T>(Vector3<T>::Zero());
  }
  Matrix3<T> torqueJacobian(const T&, const SO3<T>&) const { return Matrix3<T>::Zero(); }

  /// Total force on the centre of mass, world frame: m g + f(t).
  Vector3<T> force(const T& t) const {
    Vector3<T> f = params_.mass * params_.gravity;
    if (params_.force_world) f += params_.force_world(t);
    return f;
  }

  /// Whether f does not depend on t (no applied torque or force of time).
  bool autonomous() const { return !params_.torque_body && !params_.force_world; }

  void velocity(const T& t, const State& y, Tangent* f) const {
    f->template segment<3>(0) = y.v;
    f->template segment<3>(3) = y.omega;
    f->template segment<3>(6) = force(t) / params_.mass;
    f->template segment<3>(9) =
        J_inv_ * ((J_ * y.omega).cross(y.omega) + externalTorque(t, y.R));
  }

  /// ½ ωᵀJω + ½ m ‖v‖² − m gᵀp.
  T energy(const T& /*t*/, const State& y) const {
    return T(0.5) * y.omega.dot(J_ * y.omega) + T(0.5) * params_.mass * y.v.squaredNorm() -
           params_.mass * params_.gravity.dot(y.p);
  }

  /// R J ω + m p × v.
  Vector3<T> spatialAngularMomentum(const State& y) const {
    return y.R * (J_ * y.omega) + params_.mass * y.p.cross(y.v);
  }

  /// Conserved without torque and without force (gravity exerts a moment
  /// about the origin).
  bool conservesAngularMomentum() const {
    return !hasExternalTorque() && !params_.force_world && params_.gravity.isZero(0);
  }

 private:
  RigidBodyParameters<T> params_;
  Matrix3<T> J_;
  Matrix3<T> J_inv_;
};

// ---- as second-order systems (integrators/second_order_traits.hpp) ------------

/// J ω̇ + ω × Jω − τ(t, R) = 0.
template <typename T>
struct SecondOrderSystemTraits<RotorSystem<T>> {
  using Scalar = T;
  using State = RotorState<T>;
  using Vector = Vector3<T>;
  using Matrix = Matrix3<T>;

  // Always inlined into the stepper's Newton loop: called there, the matrices
  // stay in registers (out of line: heavy-top's genalpha step 5 % slower).
  EIGEN_ALWAYS_INLINE static void evaluate(const RotorSystem<T>& s, const T& t, const State& y, Matrix* M, Vector* g,
                                           Matrix* Ct, Matrix* Kt) {
    const Matrix3<T>& J = s.inertia();
    const Vector3<T> Jw = J * y.omega;
    *M = J;
    *g = y.omega.cross(Jw) - s.externalTorque(t, y.R);
    // ∂(ω × Jω)/∂ω = ω^ J − (Jω)^.
    if (Ct) *Ct = SO3<T>::hat(y.omega) * J - SO3<T>::hat(Jw);
    if (Kt) *Kt = -s.torqueJacobian(t, y.R);
  }
};

/// m v̇ − F(t) = 0 (world frame) and J ω̇ + ω × Jω − τ(t, R) = 0 (body frame).
template <typename T>
struct SecondOrderSystemTraits<FreeBodySystem<T>> {
  using Scalar = T;
  using State = FreeBodyState<T>;
  using Vector = Vector6<T>;
  using Matrix = Matrix6<T>;

  EIGEN_ALWAYS_INLINE static void evaluate(const FreeBodySystem<T>& s, const T& t, const State& y, Matrix* M,
                                           Vector* g, Matrix* Ct, Matrix* Kt) {
    const Matrix3<T>& J = s.inertia();
    const Vector3<T> Jw = J * y.omega;
    M->setZero();
    M->template topLeftCorner<3, 3>() = s.mass() * Matrix3<T>::Identity();
    M->template bottomRightCorner<3, 3>() = J;
    g->template head<3>() = -s.force(t);
    g->template tail<3>() = y.omega.cross(Jw) - s.externalTorque(t, y.R);
    if (Ct) {
      Ct->setZero();
      Ct->template bottomRightCorner<3, 3>() = SO3<T>::hat(y.omega) * J - SO3<T>::hat(Jw);
    }
    if (Kt) {
      Kt->setZero();
      Kt->template bottomRightCorner<3, 3>() = -s.torqueJacobian(t, y.R);
    }
  }
};

}  // namespace lieflow
