// ArticulatedSystem: the articulated-body algorithm in world coordinates
// (articulated_system.hpp states the conventions and equations).
#include <algorithm>
#include <cmath>
#include <type_traits>
#include <variant>

#include "dynamics/joint_space/articulated_system.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {
namespace articulated {

ArticulatedSystem::ArticulatedSystem(ArticulatedModel model)
    : model_(std::move(model)) {
  data_.bodies.resize(model_.bodies.size());
  data_.root_momentum.assign(model_.bodies.size(), Vector6::Zero());
  data_.udot.resize(model_.dofs());
  rotation_basis_.resize(model_.bodies.size());
  // The free trees (each free root and the bodies below it) and their masses.
  free_tree_.assign(model_.bodies.size(), -1);
  free_tree_mass_.assign(model_.rotations, 0.0);
  for (int i = 0; i < bodyCount(); ++i) {
    const ArticulatedBody& b = model_.bodies[i];
    if (b.kind == JointKind::kFree) {
      free_tree_[i] = b.rotation;
      free_root_body_.push_back(i);
    } else if (b.parent != kGround) {
      free_tree_[i] = free_tree_[b.parent];
    }
    if (free_tree_[i] >= 0) free_tree_mass_[free_tree_[i]] += b.mass;
  }
  for (int i = 0; i < bodyCount(); ++i) {
    const ArticulatedBody& b = model_.bodies[i];
    // The Rodrigues basis of jointRotation: revolute and universal joints.
    if (b.kind != JointKind::kRevolute && b.kind != JointKind::kUniversal) continue;
    const Eigen::Matrix3d aa = b.axis1 * b.axis1.transpose();
    rotation_basis_[i].A = (Eigen::Matrix3d::Identity() - aa) * b.R_ref;
    rotation_basis_[i].B = hat(b.axis1) * b.R_ref;
    rotation_basis_[i].C = aa * b.R_ref;
  }
  if (hasClosures()) {
    const int m = model_.closure_rows, n = dofs();
    data_.closure_G.setZero(m, n);
    data_.closure_Y.setZero(n, m);
    data_.closure_A.setZero(m, m);
    data_.closure_r.setZero(m);
    data_.closure_lambda.setZero(m);
    data_.closure_s.setZero(m);
    data_.closure_rhs.setZero(m);
    if (m == 1)
      data_.closure_column.resize(model_.bodies.size(), 1);
    else
      data_.closure_columns.resize(model_.bodies.size(), m);
    data_.closure_x.setZero(n);
    data_.closure_perm.assign(m, 0);
    for (const ArticulatedClosure& c : model_.closures) data_.closure_phi.push_back(c.initial_angles);
    // Which rows are a loop's positions and which a gear's velocities.
    position_rows_.setZero(m);
    for (const ArticulatedClosure& c : model_.closures) {
      const int rows = c.gear ? std::visit([](const auto& g) { return static_cast<int>(std::decay_t<decltype(g)>::kRows); }, *c.gear)
                              : std::visit([](const auto& j) { return static_cast<int>(std::decay_t<decltype(j)>::kRows); }, c.constraint);
      position_rows_.segment(c.row_begin, rows).setConstant(c.gear ? 0.0 : 1.0);
      (c.gear ? has_velocity_rows_ : has_position_rows_) = true;
    }
    if (onlyCouplings()) {
      // The coupling rows α q̇₁ + q̇₂ in joint coordinates: constant, read
      // off the closure Jacobian at the zero configuration (terms below
      // 1e-12, the rounding of the ancestors' columns that cancel, dropped).
      State zero;
      zero.q.setZero(model_.scalar_coordinates);
      zero.N.assign(model_.rotations, SO3d());
      zero.u.setZero(dofs());
      forwardPass(0.0, zero, false, false);
      closureTerms(ClosureLevel::kJacobian);
      coupling_G_ = data_.closure_G;
      coupling_G_ = (coupling_G_.array().abs() < 1e-12).select(0.0, coupling_G_);
      coupling_G_max_ = coupling_G_.cwiseAbs().maxCoeff();
      const auto unwrapped = data_.closure_phi;  // closureTerms may move them
      closureTerms(ClosureLevel::kPosition);
      coupling_phi0_ = data_.closure_r;
      data_.closure_phi = unwrapped;
    }
  }
  findIndependentBlocks();
}

void ArticulatedSystem::findIndependentBlocks() {
  // Each body's tree: the body whose parent is the ground (a free root, or
  // a joint to the ground). Trees share no term of M (the composite-rigid-
  // body algorithm fills a column's ancestors only), the drives' C_t and
  // K_t are diagonal and a rotation's T is its own 3 x 3 block. Closures
  // would join trees: then one block (none named).
  independent_blocks_.clear();
  if (hasClosures()) return;
  std::vector<int> block_of_root(model_.bodies.size(), -1);
  for (int i = 0; i < bodyCount(); ++i) {
    int root = i;
    while (model_.bodies[root].parent != kGround) root = model_.bodies[root].parent;
    if (block_of_root[root] < 0) {
      block_of_root[root] = static_cast<int>(independent_blocks_.size());
      independent_blocks_.emplace_back();
    }
    std::vector<int>& block = independent_blocks_[block_of_root[root]];
    const ArticulatedBody& b = model_.bodies[i];
    if (b.kind == JointKind::kFree) {
      for (int k = 0; k < 3; ++k) block.push_back(b.u_rotation + k);
      for (int k = 0; k < 3; ++k) block.push_back(b.u_begin + k);
    } else {
      for (int k = 0; k < b.dofs(); ++k) block.push_back(b.u_begin + k);
    }
  }
  std::size_t total = 0;
  for (std::vector<int>& block : independent_blocks_) {
    std::sort(block.begin(), block.end());
    total += block.size();
  }
  LIEFLOW_ASSERT(static_cast<int>(total) == dofs(), "findIndependentBlocks: the trees' rates do not cover u");
  if (independent_blocks_.size() < 2) independent_blocks_.clear();
}

void ArticulatedSystem::setUserTorque(int i, UserTorque torque) {
  LIEFLOW_ASSERT(i >= 0 && i < bodyCount(), "setUserTorque: no such body");
  if (user_torques_.empty()) user_torques_.resize(model_.bodies.size());
  user_torques_[i] = std::move(torque);
  has_user_torques_ = true;
}

// forwardPass's parts: the joint's kinematics per joint type, then the
// body's inertia and bias force. Defined before it in this file and always
// inlined into its loop (one pass over the tree, as before the split).

EIGEN_ALWAYS_INLINE void ArticulatedSystem::freeJointPass(const ArticulatedBody& b, BodyData& d,
                                                          const State& y, bool velocity_terms,
                                                          Vector6* Su) const {
  // A floating root: V = (ω, v_c + c × ω) from (R, c) and (ω body, v_c);
  // its columns, fixed in the body (the rotations, lines through c) and
  // in the world (the translations), give Ṡ u = (0, v_c × ω). Its six
  // degrees of freedom are solved as one block in solve(), not as columns.
  d.R = y.N[b.rotation].matrix();
  d.x = y.q.segment<3>(b.q_begin);
  const Eigen::Vector3d w = d.R * y.u.segment<3>(b.u_rotation);
  const Eigen::Vector3d vc = y.u.segment<3>(b.u_begin);
  *Su << w, vc + cross3(d.x, w);
  if (velocity_terms) d.bias.tail<3>() = cross3(vc, w);
  d.tau.setZero();
}

EIGEN_ALWAYS_INLINE void ArticulatedSystem::sphericalJointPass(const ArticulatedBody& b, BodyData& d,
                                                               const Eigen::Matrix3d& Rp, const Vector6& Vp,
                                                               const Eigen::Vector3d& line, const State& y,
                                                               bool velocity_terms, Vector6* Su) const {
  d.R = Rp * y.N[b.rotation].matrix();
  d.S.topRows<3>() = d.R;
  d.S.bottomRows<3>() = hat(line) * d.R;
  d.free = 3;
  for (int k = 0; k < 3; ++k) d.free_u[k] = b.u_begin + k;
  d.tau.setZero();
  if (velocity_terms) {
    *Su = d.S * y.u.segment<3>(b.u_begin);
    d.bias = crossMotion(Vp, *Su);
  }
}

EIGEN_ALWAYS_INLINE void ArticulatedSystem::coordinateJointPass(int i, double t, const State& y, bool dynamics,
                                                                bool velocity_terms, const Eigen::Matrix3d& Rp,
                                                                const Vector6& Vp, const Eigen::Vector3d& line,
                                                                Vector6* Su,
                                                                Eigen::Vector3d* child_anchor) const {
  const ArticulatedBody& b = model_.bodies[i];
  BodyData& d = data_.bodies[i];
  const double sigma = b.parent_is_main ? 1.0 : -1.0;
  const int nc = b.coordinates();
  for (int k = 0; k < nc; ++k) {
    if (b.prescribed(k)) {
      const TimeFunction& f = *model_.drives[i][k].prescribed;
      d.phi[k] = f(t);
      d.phidot[k] = f.derivative(t);
      d.phiddot[k] = f.secondDerivative(t);
    } else {
      d.phi[k] = y.q[b.q_begin + k];
      d.phidot[k] = y.u[b.u_begin + k];
      d.phiddot[k] = 0.0;
    }
  }
  // A slide holds the relative rotation R_ref; a hinge turns it.
  const bool slides = b.kind == JointKind::kPrismatic;
  std::array<double, 3> cos_phi{{1.0, 1.0, 1.0}}, sin_phi{{0.0, 0.0, 0.0}};
  if (!slides)
    for (int k = 0; k < nc; ++k) sinCos(d.phi[k], &cos_phi[k], &sin_phi[k]);
  // A gimbal: M = E₁E₂E₃ R_ref with E_k = exp(φ_k e_k), and its axes
  // A_k = R_main E₁…E_{k−1} e_k (each hinge turns with the ones before it).
  const bool gimbal = b.kind == JointKind::kGimbal;
  Eigen::Matrix3d M;
  Eigen::Vector3d gimbal_a2 = Eigen::Vector3d::Zero(), gimbal_a3 = Eigen::Vector3d::Zero();  // E₁e₂, E₁E₂e₃
  if (gimbal) {
    const GimbalAxes g = gimbalAxes(b, cos_phi, sin_phi);
    M = g.M;
    gimbal_a2 = g.a2;
    gimbal_a3 = g.a3;
  } else {
    // A slide and a weld hold R_ref (a weld has no column: V = V_p).
    M = slides || b.kind == JointKind::kFixed ? b.R_ref : jointRotation(i, cos_phi, sin_phi);
  }
  d.R = b.parent_is_main ? Eigen::Matrix3d(Rp * M) : Eigen::Matrix3d(Rp * M.transpose());
  const Eigen::Matrix3d& R_main = b.parent_is_main ? Rp : d.R;
  const Eigen::Matrix3d& R_sec = b.parent_is_main ? d.R : Rp;
  d.axis[0] = R_main * b.axis1;
  if (gimbal) {
    d.axis[1] = R_main * gimbal_a2;
    d.axis[2] = R_main * gimbal_a3;
  } else if (nc == 2) {
    d.axis[1] = R_sec * b.axis2;
  }
  // An offset universal joint's second column is the line through the
  // secondary anchor x₂ = x₁ + R_main exp(φ₁a₁) δ (δ = offset_ref), which
  // also carries the child; every other column's line is the anchor.
  if (b.offset) *child_anchor = d.x2 = offsetAnchor(b, d.x, R_main, cos_phi[0], sin_phi[0]);
  // A slide moves the child's anchor along A by x from the main's (σ = −1
  // when the child is the main body).
  if (slides) *child_anchor = d.x + (sigma * d.phi[0]) * d.axis[0];
  std::array<Vector6, 3> s;
  for (int k = 0; k < nc; ++k) {
    // A slide's column is a translation along A: (0, A) whatever the point.
    s[k] = slides ? (Vector6() << Eigen::Vector3d::Zero(), d.axis[k]).finished()
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
      d.tau[d.free] = dynamics && velocity_terms && b.has_force[k]
                          ? model_.drives[i][k].momentAt(t, d.phi[k], d.phidot[k])
                          : 0.0;
      ++d.free;
    }
  }
  if (velocity_terms && b.kind == JointKind::kGimbal) {
    // Ṡ u of a gimbal (parent main): s₁ turns with the parent, s₂ with the
    // parent turned by φ₁, s₃ by φ₁ and φ₂: ṡ_k = (V_p + Σ_{j<k} s_j φ̇_j) ×ₘ s_k.
    const Vector6 w1 = s[0] * d.phidot[0], w2 = s[1] * d.phidot[1], w3 = s[2] * d.phidot[2];
    d.bias += crossMotion(Vp, *Su) + crossMotion(w1, w2 + w3) + crossMotion(w2, w3);
  } else if (velocity_terms && nc == 2) {
    // Ṡ u of a universal joint: s₁ turns with the main body, s₂ with the
    // secondary (both velocities known: the child's is V_p + S u).
    const Vector6 Vc = Vp + *Su;
    const Vector6& V_main = b.parent_is_main ? Vp : Vc;
    const Vector6& V_sec = b.parent_is_main ? Vc : Vp;
    d.bias += sigma * (crossMotion(V_main, s[0]) * d.phidot[0] + crossMotion(V_sec, s[1]) * d.phidot[1]);
  } else if (velocity_terms) {
    d.bias += crossMotion(Vp, *Su);
  }
}

