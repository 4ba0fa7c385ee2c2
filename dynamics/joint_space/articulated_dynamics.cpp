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
  frames_ = modelFrames<double>(model_);
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

namespace {

/// The scene's loads with the program torques of an ArticulatedSystem.
struct SystemLoads : ModelLoads {
  const std::vector<ArticulatedSystem::UserTorque>& user_torques;
  bool any;
  /// A program torque (body axes) on body i, into its bias force.
  EIGEN_ALWAYS_INLINE void external(int i, double t, ArticulatedData::Body* d, const Eigen::Vector3d& w,
                                    const Eigen::Vector3d& vc) const {
    if (!any || !user_torques[i]) return;
    const Eigen::Quaterniond q(d->R);
    d->pA.head<3>() -= d->R * user_torques[i](t, q, d->c, d->R.transpose() * w, vc);
  }
};

}  // namespace

void ArticulatedSystem::forwardPass(double t, const State& y, bool dynamics, bool velocity_terms) const {
  passes().forwardPass(t, y, dynamics, velocity_terms, SystemLoads{{model_}, user_torques_, has_user_torques_});
}

void ArticulatedSystem::solve(const Vector6& a0, Eigen::VectorXd* udot) const { passes().solve(a0, udot); }

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
