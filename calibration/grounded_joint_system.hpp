/// \file
/// One rigid body on a revolute (N = 1) or universal (N = 2) joint to the
/// ground, in the joint coordinates φ ∈ ℝᴺ: the reduced model that
/// `lieflow calibrate spring` integrates with ceres::Jet scalars (the
/// maximal-coordinate MultibodySystem is double-only and carries 5 or 4
/// constraint rows that this body does not need).
///
/// Kinematics. Both joints of dynamics/constraints/ give the body's orientation
/// as a product of exponentials with constant rotations P_k and unit axes x_k,
///   R(φ) = P₀ exp(φ_{c₀} x₀) P₁ … exp(φ_{c_{N−1}} x_{N−1}) P_N
/// (revolute, body secondary: R = exp(φ a) R_ref; body main: R = R_ref⁻¹ exp(−φ a);
/// universal: R = exp(φ₁e₁) exp(φ₂e₂) R_ref, or R_ref⁻¹ exp(−φ₂e₂) exp(−φ₁e₁)).
/// With Z_k = exp(φ x_k) P_{k+1} ⋯ P_N the part right of factor k, the body
/// angular velocity is ω = G φ̇, column G_k = Z_kᵀ x_k (for factor k), and
/// dG_k/dt = Σ_{j>k} φ̇_{c_j} G_k × G_j (only factors to the right turn G_k).
///
/// Dynamics (Lagrange; the ideal joint's reaction does no work on G φ̇).
/// About the fixed pivot o, with J_o = J_c + m(‖c‖²I − ccᵀ) and c the centre
/// of mass from o (body axes; Euler's equation about a fixed point):
///   M(φ) φ̈ = Gᵀ(c × Rᵀ m g − ω × J_o ω − J_o Ġ φ̇) + Q,   M = Gᵀ J_o G,
///   Q_i = −k_i (φ_i − φ₀ᵢ) − c_i φ̇_i + M_i(t)   (spring, dashpot, applied moment
/// on coordinate i: a joint moment does virtual work M δφ, README "Joints").
/// A rotation-only body turns about its centre of mass (c = 0) and its weight
/// is carried by its support, as in the multibody path.
///
/// State: VectorState<T, N> (x = φ, v = φ̇), so every Lie-group stepper of
/// integrators/ advances it (on ℝᴺ × ℝᴺ exp is the identity).
#pragma once

#include <array>
#include <functional>
#include <string>

#include <Eigen/Core>
#include <Eigen/LU>

#include "integrators/vector_state.hpp"
#include "liegroup/so3.hpp"

namespace lieflow {

/// The double-precision description of the body and joint (built from a scene
/// by grounded_joint_scene.hpp).
template <int N>
struct GroundedJointModel {
  static_assert(N == 1 || N == 2, "a revolute (1) or universal (2) joint");
  /// R(φ) = P[0] exp(φ[coordinate[0]] axis[0]) P[1] … P[N].
  std::array<Eigen::Matrix3d, N + 1> P;
  std::array<Eigen::Vector3d, N> axis;   ///< x_k, unit
  std::array<int, N> coordinate;         ///< c_k: which joint coordinate factor k turns
  double mass = 1.0;
  Eigen::Matrix3d inertia_pivot = Eigen::Matrix3d::Identity();  ///< J_o, body axes
  Eigen::Vector3d com_from_pivot = Eigen::Vector3d::Zero();     ///< c, body axes
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();            ///< g acting on the body (0 if carried)
  /// Applied joint moments M_i(t) (empty: none).
  std::array<std::function<double(double)>, N> moment;

  /// R(φ) (body → world).
  Eigen::Matrix3d orientation(const Eigen::Matrix<double, N, 1>& phi) const;
};

/// Spring and dashpot of each coordinate, in the scalar of the fit.
template <typename T, int N>
struct GroundedJointForces {
  std::array<T, N> stiffness{}, rest_angle{}, damping{};
};

template <typename T, int N>
class GroundedJointSystem {
 public:
  using Scalar = T;
  using State = VectorState<T, N>;
  using Tangent = typename State::Tangent;
  using Vector = Eigen::Matrix<T, N, 1>;

