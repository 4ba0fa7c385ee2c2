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
/// affine in q̈): q̈ = M⁻¹ (Q − h). The orientations, anchors, rates and joint
/// columns of (q, q̇) are computed once per evaluation; each column of M is
/// then an acceleration-only pass (τ's part linear in u̇: no rate products,
/// no gravity): Walker and Orin's method 1 (J. Dyn. Sys. Meas. Control 104,
/// 1982). One body on a revolute joint to the ground takes a closed form
/// (GroundedHinge) read off these passes.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "dynamics/joint_space/articulated_model.hpp"
#include "dynamics/joint_space/grounded_hinge.hpp"
#include "liegroup/invalid_input.hpp"

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
  explicit ScalarDynamics(const ArticulatedModel& model, const std::string& field = "`scene`")
      : ScalarDynamics(model, field, false) {
    if (isGroundedHinge(model)) hinge_ = hingeConstants(ScalarDynamics<double>(model, field, false));
  }

  /// Replaces body i's joint's first axis (a revolute joint's axis a, unit —
  /// a fit keeps it on the sphere — in the joint's main body's frame): the
  /// axis as a parameter of a fit.
  /// (The closed form of a grounded hinge rests on the model's axis: off.)
  void setAxis(int body, const Vec3& axis) {
    axis1_[static_cast<std::size_t>(body)] = axis;
    hinge_.valid = false;
  }

  /// The spherical joints' relative rotations N (by the model's rotation
  /// index; identity until set): the part of the configuration q leaves out.
  void setRotations(const std::vector<Mat3>& rotations) { N_rel_ = rotations; }
  /// The same for spherical joint k alone.
  void setRotation(int k, const Mat3& rotation) { N_rel_[static_cast<std::size_t>(k)] = rotation; }

  int coordinates() const { return m_.scalar_coordinates; }
  int dofs() const { return m_.dofs(); }
  /// Whether accelerations() takes GroundedHinge's closed form.
  bool closedForm() const { return hinge_.valid; }
  /// Its constants (valid: false when the model is not a grounded hinge).
  const GroundedHinge& groundedHinge() const { return hinge_; }

  /// Q: the springs', dashpots' and applied moments' generalized forces.
  Vec appliedForces(double t, const Vec& q, const Vec& u, const CoordinateForces<T>& forces) const {
    Vec Q = Vec::Zero(dofs());
    for (int i = 0; i < m_.bodyCount(); ++i) {
      const ArticulatedBody& b = m_.bodies[static_cast<std::size_t>(i)];
      for (int k = 0; k < b.coordinates(); ++k) {
        const int j = b.q_begin + k, v = b.u_begin + k;
        Q[v] = -forces.stiffness[j] * (q[j] - forces.rest_angle[j]) - forces.damping[j] * u[v] +
               T(m_.drives[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)].appliedMoment(t));
      }
    }
    return Q;
  }

  /// q̈ (u̇) at (t, q, u) under `forces` and the model's applied moments:
  /// M⁻¹ (Q − h), h = τ(q, u, 0) and M's columns the acceleration-only
  /// passes τ(q, u, e_j) − h (the kinematics of q and u computed once).
  Vec accelerations(double t, const Vec& q, const Vec& u, const CoordinateForces<T>& forces) const {
    if (hinge_.valid) {
      Vec out(1);
      out[0] = groundedHingeAcceleration(hinge_, q[0], u[0], forces.stiffness[0], forces.damping[0],
                                         forces.rest_angle[0], m_.drives[0][0].appliedMoment(t));
      return out;
    }
    const int n = dofs();
    const Vec Q = appliedForces(t, q, u, forces);
    configure(q, u);
    Vec unit = Vec::Zero(n);
    const Vec h = transmitted(u, unit, true);
    Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> M(n, n);
    for (int j = 0; j < n; ++j) {
      unit[j] = T(1.0);
      M.col(j) = transmitted(u, unit, false);
      unit[j] = T(0.0);
    }
    return M.ldlt().solve(Q - h);
  }

  /// M(q): column j the acceleration-only pass for u̇ = e_j.
  Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> massMatrix(const Vec& q) const {
    const int n = dofs();
    const Vec zero = Vec::Zero(n);
    configure(q, zero);
    Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> M(n, n);
    Vec unit = zero;
    for (int j = 0; j < n; ++j) {
      unit[j] = T(1.0);
      M.col(j) = transmitted(zero, unit, false);
      unit[j] = T(0.0);
    }
    return M;
  }

  /// ½ uᵀ M(q) u − Σ m_i g · c_i + Σ ½ k_j (q_j − q₀ⱼ)² (the weight of a
  /// rotation-only body is its support's): conserved without dashpots and
  /// applied moments.
  T energy(const Vec& q, const Vec& u, const CoordinateForces<T>& forces) const {
    T e = T(0.5) * u.dot(massMatrix(q) * u);
    configure(q, u);
    const Vec3 g = m_.gravity.template cast<T>();
    for (int i = 0; i < m_.bodyCount(); ++i) {
      const ArticulatedBody& b = m_.bodies[static_cast<std::size_t>(i)];
      if (!b.rotation_only) e -= T(b.mass) * g.dot(c_[static_cast<std::size_t>(i)]);
    }
    for (int j = 0; j < coordinates(); ++j) {
      const T d = q[j] - forces.rest_angle[j];
      e += T(0.5) * forces.stiffness[j] * d * d;
    }
    return e;
  }

  /// Each body's angular velocity in its own axes (what its gyroscope reads).
  std::vector<Vec3> bodyRates(const Vec& q, const Vec& u) const {
    configure(q, u);
    std::vector<Vec3> out(w_.size());
    for (std::size_t i = 0; i < w_.size(); ++i) out[i] = R_[i].transpose() * w_[i];
    return out;
  }

  /// τ(q, u, u̇): the generalized forces the joints transmit (file comment).
  Vec inverseDynamics(const Vec& q, const Vec& u, const Vec& udot) const {
    configure(q, u);
    return transmitted(u, udot, true);
  }

 private:
  template <typename>
  friend class ScalarDynamics;

  ScalarDynamics(const ArticulatedModel& model, const std::string& field, bool /*general only*/) : m_(model) {
    requireScalarDynamics(model, field);
    const std::size_t n = model.bodies.size();
    for (auto* v : {&w_, &al_, &c_, &a_, &x_, &F_, &N_, &rp_, &rc_}) v->resize(n);
    R_.resize(n);
    Iw_.resize(n);
    u_.resize(n);
    omega_.resize(n);
    slide_.resize(n);
    turning_.resize(n);
    for (const ArticulatedBody& b : model.bodies) {  // unit axes (rotation() is Rodrigues' for unit axes)
      axis1_.push_back(b.axis1.normalized().template cast<T>());
      axis2_.push_back(b.axis2.normalized().template cast<T>());
      axis3_.push_back(b.axis3.normalized().template cast<T>());
    }
    N_rel_.assign(static_cast<std::size_t>(model.rotations), Mat3::Identity());
  }

  /// GroundedHinge's constants from the general algorithm (in double).
  static GroundedHinge hingeConstants(const ScalarDynamics<double>& general) {
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(1), one = Eigen::VectorXd::Ones(1);
    auto gravity = [&](double q) { return -general.inverseDynamics(Eigen::VectorXd::Constant(1, q), zero, zero)[0]; };
    const double g0 = gravity(0.0), g90 = gravity(0.5 * kPi), g180 = gravity(kPi);
    GroundedHinge h;
    h.gravity_const = 0.5 * (g0 + g180);
    h.gravity_cos = 0.5 * (g0 - g180);
    h.gravity_sin = g90 - h.gravity_const;
    h.inertia = general.inverseDynamics(zero, zero, one)[0] + g0;
    h.valid = h.inertia > 0.0;
    return h;
  }
  static constexpr double kPi = 3.14159265358979323846;

  /// exp(θ â) for a unit axis a (Rodrigues): I + sin θ â + (1 − cos θ) â²,
  /// â² = a aᵀ − I, with sin θ = 2 s c and 1 − cos θ = 2 s² from
  /// (s, c) = (sin, cos)(θ/2): no 1 − cos θ cancellation, one sincos.
  static Mat3 rotation(const Vec3& a, const T& angle) {
    using std::cos;
    using std::sin;
    const T half = T(0.5) * angle;
    const T s = sin(half), c = cos(half);
    const T st = T(2.0) * s * c, vt = T(2.0) * s * s;
    const Vec3 va = vt * a, sa = st * a;
    Mat3 R;
    R(0, 0) = T(1.0) + va[0] * a[0] - vt;
    R(1, 1) = T(1.0) + va[1] * a[1] - vt;
    R(2, 2) = T(1.0) + va[2] * a[2] - vt;
    R(0, 1) = va[0] * a[1] - sa[2];
    R(1, 0) = va[0] * a[1] + sa[2];
    R(0, 2) = va[0] * a[2] + sa[1];
    R(2, 0) = va[0] * a[2] - sa[1];
    R(1, 2) = va[1] * a[2] - sa[0];
    R(2, 1) = va[1] * a[2] + sa[0];
    return R;
  }

  /// Orientations, anchors, rates and each body's joint columns u_k with
  /// the rates Ω_k of the frames they are fixed in, for (q, u).
  void configure(const Vec& q, const Vec& u) const {
    for (int i = 0; i < m_.bodyCount(); ++i) {
      const std::size_t s = static_cast<std::size_t>(i);
      const ArticulatedBody& b = m_.bodies[s];
      const bool ground = b.parent == kGround;
      const std::size_t ps = ground ? 0 : static_cast<std::size_t>(b.parent);
      const Mat3 Rp = ground ? Mat3::Identity() : R_[ps];
      const Vec3 wp = ground ? Vec3::Zero() : w_[ps];
      const Vec3 cp = ground ? Vec3::Zero() : c_[ps];
      rp_[s] = ground ? Vec3(b.anchor_parent.template cast<T>()) : Vec3(Rp * b.anchor_parent);
      const T sigma = T(b.parent_is_main ? 1.0 : -1.0);
      std::array<Vec3, 3>& axes = u_[s];
      const Eigen::Matrix3d& Rref = b.R_ref;  // products with it stay in double where T is a Jet
      Mat3 M = Rref.template cast<T>();
      switch (b.kind) {
        case JointKind::kRevolute:
          M = rotation(axis1_[s], q[b.q_begin]) * Rref;
          break;
        case JointKind::kUniversal:
          M = Mat3(rotation(axis1_[s], q[b.q_begin]) * Rref) * rotation(axis2_[s], q[b.q_begin + 1]);
          break;
        case JointKind::kGimbal:
          M = rotation(axis1_[s], q[b.q_begin]) * rotation(axis2_[s], q[b.q_begin + 1]) *
              Mat3(rotation(axis3_[s], q[b.q_begin + 2]) * Rref);
          break;
        case JointKind::kSpherical:
          M = N_rel_[static_cast<std::size_t>(b.rotation)];
          break;
        default:  // prismatic, weld: R_ref held
          break;
      }
      // (A spherical joint's N turns the child relative to its parent, whichever is main.)
      const bool spherical = b.kind == JointKind::kSpherical;
      const bool forward = b.parent_is_main || spherical;
      if (ground)
        R_[s] = forward ? M : Mat3(M.transpose());
      else
        R_[s] = forward ? Mat3(Rp * M) : Mat3(Rp * M.transpose());
      Iw_[s] = Mat3(R_[s] * b.inertia) * R_[s].transpose();  // (R I) in Jet × double
      // A vector fixed in the main (secondary) body, in world axes; the
      // ground's are already.
      auto inParent = [&](const Vec3& v) { return ground ? v : Vec3(Rp * v); };
      auto inMain = [&](const Vec3& v) { return b.parent_is_main ? inParent(v) : Vec3(R_[s] * v); };
      auto inSecondary = [&](const Vec3& v) { return b.parent_is_main ? Vec3(R_[s] * v) : inParent(v); };
      // Each column's frame rate Ω_k: 0 the parent's, 1 the child's, 2 the
      // parent's plus the gimbal's earlier columns.
      std::array<int, 3>& turning = turning_[s];
      turning = {{0, 0, 0}};
      switch (b.kind) {
        case JointKind::kRevolute:
        case JointKind::kPrismatic:
          axes[0] = sigma * inMain(axis1_[s]);
          turning[0] = b.parent_is_main || b.kind == JointKind::kPrismatic ? 0 : 1;
          break;
        case JointKind::kUniversal:
          axes[0] = sigma * inMain(axis1_[s]);
          axes[1] = sigma * inSecondary(axis2_[s]);
          turning[0] = b.parent_is_main ? 0 : 1;
          turning[1] = b.parent_is_main ? 1 : 0;
          break;
        case JointKind::kGimbal: {  // the main body is the parent (articulated_model.hpp)
          const Mat3 E1 = rotation(axis1_[s], q[b.q_begin]);
          axes[0] = inParent(axis1_[s]);
          axes[1] = inParent(E1 * axis2_[s]);
          axes[2] = inParent(E1 * rotation(axis2_[s], q[b.q_begin + 1]) * axis3_[s]);
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
      w_[s] = w;
      Vec3 frame = wp;  // the gimbal's Ω: the parent's rate plus the earlier columns
      if (!slides)
        for (int k = 0; k < b.dofs(); ++k) {
          const std::size_t kk = static_cast<std::size_t>(k);
          omega_[s][kk] = turning[kk] == 0 ? wp : turning[kk] == 1 ? w : frame;
          frame += axes[kk] * u[b.u_begin + k];
        }
      if (b.rotation_only) {
        c_[s] = b.fixed_position.template cast<T>();
        x_[s] = c_[s];
      } else {
        x_[s] = cp + rp_[s];
        if (slides) {
          slide_[s] = q[b.q_begin];
          x_[s] += slide_[s] * axes[0];
        }
        rc_[s] = R_[s] * b.anchor_child;
        c_[s] = x_[s] - rc_[s];
      }
    }
  }

  /// The accelerations for u̇ and the recursive Newton–Euler pass (children
  /// first) on the configuration of the last configure(): τ(q, u, u̇) with
  /// `velocity_terms`, else its part linear in u̇ (no rate products, no
  /// gravity), which is M u̇.
  Vec transmitted(const Vec& u, const Vec& udot, bool velocity_terms) const {
    const int nb = m_.bodyCount();
    for (int i = 0; i < nb; ++i) {
      const std::size_t s = static_cast<std::size_t>(i);
      const ArticulatedBody& b = m_.bodies[s];
      const bool ground = b.parent == kGround;
      const std::size_t ps = ground ? 0 : static_cast<std::size_t>(b.parent);
      const Vec3 wp = ground ? Vec3::Zero() : w_[ps];
      const Vec3 alp = ground ? Vec3::Zero() : al_[ps];
      const Vec3 ap = ground ? Vec3::Zero() : a_[ps];
      const bool slides = b.kind == JointKind::kPrismatic;
      Vec3 al = alp;
      if (!slides)
        for (int k = 0; k < b.dofs(); ++k) {
          const std::size_t kk = static_cast<std::size_t>(k);
          al += u_[s][kk] * udot[b.u_begin + k];
          if (velocity_terms && !(ground && turning_[s][kk] == 0))  // Ω = 0: the ground's
            al += omega_[s][kk].cross(u_[s][kk]) * u[b.u_begin + k];
        }
      al_[s] = al;
      if (b.rotation_only) {
        a_[s].setZero();
      } else {
        // p̈ (the joint point; fixed on the ground), then a slide's terms.
        Vec3 ax = ground ? Vec3::Zero() : Vec3(ap + alp.cross(rp_[s]));
        if (velocity_terms && !ground) ax += wp.cross(wp.cross(rp_[s]));
        if (slides) {
          const Vec3& A = u_[s][0];
          const T& x = slide_[s];
          ax += A * udot[b.u_begin];
          if (!ground) ax += x * alp.cross(A);
          if (velocity_terms && !ground) ax += T(2.0) * u[b.u_begin] * wp.cross(A) + x * wp.cross(wp.cross(A));
        }
        const Vec3& rc = rc_[s];
        a_[s] = ax - al.cross(rc);
        if (velocity_terms) a_[s] -= w_[s].cross(w_[s].cross(rc));
      }
      F_[s].setZero();
      N_[s].setZero();
    }
    const Vec3 g = velocity_terms ? Vec3(m_.gravity.template cast<T>()) : Vec3::Zero();
    for (int i = nb - 1; i >= 0; --i) {
      const std::size_t s = static_cast<std::size_t>(i);
      const ArticulatedBody& b = m_.bodies[s];
      const Mat3& I = Iw_[s];
      N_[s] += I * al_[s];
      if (velocity_terms) N_[s] += w_[s].cross(I * w_[s]);
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

  const ArticulatedModel& m_;
  mutable std::vector<Mat3> R_, Iw_;  ///< orientations, world inertias about the centres
  mutable std::vector<Vec3> w_, al_, c_, a_, x_, F_, N_, rp_, rc_;
  mutable std::vector<std::array<Vec3, 3>> u_, omega_;
  mutable std::vector<T> slide_;  ///< a slide's q
  mutable std::vector<std::array<int, 3>> turning_;  ///< Ω_k's frame: 0 parent, 1 child, 2 gimbal
  std::vector<Vec3> axis1_, axis2_, axis3_;
  std::vector<Mat3> N_rel_;
  GroundedHinge hinge_;
};

}  // namespace articulated
}  // namespace lieflow
