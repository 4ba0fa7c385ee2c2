/// \file
/// The dynamics of a tree of revolute and universal joints hanging from the
/// ground, in joint coordinates and in any scalar (double or ceres::Jet), for
/// the spring/dashpot fit of whole mechanisms (mechanism_spring_fit.hpp). The
/// geometry comes from the joint formulation's model
/// (dynamics/joint_space/articulated_model.hpp), whose double-only
/// articulated-body algorithm is the simulator's; this one is written for
/// small trees and derivatives, and checked against it
/// (tests/calibration/mechanism_spring_test.cpp).
///
/// Kinematics, body by body in tree order (world frame, R body → world):
///   R_c = R_p M(q)  (parent main)   or   R_c = R_p M(q)ᵀ  (parent secondary),
/// M the joint's relative rotation (revolute exp(q a) R_ref, universal
/// exp(q₁a₁) R_ref exp(q₂a₂)), so the child turns relative to its parent
/// about world axes u_k, each fixed in the parent or in the child:
///   parent main:  revolute u = R_p a;  universal u₁ = R_p a₁, u₂ = R_c a₂;
///   parent secondary: revolute u = −R_c a; universal u₁ = −R_c a₁, u₂ = −R_p a₂;
///   ω_c = ω_p + Σ u_k q̇_k,  α_c = α_p + Σ (u_k q̈_k + u̇_k q̇_k),
///   u̇_k = ω_p × u_k (parent-fixed) or ω_c × u_k (child-fixed).
/// The joint point p = c_p + R_p s_p (the ground's anchor in world
/// coordinates), c_c = p − R_c s_c, so with r = R s:
///   a_c = a_p + α_p × r_p + ω_p × (ω_p × r_p) − α_c × r_c − ω_c × (ω_c × r_c).
/// A rotation-only body keeps its centre of mass where the model holds it
/// (c_c fixed, a_c = 0: a support carries it, as in the simulator), and its
/// joint only turns it.
///
/// Inverse dynamics (recursive Newton–Euler, children first): the force F
/// and the moment N about the joint point that the joint transmits,
///   F_i = m_i (a_i − g) + Σ_j F_j,
///   N_i = I_i α_i + ω_i × I_i ω_i + (c_i − p_i) × m_i (a_i − g) + Σ_j [N_j + (p_j − p_i) × F_j],
/// I_i the world inertia about the centre of mass; the joint's generalized
/// force is τ_k = u_kᵀ N_i. A rotation-only body's support takes every force
/// on it (its own weight and what its children pass on), so its joint passes
/// only a moment: F_i = 0 up the tree, and N_i is taken about its centre
/// (p_i = c_i), which the joint's pure moment leaves the same about any point. The motion satisfies τ(q, q̇, q̈) = Q with
/// Q_k = −k_k (q_k − q₀ₖ) − c_k q̇_k + M_k(t) (the springs, dashpots and
/// applied moments), so with h = τ(q, q̇, 0) and the mass matrix's columns
/// τ(q, q̇, e_j) − h (τ is affine in q̈): q̈ = M⁻¹ (Q − h).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "dynamics/joint_space/articulated_model.hpp"
#include "liegroup/invalid_input.hpp"
#include "liegroup/so3.hpp"

namespace lieflow {
namespace calibration {

/// Spring, dashpot and rest angle of every joint coordinate (size nq each),
/// in the fit's scalar.
template <typename T>
struct MechanismForces {
  std::vector<T> stiffness, damping, rest_angle;
};

/// Throws InvalidInput (field `field`) unless the model is a tree of
/// revolute and universal joints: no spherical joint (a rotation-only body no
/// joint reaches is on an implicit one) and no prescribed coordinate.
inline void requireMechanismSupported(const articulated::ArticulatedModel& model, const std::string& field) {
  for (int i = 0; i < model.bodyCount(); ++i) {
    const articulated::ArticulatedBody& b = model.bodies[static_cast<std::size_t>(i)];
    const std::string& name = model.names[static_cast<std::size_t>(i)];
    if (b.kind == articulated::JointKind::kSpherical)
      throw InvalidInput(field, "body '" + name + "' " +
                                    (b.scene_joint < 0 ? std::string("is not joined to the ground (a free body turns on "
                                                                     "no joint of the scene)")
                                                       : std::string("hangs on a spherical joint")) +
                                    ": the mechanism spring fit takes trees of revolute and universal joints "
                                    "hanging from the ground");
    for (int k = 0; k < b.coordinates(); ++k)
      if (b.prescribed(k))
        throw InvalidInput(field, "the joint of body '" + name + "' has prescribed motion: nothing to fit there");
  }
}

template <typename T>
class MechanismDynamics {
 public:
  using Vec = Eigen::Matrix<T, Eigen::Dynamic, 1>;
  using Vec3 = Eigen::Matrix<T, 3, 1>;
  using Mat3 = Eigen::Matrix<T, 3, 3>;

