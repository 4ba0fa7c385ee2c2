// ArticulatedSystem: what the joint-space variational integrator reads
// (integrators/joint_space_variational.hpp) — frames and the factored mass
// matrix at a configuration, M(q) v and ∂T/∂q, M(q)⁻¹ τ, the generalized
// forces. articulated_system.hpp states the conventions and the equations.
#include <sstream>

#include <Eigen/Cholesky>

#include "dynamics/joint_space/articulated_system.hpp"
#include "dynamics/joint_space/pivoted_cholesky.hpp"
#include "liegroup/invalid_input.hpp"
#include "liegroup/so3.hpp"

namespace lieflow {
namespace articulated {

namespace {

/// Whether a closure is one coupling row (α q̇₁ + q̇₂ = 0: linear and
/// constant in joint coordinates).
bool isCouplingRow(const ArticulatedClosure& c) {
  return c.gear && std::holds_alternative<constraints::CouplingJoint<double>>(*c.gear);
}

}  // namespace

/// The tree of `body` as the variational step's coordinates see it: its
/// floating tree's index, or −1 for the ground and the trees hung from it.
int ArticulatedSystem::stepTreeOf(int body) const { return body == kGround ? -1 : free_tree_[body]; }

bool ArticulatedSystem::variationalCovers(std::string* why) const {
  for (const ArticulatedClosure& c : model_.closures) {
    if (isCouplingRow(c)) continue;
    // Loops and gear rows: RATTLE's multipliers on the rows in the state's
    // coordinates. On a floating tree the step's coordinates move its root
    // by the tree's centre of mass (v_root = v_z − Σ m_i (v_i − v_root)/m),
    // u_state = T u_step, so its rows are G T: G itself wherever G has no
    // column on the root's translation. That holds for rows on angular rates
    // (gears, differentials, wherever their bodies are) and for rows among
    // the bodies of one floating tree (a loop inside a floating robot, a rack
    // on the tree that carries its pinion): a shift of the whole tree moves
    // them all alike. A row between a floating tree and the ground or another
    // tree is refused.
    const bool angular = c.gear && !std::holds_alternative<constraints::RackPinionJoint<double>>(*c.gear);
    if (angular) continue;
    const std::size_t involved =
        c.gear ? std::visit([](const auto& g) { return std::decay_t<decltype(g)>::kBodies; }, *c.gear) : 2;
    int floating_body = -1;
    bool mixed = false;
    for (std::size_t k = 0; k < involved; ++k) {
      if (stepTreeOf(c.bodies[k]) >= 0 && floating_body < 0) floating_body = c.bodies[k];
      mixed = mixed || stepTreeOf(c.bodies[k]) != stepTreeOf(c.bodies[0]);
    }
    if (!mixed) continue;
    if (why)
      *why = c.label + (c.gear ? " is a rack-and-pinion row" : " closes a loop") + " between the floating tree of "
             "body '" + model_.names[floating_body] + "' and the ground or another tree: lgvi in joint coordinates "
             "takes such rows only within one tree (a floating tree's step coordinates are its centre of mass, "
             "which the row would move)";
    return false;
  }
  return !hasPrescribedCoordinate("lgvi", why);
}

bool ArticulatedSystem::hasPrescribedCoordinate(const std::string& integrator, std::string* why) const {
  for (int i = 0; i < bodyCount(); ++i) {
    const ArticulatedBody& b = model_.bodies[i];
    for (int k = 0; k < b.coordinates(); ++k) {
      if (!b.prescribed(k)) continue;
      if (why)
        *why = "body '" + model_.names[i] + "' has a prescribed joint angle, a time-dependent constraint, which " +
               integrator + " in joint coordinates does not take";
      return true;
    }
  }
  return false;
}

bool ArticulatedSystem::onlyCouplings() const {
  for (const ArticulatedClosure& c : model_.closures)
    if (!isCouplingRow(c)) return false;
  return true;
}

bool ArticulatedSystem::hasVelocityDependentForces() const {
  if (has_user_torques_) return true;
  for (int i = 0; i < bodyCount(); ++i)
    for (int k = 0; k < model_.bodies[i].coordinates(); ++k) {
      const CoordinateDrive& d = model_.drives[i][k];
      if (d.damping != 0.0 || d.user_moment) return true;
    }
  return false;
}

void ArticulatedSystem::poseInto(int i, const State& y, const Frames* near, Frames* f) const {
  // The ABA's pass 1 kinematics for the joints variationalCovers() takes:
  // pose, free columns, angles.
  const ArticulatedBody& b = model_.bodies[i];
  Frame& fr = f->bodies[i];
  if (b.kind == JointKind::kFree) {
    // A free root: R from the state; its six rates are one block
    // (solveMass, momentumBack), not columns. Its tree is placed with the
    // root's centre at the origin: what these passes compute (M v, ∂T/∂q, Q,
    // M⁻¹) does not depend on where the tree is (P, v_c and the torques
    // about c are the same anywhere), and spatial inertias about a far
    // origin would carry m |c|² beside the bodies' own inertias: a tree
    // fallen 90 m lost six digits of its rates to that rounding.
    fr.R = y.N[b.rotation].matrix();
    fr.c.setZero();
    fr.free = 0;
    return;
  }
  const bool grounded = b.parent == kGround;
  static const Eigen::Matrix3d kIdentity = Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d& Rp = grounded ? kIdentity : f->bodies[b.parent].R;
  const double sigma = b.parent_is_main ? 1.0 : -1.0;
  const Eigen::Vector3d x = grounded ? b.anchor_parent : Eigen::Vector3d(f->bodies[b.parent].c + Rp * b.anchor_parent);
  const Eigen::Vector3d& line = b.rotation_only ? b.fixed_position : x;
  if (b.kind == JointKind::kSpherical) {
    // S = (R, [x]× R), u = ω_rel in the child's axes (also the implicit
    // joint of a rotation-only root, about its held centre).
    fr.R = Rp * y.N[b.rotation].matrix();
    fr.S.topRows<3>() = fr.R;
    fr.S.bottomRows<3>().noalias() = hat(line) * fr.R;
    fr.free = 3;
    for (int k = 0; k < 3; ++k) fr.free_u[k] = b.u_begin + k;
    fr.c = b.rotation_only ? b.fixed_position : Eigen::Vector3d(x - fr.R * b.anchor_child);
    return;
  }
  if (b.kind == JointKind::kFixed) {
    // A weld: R_ref and the anchors held, no column (the child is never
    // rotation-only: articulated_scene.cpp).
    fr.R = b.parent_is_main ? Eigen::Matrix3d(Rp * b.R_ref) : Eigen::Matrix3d(Rp * b.R_ref.transpose());
    fr.free = 0;
    fr.c = x - fr.R * b.anchor_child;
    return;
  }
  if (b.kind == JointKind::kPrismatic) {
    // The relative rotation R_ref held; the child's anchor at x + σ φ A, the
    // column σ (0, A), A = R_main a.
    fr.phi[0] = y.q[b.q_begin];
    fr.free_u[0] = b.u_begin;
    fr.free = 1;
    fr.R = b.parent_is_main ? Eigen::Matrix3d(Rp * b.R_ref) : Eigen::Matrix3d(Rp * b.R_ref.transpose());
    const Eigen::Vector3d A = (b.parent_is_main ? Rp : fr.R) * b.axis1;
    fr.S.col(0).head<3>().setZero();
    fr.S.col(0).tail<3>() = sigma * A;
    fr.c = x + (sigma * fr.phi[0]) * A - fr.R * b.anchor_child;
    return;
  }
  const int nc = b.coordinates();
  for (int k = 0; k < nc; ++k) {
    fr.phi[k] = y.q[b.q_begin + k];
    fr.free_u[k] = b.u_begin + k;
    if (near) {
      const Frame& n = near->bodies[i];
      sinCosNear(fr.phi[k], n.phi[k], n.cos_phi[k], n.sin_phi[k], &fr.cos_phi[k], &fr.sin_phi[k]);
    } else {
      sinCos(fr.phi[k], &fr.cos_phi[k], &fr.sin_phi[k]);
    }
  }
  fr.free = nc;
  if (b.kind == JointKind::kGimbal) {
    // M = E₁E₂E₃ R_ref, E_k = exp(φ_k e_k); the columns the lines through the
    // anchor along R_main e₁, R_main E₁ e₂, R_main E₁E₂ e₃ (the parent is main).
    const GimbalAxes<double> g = gimbalAxes(b, fr.cos_phi, fr.sin_phi);
    fr.R = Rp * g.M;
    const Eigen::Vector3d A[3] = {Rp * b.axis1, Rp * g.a2, Rp * g.a3};
    for (int k = 0; k < 3; ++k) {
      fr.S.col(k).head<3>() = A[k];
      fr.S.col(k).tail<3>() = cross3(line, A[k]);
    }
    fr.c = b.rotation_only ? b.fixed_position : Eigen::Vector3d(x - fr.R * b.anchor_child);
    return;
  }
  const Eigen::Matrix3d M = jointRotation(i, fr.cos_phi, fr.sin_phi);
  fr.R = b.parent_is_main ? Eigen::Matrix3d(Rp * M) : Eigen::Matrix3d(Rp * M.transpose());
  // Columns σ (A, x × A), written by halves (a comma initializer into a
  // temporary stalled store-to-load forwarding: 14 % of this function).
  const Eigen::Vector3d A0 = sigma * ((b.parent_is_main ? Rp : fr.R) * b.axis1);
  fr.S.col(0).head<3>() = A0;
  fr.S.col(0).tail<3>() = cross3(line, A0);
  // An offset universal joint (the parent is main): its second line passes
  // through the secondary anchor, which the child hangs from.
  const Eigen::Vector3d x2 = b.offset ? offsetAnchor(b, x, Rp, fr.cos_phi[0], fr.sin_phi[0]) : x;
  if (nc == 2) {
    const Eigen::Vector3d A1 = sigma * ((b.parent_is_main ? fr.R : Rp) * b.axis2);
    fr.S.col(1).head<3>() = A1;
    fr.S.col(1).tail<3>() = cross3(b.offset ? x2 : line, A1);
  }
  fr.c = b.rotation_only ? b.fixed_position : Eigen::Vector3d(x2 - fr.R * b.anchor_child);
}

void ArticulatedSystem::frames(double, const State& y, bool factor, Frames* f, double damping_weight) const {
  const int n = bodyCount();
  f->bodies.resize(n);
  f->factored = factor;
  for (int i = 0; i < n; ++i) poseInto(i, y, nullptr, f);
  if (!free_root_body_.empty()) {
    // Each free tree's centre of mass from its root (placed at the origin).
    f->root_offset.assign(model_.rotations, Eigen::Vector3d::Zero());
    for (int i = 0; i < n; ++i)
      if (free_tree_[i] >= 0) f->root_offset[free_tree_[i]] += model_.bodies[i].mass * f->bodies[i].c;
    for (int r : free_root_body_) f->root_offset[model_.bodies[r].rotation] /= free_tree_mass_[model_.bodies[r].rotation];
  }
  if (!factor) return;
  factorMassAndCouplings(f, damping_weight);
}

void ArticulatedSystem::factorMassAndCouplings(Frames* f, double damping_weight) const {
  const int n = bodyCount();
  // The ABA's pass 2 without bias forces, leaves to root: from the rigid
  // inertias about the origin, I_O = [J_w + m (|c|² I − c cᵀ), m [c]×;
  // −m [c]×, m I], the articulated inertias I_A, U = I_A S, D = Sᵀ U and
  // I_a = I_A − U D⁻¹ Uᵀ added to the parent's (Pᵀ I_a P past a held body).
  data_.articulated.resize(n);
  for (int i = 0; i < n; ++i) {
    const ArticulatedBody& b = model_.bodies[i];
    const Frame& fr = f->bodies[i];
    Matrix6& I = data_.articulated[i];
    const Eigen::Matrix3d cx = hat(fr.c);
    I.topLeftCorner<3, 3>().noalias() = fr.R * b.inertia * fr.R.transpose();
    I.topLeftCorner<3, 3>().noalias() -= b.mass * (fr.c * fr.c.transpose());
    I.topLeftCorner<3, 3>().diagonal().array() += b.mass * fr.c.squaredNorm();
    I.topRightCorner<3, 3>() = b.mass * cx;
    I.bottomLeftCorner<3, 3>() = -b.mass * cx;
    I.bottomRightCorner<3, 3>() = b.mass * Eigen::Matrix3d::Identity();
  }
  f->root_inverse.resize(model_.rotations);
  for (int i = n - 1; i >= 0; --i) {
    const ArticulatedBody& b = model_.bodies[i];
    Frame& fr = f->bodies[i];
    const Matrix6& I = data_.articulated[i];
    if (b.kind == JointKind::kFree) {
      // A free root (no parent): its whole articulated inertia, inverted.
      f->root_inverse[b.rotation] = I.llt().solve(Matrix6::Identity());
      continue;
    }
    Matrix6 Ia;
    // D = Sᵀ I_A S plus the dashpots' weight × c per coordinate (an armature:
    // M + w D_c, the end kick's matrix; articulated_system.hpp, frames()).
    const std::array<CoordinateDrive, 3>& drive = model_.drives[i];
    if (fr.free == 0) {
      // A weld: its inertia joins the parent's whole.
      if (b.parent == kGround) continue;
      Ia = I;
    } else if (fr.free == 3) {
      fr.U.noalias() = I * fr.S;
      Eigen::Matrix3d D = fr.S.transpose() * fr.U;
      for (int k = 0; k < 3; ++k) D(k, k) += damping_weight * drive[k].damping;
      fr.Dinv = D.inverse();
      if (b.parent == kGround) continue;
      Ia = I;
      Ia.noalias() -= fr.U * fr.Dinv * fr.U.transpose();
    } else if (fr.free == 1) {
      fr.U.col(0).noalias() = I * fr.S.col(0);
      fr.Dinv(0, 0) = 1.0 / (fr.S.col(0).dot(fr.U.col(0)) + damping_weight * drive[0].damping);
      if (b.parent == kGround) continue;
      Ia = I;
      Ia.noalias() -= (fr.Dinv(0, 0) * fr.U.col(0)) * fr.U.col(0).transpose();
    } else {
      fr.U.leftCols<2>().noalias() = I * fr.S.leftCols<2>();
      Eigen::Matrix2d D = fr.S.leftCols<2>().transpose() * fr.U.leftCols<2>();
      D(0, 0) += damping_weight * drive[0].damping;
      D(1, 1) += damping_weight * drive[1].damping;
      fr.Dinv.topLeftCorner<2, 2>() = D.inverse();
      if (b.parent == kGround) continue;
      Ia = I;
      Ia.noalias() -= fr.U.leftCols<2>() * fr.Dinv.topLeftCorner<2, 2>() * fr.U.leftCols<2>().transpose();
    }
    if (b.rotation_only) {
      const Matrix6 P = rotationOnlyMap(fr.c);
      data_.articulated[b.parent].noalias() += P.transpose() * Ia * P;
    } else {
      data_.articulated[b.parent] += Ia;
    }
  }
  if (loopRows()) {
    factorLoopRows(f);
    return;
  }
  if (coupling_G_.size() == 0) return;
  // Y = M⁻¹ Gᵀ column by column, and G Y factored.
  const int m = static_cast<int>(coupling_G_.rows());
  inverseMassColumns(*f, coupling_G_, &f->rows_Y);
  data_.coupling_GY.resize(m, m);
  data_.coupling_GY.noalias() = coupling_G_ * f->rows_Y;
  // G Y = G M⁻¹ Gᵀ is symmetric positive definite (the assembly refuses
  // redundant rows): Cholesky in place, then its inverse.
  Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> llt(data_.coupling_GY);
  f->rows_Ainv.setIdentity(m, m);
  llt.solveInPlace(f->rows_Ainv);
}

void ArticulatedSystem::inverseMassColumns(const Frames& f, const Eigen::MatrixXd& G, Eigen::MatrixXd* Y) const {
  const int m = static_cast<int>(G.rows());
  Y->resize(dofs(), m);
  data_.coupling_rhs.resize(dofs());
  for (int k = 0; k < m; ++k) {
    data_.coupling_rhs = G.row(k).transpose();
    solveStepMass(f, data_.coupling_rhs, false, &data_.coupling_x);
    Y->col(k) = data_.coupling_x;
  }
}

void ArticulatedSystem::loadFramePoses(const Frames& f) const {
  for (int i = 0; i < bodyCount(); ++i) {
    const Frame& fr = f.bodies[i];
    BodyData& d = data_.bodies[i];
    d.R = fr.R;
    d.c = fr.c;
    d.S = fr.S;
    d.free = fr.free;
    d.free_u = fr.free_u;
  }
}

void ArticulatedSystem::factorLoopRows(Frames* f) const {
  // G at f's poses (the closures read data_'s bodies), Y = M⁻¹ Gᵀ by m
  // solves with f's factorization, and the inverse of G Y on the rows with a
  // pivot (pivoted_cholesky.hpp: the rows a loop repeats get none), column
  // by column from the identity.
  const int m = model_.closure_rows;
  loadFramePoses(*f);
  closureTerms(ClosureLevel::kJacobian);
  f->rows_G = data_.closure_G;
  inverseMassColumns(*f, f->rows_G, &f->rows_Y);
  data_.closure_A.noalias() = f->rows_G * f->rows_Y;
  const int rank = pivotedCholesky(data_.closure_A, data_.closure_perm, kClosureRankTolerance);
  f->rows_Ainv.resize(m, m);
  for (int k = 0; k < m; ++k) {
    data_.closure_rhs.setZero();
    data_.closure_rhs[k] = 1.0;
    pivotedCholeskySolve(data_.closure_A, data_.closure_perm, rank, data_.closure_rhs, data_.closure_s,
                         &data_.closure_lambda);  // scratch: the dynamics' λ is recomputed where it is read
    f->rows_Ainv.col(k) = data_.closure_lambda;
  }
}

void ArticulatedSystem::solveMass(const Frames& f, const Eigen::VectorXd& rhs, Eigen::VectorXd* x) const {
  solveStepMass(f, rhs, false, x);
}


void ArticulatedSystem::solveStepMass(const Frames& f, const Eigen::VectorXd& rhs, bool state_rates,
                                      Eigen::VectorXd* x) const {
  // The ABA's passes 2 and 3 at zero rates and without forces but τ = rhs
  // (Featherstone 2008, Table 7.1): the bias forces p_A of each subtree
  // leaves to root, then the accelerations root to leaves.
  LIEFLOW_ASSERT(f.factored, "ArticulatedSystem::solveMass: frames without the factorization (frames(..., true, ...))");
  const int n = bodyCount();
  data_.accumulated.assign(n, Vector6::Zero());  // p_A
  data_.twist.resize(n);                         // the accelerations a
  x->resize(dofs());
  double* out = x->data();
  for (int i = n - 1; i >= 0; --i) {
    const Frame& fr = f.bodies[i];
    const ArticulatedBody& b = model_.bodies[i];
    if (b.kind == JointKind::kFree) continue;  // solved whole in pass 3
    const Vector6& pA = data_.accumulated[i];
    // u = τ − Sᵀ p_A, kept in x for pass 3; p_a = p_A + U D⁻¹ u to the parent
    // (formed in the sum: storing it first stalled store-to-load forwarding).
    Vector6 Ug;
    if (fr.free == 0) {
      Ug.setZero();  // a weld
    } else if (fr.free == 3) {
      Eigen::Vector3d u = rhs.segment<3>(fr.free_u[0]);
      u.noalias() -= fr.S.transpose() * pA;
      x->segment<3>(fr.free_u[0]) = u;
      Ug.noalias() = fr.U * (fr.Dinv * u);
    } else if (fr.free == 1) {
      const double u = rhs[fr.free_u[0]] - fr.S.col(0).dot(pA);
      out[fr.free_u[0]] = u;
      Ug = (fr.Dinv(0, 0) * u) * fr.U.col(0);
    } else {
      const Eigen::Vector2d u(rhs[fr.free_u[0]] - fr.S.col(0).dot(pA), rhs[fr.free_u[1]] - fr.S.col(1).dot(pA));
      out[fr.free_u[0]] = u[0];
      out[fr.free_u[1]] = u[1];
      Ug.noalias() = fr.U.leftCols<2>() * (fr.Dinv.topLeftCorner<2, 2>() * u);
    }
    if (b.parent == kGround) continue;
    Vector6& parent = data_.accumulated[b.parent];
    if (b.rotation_only) {
      const Vector6 pa = pA + Ug;
      parent.head<3>() += pa.head<3>() - cross3(fr.c, pa.tail<3>());  // Pᵀ p_a
    } else {
      parent += pA + Ug;
    }
  }
  for (int i = 0; i < n; ++i) {
    const Frame& fr = f.bodies[i];
    const ArticulatedBody& b = model_.bodies[i];
    Vector6& a = data_.twist[i];
    if (b.kind == JointKind::kFree) {
      // M_step is block-diagonal, (M_tree I, M_rel): v_z = τ_z / M_tree, and
      // the rest M⁻¹ (0, τ_rest)'s (M_rel⁻¹ is that block of M⁻¹), whose v_c
      // is the root's own with the tree's momentum zero. With S_r (x_v, x_ω)
      // = (R x_ω, x_v) (c = 0) from the ground: I_A a = S_r⁻ᵀ (0, τ_ω) − p_A.
      Vector6 force;
      force.head<3>().noalias() = fr.R * rhs.segment<3>(b.u_rotation);
      force.tail<3>().setZero();
      force -= data_.accumulated[i];
      a.noalias() = f.root_inverse[b.rotation] * force;
      x->segment<3>(b.u_rotation).noalias() = fr.R.transpose() * a.head<3>();
      const Eigen::Vector3d vz = rhs.segment<3>(b.u_begin) / free_tree_mass_[b.rotation];
      x->segment<3>(b.u_begin) = state_rates ? Eigen::Vector3d(vz + a.tail<3>()) : vz;
      continue;
    }
    if (b.parent == kGround) {
      a.setZero();
    } else if (b.rotation_only) {
      a.head<3>() = data_.twist[b.parent].head<3>();
      a.tail<3>() = cross3(fr.c, a.head<3>());
    } else {
      a = data_.twist[b.parent];
    }
    if (fr.free == 0) {
      // A weld: a = the parent's.
    } else if (fr.free == 3) {
      Eigen::Vector3d r = x->segment<3>(fr.free_u[0]);
      r.noalias() -= fr.U.transpose() * a;
      const Eigen::Vector3d qdd = fr.Dinv * r;
      a.noalias() += fr.S * qdd;
      x->segment<3>(fr.free_u[0]) = qdd;
    } else if (fr.free == 1) {
      const double qdd = fr.Dinv(0, 0) * (out[fr.free_u[0]] - fr.U.col(0).dot(a));
      a.noalias() += qdd * fr.S.col(0);
      out[fr.free_u[0]] = qdd;
    } else {
      const Eigen::Vector2d r(out[fr.free_u[0]] - fr.U.col(0).dot(a), out[fr.free_u[1]] - fr.U.col(1).dot(a));
      const Eigen::Vector2d qdd = fr.Dinv.topLeftCorner<2, 2>() * r;
      a.noalias() += fr.S.leftCols<2>() * qdd;
      out[fr.free_u[0]] = qdd[0];
      out[fr.free_u[1]] = qdd[1];
    }
  }
}

void ArticulatedSystem::momentumOut(int i, const Frame& fr, const Eigen::VectorXd& v) const {
  // V_b = (P) V_parent + S v; the body's momentum about the origin,
  // h = (R J Rᵀ ω + c × m v_c, m v_c), v_c = v_O + ω × c (zero for a held body).
  const ArticulatedBody& b = model_.bodies[i];
  Vector6& V = data_.twist[i];
  if (b.parent == kGround)
    data_.before[i].setZero();
  else
    data_.before[i] = b.rotation_only ? heldMotion(fr.c, data_.twist[b.parent]) : data_.twist[b.parent];
  V = data_.before[i];
  if (b.kind == JointKind::kFree) {
    // V = (R ω, v_c + c × R ω) with c = 0 and v_c = 0 for now: centreFreeTrees
    // then moves the tree to its centre-of-mass rest frame.
    V.head<3>().noalias() = fr.R * v.segment<3>(b.u_rotation);
    V.tail<3>().setZero();
  }
  for (int k = 0; k < fr.free; ++k) V += v[fr.free_u[k]] * fr.S.col(k);
  const Eigen::Vector3d w = V.head<3>();
  const Eigen::Vector3d mvc = b.mass * (V.tail<3>() + cross3(w, fr.c));
  data_.accumulated[i].head<3>() = fr.R * (b.inertia * (fr.R.transpose() * w)) + cross3(fr.c, mvc);
  data_.accumulated[i].tail<3>() = mvc;
}

void ArticulatedSystem::momentumBack(const Frames& f, const Eigen::VectorXd& v, Eigen::VectorXd* Mv,
                                     Eigen::VectorXd* dTdq) const {
  // The subtree momenta H; M v = Sᵀ H and ∂T/∂φ = (V⁻ ×ₘ S)ᵀ H per column,
  // V⁻ the twist before the column: a universal joint's column fixed in the
  // parent comes first (s₁ when the parent is the main body), and the other
  // column sees it turn.
  Mv->resize(dofs());
  if (dTdq) dTdq->resize(dofs());
  for (int i = bodyCount() - 1; i >= 0; --i) {
    const Frame& fr = f.bodies[i];
    const ArticulatedBody& b = model_.bodies[i];
    const Vector6& H = data_.accumulated[i];
    if (b.kind == JointKind::kFree) {
      // T = ½ M_tree |v_z|² + T_rel: the momentum M_tree v_z, and Rᵀ n of the
      // tree at rest in its centre's frame (c = 0, P = 0); T_rel does not
      // change with the tree's turn or place: ∂T/∂δ = 0, ∂T/∂z = 0.
      Mv->segment<3>(b.u_begin) = free_tree_mass_[b.rotation] * data_.tree_vz[b.rotation];
      Mv->segment<3>(b.u_rotation).noalias() = fr.R.transpose() * H.head<3>();
      if (dTdq) {
        dTdq->segment<3>(b.u_begin).setZero();
        dTdq->segment<3>(b.u_rotation).setZero();
      }
      continue;  // a root
    }
    for (int k = 0; k < fr.free; ++k) (*Mv)[fr.free_u[k]] = fr.S.col(k).dot(H);
    if (dTdq) {
      if (b.kind == JointKind::kSpherical) {
        // A spherical joint: all three columns turn the subtree from V_p.
        for (int k = 0; k < 3; ++k) (*dTdq)[fr.free_u[k]] = crossMotion(data_.before[i], fr.S.col(k)).dot(H);
      } else if (fr.free == 0) {
        // A weld: no coordinate.
      } else if (fr.free == 1) {
        (*dTdq)[fr.free_u[0]] = crossMotion(data_.before[i], fr.S.col(0)).dot(H);
      } else if (fr.free == 2) {
        const int first = b.parent_is_main ? 0 : 1, second = 1 - first;
        const Vector6 V_mid = data_.before[i] + v[fr.free_u[first]] * fr.S.col(first);
        (*dTdq)[fr.free_u[first]] = crossMotion(data_.before[i], fr.S.col(first)).dot(H);
        (*dTdq)[fr.free_u[second]] = crossMotion(V_mid, fr.S.col(second)).dot(H);
      } else {
        // A gimbal's hinges in sequence, each turned by the ones before it.
        Vector6 V_before = data_.before[i];
        for (int k = 0; k < 3; ++k) {
          (*dTdq)[fr.free_u[k]] = crossMotion(V_before, fr.S.col(k)).dot(H);
          V_before += v[fr.free_u[k]] * fr.S.col(k);
        }
      }
    }
    if (b.parent != kGround) data_.accumulated[b.parent] += b.rotation_only ? heldForce(fr.c, H) : H;
  }
}

void ArticulatedSystem::kineticPasses(const Frames& f, const Eigen::VectorXd& v, bool state_rates,
                                      Eigen::VectorXd* Mv, Eigen::VectorXd* dTdq) const {
  const int n = bodyCount();
  data_.twist.resize(n);
  data_.before.resize(n);
  data_.accumulated.resize(n);
  for (int i = 0; i < n; ++i) momentumOut(i, f.bodies[i], v);
  centreFreeTrees(f, v, state_rates);
  momentumBack(f, v, Mv, dTdq);
}

void ArticulatedSystem::kinetic(const Frames& f, const Eigen::VectorXd& v, Eigen::VectorXd* Mv,
                                Eigen::VectorXd* dTdq) const {
  kineticPasses(f, v, false, Mv, dTdq);
}

void ArticulatedSystem::momenta(const Frames& f, const Eigen::VectorXd& u, Eigen::VectorXd* p) const {
  kineticPasses(f, u, true, p, nullptr);
}

void ArticulatedSystem::kineticAt(double, const State& y, const Eigen::VectorXd& v, const Frames& near, Frames* f,
                                  Eigen::VectorXd* Mv, Eigen::VectorXd* dTdq) const {
  const int n = bodyCount();
  f->bodies.resize(n);
  f->factored = false;
  data_.twist.resize(n);
  data_.before.resize(n);
  data_.accumulated.resize(n);
  for (int i = 0; i < n; ++i) {
    poseInto(i, y, &near, f);
    momentumOut(i, f->bodies[i], v);
  }
  centreFreeTrees(*f, v, false);
  momentumBack(*f, v, Mv, dTdq);
}

void ArticulatedSystem::generalizedForces(double t, const Frames& f, const Eigen::VectorXd& u,
                                          Eigen::VectorXd* Q) const {
  const int n = bodyCount();
  data_.accumulated.resize(n);
  data_.twist.resize(n);
  Q->resize(dofs());
  // The bodies' external wrenches about the origin: gravity (c × m g, m g) on
  // each body that translates, the program's torques (R τ, 0).
  for (int i = 0; i < n; ++i) {
    const Frame& fr = f.bodies[i];
    const ArticulatedBody& b = model_.bodies[i];
    Vector6& F = data_.accumulated[i];
    if (b.rotation_only || free_tree_[i] >= 0) {
      F.setZero();  // gravity on a free tree moves its centre only (Q_z below)
    } else {
      const Eigen::Vector3d mg = b.mass * model_.gravity;
      F.head<3>() = cross3(fr.c, mg);
      F.tail<3>() = mg;
    }
    if (!has_user_torques_) continue;
    Vector6& V = data_.twist[i];
    if (b.parent == kGround)
      V.setZero();
    else
      V = b.rotation_only ? heldMotion(fr.c, data_.twist[b.parent]) : data_.twist[b.parent];
    for (int k = 0; k < fr.free; ++k) V += u[fr.free_u[k]] * fr.S.col(k);
    if (!user_torques_[i]) continue;
    const Eigen::Vector3d w = V.head<3>();
    const Eigen::Vector3d vc = V.tail<3>() + cross3(w, fr.c);
    F.head<3>() += fr.R * user_torques_[i](t, Eigen::Quaterniond(fr.R), fr.c, fr.R.transpose() * w, vc);
  }
  for (int i = n - 1; i >= 0; --i) {
    const Frame& fr = f.bodies[i];
    const ArticulatedBody& b = model_.bodies[i];
    if (b.kind == JointKind::kFree) {
      // Q_z = M_tree g; the rest of the tree's wrench about its root
      // (c = 0): S_rᵀ F = (·, Rᵀ n). Uniform gravity has none in T_rel's
      // coordinates: Q_grav = M_step (g, 0) = (M_tree g, 0).
      const Vector6& F = data_.accumulated[i];
      Q->segment<3>(b.u_begin) = free_tree_mass_[b.rotation] * model_.gravity;
      Q->segment<3>(b.u_rotation).noalias() = fr.R.transpose() * F.head<3>();
      continue;
    }
    for (int k = 0; k < fr.free; ++k) {
      const int j = fr.free_u[k];
      double q = fr.S.col(k).dot(data_.accumulated[i]);
      if (b.has_force[k]) q += model_.drives[i][k].momentAt(t, fr.phi[k], u[j]);
      (*Q)[j] = q;
    }
    if (b.parent != kGround)
      data_.accumulated[b.parent] += b.rotation_only ? heldForce(fr.c, data_.accumulated[i]) : data_.accumulated[i];
  }
}

}  // namespace articulated
}  // namespace lieflow
