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
#include <utility>
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

/// Per-joint Jacobian block storage without heap allocation (≤ 5 rows).
using JointBlock = Eigen::Matrix<double, Eigen::Dynamic, 6, 0, 5, 6>;
using JointRows = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 5, 1>;

struct JointEval {
  JointBlock Ja, Jb;  // rows × 6
  JointRows c;
};

inline void evaluateJoint(const Joint& j, const MultibodyState& s, JointEval* e) {
  const BodyPose<double> a =
      j.main == kGround ? constraints::groundPose<double>() : s.poses[j.main];
  const BodyPose<double> b =
      j.secondary == kGround ? constraints::groundPose<double>() : s.poses[j.secondary];
  const BodyVelocity<double> va =
      j.main == kGround ? constraints::groundVelocity<double>() : s.velocities[j.main];
  const BodyVelocity<double> vb =
      j.secondary == kGround ? constraints::groundVelocity<double>() : s.velocities[j.secondary];
  std::visit(
      [&](const auto& con) {
        const auto J = con.jacobians(a, b);
        e->Ja = J[0];
        e->Jb = J[1];
        e->c = con.convective(a, b, va, vb);
      },
      j.constraint);
}

}  // namespace detail

/// Reusable constrained-acceleration solver for a fixed model topology.
///
/// The sparsity pattern of J M⁻¹ Jᵀ depends only on which bodies each joint
/// connects (and on the joints' row counts and the bodies' rotation_only
/// flags): it is built structurally (full per-body blocks, explicit zeros
/// kept, so it does not depend on the state) and analysed (AMD ordering,
/// elimination tree) once; every solve() then only refills the values in
/// place and calls SimplicialLDLT::factorize. J M⁻¹ Jᵀ, J M⁻¹ F + c, Jᵀ λ and
/// the residual are assembled block-wise from per-joint 6-column blocks (no
/// sparse–sparse products, no triplet lists). Work buffers are kept between
/// calls; Eigen's factorize still allocates its permuted copy of the matrix.
///
/// The structure is rebuilt automatically when solve() is given a model with
/// a different topology (number of bodies/joints, joint bodies, row counts,
/// rotation_only flags). Masses, inertias, gravity, constraint parameters,
/// state and loads may change freely between calls.
///
/// Results are identical to solveConstrainedAccelerations (which runs a
/// temporary solver), including the reporting of redundant constraints.
class ConstrainedAccelerationSolver {
 public:
  ConstrainedAccelerationSolver() = default;
  /// Builds and analyses the pattern for `model` now (otherwise on first
  /// solve). Throws InvalidInput for a malformed model.
  explicit ConstrainedAccelerationSolver(const MultibodyModel& model) {
    model.validateModel();
    setup(model);
  }

  /// As solveConstrainedAccelerations, writing into `out` (its storage is
  /// reused). Returns out.ok.
  bool solve(const MultibodyModel& model, const MultibodyState& state,
             const std::vector<BodyLoad>& loads, AccelerationSolution& out) {
    validate(model, state);
    if (!loads.empty() && loads.size() != model.bodies.size())
      throw InvalidInput("loads", "one load per body expected");
    solveImpl(model, state, loads, out);
    return out.ok;
  }

  AccelerationSolution solve(const MultibodyModel& model, const MultibodyState& state,
                             const std::vector<BodyLoad>& loads = {}) {
    AccelerationSolution out;
    solve(model, state, loads, out);
    return out;
  }

  /// Number of times the pattern was built and analysed (analyzePattern calls).
  int analyzeCount() const { return analyze_count_; }
  /// Stored entries (both triangles, explicit zeros included) of J M⁻¹ Jᵀ.
  Eigen::Index patternNonzeros() const { return A_.nonZeros(); }

 private:
  using SpMat = Eigen::SparseMatrix<double>;  // column-major, int indices

  struct Topo {
    int main, secondary, rows;
    bool operator==(const Topo& o) const {
      return main == o.main && secondary == o.secondary && rows == o.rows;
    }
  };

