// ArticulatedSystem: the joint-space mass matrix (composite-rigid-body
// algorithm) and the terms of M v̇ + g = 0 for the generalized-α method.
#include <array>
#include <vector>

#include "dynamics/joint_space/articulated_coupled_alpha.hpp"
#include "dynamics/joint_space/articulated_system.hpp"

namespace lieflow {
namespace articulated {

namespace {

/// A free root's six slots in u in freeColumns' order: ω (body), then v_c.
std::array<int, 6> freeRootSlots(const ArticulatedBody& b) {
  return {b.u_rotation, b.u_rotation + 1, b.u_rotation + 2, b.u_begin, b.u_begin + 1, b.u_begin + 2};
}

}  // namespace

void ArticulatedSystem::secondOrderTerms(double t, const State& y, Eigen::MatrixXd* M, Eigen::VectorXd* g,
                                         Eigen::MatrixXd* Ct, Eigen::MatrixXd* Kt) const {
  const int n = dofs();
  forwardPass(t, y, true, true);
  // Composite-rigid-body algorithm, leaves to root, on the rigid inertias the
  // forward pass left in IA (before the ABA accumulates into them).
  data_.composite.resize(bodyCount());
  for (int i = 0; i < bodyCount(); ++i) data_.composite[i] = data_.bodies[i].IA;
  M->setZero(n, n);
  for (int i = bodyCount() - 1; i >= 0; --i) {
    const ArticulatedBody& b = model_.bodies[i];
    const BodyData& d = data_.bodies[i];
    const int nf = d.free;
    if (b.parent != kGround) {
      if (b.rotation_only) {
        const Matrix6 P = rotationOnlyMap(d.c);
        data_.composite[b.parent] += P.transpose() * data_.composite[i] * P;
      } else {
        data_.composite[b.parent] += data_.composite[i];
      }
    }
    if (b.kind == JointKind::kFree) {
      // A free root's block S_rᵀ I_c S_r (S_r = freeColumns: ω body, then
      // v_c); its rows against the columns below it were set from there.
      const Matrix6 S = freeColumns(d.R, d.c);
      const Matrix6 block = S.transpose() * (data_.composite[i] * S);
      const std::array<int, 6> u = freeRootSlots(b);
      for (int r = 0; r < 6; ++r)
        for (int c = 0; c < 6; ++c) (*M)(u[r], u[c]) = block(r, c);
    }
    for (int k = 0; k < nf; ++k) {
      // F = I_c s_k: the force that column k's unit rate takes through the
      // subtree; M(u_k, u_l) = s_lᵀ F for the columns l of i and its ancestors.
      Vector6 F = data_.composite[i] * d.S.col(k);
      const int row = d.free_u[k];
      for (int l = 0; l < nf; ++l) (*M)(row, d.free_u[l]) = d.S.col(l).dot(F);
      int below = i;
      for (int j = b.parent; j != kGround; below = j, j = model_.bodies[j].parent) {
        if (model_.bodies[below].rotation_only) F = heldForce(data_.bodies[below].c, F);
        const BodyData& dj = data_.bodies[j];
        if (model_.bodies[j].kind == JointKind::kFree) {
          const Vector6 m = freeColumns(dj.R, dj.c).transpose() * F;
          const std::array<int, 6> u = freeRootSlots(model_.bodies[j]);
          for (int l = 0; l < 6; ++l) {
            (*M)(row, u[l]) = m[l];
            (*M)(u[l], row) = m[l];
          }
        }
        for (int l = 0; l < dj.free; ++l) {
          const double m = dj.S.col(l).dot(F);
          (*M)(row, dj.free_u[l]) = m;
          (*M)(dj.free_u[l], row) = m;
        }
      }
    }
  }
  // Prescribed coordinates: the row v̇ = φ̈(t).
  for (int i = 0; i < bodyCount(); ++i) {
    const ArticulatedBody& b = model_.bodies[i];
    for (int k = 0; k < b.coordinates(); ++k)
      if (b.prescribed(k)) (*M)(b.u_begin + k, b.u_begin + k) = 1.0;
  }
  // g = −M u̇, u̇ from the ABA at the same state (it reads the forward pass
  // above: the rigid inertias are still in IA).
  data_.udot.resize(n);
  solve(Vector6::Zero(), &data_.udot);
  for (int i = 0; i < bodyCount(); ++i) {
    const ArticulatedBody& b = model_.bodies[i];
    for (int k = 0; k < b.coordinates(); ++k)
      if (b.prescribed(k)) data_.udot[b.u_begin + k] = data_.bodies[i].phiddot[k];
  }
  g->resize(n);
  g->noalias() = -(*M) * data_.udot;
  if (Ct) Ct->setZero(n, n);
  if (Kt) Kt->setZero(n, n);
  for (int i = 0; i < bodyCount(); ++i) {
    const ArticulatedBody& b = model_.bodies[i];
    for (int k = 0; k < b.coordinates(); ++k) {
      if (b.prescribed(k)) continue;
      const CoordinateDrive& drive = model_.drives[i][k];
      const int u = b.u_begin + k;
      if (Ct) (*Ct)(u, u) = drive.damping;
      if (Kt) (*Kt)(u, u) = drive.stiffness;
    }
  }
}

Eigen::MatrixXd CoupledArticulatedSystem::kernelBasis(const Eigen::MatrixXd& G) {
  const int n = static_cast<int>(G.cols()), m = static_cast<int>(G.rows());
  std::vector<int> touched;
  for (int j = 0; j < n; ++j)
    if (G.col(j).cwiseAbs().maxCoeff() > 0.0) touched.push_back(j);
  const int k = static_cast<int>(touched.size());
  Eigen::MatrixXd Gt(k, m);
  for (int i = 0; i < k; ++i) Gt.row(i) = G.col(touched[i]).transpose();
  // Gᵀ = Q R: Q's columns past the first m span ker G on the touched block.
  const Eigen::MatrixXd Q = Eigen::HouseholderQR<Eigen::MatrixXd>(Gt).householderQ();
  Eigen::MatrixXd N = Eigen::MatrixXd::Zero(n, n - m);
  int col = 0;
  for (int j = 0, t = 0; j < n; ++j) {
    if (t < k && touched[t] == j) {
      ++t;
      continue;
    }
    N(j, col++) = 1.0;
  }
  for (int c = m; c < k; ++c, ++col)
    for (int i = 0; i < k; ++i) N(touched[i], col) = Q(i, c);
  return N;
}

}  // namespace articulated
}  // namespace lieflow