EIGEN_ALWAYS_INLINE void ArticulatedSystem::inertiaAndBiasForce(int i, double t, bool velocity_terms) const {
  const ArticulatedBody& b = model_.bodies[i];
  BodyData& d = data_.bodies[i];
  // Rigid-body inertia about the origin: [J_w + m [c]×[c]×ᵀ, m [c]×; m [c]×ᵀ, m I].
  const Eigen::Matrix3d Jw = d.R * b.inertia * d.R.transpose();
  const Eigen::Matrix3d cx = hat(d.c);
  // −m [c]×[c]× = m (|c|² I − c cᵀ).
  d.IA.topLeftCorner<3, 3>() = Jw - b.mass * (d.c * d.c.transpose());
  d.IA.topLeftCorner<3, 3>().diagonal().array() += b.mass * d.c.squaredNorm();
  d.IA.topRightCorner<3, 3>() = b.mass * cx;
  d.IA.bottomLeftCorner<3, 3>() = -b.mass * cx;
  d.IA.bottomRightCorner<3, 3>() = b.mass * Eigen::Matrix3d::Identity();
  if (!velocity_terms) {
    d.pA.setZero();
    return;
  }
  // Bias force V ×_f (I V) − f_ext, gravity m g at c among the external forces.
  const Eigen::Vector3d w = d.V.head<3>();
  const Eigen::Vector3d vc = d.V.tail<3>() + cross3(w, d.c);
  Vector6 h;
  h.head<3>() = Jw * w + cross3(d.c, b.mass * vc);
  h.tail<3>() = b.mass * vc;
  d.pA = crossForce(d.V, h);
  if (!b.rotation_only) {
    const Eigen::Vector3d mg = b.mass * model_.gravity;
    d.pA.head<3>() -= cross3(d.c, mg);
    d.pA.tail<3>() -= mg;
  }
  if (has_user_torques_ && user_torques_[i]) {
    const Eigen::Quaterniond q(d.R);
    d.pA.head<3>() -= d.R * user_torques_[i](t, q, d.c, d.R.transpose() * w, vc);
  }
}