  GroundedJointSystem(const GroundedJointModel<N>& model, const GroundedJointForces<T, N>& forces)
      : model_(model), forces_(forces) {
    if constexpr (N == 1) hinge_ = HingeConstants(model);
  }

  const GroundedJointModel<N>& model() const { return model_; }
  const GroundedJointForces<T, N>& forces() const { return forces_; }

  /// f(t, y) = (φ̇, φ̈).
  void velocity(const T& t, const State& y, Tangent* f) const {
    if constexpr (N == 1) {  // the closed form of HingeConstants
      using std::cos;
      using std::sin;
      const T phi = y.x[0];
      T moment = T(hinge_.gravity_const) + T(hinge_.gravity_cos) * cos(phi) + T(hinge_.gravity_sin) * sin(phi) -
                 forces_.stiffness[0] * (phi - forces_.rest_angle[0]) - forces_.damping[0] * y.v[0];
      if (model_.moment[0]) moment += T(model_.moment[0](scalarValue(t)));
      (*f)[0] = y.v[0];
      (*f)[1] = moment / T(hinge_.inertia);
      return;
    }
    const Kinematics k = kinematics(y.x);
    const Eigen::Matrix3d& J = model_.inertia_pivot;
    const Vector3<T> omega = k.G * y.v;
    // J_o Ġ φ̇ with Ġ_k = Σ_{j>k} φ̇_{c_j} G_k × G_j (factor order).
    Vector3<T> gdot_v = Vector3<T>::Zero();
    for (int a = 0; a < N; ++a)
      for (int b = a + 1; b < N; ++b)
        gdot_v += (y.v[model_.coordinate[a]] * y.v[model_.coordinate[b]]) *
                  k.G.col(model_.coordinate[a]).cross(k.G.col(model_.coordinate[b]));
    const Vector3<T> J_omega = J * omega;
    const Vector3<T> J_gdot_v = J * gdot_v;
    Vector rhs = k.G.transpose() * (gravityTorque(k) - omega.cross(J_omega) - J_gdot_v);
    const double time = scalarValue(t);
    for (int i = 0; i < N; ++i) {
      rhs[i] += -forces_.stiffness[i] * (y.x[i] - forces_.rest_angle[i]) - forces_.damping[i] * y.v[i];
      if (model_.moment[i]) rhs[i] += T(model_.moment[i](time));
    }
    const Eigen::Matrix<T, 3, N> JG = J * k.G;
    const Eigen::Matrix<T, N, N> M = k.G.transpose() * JG;
    f->template head<N>() = y.v;
    f->template tail<N>() = M.inverse() * rhs;  // N ≤ 2: closed-form inverse
  }

  /// M(φ) = Gᵀ J_o G.
  Eigen::Matrix<T, N, N> massMatrix(const Vector& phi) const {
    const Kinematics k = kinematics(phi);
    const Eigen::Matrix<T, 3, N> JG = model_.inertia_pivot * k.G;
    return k.G.transpose() * JG;
  }

  /// The generalized gravity moments Gᵀ (c × Rᵀ m g) at φ.
  Vector gravityForce(const Vector& phi) const {
    const Kinematics k = kinematics(phi);
    return k.G.transpose() * gravityTorque(k);
  }

  /// ½ φ̇ᵀ M φ̇ − m gᵀ R c + Σ ½ k (φ − φ₀)²  (conserved without dashpots and
  /// applied moments); m gᵀ R c = (Rᵀ m g)·c.
  T energy(const T& /*t*/, const State& y) const {
    const Kinematics k = kinematics(y.x);
    const Vector3<T> omega = k.G * y.v;
    const Vector3<T> J_omega = model_.inertia_pivot * omega;
    T e = T(0.5) * omega.dot(J_omega) - k.weight.dot(model_.com_from_pivot.template cast<T>());
    for (int i = 0; i < N; ++i) {
      const T d = y.x[i] - forces_.rest_angle[i];
      e += T(0.5) * forces_.stiffness[i] * d * d;
    }
    return e;
  }

  /// Body angular velocity ω = G(φ) φ̇ (body frame).
  Vector3<T> angularVelocity(const State& y) const { return kinematics(y.x).G * y.v; }

