/// \file
/// The constrained acceleration solve of a multibody system in maximal
/// coordinates (index-1 form), linear in the number of bodies along chains:
///
///   M q̈ + Jᵀ λ = F(q, q̇),     J q̈ = −c,
///
/// with q̈ the stacked per-body accelerations (v̇ world, ω̇ body), M block
/// diagonal (m I₃ for v̇, J_i for ω̇), F = (m g + f, τ − ω × J ω) and J, c the
/// stacked constraint blocks and convective terms of joints/constraints/
/// (Φ̈ = J q̈ + c). Schur complement (Haug 1989, ch. 11; Baraff 1996,
/// "Linear-time dynamics using Lagrange multipliers"):
///
///   (J M⁻¹ Jᵀ) λ = J M⁻¹ F + c,      q̈ = M⁻¹ (F − Jᵀ λ).
///
/// J M⁻¹ Jᵀ is assembled sparse (two joints couple only if they share a body:
/// block-tridiagonal for a chain) and factored with Eigen::SimplicialLDLT and
/// its default AMD ordering, so the factor's fill and the cost grow linearly
/// along chains and trees. No dense factorization of the whole system.
///
/// Redundant constraints make J M⁻¹ Jᵀ singular: a pivot of the LDLᵀ factor
/// below kPivotTolerance × its diagonal entry (or negative) is reported as a
/// failure naming the joint of that row (status, or InvalidInput from
/// solveConstrainedAccelerationsOrThrow); no multipliers are returned then.
///
/// Reactions: the joint's generalized force on a body is −J_kᵀ λ_k (rows of
/// joint k, block of that body): a force (world) through the CoM and a moment
/// (body frame) about the CoM; they are also given as force and moment about
/// the joint's anchor point in the world frame, and, for a revolute joint, the
/// moment about the axis M_J = M_M · a (M_M the moment on the main body about
/// the hinge point, a = R_a a_a the world axis).
#pragma once

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "joints/multibody/multibody_model.hpp"