void ArticulatedSystem::forwardPass(double t, const State& y, bool dynamics, bool velocity_terms) const {
  const Vector6 zero = Vector6::Zero();
  for (int i = 0; i < bodyCount(); ++i) {
    const ArticulatedBody& b = model_.bodies[i];
    BodyData& d = data_.bodies[i];
    const bool grounded = b.parent == kGround;
    static const Eigen::Matrix3d kIdentity = Eigen::Matrix3d::Identity();  // (no copy of the parent's R)
    const Eigen::Matrix3d& Rp = grounded ? kIdentity : data_.bodies[b.parent].R;
    const Vector6& Vp = grounded ? zero : data_.bodies[b.parent].V;
    d.x = grounded ? b.anchor_parent : Eigen::Vector3d(data_.bodies[b.parent].c + Rp * b.anchor_parent);
    // The line the joint's columns turn about: the anchor, or the held
    // centre of mass of a rotation-only body (S = P S_x).
    const Eigen::Vector3d& line = b.rotation_only ? b.fixed_position : d.x;
    d.free = 0;
    d.bias.setZero();
    // Where the child's anchor_child sits: the joint's anchor, moved by a
    // slide or an offset universal joint's first hinge.
    Eigen::Vector3d child_anchor = d.x;
    Vector6 Su = Vector6::Zero();  // S u, the joint's relative twist
    if (b.kind == JointKind::kFree) {
      freeJointPass(b, d, y, velocity_terms, &Su);
      child_anchor = d.x;
    } else if (b.kind == JointKind::kSpherical) {
      sphericalJointPass(b, d, Rp, Vp, line, y, velocity_terms, &Su);
    } else {
      coordinateJointPass(i, t, y, dynamics, velocity_terms, Rp, Vp, line, &Su, &child_anchor);
    }
    if (b.rotation_only) {
      // P (ω, v) = (ω, c × ω) on the parent's motion and on the bias.
      d.c = b.fixed_position;
      d.V.head<3>() = Vp.head<3>() + Su.head<3>();
      d.V.tail<3>() = cross3(d.c, d.V.head<3>());
      d.bias.tail<3>() = cross3(d.c, d.bias.head<3>());
    } else {
      d.V = Vp + Su;
      d.c = child_anchor - d.R * b.anchor_child;
    }
    if (dynamics) inertiaAndBiasForce(i, t, velocity_terms);
  }
}

