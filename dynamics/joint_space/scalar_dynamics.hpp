/// \file
/// The joint formulation's dynamics in any scalar (double or ceres::Jet): the
/// recursive Newton–Euler algorithm, the mass matrix and q̈ = M⁻¹(Q − h) of a
/// tree hanging from the ground, on the model of articulated_model.hpp. The
/// simulator's articulated-body algorithm (articulated_system.hpp, O(n), its
/// passes written for double and tuned for speed) and this one solve the
/// same equations; this one is written for small trees and derivatives (the
/// calibration fits differentiate the discrete flow through it) and is
/// checked against the other to 1e-11 (tests/dynamics/scalar_dynamics_test.cpp).
///
/// Joints: revolute, universal, gimbal, prismatic, spherical and welds, on
/// either side of their joint (the parent main or secondary); a
/// rotation-only body keeps its centre of mass where the model holds it (a
/// support carries it). Not here: free roots and offset universal joints
/// (requireScalarDynamics says so).
///
/// Kinematics, body by body in tree order (world frame, R body → world):
///   R_c = R_p M  (parent main)   or   R_c = R_p Mᵀ  (parent secondary),
/// M the joint's relative rotation (revolute exp(q a) R_ref, universal
/// exp(q₁a₁) R_ref exp(q₂a₂), gimbal exp(q₁e₁) exp(q₂e₂) exp(q₃e₃) R_ref,
/// prismatic and weld R_ref), so the child turns
/// relative to its parent about world axes u_k, each fixed in a frame that
/// turns at a known rate Ω_k:
///   parent main:  revolute u = R_p a;  universal u₁ = R_p a₁ (Ω = ω_p),
///                 u₂ = R_c a₂ (Ω = ω_c); gimbal u_k = R_p E₁…E_{k−1} e_k
///                 (Ω_k = ω_p + Σ_{j<k} u_j q̇_j); spherical u_k = R_c e_k (Ω = ω_c);
///   parent secondary: revolute u = −R_c a; universal u₁ = −R_c a₁ (ω_c),
///                 u₂ = −R_p a₂ (ω_p);
///   ω_c = ω_p + Σ u_k q̇_k,  α_c = α_p + Σ (u_k q̈_k + Ω_k × u_k q̇_k).
/// A spherical joint's N turns the child relative to its parent whichever
/// body is main (articulated_state.hpp): R_c = R_p N, its rates ω_rel in the
/// child's axes (Ṅ = N ω̂_rel), so u_k = R_c e_k, fixed in the child.
/// A slide moves the child's anchor along A = σ R_main a by q (σ = −1 when
/// the child is the main body; A turns with the parent, whose rotation the
/// child shares): x = p + q A, ẍ = p̈ + q̈ A + 2 q̇ ω_p × A + q (α_p × A + ω_p × (ω_p × A)).
/// The joint point p = c_p + R_p s_p (the ground's anchor in world
/// coordinates), the child's anchor x (x = p but for a slide), c_c = x − R_c s_c:
///   a_c = ẍ − α_c × r_c − ω_c × (ω_c × r_c),  r = R s.
///
/// Inverse dynamics (recursive Newton–Euler, children first): the force F
/// and the moment N about the child's anchor x_i that its joint transmits,
///   F_i = m_i (a_i − g) + Σ_j F_j,
///   N_i = I_i α_i + ω_i × I_i ω_i + (c_i − x_i) × m_i (a_i − g) + Σ_j [N_j + (x_j − x_i) × F_j],
/// I_i the world inertia about the centre of mass; the joint's generalized
/// force is τ_k = u_kᵀ N_i (a hinge) or u_kᵀ F_i (a slide). A rotation-only
/// body's support takes every force on it (its weight and what its children
/// pass on), so its joint passes only a moment: F_i = 0 up the tree, and N_i
/// is taken about its centre (x_i = c_i). The motion satisfies
/// τ(q, q̇, q̈) = Q with Q_k = −k_k (q_k − q₀ₖ) − c_k q̇_k + M_k(t) (springs,
/// dashpots and applied moments, on the coordinates that have them), so with
/// h = τ(q, q̇, 0) and the mass matrix's columns τ(q, q̇, e_j) − h (τ is
/// affine in q̈): q̈ = M⁻¹ (Q − h).
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "dynamics/joint_space/articulated_model.hpp"
#include "liegroup/invalid_input.hpp"
#include "liegroup/so3.hpp"