  // Same checks as model.validate(state) (and sets up the pattern when the
  // topology changed), but a body is re-checked (3×3
  // eigenvalues) only when its mass or inertia changed since it was last
  // checked, and joints only when the topology changed (a matching topology
  // was checked when it was set up).
  void validate(const MultibodyModel& model, const MultibodyState& state) {
    if (!matches(model) || checked_mass_.size() != model.bodies.size()) {
      model.validate(state);
      if (!matches(model)) setup(model);
      checked_mass_.clear();
      checked_inertia_.clear();
      for (const RigidBody& b : model.bodies) {
        checked_mass_.push_back(b.mass);
        checked_inertia_.push_back(b.inertia);
      }
      return;
    }
    for (int i = 0; i < nb_; ++i) {
      const RigidBody& b = model.bodies[i];
      // Bitwise-equal data passed before (NaN never compares equal: re-checked).
      if (b.mass == checked_mass_[i] && b.inertia == checked_inertia_[i]) continue;
      model.validateBody(i);
      checked_mass_[i] = b.mass;
      checked_inertia_[i] = b.inertia;
    }
    model.validateState(state);
  }

  bool matches(const MultibodyModel& model) const {
    if (!analyzed_ || model.bodies.size() != rot_.size() || model.joints.size() != topo_.size())
      return false;
    for (std::size_t i = 0; i < rot_.size(); ++i)
      if (model.bodies[i].rotation_only != static_cast<bool>(rot_[i])) return false;
    for (std::size_t k = 0; k < topo_.size(); ++k) {
      const Joint& j = model.joints[k];
      if (!(topo_[k] == Topo{j.main, j.secondary, constraintRows(j.constraint)})) return false;
    }
    return true;
  }

  // Position in A_.valuePtr() of entry (row[k] + r, row[l] + c): colStart of
  // that column + offset of joint k's rows within joint l's column block + r.
  Eigen::Index slot(int k, int l, int r, int c) const {
    const auto& cl = coupled_[l];
    int offk = 0;
    for (const auto& kv : cl) {
      if (kv.first == k) {
        offk = kv.second;
        break;
      }
    }
    return A_.outerIndexPtr()[row_[l] + c] + offk + r;
  }

