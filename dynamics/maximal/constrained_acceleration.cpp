#include "dynamics/maximal/constrained_acceleration.hpp"
#include "liegroup/number_text.hpp"

namespace lieflow {
namespace multibody {

namespace {

struct JointPoses {
  BodyPose<double> a, b;
  BodyVelocity<double> va, vb;
};

JointPoses jointPoses(const Joint& j, const MultibodyState& s) {
  JointPoses p;
  p.a = j.main == kGround ? constraints::groundPose<double>() : s.poses[j.main];
  p.b = j.secondary == kGround ? constraints::groundPose<double>() : s.poses[j.secondary];
  p.va = j.main == kGround ? constraints::groundVelocity<double>() : s.velocities[j.main];
  p.vb = j.secondary == kGround ? constraints::groundVelocity<double>() : s.velocities[j.secondary];
  return p;
}

}  // namespace

ConstrainedAccelerationSolver::ConstrainedAccelerationSolver(const MultibodyModel& model) {
  model.validateModel();
  setup(model);
}

std::vector<RowGroup> ConstrainedAccelerationSolver::topology(const MultibodyModel& model) const {
  std::vector<RowGroup> groups(model.joints.size());
  for (std::size_t k = 0; k < model.joints.size(); ++k) {
    const Joint& j = model.joints[k];
    groups[k].bodies = {{j.main, j.secondary, kGround, kGround}};
    groups[k].rows = constraintRows(j.constraint);
  }
  return groups;
}

void ConstrainedAccelerationSolver::setup(const MultibodyModel& model) {
  rot_.resize(model.bodies.size());
  for (std::size_t i = 0; i < model.bodies.size(); ++i) rot_[i] = model.bodies[i].rotation_only ? 1 : 0;
  schur_.setup(rot_, topology(model));
  checked_mass_.clear();  // the next solve validates the whole model
  checked_inertia_.clear();
}

// Same checks as model.validate(state), but a body is re-checked (3×3
// eigenvalues) only when its mass or inertia changed since it was last
// checked, and joints only when the topology changed.
void ConstrainedAccelerationSolver::validate(const MultibodyModel& model, const MultibodyState& state) {
  std::vector<char> rot(model.bodies.size());
  for (std::size_t i = 0; i < model.bodies.size(); ++i) rot[i] = model.bodies[i].rotation_only ? 1 : 0;
  const bool same = schur_.matches(rot, topology(model));
  if (!same || checked_mass_.size() != model.bodies.size()) {
    model.validate(state);
    if (!same) setup(model);
    checked_mass_.clear();
    checked_inertia_.clear();
    for (const RigidBody& b : model.bodies) {
      checked_mass_.push_back(b.mass);
      checked_inertia_.push_back(b.inertia);
    }
    return;
  }
  for (std::size_t i = 0; i < model.bodies.size(); ++i) {
    const RigidBody& b = model.bodies[i];
    // Bitwise-equal data passed before (NaN never compares equal: re-checked).
    if (b.mass == checked_mass_[i] && b.inertia == checked_inertia_[i]) continue;
    model.validateBody(static_cast<int>(i));
    checked_mass_[i] = b.mass;
    checked_inertia_[i] = b.inertia;
  }
  model.validateState(state);
}

void ConstrainedAccelerationSolver::assembleForces(const MultibodyModel& model, const MultibodyState& state,
                                                   const std::vector<BodyLoad>& loads) {
  const int nb = schur_.bodyCount();
  // F = (m g + f, τ − ω × J ω) and M⁻¹ per body.
  F_.resize(schur_.dofs());
  for (int i = 0; i < nb; ++i) {
    const RigidBody& b = model.bodies[i];
    const Eigen::Vector3d& w = state.velocities[i].omega;
    Eigen::Vector3d tau = -w.cross(b.inertia * w);
    Eigen::Vector3d f = b.mass * model.gravity;
    if (!loads.empty()) {
      tau += loads[i].moment;
      f += loads[i].force;
    }
    const int o = schur_.dofBegin(i);
    if (rot_[i]) {
      F_.segment<3>(o) = tau;
    } else {
      F_.segment<3>(o) = f;
      F_.segment<3>(o + 3) = tau;
    }
    schur_.setInverseMass(i, 1.0 / b.mass, b.inertia.inverse());
  }
}

void ConstrainedAccelerationSolver::storeAccelerations(AccelerationSolution& out) const {
  const int nb = schur_.bodyCount();
  for (int i = 0; i < nb; ++i) {
    const int o = schur_.dofBegin(i);
    if (rot_[i]) {
      out.omegadot[i] = qdd_.segment<3>(o);
    } else {
      out.vdot[i] = qdd_.segment<3>(o);
      out.omegadot[i] = qdd_.segment<3>(o + 3);
    }
  }
}

void ConstrainedAccelerationSolver::assembleJointRows(const MultibodyModel& model, const MultibodyState& state) {
  const int nj = schur_.groupCount();
  // Joint blocks and convective terms.
  c_.resize(schur_.rows());
  for (int k = 0; k < nj; ++k) {
    const Joint& j = model.joints[k];
    const JointPoses P = jointPoses(j, state);
    std::visit(
        [&](const auto& con) {
          const auto J = con.jacobians(P.a, P.b);
          schur_.block(k, 0) = J[0];
          schur_.block(k, 1) = J[1];
          c_.segment(schur_.rowBegin(k), schur_.groupRows(k)) = con.convective(P.a, P.b, P.va, P.vb);
        },
        j.constraint);
  }
}

bool ConstrainedAccelerationSolver::fail(const MultibodyModel& model, int r, const std::string& why,
                                         AccelerationSolution& out) const {
  const int k = schur_.groupOfRow(r);
  out.ok = false;
  out.failed_joint = k;
  std::ostringstream s;
  s << model.jointLabel(k) << ": " << constraintTypeName(model.joints[k].constraint) << " row "
    << (r - schur_.rowBegin(k)) << " " << why;
  out.reason = s.str();
  out.lambda.resize(0);
  return false;
}

void ConstrainedAccelerationSolver::jointReactions(const MultibodyModel& model, const MultibodyState& state,
                                                   AccelerationSolution& out) const {
  const int nj = schur_.groupCount();
  // Reactions −J_kᵀ λ_k per body.
  for (int k = 0; k < nj; ++k) {
    const Joint& jt = model.joints[k];
    const auto lk = out.lambda.segment(schur_.rowBegin(k), schur_.groupRows(k));
    const JointPoses P = jointPoses(jt, state);
    const Eigen::Vector3d anchor_world = P.a.toWorld(jointAnchors(jt.constraint).first);
    auto react = [&](const GroupBlock& B, const BodyPose<double>& pose) {
      const Eigen::Matrix<double, 6, 1> g = -(B.transpose() * lk);
      BodyReaction r;
      r.force = g.head<3>();
      r.moment_body = g.tail<3>();
      // Moment about the anchor: τ_c (world) − (anchor − p) × f.
      r.moment_anchor = pose.R * r.moment_body - (anchor_world - pose.p).cross(r.force);
      return r;
    };
    JointReaction& R = out.reactions[k];
    R.main = react(schur_.block(k, 0), P.a);
    R.secondary = react(schur_.block(k, 1), P.b);
    if (const auto* rev = std::get_if<constraints::RevoluteJoint<double>>(&jt.constraint)) {
      const Eigen::Vector3d axis = P.a.R * rev->axis_main;
      R.axial_moment = jt.main != kGround ? R.main.moment_anchor.dot(axis)
                                          : -R.secondary.moment_anchor.dot(axis);
    }
  }
}

bool ConstrainedAccelerationSolver::solve(const MultibodyModel& model, const MultibodyState& state,
                                          const std::vector<BodyLoad>& loads,
                                          AccelerationSolution& out) {
  validate(model, state);
  if (!loads.empty() && loads.size() != model.bodies.size())
    throw InvalidInput("loads", "one load per body expected");
  const int nb = schur_.bodyCount();
  const int nj = schur_.groupCount();
  const int m = schur_.rows();
  out.ok = false;
  out.reason.clear();
  out.failed_joint = -1;
  out.constraint_residual = 0.0;
  out.factor_nonzeros = 0;
  out.vdot.assign(nb, Eigen::Vector3d::Zero());
  out.omegadot.assign(nb, Eigen::Vector3d::Zero());
  out.reactions.assign(nj, JointReaction{});

  assembleForces(model, state, loads);
  if (m == 0) {
    schur_.applyInverseMass(F_, qdd_);
    storeAccelerations(out);
    out.lambda.resize(0);
    out.ok = true;
    return true;
  }

  assembleJointRows(model, state);

  const FactorStatus st = schur_.factor();
  if (!st.ok) {
    if (!std::isfinite(st.pivot) && !schur_.diagonal().allFinite())
      return fail(model, st.row, "gives a non-finite J M⁻¹ Jᵀ", out);
    std::ostringstream why;
    why << "is redundant or conflicting with other constraints (singular J M⁻¹ Jᵀ: pivot "
        << formatNumber(st.pivot) << " vs diagonal " << formatNumber(st.diagonal) << ")";
    return fail(model, st.row, why.str(), out);
  }
  out.factor_nonzeros = schur_.factorNonzeros();

  // (J M⁻¹ Jᵀ) λ = J M⁻¹ F + c,  q̈ = M⁻¹ (F − Jᵀ λ).
  schur_.applyInverseMass(F_, y_);
  schur_.multiplyJ(y_, rhs_);
  rhs_ += c_;
  schur_.solve(rhs_, out.lambda);
  if (!out.lambda.allFinite()) return fail(model, 0, "gave non-finite multipliers", out);
  y_ = F_;
  schur_.addJTranspose(out.lambda, -1.0, y_);
  schur_.applyInverseMass(y_, qdd_);
  storeAccelerations(out);
  schur_.multiplyJ(qdd_, res_);
  out.constraint_residual = (res_ + c_).lpNorm<Eigen::Infinity>();

  jointReactions(model, state, out);
  out.ok = true;
  return true;
}

}  // namespace multibody
}  // namespace lieflow