 private:
  /// A hinge (N = 1) in closed form. G = P₁ᵀx is constant in the body, so
  /// M = GᵀJ_oG is constant and ω × J_oω has no component along G; the
  /// gravity moment (c × Rᵀ W)·G = (P₀ᵀW)·exp(φx)u with W = m g and
  /// u = P₁(G × c) is, by Rodrigues' formula,
  ///   Q_g(φ) = a·x (x·u) + cos φ a·(u − x(x·u)) + sin φ a·(x × u),  a = P₀ᵀW.
  struct HingeConstants {
    HingeConstants() = default;
    explicit HingeConstants(const GroundedJointModel<N>& m) {
      const Eigen::Vector3d& x = m.axis[0];
      const Eigen::Vector3d G = m.P[1].transpose() * x;
      inertia = G.dot(m.inertia_pivot * G);
      const Eigen::Vector3d u = m.P[1] * G.cross(m.com_from_pivot);
      const Eigen::Vector3d a = m.P[0].transpose() * (m.mass * m.gravity);
      const Eigen::Vector3d u_par = x * x.dot(u);
      gravity_const = a.dot(u_par);
      gravity_cos = a.dot(u - u_par);
      gravity_sin = a.dot(x.cross(u));
    }
    double inertia = 1.0, gravity_const = 0.0, gravity_cos = 0.0, gravity_sin = 0.0;
  };

  /// Everything the equations need from R(φ), without forming R: the
  /// columns of G and the weight in the body frame. Only vectors are turned
  /// (Rodrigues), so a Jet evaluation costs a few dozen Jet operations.
  struct Kinematics {
    Eigen::Matrix<T, 3, N> G;  ///< column i: the body-frame axis of coordinate i
    Vector3<T> weight;         ///< Rᵀ m g, body frame
  };

  /// exp(θ x) v = v + sin θ (x × v) + 2 sin²(θ/2) x × (x × v)  (x unit; no
  /// 1 − cos θ cancellation).
  static Vector3<T> rotate(const T& theta, const Eigen::Vector3d& axis, const Vector3<T>& v) {
    using std::sin;
    const Vector3<T> x = axis.template cast<T>();
    const Vector3<T> xv = x.cross(v);
    const T half = sin(T(0.5) * theta);
    return v + sin(theta) * xv + (T(2) * half * half) * x.cross(xv);
  }

  /// c × Rᵀ m g (body frame).
  Vector3<T> gravityTorque(const Kinematics& k) const {
    return model_.com_from_pivot.template cast<T>().cross(k.weight);
  }

  /// With E_f = exp(φ_{c_f} x_f):  Rᵀ W = P_Nᵀ E_{N−1}ᵀ ⋯ P₁ᵀ E₀ᵀ P₀ᵀ W and
  /// G_f = Z_fᵀ x_f = P_Nᵀ E_{N−1}ᵀ ⋯ E_{f+1}ᵀ P_{f+1}ᵀ x_f.
  Kinematics kinematics(const Vector& phi) const {
    Kinematics k;
    Vector3<T> w = (model_.P[0].transpose() * (model_.mass * model_.gravity)).template cast<T>();
    for (int f = 0; f < N; ++f) {
      const Vector3<T> turned = rotate(-phi[model_.coordinate[f]], model_.axis[f], w);
      w = model_.P[f + 1].transpose() * turned;
    }
    k.weight = w;
    for (int f = 0; f < N; ++f) {
      Vector3<T> v = (model_.P[f + 1].transpose() * model_.axis[f]).template cast<T>();
      for (int g = f + 1; g < N; ++g) {
        const Vector3<T> turned = rotate(-phi[model_.coordinate[g]], model_.axis[g], v);
        v = model_.P[g + 1].transpose() * turned;
      }
      k.G.col(model_.coordinate[f]) = v;
    }
    return k;
  }

  const GroundedJointModel<N>& model_;  ///< must outlive the system
  GroundedJointForces<T, N> forces_;
  HingeConstants hinge_;
};

template <int N>
Eigen::Matrix3d GroundedJointModel<N>::orientation(const Eigen::Matrix<double, N, 1>& phi) const {
  Eigen::Matrix3d R = P[0];
  for (int f = 0; f < N; ++f) R = R * SO3d::exp(phi[coordinate[f]] * axis[f]).matrix() * P[f + 1];
  return R;
}

}  // namespace lieflow