  void setup(const MultibodyModel& model) {
    checked_mass_.clear();  // the next solve validates the whole model
    checked_inertia_.clear();
    nb_ = static_cast<int>(model.bodies.size());
    nj_ = static_cast<int>(model.joints.size());
    rot_.assign(nb_, 0);
    topo_.resize(nj_);
    off_.assign(nb_ + 1, 0);
    for (int i = 0; i < nb_; ++i) {
      rot_[i] = model.bodies[i].rotation_only ? 1 : 0;
      off_[i + 1] = off_[i] + model.bodies[i].dofs();
    }
    n_ = off_[nb_];
    row_.assign(nj_ + 1, 0);
    for (int k = 0; k < nj_; ++k) {
      const Joint& j = model.joints[k];
      topo_[k] = Topo{j.main, j.secondary, constraintRows(j.constraint)};
      row_[k + 1] = row_[k] + topo_[k].rows;
    }
    m_ = row_[nj_];
    // Joints per body, and joints coupled to each joint (sharing a body).
    body_joints_.assign(nb_, {});
    for (int k = 0; k < nj_; ++k) {
      if (topo_[k].main != kGround) body_joints_[topo_[k].main].push_back(k);
      if (topo_[k].secondary != kGround) body_joints_[topo_[k].secondary].push_back(k);
    }
    coupled_.assign(nj_, {});
    for (int l = 0; l < nj_; ++l) {
      std::vector<int> ks{l};
      for (int b : {topo_[l].main, topo_[l].secondary})
        if (b != kGround) ks.insert(ks.end(), body_joints_[b].begin(), body_joints_[b].end());
      std::sort(ks.begin(), ks.end());
      ks.erase(std::unique(ks.begin(), ks.end()), ks.end());
      int o = 0;
      for (int k : ks) {
        coupled_[l].emplace_back(k, o);
        o += topo_[k].rows;
      }
    }
    // Compressed column pattern of A (m × m), dense joint-by-joint blocks.
    A_.resize(m_, m_);
    std::vector<int> colnnz(m_, 0);
    for (int l = 0; l < nj_; ++l) {
      int len = 0;
      for (const auto& kv : coupled_[l]) len += topo_[kv.first].rows;
      for (int c = row_[l]; c < row_[l + 1]; ++c) colnnz[c] = len;
    }
    if (m_ > 0) {  // (Eigen's reserve/makeCompressed misbehave on 0 × 0)
      A_.reserve(colnnz);
      for (int l = 0; l < nj_; ++l)
        for (int c = row_[l]; c < row_[l + 1]; ++c)
          for (const auto& kv : coupled_[l])
            for (int r = row_[kv.first]; r < row_[kv.first + 1]; ++r) A_.insert(r, c) = 0.0;
      A_.makeCompressed();
    }
    diag_slot_.resize(m_);
    for (int l = 0; l < nj_; ++l)
      for (int c = 0; c < topo_[l].rows; ++c) diag_slot_[row_[l] + c] = slot(l, l, c, c);
    // Work buffers.
    ev_.resize(nj_);
    F_.resize(n_);
    y_.resize(n_);
    qdd_.resize(n_);
    rhs_.resize(m_);
    c_.resize(m_);
    diagA_.resize(m_);
    Jinv_.resize(nb_);
    invm_.resize(nb_);
    G_.resize(nj_ > 0 ? 2 * nj_ : 0);
    analyzed_ = true;
    if (m_ > 0) {
      // AMD on the symmetric pattern, as SimplicialLDLT::analyzePattern does;
      // the permuted upper triangle Ap = (P A Pᵀ)ᵤ is kept with a value map,
      // so factorize (natural ordering, Upper) reads it in place instead of
      // building a permuted copy every step.
      Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> pinv;
      Eigen::AMDOrdering<int>()(A_, pinv);
      const Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> pm = pinv.inverse();
      perm_ = pm.indices();  // row r goes to position perm_[r]
      orig_.resize(m_);
      for (int r = 0; r < m_; ++r) orig_[perm_[r]] = r;
      std::vector<Eigen::Triplet<double, int>> t;
      for (int c = 0; c < m_; ++c)
        for (SpMat::InnerIterator it(A_, c); it; ++it) {
          const int pr = perm_[it.row()], pc = perm_[c];
          if (pr <= pc) t.emplace_back(pr, pc, 0.0);
        }
      Ap_.resize(m_, m_);
      Ap_.setFromTriplets(t.begin(), t.end());
      Ap_.makeCompressed();
      ap_slot_.assign(A_.nonZeros(), -1);
      for (int c = 0; c < m_; ++c)
        for (Eigen::Index q = A_.outerIndexPtr()[c]; q < A_.outerIndexPtr()[c + 1]; ++q) {
          const int pr = perm_[A_.innerIndexPtr()[q]], pc = perm_[c];
          if (pr > pc) continue;
          const int* b = Ap_.innerIndexPtr() + Ap_.outerIndexPtr()[pc];
          const int* e = Ap_.innerIndexPtr() + Ap_.outerIndexPtr()[pc + 1];
          ap_slot_[q] = std::lower_bound(b, e, pr) - Ap_.innerIndexPtr();
        }
      ap_diag_slot_.resize(m_);
      for (int r = 0; r < m_; ++r) ap_diag_slot_[r] = ap_slot_[diag_slot_[r]];
      rhsp_.resize(m_);
      lamp_.resize(m_);
      ldlt_.analyzePattern(Ap_);
      ++analyze_count_;
    }
  }

  // Columns of body b's dofs within a 6-column joint block.
  int colBegin(int body) const { return rot_[body] ? 3 : 0; }