  explicit MechanismDynamics(const articulated::ArticulatedModel& model) : m_(model) {
    requireMechanismSupported(model, "--scene");
    const std::size_t n = model.bodies.size();
    R_.resize(n);
    w_.resize(n);
    al_.resize(n);
    c_.resize(n);
    a_.resize(n);
    p_.resize(n);
    F_.resize(n);
    N_.resize(n);
    u_.resize(n);
    for (const articulated::ArticulatedBody& b : model.bodies) axis1_.push_back(b.axis1.template cast<T>());
  }

  /// Replaces body i's joint's first axis (a revolute joint's axis a, unit,
  /// in the joint's main body's frame): the axis as a parameter of a fit.
  void setAxis(int body, const Vec3& axis) { axis1_[static_cast<std::size_t>(body)] = axis; }

  int dofs() const { return m_.scalar_coordinates; }

  /// q̈ at (t, q, q̇) under `forces` and the model's applied moments.
  Vec accelerations(double t, const Vec& q, const Vec& qd, const MechanismForces<T>& forces) const {
    const int n = dofs();
    Vec Q(n);
    for (int i = 0; i < m_.bodyCount(); ++i) {
      const articulated::ArticulatedBody& b = m_.bodies[static_cast<std::size_t>(i)];
      for (int k = 0; k < b.coordinates(); ++k) {
        const int j = b.q_begin + k;
        Q[j] = -forces.stiffness[j] * (q[j] - forces.rest_angle[j]) - forces.damping[j] * qd[j];
        const auto& drive = m_.drives[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)];
        if (drive.moment) Q[j] += T((*drive.moment)(t));
      }
    }
    Vec zero = Vec::Zero(n);
    const Vec h = inverseDynamics(q, qd, zero);
    Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> M(n, n);
    for (int j = 0; j < n; ++j) {
      zero[j] = T(1.0);
      M.col(j) = inverseDynamics(q, qd, zero) - h;
      zero[j] = T(0.0);
    }
    return M.ldlt().solve(Q - h);
  }

  /// Each body's angular velocity in its own axes (what its gyroscope reads).
  std::vector<Vec3> bodyRates(const Vec& q, const Vec& qd) const {
    kinematics(q, qd, Vec::Zero(dofs()));
    std::vector<Vec3> out(w_.size());
    for (std::size_t i = 0; i < w_.size(); ++i) out[i] = R_[i].transpose() * w_[i];
    return out;
  }

  /// τ(q, q̇, q̈): the generalized forces the joints transmit (file comment).
  Vec inverseDynamics(const Vec& q, const Vec& qd, const Vec& qdd) const {
    kinematics(q, qd, qdd);
    const Vec3 g = m_.gravity.template cast<T>();
    const int nb = m_.bodyCount();
    for (int i = nb - 1; i >= 0; --i) {
      const std::size_t s = static_cast<std::size_t>(i);
      const articulated::ArticulatedBody& b = m_.bodies[s];
      const Mat3 I = R_[s] * b.inertia.template cast<T>() * R_[s].transpose();
      N_[s] += I * al_[s] + w_[s].cross(I * w_[s]);
      if (b.rotation_only) {
        F_[s].setZero();  // the support's (p_i = c_i: the moments are about the centre)
      } else {
        const Vec3 ma = T(b.mass) * (a_[s] - g);
        F_[s] += ma;
        N_[s] += (c_[s] - p_[s]).cross(ma);
      }
      if (b.parent != articulated::kGround) {
        const std::size_t ps = static_cast<std::size_t>(b.parent);
        F_[ps] += F_[s];
        N_[ps] += N_[s] + (p_[s] - p_[ps]).cross(F_[s]);
      }
    }
    Vec tau(dofs());
    for (int i = 0; i < nb; ++i) {
      const articulated::ArticulatedBody& b = m_.bodies[static_cast<std::size_t>(i)];
      for (int k = 0; k < b.coordinates(); ++k) tau[b.q_begin + k] = u_[static_cast<std::size_t>(i)][k].dot(N_[static_cast<std::size_t>(i)]);
    }
    return tau;
  }

 private:
  static Mat3 rotation(const Vec3& axis, const T& angle) { return SO3<T>::exp(axis * angle).matrix(); }