void ArticulatedSystem::passToParent(int i, const Matrix6& Ia, const Vector6& pa) const {
  const ArticulatedBody& b = model_.bodies[i];
  BodyData& parent = data_.bodies[b.parent];
  if (!b.rotation_only) {
    parent.IA += Ia;
    parent.pA += pa;
    return;
  }
  const Matrix6 P = rotationOnlyMap(data_.bodies[i].c);
  parent.IA += P.transpose() * Ia * P;
  parent.pA += P.transpose() * pa;
}

void ArticulatedSystem::solve(const Vector6& a0, Eigen::VectorXd* udot) const {
  // Pass 2, leaves to root: articulated inertias and bias forces,
  //   I_a = I_A − U D⁻¹ Uᵀ,  p_a = p_A + I_a c + U D⁻¹ u = p_A + I_A c + U D⁻¹ (u − Uᵀ c),
  // passed to the parent (through Pᵀ · P for a rotation-only child).
  for (int i = bodyCount() - 1; i >= 0; --i) {
    BodyData& d = data_.bodies[i];
    const ArticulatedBody& b = model_.bodies[i];
    const int p = b.parent;
    const int nf = d.free;
    if (nf == 1) {
      const Vector6 s = d.S.col(0);
      const Vector6 U = d.IA * s;
      const double Dinv = 1.0 / s.dot(U);
      d.U.col(0) = U;
      d.Dinv(0, 0) = Dinv;
      d.tau[0] -= s.dot(d.pA);
      if (p == kGround) continue;
      const Vector6 DU = Dinv * U;
      const Vector6 pa = d.pA + d.IA * d.bias + (d.tau[0] - U.dot(d.bias)) * DU;
      if (b.rotation_only) {
        passToParent(i, d.IA - DU * U.transpose(), pa);
      } else {
        data_.bodies[p].IA += d.IA;
        data_.bodies[p].IA.noalias() -= DU * U.transpose();
        data_.bodies[p].pA += pa;
      }
    } else if (nf > 1) {
      d.U.leftCols(nf) = d.IA * d.S.leftCols(nf);
      const Eigen::Matrix3d D = d.S.transpose() * d.U;
      if (nf == 2) {
        d.Dinv.topLeftCorner<2, 2>() = D.topLeftCorner<2, 2>().inverse();
      } else {
        d.Dinv = D.inverse();
      }
      d.tau.head(nf) -= d.S.leftCols(nf).transpose() * d.pA;
      if (p == kGround) continue;
      const auto Dinv = d.Dinv.topLeftCorner(nf, nf);
      const Matrix6 Ia = d.IA - d.U.leftCols(nf) * Dinv * d.U.leftCols(nf).transpose();
      passToParent(i, Ia, d.pA + Ia * d.bias + d.U.leftCols(nf) * (Dinv * d.tau.head(nf)));
    } else if (p != kGround) {
      passToParent(i, d.IA, d.pA + d.IA * d.bias);
    }
  }
  // Pass 3, root to leaves: accelerations.
  for (int i = 0; i < bodyCount(); ++i) {
    BodyData& d = data_.bodies[i];
    const ArticulatedBody& b = model_.bodies[i];
    const int p = b.parent;
    if (b.kind == JointKind::kFree) {
      // I_A a + p_A = h: no joint force (h = 0), or the given momentum when
      // projecting velocities (projectVelocities); then from a = (α, a_O):
      // ω̇ = Rᵀα, v̇_c = a_O + α × c + ω × v_c (without the last term, velocities).
      d.a = d.IA.ldlt().solve(data_.root_momentum[i] - d.pA);
      const Eigen::Vector3d alpha = d.a.head<3>();
      Eigen::Vector3d ac = d.a.tail<3>() + cross3(alpha, d.c);
      if (!data_.projecting) ac += cross3(d.V.head<3>(), velocityOfCentre(i));
      udot->segment<3>(b.u_rotation) = d.R.transpose() * alpha;
      udot->segment<3>(b.u_begin) = ac;
      continue;
    }
    if (p == kGround) {
      d.a = a0 + d.bias;
    } else if (b.rotation_only) {
      const Eigen::Vector3d alpha = data_.bodies[p].a.head<3>();
      d.a.head<3>() = alpha;
      d.a.tail<3>() = cross3(d.c, alpha);
      d.a += d.bias;
    } else {
      d.a = data_.bodies[p].a + d.bias;
    }
    const int nf = d.free;
    if (nf == 1) {
      const double qdd = d.Dinv(0, 0) * (d.tau[0] - d.U.col(0).dot(d.a));
      d.a += qdd * d.S.col(0);
      (*udot)[d.free_u[0]] = qdd;
    } else if (nf > 1) {
      const Eigen::Vector3d r = d.tau - d.U.transpose() * d.a;
      Eigen::Vector3d qdd = Eigen::Vector3d::Zero();
      qdd.head(nf) = d.Dinv.topLeftCorner(nf, nf) * r.head(nf);
      d.a += d.S.leftCols(nf) * qdd.head(nf);
      for (int k = 0; k < nf; ++k) (*udot)[d.free_u[k]] = qdd[k];
    }
  }
}