  void solveImpl(const MultibodyModel& model, const MultibodyState& state,
                 const std::vector<BodyLoad>& loads, AccelerationSolution& out) {
    out.ok = false;
    out.reason.clear();
    out.failed_joint = -1;
    out.constraint_residual = 0.0;
    out.factor_nonzeros = 0;
    out.vdot.assign(nb_, Eigen::Vector3d::Zero());
    out.omegadot.assign(nb_, Eigen::Vector3d::Zero());
    out.reactions.assign(nj_, JointReaction{});

    // F and M⁻¹ (block diagonal, stored per body).
    for (int i = 0; i < nb_; ++i) {
      const RigidBody& b = model.bodies[i];
      const Eigen::Vector3d& w = state.velocities[i].omega;
      Eigen::Vector3d tau = -w.cross(b.inertia * w);
      Eigen::Vector3d f = b.mass * model.gravity;
      if (!loads.empty()) {
        tau += loads[i].moment;
        f += loads[i].force;
      }
      if (rot_[i]) {
        F_.segment<3>(off_[i]) = tau;
      } else {
        F_.segment<3>(off_[i]) = f;
        F_.segment<3>(off_[i] + 3) = tau;
      }
      Jinv_[i] = b.inertia.inverse();  // 3×3 SPD
      invm_[i] = 1.0 / b.mass;
    }
    auto applyMinv = [&](const Eigen::VectorXd& x, Eigen::VectorXd& y) {
      for (int i = 0; i < nb_; ++i) {
        if (rot_[i]) {
          y.segment<3>(off_[i]).noalias() = Jinv_[i] * x.segment<3>(off_[i]);
        } else {
          y.segment<3>(off_[i]) = x.segment<3>(off_[i]) * invm_[i];
          y.segment<3>(off_[i] + 3).noalias() = Jinv_[i] * x.segment<3>(off_[i] + 3);
        }
      }
    };
    auto storeQdd = [&]() {
      for (int i = 0; i < nb_; ++i) {
        if (rot_[i]) {
          out.omegadot[i] = qdd_.segment<3>(off_[i]);
        } else {
          out.vdot[i] = qdd_.segment<3>(off_[i]);
          out.omegadot[i] = qdd_.segment<3>(off_[i] + 3);
        }
      }
    };

    if (m_ == 0) {
      applyMinv(F_, qdd_);
      storeQdd();
      out.lambda.resize(0);
      out.ok = true;
      return;
    }

    // Joint blocks; rotation-only bodies keep only the δθ columns (zero the δp
    // columns so that full 6-column products equal the 3-column ones).
    for (int k = 0; k < nj_; ++k) {
      detail::evaluateJoint(model.joints[k], state, &ev_[k]);
      c_.segment(row_[k], topo_[k].rows) = ev_[k].c;
    }
    // G = J_k,b M_b⁻¹ (rows × 6, δp columns zero for rotation-only bodies).
    auto gIndex = [](int k, bool sec) { return 2 * k + (sec ? 1 : 0); };
    for (int k = 0; k < nj_; ++k) {
      for (int side = 0; side < 2; ++side) {
        const int b = side == 0 ? topo_[k].main : topo_[k].secondary;
        if (b == kGround) continue;
        const detail::JointBlock& B = side == 0 ? ev_[k].Ja : ev_[k].Jb;
        detail::JointBlock& G = G_[gIndex(k, side == 1)];
        G.resize(B.rows(), 6);
        if (rot_[b]) {
          G.leftCols<3>().setZero();
        } else {
          G.leftCols<3>() = B.leftCols<3>() * invm_[b];
        }
        G.rightCols<3>().noalias() = B.rightCols<3>() * Jinv_[b];
      }
    }
    auto blockOf = [&](int k, int b) -> const detail::JointBlock& {
      return topo_[k].main == b ? ev_[k].Ja : ev_[k].Jb;
    };
    auto gOf = [&](int k, int b) -> const detail::JointBlock& {
      return G_[gIndex(k, topo_[k].main != b)];
    };
    // A = J M⁻¹ Jᵀ = Σ_b J_b M_b⁻¹ J_bᵀ, written into the fixed pattern.
    double* val = A_.valuePtr();
    std::fill(val, val + A_.nonZeros(), 0.0);
    for (int b = 0; b < nb_; ++b) {
      const int c0 = colBegin(b);
      for (int l : body_joints_[b]) {
        const detail::JointBlock& Bl = blockOf(l, b);
        for (int k : body_joints_[b]) {
          const detail::JointBlock& Gk = gOf(k, b);
          const int rk = topo_[k].rows, rl = topo_[l].rows;
          for (int c = 0; c < rl; ++c) {
            double* col = val + slot(k, l, 0, c);
            for (int r = 0; r < rk; ++r)
              col[r] += Gk.row(r).tail(6 - c0).dot(Bl.row(c).tail(6 - c0));
          }
        }
      }
    }
    for (int r = 0; r < m_; ++r) diagA_[r] = val[diag_slot_[r]];
    double* pval = Ap_.valuePtr();
    for (Eigen::Index q = 0; q < A_.nonZeros(); ++q)
      if (ap_slot_[q] >= 0) pval[ap_slot_[q]] = val[q];

    auto jointOfRow = [&](int r) {
      return static_cast<int>(std::upper_bound(row_.begin(), row_.end(), r) - row_.begin()) - 1;
    };
    auto fail = [&](int r, const std::string& why) {
      const int k = jointOfRow(r);
      out.ok = false;
      out.failed_joint = k;
      const Joint& jt = model.joints[k];
      std::ostringstream s;
      s << model.jointLabel(k) << ": " << constraintTypeName(jt.constraint) << " row "
        << (r - row_[k]) << " " << why;
      out.reason = s.str();
      out.lambda.resize(0);
    };
    if (!diagA_.allFinite()) return fail(0, "gives a non-finite J M⁻¹ Jᵀ");
    // Pivot check in the permuted order (row r goes to position perm[r]); the
    // first row with a pivot ≤ kPivotTolerance × its diagonal is reported.
    auto findSingularRow = [&](double* pivot) {
      const Eigen::VectorXd D = ldlt_.vectorD();
      for (int p = 0; p < m_; ++p) {
        const int r = orig_[p];
        if (!std::isfinite(D[p]) || !(D[p] > kPivotTolerance * diagA_[r])) {
          *pivot = D[p];
          return r;
        }
      }
      return -1;
    };
    auto redundant = [&](int r, double pivot) {
      std::ostringstream why;
      why << "is redundant or conflicting with other constraints (singular J M⁻¹ Jᵀ: pivot "
          << pivot << " vs diagonal " << diagA_[r] << ")";
      fail(r, why.str());
    };

    ldlt_.factorize(Ap_);
    if (ldlt_.info() != Eigen::Success) {
      // An exactly zero pivot stops Eigen's factorization: locate the row on
      // A + 1e-12 diag(A) (same pattern), whose redundant rows have pivots
      // ≈ 1e-12 × diagonal.
      for (int r = 0; r < m_; ++r)
        pval[ap_diag_slot_[r]] += 1e-12 * std::max(diagA_[r], 1e-300);
      ldlt_.factorize(Ap_);
      double pivot = 0.0;
      const int r = ldlt_.info() == Eigen::Success ? findSingularRow(&pivot) : -1;
      if (r >= 0) return redundant(r, 0.0);
      out.ok = false;
      out.reason =
          "J M⁻¹ Jᵀ could not be factored (singular: redundant or conflicting constraints)";
      out.lambda.resize(0);
      return;
    }
    out.factor_nonzeros = ldlt_.matrixL().nestedExpression().nonZeros();
    {
      double pivot = 0.0;
      const int r = findSingularRow(&pivot);
      if (r >= 0) return redundant(r, pivot);
    }

    // rhs = J M⁻¹ F + c.
    for (int k = 0; k < nj_; ++k) {
      auto seg = rhs_.segment(row_[k], topo_[k].rows);
      seg = c_.segment(row_[k], topo_[k].rows);
      for (int b : {topo_[k].main, topo_[k].secondary}) {
        if (b == kGround) continue;
        const int c0 = colBegin(b);
        seg.noalias() += gOf(k, b).rightCols(6 - c0) * F_.segment(off_[b], 6 - c0);
      }
    }
    out.lambda.resize(m_);
    for (int r = 0; r < m_; ++r) rhsp_[perm_[r]] = rhs_[r];
    lamp_ = ldlt_.solve(rhsp_);
    for (int r = 0; r < m_; ++r) out.lambda[r] = lamp_[perm_[r]];
    if (!out.lambda.allFinite()) return fail(0, "gave non-finite multipliers");
    // y = F − Jᵀ λ, q̈ = M⁻¹ y.
    y_ = F_;
    for (int k = 0; k < nj_; ++k) {
      const auto lk = out.lambda.segment(row_[k], topo_[k].rows);
      for (int b : {topo_[k].main, topo_[k].secondary}) {
        if (b == kGround) continue;
        const int c0 = colBegin(b);
        y_.segment(off_[b], 6 - c0).noalias() -= blockOf(k, b).rightCols(6 - c0).transpose() * lk;
      }
    }
    applyMinv(y_, qdd_);
    storeQdd();
    // Residual ‖J q̈ + c‖∞.
    double res = 0.0;
    for (int k = 0; k < nj_; ++k) {
      detail::JointRows e = c_.segment(row_[k], topo_[k].rows);
      for (int b : {topo_[k].main, topo_[k].secondary}) {
        if (b == kGround) continue;
        const int c0 = colBegin(b);
        e.noalias() += blockOf(k, b).rightCols(6 - c0) * qdd_.segment(off_[b], 6 - c0);
      }
      res = std::max(res, e.lpNorm<Eigen::Infinity>());
    }
    out.constraint_residual = res;

    // Reactions −J_kᵀ λ_k per body.
    for (int k = 0; k < nj_; ++k) {
      const Joint& jt = model.joints[k];
      const auto lk = out.lambda.segment(row_[k], topo_[k].rows);
      const BodyPose<double> pa =
          jt.main == kGround ? constraints::groundPose<double>() : state.poses[jt.main];
      const BodyPose<double> pb =
          jt.secondary == kGround ? constraints::groundPose<double>() : state.poses[jt.secondary];
      const auto& sph = std::visit(
          [](const auto& con) -> const constraints::SphericalJoint<double>& {
            if constexpr (std::is_same_v<std::decay_t<decltype(con)>,
                                         constraints::SphericalJoint<double>>)
              return con;
            else
              return con.point;
          },
          jt.constraint);
      const Eigen::Vector3d anchor_world = pa.toWorld(sph.anchor_main);
      auto react = [&](const detail::JointBlock& B, const BodyPose<double>& P) {
        const Eigen::Matrix<double, 6, 1> g = -(B.transpose() * lk);
        BodyReaction r;
        r.force = g.head<3>();
        r.moment_body = g.tail<3>();
        // Moment about the anchor: τ_c (world) − (anchor − p) × f.
        r.moment_anchor = P.R * r.moment_body - (anchor_world - P.p).cross(r.force);
        return r;
      };
      JointReaction& R = out.reactions[k];
      R.main = react(ev_[k].Ja, pa);
      R.secondary = react(ev_[k].Jb, pb);
      if (const auto* rev = std::get_if<constraints::RevoluteJoint<double>>(&jt.constraint)) {
        const Eigen::Vector3d axis = pa.R * rev->axis_main;
        R.axial_moment = jt.main != kGround ? R.main.moment_anchor.dot(axis)
                                            : -R.secondary.moment_anchor.dot(axis);
      }
    }
    out.ok = true;
  }