namespace lieflow {
namespace articulated {

/// Spring, dashpot and rest position of every joint coordinate (size nq
/// each, by the model's q index), in the scalar of the evaluation.
template <typename T>
struct CoordinateForces {
  std::vector<T> stiffness, damping, rest_angle;
};

/// The model's own springs, dashpots and rest positions (its drives).
template <typename T>
CoordinateForces<T> modelForces(const ArticulatedModel& model) {
  CoordinateForces<T> f;
  f.stiffness.assign(model.scalar_coordinates, T(0.0));
  f.damping = f.rest_angle = f.stiffness;
  for (int i = 0; i < model.bodyCount(); ++i)
    for (int k = 0; k < model.bodies[i].coordinates(); ++k) {
      const CoordinateDrive& d = model.drives[i][k];
      const int j = model.bodies[i].q_begin + k;
      f.stiffness[j] = T(d.stiffness);
      f.damping[j] = T(d.damping);
      f.rest_angle[j] = T(d.rest_angle);
    }
  return f;
}

/// Throws InvalidInput (field `field`) unless ScalarDynamics models the
/// tree: no free root, no offset universal joint, no prescribed coordinate.
inline void requireScalarDynamics(const ArticulatedModel& model, const std::string& field) {
  for (int i = 0; i < model.bodyCount(); ++i) {
    const ArticulatedBody& b = model.bodies[i];
    const std::string& name = model.names[i];
    if (b.kind == JointKind::kFree)
      throw InvalidInput(field, "body '" + name + "' is a free root (no joint of the scene reaches it from the "
                                "ground): the joint-coordinate dynamics on any scalar takes trees hanging from the ground");
    if (b.offset)
      throw InvalidInput(field, "body '" + name + "' hangs on an offset universal joint, which the joint-coordinate "
                                "dynamics on any scalar does not take");
    if (b.kind == JointKind::kGimbal && !b.parent_is_main)
      throw InvalidInput(field, "body '" + name + "' is the main body of its gimbal: the joint-coordinate dynamics "
                                "on any scalar takes gimbals hanging from their main body");
    for (int k = 0; k < b.coordinates(); ++k)
      if (b.prescribed(k))
        throw InvalidInput(field, "the joint of body '" + name + "' has prescribed motion: nothing to fit there");
  }
}

template <typename T>
class ScalarDynamics {
 public:
  using Vec = Eigen::Matrix<T, Eigen::Dynamic, 1>;
  using Vec3 = Eigen::Matrix<T, 3, 1>;
  using Mat3 = Eigen::Matrix<T, 3, 3>;

  /// The model must outlive the dynamics. Throws as requireScalarDynamics.
  explicit ScalarDynamics(const ArticulatedModel& model, const std::string& field = "`scene`") : m_(model) {
    requireScalarDynamics(model, field);
    const std::size_t n = model.bodies.size();
    for (auto* v : {&w_, &al_, &c_, &a_, &x_, &F_, &N_}) v->resize(n);
    R_.resize(n);
    u_.resize(n);
    turning_.resize(n);
    for (const ArticulatedBody& b : model.bodies) axis1_.push_back(b.axis1.template cast<T>());
    N_rel_.assign(static_cast<std::size_t>(model.rotations), Mat3::Identity());
  }

  /// Replaces body i's joint's first axis (a revolute joint's axis a, unit,
  /// in the joint's main body's frame): the axis as a parameter of a fit.
  void setAxis(int body, const Vec3& axis) { axis1_[static_cast<std::size_t>(body)] = axis; }

  /// The spherical joints' relative rotations N (by the model's rotation
  /// index; identity until set): the part of the configuration q leaves out.
  void setRotations(const std::vector<Mat3>& rotations) { N_rel_ = rotations; }

  int coordinates() const { return m_.scalar_coordinates; }
  int dofs() const { return m_.dofs(); }

  /// q̈ (u̇) at (t, q, u) under `forces` and the model's applied moments.
  Vec accelerations(double t, const Vec& q, const Vec& u, const CoordinateForces<T>& forces) const {
    const int n = dofs();
    Vec Q = Vec::Zero(n);
    for (int i = 0; i < m_.bodyCount(); ++i) {
      const ArticulatedBody& b = m_.bodies[static_cast<std::size_t>(i)];
      for (int k = 0; k < b.coordinates(); ++k) {
        const int j = b.q_begin + k, v = b.u_begin + k;
        Q[v] = -forces.stiffness[j] * (q[j] - forces.rest_angle[j]) - forces.damping[j] * u[v];
        const CoordinateDrive& drive = m_.drives[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)];
        if (drive.moment) Q[v] += T((*drive.moment)(t));
      }
    }
    Vec unit = Vec::Zero(n);
    const Vec h = inverseDynamics(q, u, unit);
    Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> M(n, n);
    for (int j = 0; j < n; ++j) {
      unit[j] = T(1.0);
      M.col(j) = inverseDynamics(q, u, unit) - h;
      unit[j] = T(0.0);
    }
    return M.ldlt().solve(Q - h);
  }

