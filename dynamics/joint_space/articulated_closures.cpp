// ArticulatedSystem: loops closed with multipliers on top of the
// articulated-body algorithm (articulated_system.hpp states the equations).
//
// A closing joint's rows come from the maximal formulation's constraint
// library (dynamics/constraints/): Φ(pose_a, pose_b), its blocks J = [J_v J_ω]
// on a body's (v_c world, ω body) and its convective term c = Φ̈ − J q̈.
// Here the bodies' motions are the tree's spatial twists V = (ω, v_O)
// (world, reference point the origin), so a block becomes the row
//   W = [−J_v [c]× + J_ω Rᵀ,  J_v]   on (ω, v_O):
// v_c = v_O + ω × c and ω_body = Rᵀ ω give J (v_c, ω_b) = W V, and with
// a_c = a_O + α × c + ω × v_c, ω̇_b = Rᵀ α,
//   Φ̈ = Σ_bodies (W a + J_v (ω × v_c)) + c.
// The twist of a body is the sum of the columns S of the joints on its path
// to the ground, each passed through P (ω, v) = (ω, c × ω) of the deepest
// rotation-only body below it: W P = [W_ω + W_v [c]×, 0].
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <type_traits>

#include "dynamics/joint_space/articulated_system.hpp"
#include "dynamics/joint_space/pivoted_cholesky.hpp"