  bool analyzed_ = false;
  int analyze_count_ = 0;
  int nb_ = 0, nj_ = 0, n_ = 0, m_ = 0;
  std::vector<char> rot_;
  std::vector<Topo> topo_;
  std::vector<int> off_, row_;
  std::vector<std::vector<int>> body_joints_;
  std::vector<std::vector<std::pair<int, int>>> coupled_;  // (joint k, row offset in column)
  std::vector<Eigen::Index> diag_slot_;
  std::vector<int> orig_;  // permuted position → original row
  Eigen::VectorXi perm_;   // original row → permuted position (AMD)
  SpMat A_;                // J M⁻¹ Jᵀ, both triangles, original order
  SpMat Ap_;               // upper triangle of P A Pᵀ (what is factored)
  std::vector<Eigen::Index> ap_slot_;  // A_ value index → Ap_ value index, or −1
  std::vector<Eigen::Index> ap_diag_slot_;
  Eigen::SimplicialLDLT<SpMat, Eigen::Upper, Eigen::NaturalOrdering<int>> ldlt_;
  Eigen::VectorXd rhsp_, lamp_;
  std::vector<detail::JointEval> ev_;
  std::vector<detail::JointBlock> G_;
  std::vector<Eigen::Matrix3d> Jinv_;
  std::vector<double> checked_mass_;
  std::vector<Eigen::Matrix3d> checked_inertia_;
  std::vector<double> invm_;
  Eigen::VectorXd F_, y_, qdd_, rhs_, c_, diagA_;
};

/// Solves the constrained accelerations at `state` under gravity and the
/// optional external loads (one per body, or empty). Never throws on a
/// singular system: returns ok = false with the reason. Throws InvalidInput
/// for malformed model/state (MultibodyModel::validate). Builds a temporary
/// ConstrainedAccelerationSolver: reuse one across steps for a fixed model.
inline AccelerationSolution solveConstrainedAccelerations(const MultibodyModel& model,
                                                          const MultibodyState& state,
                                                          const std::vector<BodyLoad>& loads = {}) {
  ConstrainedAccelerationSolver solver;
  return solver.solve(model, state, loads);
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