void ArticulatedSystem::accelerations(double t, const State& y, Eigen::VectorXd* udot) const {
  forwardPass(t, y, true, true);
  udot->resize(dofs());
  solve(Vector6::Zero(), udot);
  for (int i = 0; i < bodyCount(); ++i) {
    const ArticulatedBody& b = model_.bodies[i];
    for (int k = 0; k < b.coordinates(); ++k)
      if (b.prescribed(k)) (*udot)[b.u_begin + k] = data_.bodies[i].phiddot[k];
  }
  if (hasClosures()) closureAccelerations(udot);
}

void ArticulatedSystem::velocity(double t, const State& y, Tangent* F) const {
  const int n = dofs();
  F->resize(2 * n);
  accelerations(t, y, &data_.udot);
  F->head(n) = y.u;
  F->tail(n) = data_.udot;
  for (int i = 0; i < bodyCount(); ++i) {
    const ArticulatedBody& b = model_.bodies[i];
    for (int k = 0; k < b.coordinates(); ++k)
      if (b.prescribed(k)) (*F)[b.u_begin + k] = data_.bodies[i].phidot[k];
  }
}

bool ArticulatedSystem::autonomous() const {
  if (has_user_torques_) return false;
  for (int i = 0; i < bodyCount(); ++i)
    for (int k = 0; k < model_.bodies[i].coordinates(); ++k)
      if (model_.drives[i][k].dependsOnTime()) return false;
  return true;
}