namespace lieflow {
namespace articulated {

namespace {

/// The force W_bᵀ λ of a closing joint's rows on one body, a spatial force
/// (n_O, f) about the origin, from the body's block J = [J_v J_ω] on (v_c, ω
/// body), its rotation R and centre of mass c: f = J_vᵀ λ, n_O = R J_ωᵀ λ + c × f.
template <typename Block, typename Lambda>
void closureWrench(const Block& J, const Lambda& lambda, const Eigen::Matrix3d& R, const Eigen::Vector3d& c,
                   Eigen::Vector3d* n, Eigen::Vector3d* f) {
  *f = J.template leftCols<3>().transpose() * lambda;
  *n = R * (J.template rightCols<3>().transpose() * lambda) + cross3(c, *f);
}

}  // namespace

constraints::BodyPose<double> ArticulatedSystem::closurePose(int i) const {
  return i == kGround ? constraints::groundPose<double>()
                      : constraints::BodyPose<double>{SO3d(Eigen::Quaterniond(data_.bodies[i].R)), data_.bodies[i].c};
}

constraints::BodyVelocity<double> ArticulatedSystem::closureVelocity(int i) const {
  return i == kGround ? constraints::groundVelocity<double>()
                      : constraints::BodyVelocity<double>{velocityOfCentre(i), angularVelocityBody(i)};
}

template <typename F>
void ArticulatedSystem::forEachClosure(ClosureLevel level, F&& f) const {
  const bool moving = level == ClosureLevel::kVelocity || level == ClosureLevel::kAcceleration;
  auto pose = [&](int i) { return closurePose(i); };
  auto velocity = [&](int i) { return moving ? closureVelocity(i) : constraints::groundVelocity<double>(); };
  for (const ArticulatedClosure& closure : model_.closures) {
    if (closure.gear) {
      // Gear rows: velocity level only (B u = 0; gear.hpp), no position rows.
      std::visit(
          [&](const auto& gear) {
            using C = std::decay_t<decltype(gear)>;
            typename C::Poses X;
            typename C::Velocities V;
            std::array<int, C::kBodies> bodies;
            for (std::size_t k = 0; k < C::kBodies; ++k) {
              bodies[k] = closure.bodies[k];
              X[k] = pose(bodies[k]);
              V[k] = velocity(bodies[k]);
            }
            Eigen::Matrix<double, C::kRows, 1> value = Eigen::Matrix<double, C::kRows, 1>::Zero();
            if (level == ClosureLevel::kAcceleration) value = gear.convective(X, V);
            f(closure, bodies, gear.rows(X), value);
          },
          *closure.gear);
      continue;
    }
    std::visit(
        [&](const auto& joint) {
          using C = std::decay_t<decltype(joint)>;
          const std::array<int, 2> bodies{{closure.bodies[0], closure.bodies[1]}};
          const constraints::BodyPose<double> a = pose(bodies[0]), b = pose(bodies[1]);
          Eigen::Matrix<double, C::kRows, 1> value = Eigen::Matrix<double, C::kRows, 1>::Zero();
          if (level == ClosureLevel::kPosition) value = joint.residual(a, b);
          if (level == ClosureLevel::kAcceleration)
            value = joint.convective(a, b, velocity(bodies[0]), velocity(bodies[1]));
          f(closure, bodies, joint.jacobians(a, b), value);
        },
        closure.constraint);
  }
}

void ArticulatedSystem::closureTerms(ClosureLevel level) const {
  data_.closure_G.setZero();
  forEachClosure(level, [&](const ArticulatedClosure& closure, const auto& bodies, const auto& J, const auto& value) {
    constexpr int R = std::decay_t<decltype(value)>::RowsAtCompileTime;
    const int r0 = closure.row_begin;
    data_.closure_r.segment<R>(r0) = value;  // Φ, 0 (velocities: summed below) or the convective term
    for (std::size_t side = 0; side < bodies.size(); ++side) {
      const int i = bodies[side];
      if (i == kGround) continue;
      const BodyData& d = data_.bodies[i];
      Eigen::Matrix<double, R, 6> W;
      W.template leftCols<3>() =
          J[side].template rightCols<3>() * d.R.transpose() - J[side].template leftCols<3>() * hat(d.c);
      W.template rightCols<3>() = J[side].template leftCols<3>();
      if (level == ClosureLevel::kVelocity) data_.closure_r.segment<R>(r0) += W * d.V;
      if (level == ClosureLevel::kAcceleration)
        data_.closure_r.segment<R>(r0) +=
            W * d.a + J[side].template leftCols<3>() * cross3(d.V.template head<3>(), velocityOfCentre(i));
      // The columns on the path to the ground.
      for (int k = i; k != kGround; k = model_.bodies[k].parent) {
        const BodyData& dk = data_.bodies[k];
        for (int f = 0; f < dk.free; ++f) data_.closure_G.block<R, 1>(r0, dk.free_u[f]).noalias() += W * dk.S.col(f);
        const ArticulatedBody& bk = model_.bodies[k];
        if (bk.kind == JointKind::kFree) {
          // A floating root's six columns (freeColumns: ω body, then v_c).
          const Matrix6 S = freeColumns(dk.R, dk.c);
          data_.closure_G.block<R, 3>(r0, bk.u_rotation).noalias() += W * S.leftCols<3>();
          data_.closure_G.block<R, 3>(r0, bk.u_begin).noalias() += W * S.rightCols<3>();
        }
        if (model_.bodies[k].rotation_only) {
          // Past a held body: W P (the columns above move it through P).
          W.template leftCols<3>() += W.template rightCols<3>() * hat(dk.c);
          W.template rightCols<3>().setZero();
        }
      }
    }
  });
}

void ArticulatedSystem::closureInverseMass() const {
  if (model_.closure_rows == 1)
    closureInverseMassWith(data_.closure_column);
  else
    closureInverseMassWith(data_.closure_columns);
}

template <int C>
void ArticulatedSystem::closureInverseMassWith(ArticulatedData::ClosureColumns<C>& w) const {
  // Y = M⁻¹ Gᵀ: the ABA's passes 2 and 3 at zero rates (Featherstone 2008,
  // Table 7.1) with the generalized forces τ = Gᵀ, all m columns in one sweep
  // (6 × m per body), with the factorization (U = I_A S, D⁻¹) of the last
  // solve(): leaves to root the subtrees' forces p_A, root to leaves the
  // accelerations. Prescribed entries stay 0.
  const int n = bodyCount();
  const int m = model_.closure_rows;
  Eigen::MatrixXd& Y = data_.closure_Y;
  const Eigen::MatrixXd& G = data_.closure_G;
  // Row k of Y and column k of G, C wide (fixed for one row).
  const auto y = [&](int k) { return Y.template block<1, C>(k, 0, 1, m); };
  const auto gt = [&](int k) { return G.template block<C, 1>(0, k, m, 1).transpose(); };
  Y.setZero();
  for (int i = 0; i < n; ++i) w.pA[i].setZero();
  for (int i = n - 1; i >= 0; --i) {
    const BodyData& d = data_.bodies[i];
    const ArticulatedBody& b = model_.bodies[i];
    Eigen::Matrix<double, 6, C>& P = w.pA[i];
    // u = τ − Sᵀ p_A (kept in Y for pass 3), p_a = p_A + U D⁻¹ u.
    // (Each product assigned on its own: inside a sum Eigen would evaluate it
    // into a heap temporary.)
    for (int f = 0; f < d.free; ++f) {
      y(d.free_u[f]) = gt(d.free_u[f]);
      y(d.free_u[f]).noalias() -= d.S.col(f).transpose() * P;
    }
    if (d.free == 1) {
      P.noalias() += (d.Dinv(0, 0) * d.U.col(0)) * y(d.free_u[0]);
    } else {
      for (int f = 0; f < d.free; ++f)
        for (int g = 0; g < d.free; ++g) P.noalias() += (d.Dinv(f, g) * d.U.col(f)) * y(d.free_u[g]);
    }
    if (b.parent == kGround) continue;
    Eigen::Matrix<double, 6, C>& parent = w.pA[b.parent];
    if (b.rotation_only) {
      // Pᵀ p_a = (n − c × f, 0), column by column.
      for (int k = 0; k < P.cols(); ++k)
        parent.col(k).template head<3>() += P.col(k).template head<3>() - cross3(d.c, P.col(k).template tail<3>());
    } else {
      parent += P;
    }
  }
  for (int i = 0; i < n; ++i) {
    const BodyData& d = data_.bodies[i];
    const ArticulatedBody& b = model_.bodies[i];
    Eigen::Matrix<double, 6, C>& a = w.pA[i];  // p_A is spent: the accelerations
    if (b.kind == JointKind::kFree) {
      // A floating root: I_A a = S⁻ᵀ τ − p_A with τ = Gᵀ's rows of its u
      // (S⁻ᵀ τ = (R τ_ω + c × τ_v, τ_v)), then its u̇ = S⁻¹ a
      // (ω̇ = Rᵀ α, v̇_c = a_O + α × c).
      Eigen::Matrix<double, 6, C>& f = w.root_force;  // sized at construction
      f.template topRows<3>().noalias() = d.R * G.template block<C, 3>(0, b.u_rotation, m, 3).transpose();
      f.template bottomRows<3>() = G.template block<C, 3>(0, b.u_begin, m, 3).transpose();
      for (int k = 0; k < m; ++k) f.col(k).template head<3>() += cross3(d.c, f.col(k).template tail<3>());
      f -= a;
      const Eigen::LDLT<Matrix6> IA(d.IA);
      a = IA.solve(f);
      Y.template block<3, C>(b.u_rotation, 0, 3, m).noalias() = d.R.transpose() * a.template topRows<3>();
      for (int k = 0; k < m; ++k)
        Y.template block<3, 1>(b.u_begin, k) = a.col(k).template tail<3>() + cross3(a.col(k).template head<3>(), d.c);
      continue;
    }
    if (b.parent == kGround) {
      a.setZero();
    } else if (b.rotation_only) {
      const Eigen::Matrix<double, 6, C>& ap = w.pA[b.parent];
      for (int k = 0; k < a.cols(); ++k) {
        a.col(k).template head<3>() = ap.col(k).template head<3>();
        a.col(k).template tail<3>() = cross3(d.c, ap.col(k).template head<3>());
      }
    } else {
      a = w.pA[b.parent];
    }
    if (d.free == 1) {
      // q̈ = D⁻¹ (u − Uᵀ a), a += S q̈.
      w.rows3.row(0).noalias() = d.U.col(0).transpose() * a;
      y(d.free_u[0]) = d.Dinv(0, 0) * (y(d.free_u[0]) - w.rows3.row(0));
      a.noalias() += d.S.col(0) * y(d.free_u[0]);
    } else if (d.free > 1) {
      const int nf = d.free;
      w.rows3.topRows(nf).noalias() = -d.U.leftCols(nf).transpose() * a;
      for (int f = 0; f < nf; ++f) w.rows3.row(f) += y(d.free_u[f]);
      for (int f = 0; f < nf; ++f) {
        y(d.free_u[f]).setZero();
        for (int g = 0; g < nf; ++g) y(d.free_u[f]) += d.Dinv(f, g) * w.rows3.row(g);
        a.noalias() += d.S.col(f) * y(d.free_u[f]);
      }
    }
  }
}

template void ArticulatedSystem::closureInverseMassWith(ArticulatedData::ClosureColumns<Eigen::Dynamic>&) const;
template void ArticulatedSystem::closureInverseMassWith(ArticulatedData::ClosureColumns<1>&) const;

int ArticulatedSystem::factorClosureRows() const {
  closureInverseMass();
  data_.closure_A.noalias() = data_.closure_G * data_.closure_Y;
  return pivotedCholesky(data_.closure_A, data_.closure_perm, kClosureRankTolerance);
}

void ArticulatedSystem::closureMultipliers() const {
  // G Y λ = −r on the rows with a pivot (pivoted_cholesky.hpp), λ = 0 on the
  // rows a loop repeats.
  const int rank = factorClosureRows();
  data_.closure_rhs = -data_.closure_r;
  pivotedCholeskySolve(data_.closure_A, data_.closure_perm, rank, data_.closure_rhs, data_.closure_s,
                       &data_.closure_lambda);
}

void ArticulatedSystem::applyClosureForces() const {
  forEachClosure(ClosureLevel::kJacobian,
                 [&](const ArticulatedClosure& closure, const auto& bodies, const auto& J, const auto& value) {
                   constexpr int R = std::decay_t<decltype(value)>::RowsAtCompileTime;
                   const Eigen::Matrix<double, R, 1> lambda = data_.closure_lambda.segment<R>(closure.row_begin);
                   for (std::size_t side = 0; side < bodies.size(); ++side) {
                     const int i = bodies[side];
                     if (i == kGround) continue;
                     BodyData& d = data_.bodies[i];
                     Eigen::Vector3d n, f;
                     closureWrench(J[side], lambda, d.R, d.c, &n, &f);
                     d.pA.head<3>() -= n;
                     d.pA.tail<3>() -= f;
                   }
                 });
}

void ArticulatedSystem::closureAccelerations(Eigen::VectorXd* udot) const {
  if (coupling_G_.size() != 0) {
    // Coupling rows only: G is constant in joint coordinates, Φ̈ = G u̇ (no
    // convective term), read off the ABA's u̇₀ without the bodies' poses
    // (closureTerms took 18 % of an rkmk4 step on Talos with its twelve
    // gripper couplings).
    data_.closure_G = coupling_G_;
    data_.closure_r.noalias() = coupling_G_ * *udot;
  } else {
    closureTerms(ClosureLevel::kAcceleration);
  }
  closureMultipliers();
  // u̇ = u̇₀ + Y λ, and the bodies' accelerations by the same increment
  // (pass 3 of the correction alone).
  data_.closure_x.noalias() = data_.closure_Y * data_.closure_lambda;
  *udot += data_.closure_x;
  data_.twist.resize(bodyCount());  // the bodies' acceleration increments
  for (int i = 0; i < bodyCount(); ++i) {
    const BodyData& d = data_.bodies[i];
    const ArticulatedBody& b = model_.bodies[i];
    Vector6& da = data_.twist[i];
    da = b.parent == kGround ? Vector6::Zero()
         : b.rotation_only   ? heldMotion(d.c, data_.twist[b.parent])
                             : data_.twist[b.parent];
    for (int f = 0; f < d.free; ++f) da += data_.closure_x[d.free_u[f]] * d.S.col(f);
    if (b.kind == JointKind::kFree) {
      Vector6 x;
      x << data_.closure_x.segment<3>(b.u_rotation), data_.closure_x.segment<3>(b.u_begin);
      da += freeColumns(d.R, d.c) * x;
    }
    data_.bodies[i].a += da;
  }
}

double ArticulatedSystem::constraintError(double t, const State& y) const {
  if (!hasClosures()) return 0.0;
  forwardPass(t, y, false, false);
  closureTerms(ClosureLevel::kPosition);
  return data_.closure_r.cwiseAbs().maxCoeff();
}

bool ArticulatedSystem::projectPositions(double t, State* y, double tolerance, int max_iterations, int* iterations,
                                         std::string* why) const {
  *iterations = 0;
  if (!hasClosures()) return true;
  if (coupling_G_.size() != 0) {
    // Linear in joint coordinates: no poses needed to check it.
    const int nq = y->scalarCount();
    data_.closure_r = coupling_phi0_;
    data_.closure_r.noalias() += coupling_G_.leftCols(nq) * y->q;
    if (data_.closure_r.cwiseAbs().maxCoeff() <= tolerance) return true;
  }
  double last = std::numeric_limits<double>::infinity();
  for (int it = 0;; ++it) {
    forwardPass(t, *y, false, false);  // poses only: most steps end here
    closureTerms(ClosureLevel::kPosition);
    const double error = data_.closure_r.cwiseAbs().maxCoeff();
    *iterations = it;
    if (error <= tolerance) return true;
    if (it == max_iterations || !(error < last)) {
      std::ostringstream s;
      s << "the loops' rows stay at max |Phi| = " << error << " after " << it << " Gauss-Newton steps"
        << (it == max_iterations ? " (max_iterations)" : " (a step did not reduce it: the loop cannot close there)");
      *why = s.str();
      return false;
    }
    last = error;
    forwardPass(t, *y, true, false);
    solve(Vector6::Zero(), &data_.udot);  // the factorization of M(q)
    closureMultipliers();  // G Y λ = −Φ: the step δ = Y λ has G δ = −Φ
    data_.closure_x.noalias() = data_.closure_Y * data_.closure_lambda;
    const int nq = y->scalarCount();
    y->q += data_.closure_x.head(nq);
    for (std::size_t s = 0; s < y->N.size(); ++s)
      y->N[s] = y->N[s] * SO3d::exp(data_.closure_x.segment<3>(nq + 3 * static_cast<int>(s)));
  }
}

bool ArticulatedSystem::projectVelocities(double t, State* y, std::string* why) const {
  (void)why;
  if (!hasClosures()) return true;
  if (coupling_G_.size() != 0) {
    data_.closure_r.noalias() = coupling_G_ * y->u;
    const double floor = kCouplingRateUlps * std::numeric_limits<double>::epsilon() * coupling_G_max_ *
                         y->u.cwiseAbs().maxCoeff();
    if (data_.closure_r.cwiseAbs().maxCoeff() <= floor) return true;
  }
  forwardPass(t, *y, true, true);
  solve(Vector6::Zero(), &data_.udot);
  closureTerms(ClosureLevel::kVelocity);
  closureMultipliers();
  y->u.noalias() += data_.closure_Y * data_.closure_lambda;
  return true;
}

void ArticulatedSystem::closureOutputs(double t, std::vector<ArticulatedJointOutput>* out) const {
  // After jointOutputs' dynamics: poses, velocities and λ in data_ and
  // data_.closure_lambda. The closing joint's force on its main body is W_aᵀ λ
  // (n_O, f) (minus W_bᵀ λ on the secondary when the main is the ground), its
  // moment about the anchor n_O − x × f, and about each axis its component
  // (JointOutput's definition).
  for (std::size_t c = 0; c < model_.closures.size(); ++c) {
    const ArticulatedClosure& closure = model_.closures[c];
    if (closure.gear) continue;  // gear rows have no columns
    const std::array<int, 2> bodies{{closure.bodies[0], closure.bodies[1]}};
    const std::array<constraints::BodyPose<double>, 2> pose{{closurePose(bodies[0]), closurePose(bodies[1])}};
    const std::array<constraints::BodyVelocity<double>, 2> vel{
        {closureVelocity(bodies[0]), closureVelocity(bodies[1])}};
    if (t <= 0.0) data_.closure_phi[c] = closure.initial_angles;
    ArticulatedJointOutput& o = (*out)[closure.scene_joint];
    std::array<Eigen::Vector3d, 2> axes;
    Eigen::Vector3d anchor = Eigen::Vector3d::Zero();
    if (const auto* rev = std::get_if<constraints::RevoluteJoint<double>>(&closure.constraint)) {
      o.coordinates = 1;
      o.phi[0] = constraints::revoluteAngle(*rev, pose[0], pose[1], data_.closure_phi[c][0]);
      o.phidot[0] = constraints::revoluteAngleRate(*rev, pose[0], pose[1], vel[0], vel[1]);
      axes[0] = constraints::revoluteAxisWorld(*rev, pose[0]);
      anchor = pose[0].toWorld(rev->point.anchor_main);
    } else if (const auto* uni = std::get_if<constraints::UniversalJoint<double>>(&closure.constraint)) {
      o.coordinates = 2;
      const auto angles =
          constraints::universalAngles(*uni, pose[0], pose[1], data_.closure_phi[c][0], data_.closure_phi[c][1]);
      const Eigen::Vector2d rates = constraints::universalAngleRates(*uni, pose[0], pose[1], vel[0], vel[1]);
      o.phi = {{angles.phi1, angles.phi2}};
      o.phidot = {{rates[0], rates[1]}};
      axes = {{pose[0].R * uni->axis1_main, pose[1].R * uni->axis2_secondary}};
      anchor = pose[0].toWorld(uni->point.anchor_main);
    } else {
      continue;  // spherical: no coordinate, no columns
    }
    data_.closure_phi[c] = {{o.phi[0], o.phi[1]}};
    const bool use_main = closure.bodies[0] != kGround;
    const int side = use_main ? 0 : 1;
    const BodyData& d = data_.bodies[bodies[side]];
    Eigen::Vector3d n = Eigen::Vector3d::Zero(), f = Eigen::Vector3d::Zero();
    std::visit(
        [&](const auto& joint) {
          constexpr int R = std::decay_t<decltype(joint)>::kRows;
          const auto J = joint.jacobians(pose[0], pose[1]);
          closureWrench(J[side], Eigen::Matrix<double, R, 1>(data_.closure_lambda.segment<R>(closure.row_begin)), d.R,
                        d.c, &n, &f);
        },
        closure.constraint);
    const double sign = use_main ? 1.0 : -1.0;
    const Eigen::Vector3d moment = sign * (n - cross3(anchor, f));
    for (int k = 0; k < o.coordinates; ++k) o.moment[k] = moment.dot(axes[k]);
  }
}

void ArticulatedSystem::closureRowsAt(double t, const State& y, Eigen::MatrixXd* G, Eigen::VectorXd* phi) const {
  forwardPass(t, y, false, false);
  closureTerms(ClosureLevel::kPosition);
  *G = data_.closure_G;
  *phi = data_.closure_r;
}

std::vector<int> ArticulatedSystem::independentClosureRows(double t, const State& y) const {
  std::vector<int> rows;
  if (!hasClosures()) return rows;
  forwardPass(t, y, true, false);
  solve(Vector6::Zero(), &data_.udot);  // the factorization of M(q)
  closureTerms(ClosureLevel::kJacobian);
  const int rank = factorClosureRows();
  rows.assign(data_.closure_perm.begin(), data_.closure_perm.begin() + rank);
  return rows;
}

double ArticulatedSystem::achievablePositionTolerance(const State& y, double tolerance) const {
  forwardPass(0.0, y, false, false);
  double extent = 1.0;
  for (int i = 0; i < bodyCount(); ++i) extent = std::max(extent, data_.bodies[i].c.lpNorm<Eigen::Infinity>());
  return std::max(tolerance, kPositionRoundoffUlps * std::numeric_limits<double>::epsilon() * extent);
}

}  // namespace articulated
}  // namespace lieflow
