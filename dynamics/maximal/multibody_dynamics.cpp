// MultibodySystem: applied forces, the constraint rows into the Schur solver,
// its factorization (and reuse) and the constrained accelerations.
#include "dynamics/maximal/multibody_system.hpp"
#include "liegroup/number_text.hpp"

#include <cmath>
#include <limits>
#include <sstream>

namespace lieflow {
namespace multibody {

using constraints::BodyPose;
using constraints::BodyVelocity;
using Row6 = Eigen::Matrix<double, 1, 6>;

// --- Dynamics ------------------------------------------------------------------

void MultibodySystem::forces(double t, const State& y, bool gyroscopic, Eigen::VectorXd* F) const {
  F->setZero(n_);
  for (int i = 0; i < bodyCount(); ++i) {
    const RigidBody& body = model_.bodies[i];
    const int o = off_[i];
    const Eigen::Vector3d& w = y.bodies.velocities[i].omega;
    const int r = rot_[i] ? 0 : 3;
    if (!rot_[i]) F->segment<3>(o) = body.mass * model_.gravity;
    if (gyroscopic) F->segment<3>(o + r) = -w.cross(body.inertia * w);
    if (!user_torques_.empty() && user_torques_[i])
      F->segment<3>(o + r) += user_torques_[i](t, y.bodies.poses[i], y.bodies.velocities[i]);
  }
  for (std::size_t k = 0; k < model_.joints.size(); ++k) {
    const int nc = coordinateCount(static_cast<int>(k));
    bool any = false;
    for (int i = 0; i < nc; ++i) any = any || drives_[k][i].hasForce();
    if (!any) continue;
    const Joint& j = model_.joints[k];
    std::array<double, kMaxJointCoordinates> phi;
    CoordinateRows Ja, Jb;
    coordinates(y, static_cast<int>(k), &phi, &Ja, &Jb);
    for (int i = 0; i < nc; ++i) {
      const CoordinateDrive& d = drives_[k][i];
      if (!d.hasForce()) continue;
      const double phidot = coordinateRate(y, j.main, j.secondary, Ja[i], Jb[i]);
      // Generalized force J_φᵀ M (the moment, or a prismatic joint's force).
      const double M = d.momentAt(t, phi[i], phidot);
      addCoordinateForce(j.main, Ja[i], M, F);
      addCoordinateForce(j.secondary, Jb[i], M, F);
    }
  }
}

void MultibodySystem::fillGroups(double t, const State& y, SchurSolver& S, bool gears, Eigen::VectorXd* phi,
                                 Eigen::VectorXd* b, Eigen::VectorXd* c, bool jacobians) const {
  // New blocks no longer match the factorization held by the solvers.
  if (jacobians) data_.factor_cache.valid = false;
  const int nj = static_cast<int>(model_.joints.size());
  int g = 0;
  for (int k = 0; k < nj; ++k, ++g) {
    const Joint& j = model_.joints[k];
    BodyPose<double> pa, pb;
    BodyVelocity<double> va, vb;
    poses(y, j.main, j.secondary, &pa, &pb, &va, &vb);
    const int r0 = S.rowBegin(g), rows = S.groupRows(g);
    if (rows == 0) continue;
    if (const auto* rev = std::get_if<constraints::RevoluteJoint<double>>(&j.constraint)) {
      // The fused evaluation (one pair of rotation matrices).
      constraints::RevoluteJoint<double>::Residual res, conv;
      constraints::RevoluteJoint<double>::Blocks J;
      rev->evaluate(pa, pb, &va, &vb, phi ? &res : nullptr, jacobians ? &J : nullptr, c ? &conv : nullptr);
      if (jacobians) {
        S.block(g, 0) = J[0].bottomRows(rows);
        S.block(g, 1) = J[1].bottomRows(rows);
      }
      if (phi) phi->segment(r0, rows) = res.tail(rows);
      if (b) b->segment(r0, rows).setZero();
      if (c) c->segment(r0, rows) = conv.tail(rows);
      continue;
    }
    std::visit(
        [&](const auto& con) {
          if (jacobians) {
            const auto J = con.jacobians(pa, pb);
            S.block(g, 0) = J[0].bottomRows(rows);
            S.block(g, 1) = J[1].bottomRows(rows);
          }
          if (phi) phi->segment(r0, rows) = con.residual(pa, pb).tail(rows);
          if (b) b->segment(r0, rows).setZero();
          if (c) c->segment(r0, rows) = con.convective(pa, pb, va, vb).tail(rows);
        },
        j.constraint);
  }
  for (const CoordinateRef& p : prescribed_) {
    const TimeFunction& f = *drives_[p.joint][p.coordinate].prescribed;
    if (jacobians || phi) {
      Row6 Ja, Jb;
      const double value = coordinate(y, p.joint, p.coordinate, &Ja, &Jb);
      if (jacobians) {
        S.block(g, 0) = Ja;
        S.block(g, 1) = Jb;
      }
      if (phi) (*phi)[S.rowBegin(g)] = value - f(t);
    }
    const int r0 = S.rowBegin(g);
    if (b) (*b)[r0] = f.derivative(t);
    if (c) (*c)[r0] = coordinateConvective(y, p.joint, p.coordinate) - f.secondDerivative(t);
    ++g;
  }
  if (!gears) return;
  for (std::size_t gi = 0; gi < gears_.size(); ++gi) {
    const Gear& gear = gears_[gi];
    const std::vector<int>& sel = gear_rows_[gi];
    std::visit(
        [&](const auto& con) {
          using C = std::decay_t<decltype(con)>;
          typename C::Poses X;
          typename C::Velocities V;
          gearNodes<C>(gear, y, false, &X, &V);
          const int rows = static_cast<int>(sel.size());
          if (jacobians) {
            const auto B = con.rows(X);
            for (std::size_t s = 0; s < C::kBodies; ++s) {
              GroupBlock& blk = S.block(g, static_cast<int>(s));
              blk.resize(rows, 6);
              for (int r = 0; r < rows; ++r) blk.row(r) = B[s].row(sel[r]);
            }
          }
          const int r0 = S.rowBegin(g);
          if (b) b->segment(r0, rows).setZero();
          if (c) {
            const auto cc = con.convective(X, V);
            for (int r = 0; r < rows; ++r) (*c)[r0 + r] = cc[sel[r]];
          }
        },
        gear.constraint);
    ++g;
  }
}

bool MultibodySystem::factorConstraints(double t, const State& y, RowSet set, std::string* why,
                                        Eigen::VectorXd* b, Eigen::VectorXd* c) const {
  SchurSolver& S = schur(set);
  const bool gears = &S == &data_.all && hasGears();
  if (b) b->resize(S.rows());
  if (c) c->resize(S.rows());
  if (data_.factor_cache.valid && data_.factor_cache.solver == &S && samePoses(y)) {
    // S already holds J(q) and its factorization at these positions (the
    // velocity projection of the last step, for the first stage of the
    // next): only the velocity-dependent targets are new.
    if (b || c) fillGroups(t, y, S, gears, nullptr, b, c, false);
    return true;
  }
  for (int i = 0; i < bodyCount(); ++i) {
    const RigidBody& body = model_.bodies[i];
    S.setInverseMass(i, body.rotation_only ? 0.0 : 1.0 / body.mass, body.inertia.inverse());
  }
  fillGroups(t, y, S, gears, nullptr, b, c);
  const FactorStatus st = S.factor();
  if (st.ok) {
    data_.factor_cache.valid = true;
    data_.factor_cache.solver = &S;
    data_.factor_cache.poses.resize(y.bodies.poses.size());
    std::copy(y.bodies.poses.begin(), y.bodies.poses.end(), data_.factor_cache.poses.begin());
    return true;
  }
  if (why) {
    const int g = S.groupOfRow(st.row);
    const int nj = static_cast<int>(model_.joints.size());
    const int np = static_cast<int>(prescribed_.size());
    std::ostringstream s;
    if (g < nj)
      s << model_.jointLabel(g) << ": " << constraintTypeName(model_.joints[g].constraint) << " row "
        << (st.row - S.rowBegin(g));
    else if (g < nj + np)
      s << model_.jointLabel(prescribed_[g - nj].joint) << ": prescribed motion of coordinate "
        << prescribed_[g - nj].coordinate + 1;
    else
      s << gears_[g - nj - np].name << ": gear row " << (st.row - S.rowBegin(g));
    s << " is redundant or conflicting with other constraints (singular J M⁻¹ Jᵀ: pivot " << formatNumber(st.pivot)
      << " vs diagonal " << formatNumber(st.diagonal) << ")";
    *why = s.str();
  }
  return false;
}

bool MultibodySystem::accelerations(double t, const State& y, Eigen::VectorXd* udot, Eigen::VectorXd* lambda,
                                    std::string* why) const {
  forces(t, y, true, &data_.F);
  if (!hasConstraints()) {
    // M⁻¹ F per body.
    udot->resize(n_);
    for (int i = 0; i < bodyCount(); ++i) {
      const RigidBody& body = model_.bodies[i];
      const int o = off_[i];
      if (rot_[i]) {
        udot->segment<3>(o) = body.inertia.ldlt().solve(data_.F.segment<3>(o));
      } else {
        udot->segment<3>(o) = data_.F.segment<3>(o) / body.mass;
        udot->segment<3>(o + 3) = body.inertia.ldlt().solve(data_.F.segment<3>(o + 3));
      }
    }
    if (lambda) lambda->resize(0);
    return true;
  }
  if (!factorConstraints(t, y, RowSet::kAll, why, nullptr, &data_.c)) return false;
  SchurSolver& S = data_.all;
  S.applyInverseMass(data_.F, data_.y);
  S.multiplyJ(data_.y, data_.rhs);
  data_.rhs += data_.c;
  S.solve(data_.rhs, data_.lam);
  data_.tmp = data_.F;
  S.addJTranspose(data_.lam, -1.0, data_.tmp);
  S.applyInverseMass(data_.tmp, *udot);
  if (lambda) *lambda = data_.lam;
  return true;
}

void MultibodySystem::velocity(double t, const State& y, Eigen::VectorXd* f) const {
  f->resize(2 * n_);
  for (int i = 0; i < bodyCount(); ++i) {
    const int o = off_[i];
    if (rot_[i]) {
      f->segment<3>(o) = y.bodies.velocities[i].omega;
    } else {
      f->segment<3>(o) = y.bodies.velocities[i].v;
      f->segment<3>(o + 3) = y.bodies.velocities[i].omega;
    }
  }
  if (!accelerations(t, y, &data_.udot, nullptr, nullptr)) {
    f->tail(n_).setConstant(std::numeric_limits<double>::quiet_NaN());
    return;
  }
  f->tail(n_) = data_.udot;
}

}  // namespace multibody
}  // namespace lieflow