void ArticulatedSystem::projectVelocities(double t, const std::vector<Eigen::Vector3d>& omega_body,
                                          const std::vector<Eigen::Vector3d>& v_com, State* y) const {
  forwardPass(t, *y, true, false);
  // Right-hand side Sᵀ Σ_subtree I_O V_given: the generalized momenta of the
  // given body velocities (accumulated leaves to root in pA, then moved to
  // tau), with the ABA's pA cleared for the solve.
  std::vector<Vector6> H(bodyCount(), Vector6::Zero());
  for (int i = bodyCount() - 1; i >= 0; --i) {
    const ArticulatedBody& b = model_.bodies[i];
    BodyData& d = data_.bodies[i];
    const Eigen::Vector3d w = d.R * omega_body[i];
    const Eigen::Vector3d vc = b.rotation_only ? Eigen::Vector3d::Zero() : v_com[i];
    const Eigen::Matrix3d Jw = d.R * b.inertia * d.R.transpose();
    Vector6 h;
    h << Jw * w + d.c.cross(b.mass * vc), b.mass * vc;
    H[i] += h;
    if (b.parent == kGround) continue;
    if (b.rotation_only) {
      H[b.parent].head<3>() += H[i].head<3>() - d.c.cross(H[i].tail<3>());  // Pᵀ H: the momentum about c
    } else {
      H[b.parent] += H[i];
    }
  }
  for (int i = 0; i < bodyCount(); ++i) {
    BodyData& d = data_.bodies[i];
    d.tau.head(d.free) = d.S.leftCols(d.free).transpose() * H[i];
    // A floating root takes its subtree's whole momentum.
    if (model_.bodies[i].kind == JointKind::kFree) data_.root_momentum[i] = H[i];
  }
  data_.udot.setZero(dofs());
  data_.projecting = true;
  solve(Vector6::Zero(), &data_.udot);
  data_.projecting = false;
  for (Vector6& h : data_.root_momentum) h.setZero();
  y->u = data_.udot;
  for (int i = 0; i < bodyCount(); ++i) {
    const ArticulatedBody& b = model_.bodies[i];
    for (int k = 0; k < b.coordinates(); ++k)
      if (b.prescribed(k)) {
        y->u[b.u_begin + k] = data_.bodies[i].phidot[k];
        y->q[b.q_begin + k] = data_.bodies[i].phi[k];
      }
  }
}

}  // namespace articulated
}  // namespace lieflow