namespace lieflow {
namespace multibody {

/// A pivot d_k of the LDLᵀ factor with d_k ≤ kPivotTolerance · (J M⁻¹ Jᵀ)_kk
/// marks a row that depends on earlier-eliminated rows (redundant constraints).
constexpr double kPivotTolerance = 1e-10;

/// Reaction of joint k on one of its bodies.
struct BodyReaction {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();          ///< world, on the body
  Eigen::Vector3d moment_body = Eigen::Vector3d::Zero();    ///< body frame, about the CoM
  Eigen::Vector3d moment_anchor = Eigen::Vector3d::Zero();  ///< world, about the anchor point
};

struct JointReaction {
  BodyReaction main;       ///< zero when main is ground
  BodyReaction secondary;  ///< zero when secondary is ground
  /// On the ground side (world, about the anchor) when that side is ground.
  /// Revolute joints: M_J = M_M · a, the moment on the main body about the
  /// hinge axis (zero for an ideal hinge without applied/prescribed moments;
  /// computed from the secondary side, M_J = −M_S · a, when main is ground).
  std::optional<double> axial_moment;
};

struct AccelerationSolution {
  bool ok = false;
  std::string reason;        ///< why !ok (names the joint)
  int failed_joint = -1;     ///< joint of the first singular pivot, −1 if none
  std::vector<Eigen::Vector3d> vdot;      ///< per body, world (zero for rotation-only)
  std::vector<Eigen::Vector3d> omegadot;  ///< per body, body frame
  Eigen::VectorXd lambda;                 ///< multipliers, rows in joint order
  std::vector<JointReaction> reactions;   ///< per joint
  double constraint_residual = 0.0;       ///< ‖J q̈ + c‖∞
  Eigen::Index factor_nonzeros = 0;       ///< nnz of the strictly lower L factor
};

namespace detail {


struct JointEval {
  Eigen::MatrixXd Ja, Jb;  // rows × 6
  Eigen::VectorXd c;
};

inline JointEval evaluateJoint(const Joint& j, const MultibodyState& s) {
  const BodyPose<double> a =
      j.main == kGround ? constraints::groundPose<double>() : s.poses[j.main];
  const BodyPose<double> b =
      j.secondary == kGround ? constraints::groundPose<double>() : s.poses[j.secondary];
  const BodyVelocity<double> va =
      j.main == kGround ? constraints::groundVelocity<double>() : s.velocities[j.main];
  const BodyVelocity<double> vb =
      j.secondary == kGround ? constraints::groundVelocity<double>() : s.velocities[j.secondary];
  return std::visit(
      [&](const auto& con) {
        const auto J = con.jacobians(a, b);
        JointEval e;
        e.Ja = J[0];
        e.Jb = J[1];
        e.c = con.convective(a, b, va, vb);
        return e;
      },
      j.constraint);
}

}  // namespace detail

/// Solves the constrained accelerations at `state` under gravity and the
/// optional external loads (one per body, or empty). Never throws on a
/// singular system: returns ok = false with the reason. Throws InvalidInput
/// for malformed model/state (MultibodyModel::validate).
inline AccelerationSolution solveConstrainedAccelerations(const MultibodyModel& model,
                                                          const MultibodyState& state,
                                                          const std::vector<BodyLoad>& loads = {}) {
  model.validate(state);
  if (!loads.empty() && loads.size() != model.bodies.size())
    throw InvalidInput("loads", "one load per body expected");
  const int nb = static_cast<int>(model.bodies.size());
  const int nj = static_cast<int>(model.joints.size());

  // Coordinate offsets: body i owns q̈[off, off + dofs), (v̇, ω̇) or ω̇ only.
  std::vector<int> off(nb + 1, 0);
  for (int i = 0; i < nb; ++i) off[i + 1] = off[i] + model.bodies[i].dofs();
  const int n = off[nb];
  std::vector<int> row(nj + 1, 0);
  for (int k = 0; k < nj; ++k) row[k + 1] = row[k] + constraintRows(model.joints[k].constraint);
  const int m = row[nj];

  AccelerationSolution out;
  out.vdot.assign(nb, Eigen::Vector3d::Zero());
  out.omegadot.assign(nb, Eigen::Vector3d::Zero());
  out.reactions.assign(nj, JointReaction{});

  // F and M⁻¹ (block diagonal, stored per body).
  Eigen::VectorXd F(n);
  std::vector<Eigen::Matrix3d> Jinv(nb);
  for (int i = 0; i < nb; ++i) {
    const RigidBody& b = model.bodies[i];
    const Eigen::Vector3d& w = state.velocities[i].omega;
    Eigen::Vector3d tau = -w.cross(b.inertia * w);
    Eigen::Vector3d f = b.mass * model.gravity;
    if (!loads.empty()) {
      tau += loads[i].moment;
      f += loads[i].force;
    }
    if (b.rotation_only) {
      F.segment<3>(off[i]) = tau;
    } else {
      F.segment<3>(off[i]) = f;
      F.segment<3>(off[i] + 3) = tau;
    }
    Jinv[i] = b.inertia.inverse();  // 3×3 SPD
  }
  auto applyMinv = [&](const Eigen::VectorXd& x) {
    Eigen::VectorXd y(n);
    for (int i = 0; i < nb; ++i) {
      const RigidBody& b = model.bodies[i];
      if (b.rotation_only) {
        y.segment<3>(off[i]) = Jinv[i] * x.segment<3>(off[i]);
      } else {
        y.segment<3>(off[i]) = x.segment<3>(off[i]) / b.mass;
        y.segment<3>(off[i] + 3) = Jinv[i] * x.segment<3>(off[i] + 3);
      }
    }
    return y;
  };

  if (m == 0) {
    const Eigen::VectorXd qdd = applyMinv(F);
    for (int i = 0; i < nb; ++i) {
      if (model.bodies[i].rotation_only) {
        out.omegadot[i] = qdd.segment<3>(off[i]);
      } else {
        out.vdot[i] = qdd.segment<3>(off[i]);
        out.omegadot[i] = qdd.segment<3>(off[i] + 3);
      }
    }
    out.ok = true;
    return out;
  }

  // Sparse J (m × n), c, and the blocks of J M⁻¹ kept per joint.
  std::vector<Eigen::Triplet<double>> tj;
  tj.reserve(static_cast<std::size_t>(m) * 12);
  Eigen::VectorXd c(m);
  std::vector<detail::JointEval> ev(nj);
  auto addBlock = [&](int k, int body, const Eigen::MatrixXd& B) {
    if (body == kGround) return;
    const bool rot = model.bodies[body].rotation_only;
    const int c0 = rot ? 3 : 0;
    for (int r = 0; r < B.rows(); ++r)
      for (int col = c0; col < 6; ++col)
        if (B(r, col) != 0.0) tj.emplace_back(row[k] + r, off[body] + col - c0, B(r, col));
  };
  for (int k = 0; k < nj; ++k) {
    const Joint& j = model.joints[k];
    ev[k] = detail::evaluateJoint(j, state);
    c.segment(row[k], ev[k].c.size()) = ev[k].c;
    addBlock(k, j.main, ev[k].Ja);
    addBlock(k, j.secondary, ev[k].Jb);
  }
  Eigen::SparseMatrix<double> J(m, n);
  J.setFromTriplets(tj.begin(), tj.end());

  // Sparse M⁻¹ (block diagonal), then A = J M⁻¹ Jᵀ (sparse products: linear in
  // the number of bodies for bounded joints per body).
  std::vector<Eigen::Triplet<double>> tm;
  tm.reserve(static_cast<std::size_t>(nb) * 12);
  for (int i = 0; i < nb; ++i) {
    const RigidBody& b = model.bodies[i];
    int r0 = off[i];
    if (!b.rotation_only) {
      for (int d = 0; d < 3; ++d) tm.emplace_back(off[i] + d, off[i] + d, 1.0 / b.mass);
      r0 += 3;
    }
    for (int r = 0; r < 3; ++r)
      for (int s = 0; s < 3; ++s) tm.emplace_back(r0 + r, r0 + s, Jinv[i](r, s));
  }
  Eigen::SparseMatrix<double> Minv(n, n);
  Minv.setFromTriplets(tm.begin(), tm.end());
  const Eigen::SparseMatrix<double> JMinv = J * Minv;
  const Eigen::SparseMatrix<double> Jt = J.transpose();
  Eigen::SparseMatrix<double> A = JMinv * Jt;
  A.makeCompressed();

  auto jointOfRow = [&](int r) {
    return static_cast<int>(std::upper_bound(row.begin(), row.end(), r) - row.begin()) - 1;
  };
  auto fail = [&](int r, const std::string& why) {
    const int k = jointOfRow(r);
    out.ok = false;
    out.failed_joint = k;
    const Joint& jt = model.joints[k];
    std::ostringstream s;
    s << model.jointLabel(k) << ": " << constraintTypeName(jt.constraint) << " row " << (r - row[k])
      << " " << why;
    out.reason = s.str();
    out.lambda.resize(0);
    return out;
  };

  const Eigen::VectorXd diagA = A.diagonal();
  if (!diagA.allFinite()) return fail(0, "gives a non-finite J M⁻¹ Jᵀ");
  // Pivot check in the permuted order (row r goes to position perm[r]); the
  // first row with a pivot ≤ kPivotTolerance × its diagonal is reported.
  auto findSingularRow = [&](const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>& f,
                             double* pivot) {
    const Eigen::VectorXd D = f.vectorD();
    const auto& perm = f.permutationP().indices();
    std::vector<int> orig(m);
    for (int r = 0; r < m; ++r) orig[perm[r]] = r;
    for (int p = 0; p < m; ++p) {
      const int r = orig[p];
      if (!std::isfinite(D[p]) || !(D[p] > kPivotTolerance * diagA[r])) {
        *pivot = D[p];
        return r;
      }
    }
    return -1;
  };
  auto redundant = [&](int r, double pivot) {
    std::ostringstream why;
    why << "is redundant or conflicting with other constraints (singular J M⁻¹ Jᵀ: pivot " << pivot
        << " vs diagonal " << diagA[r] << ")";
    return fail(r, why.str());
  };

  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt;
  ldlt.compute(A);
  if (ldlt.info() != Eigen::Success) {
    // An exactly zero pivot stops Eigen's factorization: locate the row on
    // A + 1e-12 diag(A), whose redundant rows have pivots ≈ 1e-12 × diagonal.
    Eigen::SparseMatrix<double> Areg = A;
    for (int r = 0; r < m; ++r) Areg.coeffRef(r, r) += 1e-12 * std::max(diagA[r], 1e-300);
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> reg(Areg);
    double pivot = 0.0;
    const int r = reg.info() == Eigen::Success ? findSingularRow(reg, &pivot) : -1;
    if (r >= 0) return redundant(r, 0.0);
    out.ok = false;
    out.reason = "J M⁻¹ Jᵀ could not be factored (singular: redundant or conflicting constraints)";
    return out;
  }
  out.factor_nonzeros = ldlt.matrixL().nestedExpression().nonZeros();
  {
    double pivot = 0.0;
    const int r = findSingularRow(ldlt, &pivot);
    if (r >= 0) return redundant(r, pivot);
  }

  const Eigen::VectorXd rhs = JMinv * F + c;
  out.lambda = ldlt.solve(rhs);
  if (!out.lambda.allFinite()) return fail(0, "gave non-finite multipliers");
  const Eigen::VectorXd JtL = Jt * out.lambda;
  const Eigen::VectorXd qdd = applyMinv(F - JtL);

  for (int i = 0; i < nb; ++i) {
    if (model.bodies[i].rotation_only) {
      out.omegadot[i] = qdd.segment<3>(off[i]);
    } else {
      out.vdot[i] = qdd.segment<3>(off[i]);
      out.omegadot[i] = qdd.segment<3>(off[i] + 3);
    }
  }
  out.constraint_residual = (J * qdd + c).lpNorm<Eigen::Infinity>();

  // Reactions −J_kᵀ λ_k per body.
  for (int k = 0; k < nj; ++k) {
    const Joint& jt = model.joints[k];
    const Eigen::VectorXd lk = out.lambda.segment(row[k], row[k + 1] - row[k]);
    const BodyPose<double> pa =
        jt.main == kGround ? constraints::groundPose<double>() : state.poses[jt.main];
    const BodyPose<double> pb =
        jt.secondary == kGround ? constraints::groundPose<double>() : state.poses[jt.secondary];
    const auto& sph = std::visit(
        [](const auto& con) -> const constraints::SphericalJoint<double>& {
          if constexpr (std::is_same_v<std::decay_t<decltype(con)>, constraints::SphericalJoint<double>>)
            return con;
          else
            return con.point;
        },
        jt.constraint);
    const Eigen::Vector3d anchor_world = pa.toWorld(sph.anchor_main);
    auto react = [&](const Eigen::MatrixXd& B, const BodyPose<double>& P) {
      const Eigen::Matrix<double, 6, 1> g = -(B.transpose() * lk);
      BodyReaction r;
      r.force = g.head<3>();
      r.moment_body = g.tail<3>();
      // Moment about the anchor: τ_c (world) − (anchor − p) × f.
      r.moment_anchor = P.R * r.moment_body - (anchor_world - P.p).cross(r.force);
      return r;
    };
    JointReaction& R = out.reactions[k];
    R.main = react(ev[k].Ja, pa);
    R.secondary = react(ev[k].Jb, pb);
    if (const auto* rev = std::get_if<constraints::RevoluteJoint<double>>(&jt.constraint)) {
      const Eigen::Vector3d axis = pa.R * rev->axis_main;
      R.axial_moment = jt.main != kGround ? R.main.moment_anchor.dot(axis)
                                          : -R.secondary.moment_anchor.dot(axis);
    }
  }
  out.ok = true;
  return out;
}

/// As solveConstrainedAccelerations, but a singular system throws
/// InvalidInput whose field names the joint ("joints[k] (name)").
inline AccelerationSolution solveConstrainedAccelerationsOrThrow(
    const MultibodyModel& model, const MultibodyState& state, const std::vector<BodyLoad>& loads = {}) {
  AccelerationSolution s = solveConstrainedAccelerations(model, state, loads);
  if (!s.ok) {
    const std::string field =
        s.failed_joint >= 0 ? "joints[" + std::to_string(s.failed_joint) + "]" : "joints";
    throw InvalidInput(field, s.reason);
  }
  return s;
}

}  // namespace multibody
}  // namespace lieflow
