/// \file
/// TreePasses' definitions (tree_passes.hpp states the equations; the
/// conventions are articulated_system.hpp's). Included by tree_passes.hpp:
/// the passes are templates, inlined into each user's evaluation.
#pragma once

#include "dynamics/joint_space/tree_passes.hpp"

namespace lieflow {
namespace articulated {

/// A spherical or free joint's rotation in a simulator state (SO3d) ...
template <class Rotation>
EIGEN_ALWAYS_INLINE auto rotationMatrixOf(const Rotation& r) -> decltype(r.matrix()) {
  return r.matrix();
}
/// ... or a fit's (a 3 × 3 matrix).
template <typename T>
EIGEN_ALWAYS_INLINE const Eigen::Matrix<T, 3, 3>& rotationMatrixOf(const Eigen::Matrix<T, 3, 3>& R) {
  return R;
}

template <typename T>
EIGEN_ALWAYS_INLINE void TreePasses<T>::freeJointPass(const ArticulatedBody& b, Body& d, const Mat3& R, const Vec3& x,
                                                      const Vec3& w_body, const Vec3& vc, bool velocity_terms,
                                                      Vec6* Su) const {
  // A floating root: V = (ω, v_c + c × ω) from (R, c) and (ω body, v_c);
  // its columns, fixed in the body (the rotations, lines through c) and
  // in the world (the translations), give Ṡ u = (0, v_c × ω). Its six
  // degrees of freedom are solved as one block in solve(), not as columns.
  (void)b;
  d.R = R;
  d.x = x;
  const Vec3 w = d.R * w_body;
  *Su << w, vc + cross3(d.x, w);
  if (velocity_terms) d.bias.template tail<3>() = cross3(vc, w);
  d.tau.setZero();
}

template <typename T>
EIGEN_ALWAYS_INLINE void TreePasses<T>::sphericalJointPass(const ArticulatedBody& b, Body& d, const Mat3& Rp,
                                                           const Mat3& N, const Vec6& Vp, const Vec3& line,
                                                           const VecX& u, bool velocity_terms, Vec6* Su) const {
  d.R = Rp * N;
  d.S.template topRows<3>() = d.R;
  d.S.template bottomRows<3>() = hat(line) * d.R;
  d.free = 3;
  for (int k = 0; k < 3; ++k) d.free_u[k] = b.u_begin + k;
  d.tau.setZero();
  if (velocity_terms) {
    *Su = d.S * u.template segment<3>(b.u_begin);
    d.bias = crossMotion(Vp, *Su);
  }
}

template <typename T>
template <class State, class Loads>
EIGEN_ALWAYS_INLINE void TreePasses<T>::coordinateJointPass(int i, double t, const State& y, bool dynamics,
                                                            bool velocity_terms, const Mat3& Rp, const Vec6& Vp,
                                                            const Vec3& line, const Loads& loads, Vec6* Su,
                                                            Vec3* child_anchor) const {
  const ArticulatedBody& b = model_.bodies[i];
  Body& d = bodies_[i];
  const double sigma = b.parent_is_main ? 1.0 : -1.0;  // (constants stay double: no Jet products)
  const int nc = b.coordinates();
  for (int k = 0; k < nc; ++k) {
    if (b.prescribed(k)) {
      const TimeFunction& f = *model_.drives[i][k].prescribed;
      d.phi[k] = T(f(t));
      d.phidot[k] = T(f.derivative(t));
      d.phiddot[k] = T(f.secondDerivative(t));
    } else {
      d.phi[k] = y.q[b.q_begin + k];
      d.phidot[k] = y.u[b.u_begin + k];
      d.phiddot[k] = T(0.0);
    }
  }
  // A slide holds the relative rotation R_ref; a hinge turns it.
  const bool slides = b.kind == JointKind::kPrismatic;
  std::array<T, 3> cos_phi{{T(1.0), T(1.0), T(1.0)}}, sin_phi{{T(0.0), T(0.0), T(0.0)}};
  if (!slides)
    for (int k = 0; k < nc; ++k) sinCos(d.phi[k], &cos_phi[k], &sin_phi[k]);
  // A gimbal: M = E₁E₂E₃ R_ref with E_k = exp(φ_k e_k), and its axes
  // A_k = R_main E₁…E_{k−1} e_k (each hinge turns with the ones before it).
  const bool gimbal = b.kind == JointKind::kGimbal;
  Mat3 M;
  Vec3 gimbal_a2 = Vec3::Zero(), gimbal_a3 = Vec3::Zero();  // E₁e₂, E₁E₂e₃
  if (gimbal) {
    const GimbalAxes<T> g = gimbalAxes(b, cos_phi, sin_phi);
    M = g.M;
    gimbal_a2 = g.a2;
    gimbal_a3 = g.a3;
  } else if (slides || b.kind == JointKind::kFixed) {
    M = b.R_ref.template cast<T>();  // a slide and a weld hold R_ref (a weld has no column: V = V_p)
  } else {
    M = jointRotation(b, frames_[i], cos_phi, sin_phi);
  }
  // (On the ground, R_p = I: its products are left out.)
  const bool grounded = b.parent == kGround;
  if (grounded)
    d.R = b.parent_is_main ? M : Mat3(M.transpose());
  else
    d.R = b.parent_is_main ? Mat3(Rp * M) : Mat3(Rp * M.transpose());
  const Mat3& R_main = b.parent_is_main ? Rp : d.R;
  const Mat3& R_sec = b.parent_is_main ? d.R : Rp;
  const bool main_grounded = grounded && b.parent_is_main, sec_grounded = grounded && !b.parent_is_main;
  const JointFrame<T>& frame = frames_[i];
  if (frame.parameter)
    d.axis[0] = main_grounded ? frame.axis1 : Vec3(R_main * frame.axis1);
  else  // (the model's axis, a constant)
    d.axis[0] = main_grounded ? Vec3(b.axis1.template cast<T>()) : Vec3(R_main * b.axis1);
  if (gimbal) {
    d.axis[1] = main_grounded ? gimbal_a2 : Vec3(R_main * gimbal_a2);
    d.axis[2] = main_grounded ? gimbal_a3 : Vec3(R_main * gimbal_a3);
  } else if (nc == 2) {
    d.axis[1] = sec_grounded ? Vec3(b.axis2.template cast<T>()) : Vec3(R_sec * b.axis2);
  }
  // An offset universal joint's second column is the line through the
  // secondary anchor x₂ = x₁ + R_main exp(φ₁a₁) δ (δ = offset_ref), which
  // also carries the child; every other column's line is the anchor.
  if (b.offset) *child_anchor = d.x2 = offsetAnchor(b, d.x, R_main, cos_phi[0], sin_phi[0]);
  // A slide moves the child's anchor along A by x from the main's (σ = −1
  // when the child is the main body).
  if (slides) *child_anchor = d.x + (sigma * d.phi[0]) * d.axis[0];
  std::array<Vec6, 3> s;
  for (int k = 0; k < nc; ++k) {
    // A slide's column is a translation along A: (0, A) whatever the point.
    if (slides)
      s[k] << Vec3::Zero(), d.axis[k];
    else
      s[k] = grounded && !b.rotation_only && !(k == 1 && b.offset)
                 ? lineTwist(d.axis[k], b.anchor_parent)  // (the ground's anchor: a constant)
                 : lineTwist(d.axis[k], k == 1 && b.offset ? d.x2 : line);
    // Projection (velocity_terms off): the prescribed rates stand in the
    // place of accelerations, the free ones are unknown.
    if (velocity_terms) {
      *Su += (sigma * d.phidot[k]) * s[k];
    } else if (b.prescribed(k)) {
      d.bias += (sigma * d.phidot[k]) * s[k];
    }
    if (b.prescribed(k)) {
      if (velocity_terms) d.bias += (sigma * d.phiddot[k]) * s[k];
    } else {
      d.S.col(d.free) = sigma * s[k];
      d.free_u[d.free] = b.u_begin + k;
      d.tau[d.free] = dynamics && velocity_terms && loads.acts(b, k) ? loads.coordinate(i, k, t, d.phi[k], d.phidot[k])
                                                                     : T(0.0);
      ++d.free;
    }
  }
  if (velocity_terms && b.kind == JointKind::kGimbal) {
    // Ṡ u of a gimbal (parent main): s₁ turns with the parent, s₂ with the
    // parent turned by φ₁, s₃ by φ₁ and φ₂: ṡ_k = (V_p + Σ_{j<k} s_j φ̇_j) ×ₘ s_k.
    const Vec6 w1 = s[0] * d.phidot[0], w2 = s[1] * d.phidot[1], w3 = s[2] * d.phidot[2];
    d.bias += crossMotion(Vp, *Su) + crossMotion(w1, Vec6(w2 + w3)) + crossMotion(w2, w3);
  } else if (velocity_terms && nc == 2) {
    // Ṡ u of a universal joint: s₁ turns with the main body, s₂ with the
    // secondary (both velocities known: the child's is V_p + S u).
    // (The ground's V_p = 0: its term is left out.)
    const Vec6 Vc = Vp + *Su;
    if (grounded) {
      d.bias += sigma * (b.parent_is_main ? Vec6(crossMotion(Vc, s[1]) * d.phidot[1])
                                          : Vec6(crossMotion(Vc, s[0]) * d.phidot[0]));
    } else {
      const Vec6& V_main = b.parent_is_main ? Vp : Vc;
      const Vec6& V_sec = b.parent_is_main ? Vc : Vp;
      d.bias += sigma * (crossMotion(V_main, s[0]) * d.phidot[0] + crossMotion(V_sec, s[1]) * d.phidot[1]);
    }
  } else if (velocity_terms && !grounded) {
    d.bias += crossMotion(Vp, *Su);
  }
}

template <typename T>
template <class Loads>
EIGEN_ALWAYS_INLINE void TreePasses<T>::inertiaAndBiasForce(int i, double t, bool velocity_terms,
                                                            const Loads& loads) const {
  const ArticulatedBody& b = model_.bodies[i];
  Body& d = bodies_[i];
  const double mass = b.mass;
  d.Jw = d.R * b.inertia * d.R.transpose();
  const Mat3& Jw = d.Jw;
  if (articulated_) {
    // Rigid-body inertia about the origin: [J_w + m [c]×[c]×ᵀ, m [c]×; m [c]×ᵀ, m I].
    const Mat3 cx = hat(d.c);
    // −m [c]×[c]× = m (|c|² I − c cᵀ).
    d.IA.template topLeftCorner<3, 3>() = Jw - mass * (d.c * d.c.transpose());
    d.IA.template topLeftCorner<3, 3>().diagonal().array() += mass * d.c.squaredNorm();
    d.IA.template topRightCorner<3, 3>() = mass * cx;
    d.IA.template bottomLeftCorner<3, 3>() = -mass * cx;
    d.IA.template bottomRightCorner<3, 3>() = mass * Mat3::Identity();
  }
  if (!velocity_terms) {
    d.pA.setZero();
    return;
  }
  // Bias force V ×_f (I V) − f_ext, gravity m g at c among the external forces.
  const Vec3 w = d.V.template head<3>();
  const Vec3 vc = d.V.template tail<3>() + cross3(w, d.c);
  Vec6 h;
  h.template head<3>() = Jw * w + cross3(d.c, mass * vc);
  h.template tail<3>() = mass * vc;
  d.pA = crossForce(d.V, h);
  if (!b.rotation_only) {
    const Eigen::Vector3d mg = mass * model_.gravity;
    d.pA.template head<3>() -= cross3(d.c, mg);
    d.pA.template tail<3>() -= mg;
  }
  loads.external(i, t, &d, w, vc);
}

template <typename T>
template <class State, class Loads>
EIGEN_ALWAYS_INLINE void TreePasses<T>::forwardPass(double t, const State& y, bool dynamics, bool velocity_terms,
                                                    const Loads& loads) const {
  const Vec6 zero = Vec6::Zero();
  const Mat3 identity = Mat3::Identity();  // (a reference to it: no copy of the parent's R)
  for (int i = 0; i < static_cast<int>(model_.bodies.size()); ++i) {
    const ArticulatedBody& b = model_.bodies[i];
    Body& d = bodies_[i];
    const bool grounded = b.parent == kGround;
    const Mat3& Rp = grounded ? identity : bodies_[b.parent].R;
    const Vec6& Vp = grounded ? zero : bodies_[b.parent].V;
    if (grounded)
      d.x = b.anchor_parent.template cast<T>();
    else
      d.x = bodies_[b.parent].c + Rp * b.anchor_parent;
    // The line the joint's columns turn about: the anchor, or the held
    // centre of mass of a rotation-only body (S = P S_x).
    Vec3 held;  // (only a rotation-only body's line is not its anchor)
    if (b.rotation_only) held = b.fixed_position.template cast<T>();
    const Vec3& line = b.rotation_only ? held : d.x;
    d.free = 0;
    d.bias.setZero();
    // Where the child's anchor_child sits: the joint's anchor, moved by a
    // slide or an offset universal joint's first hinge.
    Vec3 child_anchor = d.x;
    Vec6 Su = Vec6::Zero();  // S u, the joint's relative twist
    if (b.kind == JointKind::kFree) {
      freeJointPass(b, d, rotationMatrixOf(y.N[b.rotation]), y.q.template segment<3>(b.q_begin),
                    y.u.template segment<3>(b.u_rotation), y.u.template segment<3>(b.u_begin), velocity_terms, &Su);
      child_anchor = d.x;
    } else if (b.kind == JointKind::kSpherical) {
      sphericalJointPass(b, d, Rp, rotationMatrixOf(y.N[b.rotation]), Vp, line, y.u, velocity_terms, &Su);
    } else {
      coordinateJointPass(i, t, y, dynamics, velocity_terms, Rp, Vp, line, loads, &Su, &child_anchor);
    }
    if (b.rotation_only) {
      // P (ω, v) = (ω, c × ω) on the parent's motion and on the bias.
      d.c = b.fixed_position.template cast<T>();
      d.V.template head<3>() = Vp.template head<3>() + Su.template head<3>();
      d.V.template tail<3>() = cross3(d.c, d.V.template head<3>());
      d.bias.template tail<3>() = cross3(d.c, d.bias.template head<3>());
    } else {
      d.V = Vp + Su;
      d.c = child_anchor - d.R * b.anchor_child;
    }
    if (dynamics) inertiaAndBiasForce(i, t, velocity_terms, loads);
  }
}

template <typename T>
void TreePasses<T>::passToParent(int i, const Mat6& Ia, const Vec6& pa) const {
  const ArticulatedBody& b = model_.bodies[i];
  Body& parent = bodies_[b.parent];
  if (!b.rotation_only) {
    parent.IA += Ia;
    parent.pA += pa;
    return;
  }
  const Mat6 P = rotationOnlyMap(bodies_[i].c);
  parent.IA += P.transpose() * Ia * P;
  parent.pA += P.transpose() * pa;
}

template <typename T>
EIGEN_ALWAYS_INLINE void TreePasses<T>::solve(const Vec6& a0, VecX* udot) const {
  const int n = static_cast<int>(model_.bodies.size());
  // Pass 2, leaves to root: articulated inertias and bias forces,
  //   I_a = I_A − U D⁻¹ Uᵀ,  p_a = p_A + I_a c + U D⁻¹ u = p_A + I_A c + U D⁻¹ (u − Uᵀ c),
  // passed to the parent (through Pᵀ · P for a rotation-only child).
  for (int i = n - 1; i >= 0; --i) {
    Body& d = bodies_[i];
    const ArticulatedBody& b = model_.bodies[i];
    const int p = b.parent;
    const int nf = d.free;
    if (nf == 1) {
      const Vec6 s = d.S.col(0);
      const Vec6 U = d.IA * s;
      const T Dinv = T(1.0) / s.dot(U);
      d.U.col(0) = U;
      d.Dinv(0, 0) = Dinv;
      d.tau[0] -= s.dot(d.pA);
      if (p == kGround) continue;
      const Vec6 DU = Dinv * U;
      const Vec6 pa = d.pA + d.IA * d.bias + (d.tau[0] - U.dot(d.bias)) * DU;
      if (b.rotation_only) {
        passToParent(i, d.IA - DU * U.transpose(), pa);
      } else {
        bodies_[p].IA += d.IA;
        bodies_[p].IA.noalias() -= DU * U.transpose();
        bodies_[p].pA += pa;
      }
    } else if (nf > 1) {
      d.U.leftCols(nf) = d.IA * d.S.leftCols(nf);
      const Mat3 D = d.S.transpose() * d.U;
      if (nf == 2) {
        d.Dinv.template topLeftCorner<2, 2>() = D.template topLeftCorner<2, 2>().inverse();
      } else {
        d.Dinv = D.inverse();
      }
      d.tau.head(nf) -= d.S.leftCols(nf).transpose() * d.pA;
      if (p == kGround) continue;
      const auto Dinv = d.Dinv.topLeftCorner(nf, nf);
      const Mat6 Ia = d.IA - d.U.leftCols(nf) * Dinv * d.U.leftCols(nf).transpose();
      passToParent(i, Ia, d.pA + Ia * d.bias + d.U.leftCols(nf) * (Dinv * d.tau.head(nf)));
    } else if (p != kGround) {
      passToParent(i, d.IA, d.pA + d.IA * d.bias);
    }
  }
  // Pass 3, root to leaves: accelerations.
  for (int i = 0; i < n; ++i) {
    Body& d = bodies_[i];
    const ArticulatedBody& b = model_.bodies[i];
    const int p = b.parent;
    if (b.kind == JointKind::kFree) {
      // I_A a + p_A = h: no joint force (h = 0), or the given momentum when
      // projecting velocities (projectVelocities); then from a = (α, a_O):
      // ω̇ = Rᵀα, v̇_c = a_O + α × c + ω × v_c (without the last term, velocities).
      d.a = d.IA.ldlt().solve(root_momentum_[i] - d.pA);
      const Vec3 alpha = d.a.template head<3>();
      Vec3 ac = d.a.template tail<3>() + cross3(alpha, d.c);
      if (!projecting_) {
        const Vec3 vc = d.V.template tail<3>() + cross3(d.V.template head<3>(), d.c);
        ac += cross3(d.V.template head<3>(), vc);
      }
      udot->template segment<3>(b.u_rotation) = d.R.transpose() * alpha;
      udot->template segment<3>(b.u_begin) = ac;
      continue;
    }
    if (p == kGround) {
      d.a = a0 + d.bias;
    } else if (b.rotation_only) {
      const Vec3 alpha = bodies_[p].a.template head<3>();
      d.a.template head<3>() = alpha;
      d.a.template tail<3>() = cross3(d.c, alpha);
      d.a += d.bias;
    } else {
      d.a = bodies_[p].a + d.bias;
    }
    const int nf = d.free;
    if (nf == 1) {
      const T qdd = d.Dinv(0, 0) * (d.tau[0] - d.U.col(0).dot(d.a));
      d.a += qdd * d.S.col(0);
      (*udot)[d.free_u[0]] = qdd;
    } else if (nf > 1) {
      const Vec3 r = d.tau - d.U.transpose() * d.a;
      Vec3 qdd = Vec3::Zero();
      qdd.head(nf) = d.Dinv.topLeftCorner(nf, nf) * r.head(nf);
      d.a += d.S.leftCols(nf) * qdd.head(nf);
      for (int k = 0; k < nf; ++k) (*udot)[d.free_u[k]] = qdd[k];
    }
  }
}

template <typename T>
template <class AddColumn>
EIGEN_ALWAYS_INLINE void TreePasses<T>::newtonEuler(const AddColumn& add_column, bool velocity_terms, int n_u,
                                                    VecX* tau) const {
  const int n = static_cast<int>(model_.bodies.size());
  // Root to leaves: accelerations and each body's own force I a (+ p).
  for (int i = 0; i < n; ++i) {
    Body& d = bodies_[i];
    const ArticulatedBody& b = model_.bodies[i];
    if (b.parent == kGround)
      d.a.setZero();
    else if (b.rotation_only)
      d.a = heldMotion(d.c, bodies_[b.parent].a);
    else
      d.a = bodies_[b.parent].a;
    if (velocity_terms) d.a += d.bias;
    for (int k = 0; k < d.free; ++k) add_column(d.free_u[k], d.S.col(k), &d.a);
    const Vec3 alpha = d.a.template head<3>();
    const Vec3 f_lin = b.mass * (d.a.template tail<3>() + cross3(alpha, d.c));
    d.f.template head<3>() = d.Jw * alpha + cross3(d.c, f_lin);
    d.f.template tail<3>() = f_lin;
    if (velocity_terms) d.f += d.pA;
  }
  // Leaves to root: the subtrees' forces, and τ = Sᵀ f.
  tau->setZero(n_u);
  for (int i = n - 1; i >= 0; --i) {
    const Body& d = bodies_[i];
    const ArticulatedBody& b = model_.bodies[i];
    for (int k = 0; k < d.free; ++k) (*tau)[d.free_u[k]] = d.S.col(k).dot(d.f);
    if (b.parent == kGround) continue;
    bodies_[b.parent].f += b.rotation_only ? heldForce(d.c, d.f) : d.f;
  }
}

template <typename T>
void TreePasses<T>::inverseDynamics(const VecX& udot, VecX* tau) const {
  newtonEuler([&](int v, const auto& s, Vec6* a) { *a += s * udot[v]; }, true, static_cast<int>(udot.size()), tau);
}

template <typename T>
void TreePasses<T>::biasForces(VecX* h) const {
  newtonEuler([](int, const auto&, Vec6*) {}, true, model_.dofs(), h);
}

template <typename T>
void TreePasses<T>::massMatrixColumn(int j, VecX* column) const {
  newtonEuler([&](int v, const auto& s, Vec6* a) { if (v == j) *a += s; }, false, model_.dofs(), column);
}

}  // namespace articulated
}  // namespace lieflow