  /// Orientations, rates, accelerations and joint points for (q, q̇, q̈);
  /// zeroes F and N.
  void kinematics(const Vec& q, const Vec& qd, const Vec& qdd) const {
    for (int i = 0; i < m_.bodyCount(); ++i) {
      const std::size_t s = static_cast<std::size_t>(i);
      const articulated::ArticulatedBody& b = m_.bodies[s];
      const bool ground = b.parent == articulated::kGround;
      const std::size_t ps = ground ? 0 : static_cast<std::size_t>(b.parent);
      const Mat3 Rp = ground ? Mat3::Identity() : R_[ps];
      const Vec3 wp = ground ? Vec3::Zero() : w_[ps];
      const Vec3 alp = ground ? Vec3::Zero() : al_[ps];
      const Vec3 ap = ground ? Vec3::Zero() : a_[ps];
      const Vec3 cp = ground ? Vec3::Zero() : c_[ps];
      const Vec3 rp = ground ? Vec3(b.anchor_parent.template cast<T>()) : Vec3(Rp * b.anchor_parent.template cast<T>());
      const Mat3 Rref = b.R_ref.template cast<T>();
      const bool universal = b.kind == articulated::JointKind::kUniversal;
      const T q1 = q[b.q_begin];
      const Vec3& a1 = axis1_[s];
      const Vec3 a2 = b.axis2.template cast<T>();
      const Mat3 M = universal ? Mat3(rotation(a1, q1) * Rref * rotation(a2, q[b.q_begin + 1]))
                               : Mat3(rotation(a1, q1) * Rref);
      R_[s] = b.parent_is_main ? Mat3(Rp * M) : Mat3(Rp * M.transpose());
      // World axes and whether each turns with the parent (true) or the child.
      Vec3 u[2];
      bool with_parent[2];
      if (b.parent_is_main) {
        u[0] = Rp * a1;
        with_parent[0] = true;
        u[1] = R_[s] * a2;
        with_parent[1] = false;
      } else {
        u[0] = -(R_[s] * a1);
        with_parent[0] = false;
        u[1] = -(Rp * a2);
        with_parent[1] = true;
      }
      Vec3 w = wp;
      for (int k = 0; k < b.coordinates(); ++k) w += u[k] * qd[b.q_begin + k];
      Vec3 al = alp;
      for (int k = 0; k < b.coordinates(); ++k)
        al += u[k] * qdd[b.q_begin + k] + (with_parent[k] ? wp : w).cross(u[k]) * qd[b.q_begin + k];
      w_[s] = w;
      al_[s] = al;
      if (b.rotation_only) {
        c_[s] = b.fixed_position.template cast<T>();
        p_[s] = c_[s];
        a_[s].setZero();
      } else {
        const Vec3 rc = R_[s] * b.anchor_child.template cast<T>();
        p_[s] = cp + rp;
        c_[s] = p_[s] - rc;
        a_[s] = ap + alp.cross(rp) + wp.cross(wp.cross(rp)) - al.cross(rc) - w.cross(w.cross(rc));
      }
      u_[s][0] = u[0];
      u_[s][1] = u[1];
      F_[s].setZero();
      N_[s].setZero();
    }
  }

  const articulated::ArticulatedModel& m_;
  mutable std::vector<Mat3> R_;
  mutable std::vector<Vec3> w_, al_, c_, a_, p_, F_, N_;
  mutable std::vector<std::array<Vec3, 2>> u_;
  std::vector<Vec3> axis1_;
};

/// One classical RK4 step of (q, q̇) from t to t + h (on ℝ²ⁿ RKMK4 is RK4).
template <typename T>
void rk4Step(const MechanismDynamics<T>& dynamics, const MechanismForces<T>& forces, double t, double h,
             typename MechanismDynamics<T>::Vec* q, typename MechanismDynamics<T>::Vec* v) {
  using Vec = typename MechanismDynamics<T>::Vec;
  const Vec a1 = dynamics.accelerations(t, *q, *v, forces);
  const Vec q2 = *q + (0.5 * h) * *v, v2 = *v + (0.5 * h) * a1;
  const Vec a2 = dynamics.accelerations(t + 0.5 * h, q2, v2, forces);
  const Vec q3 = *q + (0.5 * h) * v2, v3 = *v + (0.5 * h) * a2;
  const Vec a3 = dynamics.accelerations(t + 0.5 * h, q3, v3, forces);
  const Vec q4 = *q + h * v3, v4 = *v + h * a3;
  const Vec a4 = dynamics.accelerations(t + h, q4, v4, forces);
  *q += (h / 6.0) * (*v + 2.0 * v2 + 2.0 * v3 + v4);
  *v += (h / 6.0) * (a1 + 2.0 * a2 + 2.0 * a3 + a4);
}

}  // namespace calibration
}  // namespace lieflow