  /// Each body's angular velocity in its own axes (what its gyroscope reads).
  std::vector<Vec3> bodyRates(const Vec& q, const Vec& u) const {
    kinematics(q, u, Vec::Zero(dofs()));
    std::vector<Vec3> out(w_.size());
    for (std::size_t i = 0; i < w_.size(); ++i) out[i] = R_[i].transpose() * w_[i];
    return out;
  }

  /// τ(q, u, u̇): the generalized forces the joints transmit (file comment).
  Vec inverseDynamics(const Vec& q, const Vec& u, const Vec& udot) const {
    kinematics(q, u, udot);
    const Vec3 g = m_.gravity.template cast<T>();
    const int nb = m_.bodyCount();
    for (int i = nb - 1; i >= 0; --i) {
      const std::size_t s = static_cast<std::size_t>(i);
      const ArticulatedBody& b = m_.bodies[s];
      const Mat3 I = R_[s] * b.inertia.template cast<T>() * R_[s].transpose();
      N_[s] += I * al_[s] + w_[s].cross(I * w_[s]);
      if (b.rotation_only) {
        F_[s].setZero();  // the support's (x_i = c_i: the moments are about the centre)
      } else {
        const Vec3 ma = T(b.mass) * (a_[s] - g);
        F_[s] += ma;
        N_[s] += (c_[s] - x_[s]).cross(ma);
      }
      if (b.parent != kGround) {
        const std::size_t ps = static_cast<std::size_t>(b.parent);
        F_[ps] += F_[s];
        N_[ps] += N_[s] + (x_[s] - x_[ps]).cross(F_[s]);
      }
    }
    Vec tau(dofs());
    for (int i = 0; i < nb; ++i) {
      const std::size_t s = static_cast<std::size_t>(i);
      const ArticulatedBody& b = m_.bodies[s];
      const Vec3& load = b.kind == JointKind::kPrismatic ? F_[s] : N_[s];
      for (int k = 0; k < b.dofs(); ++k) tau[b.u_begin + k] = u_[s][static_cast<std::size_t>(k)].dot(load);
    }
    return tau;
  }

 private:
  static Mat3 rotation(const Vec3& axis, const T& angle) { return SO3<T>::exp(axis * angle).matrix(); }

  /// Orientations, rates, accelerations, anchors and each body's joint
  /// columns u_k for (q, u, u̇); zeroes F and N.
  void kinematics(const Vec& q, const Vec& u, const Vec& udot) const {
    for (int i = 0; i < m_.bodyCount(); ++i) {
      const std::size_t s = static_cast<std::size_t>(i);
      const ArticulatedBody& b = m_.bodies[s];
      const bool ground = b.parent == kGround;
      const std::size_t ps = ground ? 0 : static_cast<std::size_t>(b.parent);
      const Mat3 Rp = ground ? Mat3::Identity() : R_[ps];
      const Vec3 wp = ground ? Vec3::Zero() : w_[ps];
      const Vec3 alp = ground ? Vec3::Zero() : al_[ps];
      const Vec3 ap = ground ? Vec3::Zero() : a_[ps];
      const Vec3 cp = ground ? Vec3::Zero() : c_[ps];
      const Vec3 rp = ground ? Vec3(b.anchor_parent.template cast<T>()) : Vec3(Rp * b.anchor_parent.template cast<T>());
      const T sigma = T(b.parent_is_main ? 1.0 : -1.0);
      std::array<Vec3, 3>& axes = u_[s];
      // Each column's frame rate Ω_k: 0 the parent's, 1 the child's, 2 the
      // parent's plus the gimbal's earlier columns.
      std::array<int, 3>& turning = turning_[s];
      const Mat3 Rref = b.R_ref.template cast<T>();
      Mat3 M = Rref;
      switch (b.kind) {
        case JointKind::kRevolute:
          M = rotation(axis1_[s], q[b.q_begin]) * Rref;
          break;
        case JointKind::kUniversal:
          M = rotation(axis1_[s], q[b.q_begin]) * Rref * rotation(b.axis2.template cast<T>(), q[b.q_begin + 1]);
          break;
        case JointKind::kGimbal:
          M = rotation(axis1_[s], q[b.q_begin]) * rotation(b.axis2.template cast<T>(), q[b.q_begin + 1]) *
              rotation(b.axis3.template cast<T>(), q[b.q_begin + 2]) * Rref;
          break;
        case JointKind::kSpherical:
          M = N_rel_[static_cast<std::size_t>(b.rotation)];
          break;
        default:  // prismatic, weld: R_ref held
          break;
      }
      // (A spherical joint's N turns the child relative to its parent, whichever is main.)
      const bool spherical = b.kind == JointKind::kSpherical;
      R_[s] = b.parent_is_main || spherical ? Mat3(Rp * M) : Mat3(Rp * M.transpose());
      const Mat3& R_main = b.parent_is_main ? Rp : R_[s];
      const Mat3& R_sec = b.parent_is_main ? R_[s] : Rp;
      switch (b.kind) {
        case JointKind::kRevolute:
        case JointKind::kPrismatic:
          axes[0] = sigma * (R_main * axis1_[s]);
          turning[0] = b.parent_is_main || b.kind == JointKind::kPrismatic ? 0 : 1;
          break;
        case JointKind::kUniversal:
          axes[0] = sigma * (R_main * axis1_[s]);
          axes[1] = sigma * (R_sec * b.axis2.template cast<T>());
          turning[0] = b.parent_is_main ? 0 : 1;
          turning[1] = b.parent_is_main ? 1 : 0;
          break;
        case JointKind::kGimbal: {  // the main body is the parent (articulated_model.hpp)
          const Mat3 E1 = rotation(axis1_[s], q[b.q_begin]);
          axes[0] = Rp * axis1_[s];
          axes[1] = Rp * (E1 * b.axis2.template cast<T>());
          axes[2] = Rp * (E1 * rotation(b.axis2.template cast<T>(), q[b.q_begin + 1]) * b.axis3.template cast<T>());
          turning = {{0, 2, 2}};
          break;
        }
        case JointKind::kSpherical:
          for (int k = 0; k < 3; ++k) {
            axes[static_cast<std::size_t>(k)] = R_[s].col(k);
            turning[static_cast<std::size_t>(k)] = 1;
          }
          break;
        default:
          break;
      }
      const bool slides = b.kind == JointKind::kPrismatic;
      Vec3 w = wp;
      if (!slides)
        for (int k = 0; k < b.dofs(); ++k) w += axes[static_cast<std::size_t>(k)] * u[b.u_begin + k];
      Vec3 al = alp;
      Vec3 frame = wp;  // the gimbal's Ω: the parent's rate plus the earlier columns
      if (!slides)
        for (int k = 0; k < b.dofs(); ++k) {
          const std::size_t kk = static_cast<std::size_t>(k);
          const Vec3& omega = turning[kk] == 0 ? wp : turning[kk] == 1 ? w : frame;
          al += axes[kk] * udot[b.u_begin + k] + omega.cross(axes[kk]) * u[b.u_begin + k];
          frame += axes[kk] * u[b.u_begin + k];
        }
      w_[s] = w;
      al_[s] = al;
      if (b.rotation_only) {
        c_[s] = b.fixed_position.template cast<T>();
        x_[s] = c_[s];
        a_[s].setZero();
      } else {
        const Vec3 p = cp + rp;
        Vec3 ax = ap + alp.cross(rp) + wp.cross(wp.cross(rp));  // p̈
        x_[s] = p;
        if (slides) {
          const Vec3& A = axes[0];
          const T& x = q[b.q_begin];
          const T& xd = u[b.u_begin];
          x_[s] = p + x * A;
          ax += A * udot[b.u_begin] + T(2.0) * xd * wp.cross(A) + x * (alp.cross(A) + wp.cross(wp.cross(A)));
        }
        const Vec3 rc = R_[s] * b.anchor_child.template cast<T>();
        c_[s] = x_[s] - rc;
        a_[s] = ax - al.cross(rc) - w.cross(w.cross(rc));
      }
      F_[s].setZero();
      N_[s].setZero();
    }
  }

  const ArticulatedModel& m_;
  mutable std::vector<Mat3> R_;
  mutable std::vector<Vec3> w_, al_, c_, a_, x_, F_, N_;
  mutable std::vector<std::array<Vec3, 3>> u_;
  mutable std::vector<std::array<int, 3>> turning_;
  std::vector<Vec3> axis1_;
  std::vector<Mat3> N_rel_;
};

}  // namespace articulated
}  // namespace lieflow
