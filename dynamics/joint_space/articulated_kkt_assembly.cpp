// genalpha's iteration matrix for a tree with loops in joint coordinates
// (articulated_kkt_assembly.hpp states the matrix and its terms).
#include "dynamics/joint_space/articulated_kkt_assembly.hpp"

#include <algorithm>

namespace lieflow {
namespace articulated {

bool ArticulatedKktAssembly::bind(const ArticulatedSystem& system) {
  if (system_ == &system) return false;
  system_ = &system;
  n_ = system.dofs();
  // The system's closure rows in the stepper's order: a loop's position
  // rows first, then the gear rows.
  rows_.clear();
  const int m = system.model().closure_rows;
  for (int k = 0; k < m; ++k)
    if (system.isPositionRow(k)) rows_.push_back(k);
  for (int k = 0; k < m; ++k)
    if (!system.isPositionRow(k)) rows_.push_back(k);
  shapeMatrix();
  return true;
}

void ArticulatedKktAssembly::shapeMatrix() {
  m_ = static_cast<int>(rows_.size());
  mp_ = 0;
  for (int k : rows_) mp_ += system_->isPositionRow(k) ? 1 : 0;
  const int size = n_ + m_ + (stabilized_ ? mp_ : 0);
  // A full pattern: column j holds rows 0 … size − 1, so that the values in
  // column-major order are a dense matrix's (matrix() copies them).
  A_.resize(size, size);
  A_.reserve(Eigen::VectorXi::Constant(size, size));
  for (int j = 0; j < size; ++j)
    for (int i = 0; i < size; ++i) A_.insert(i, j) = 0.0;
  A_.makeCompressed();
  dense_.setZero(size, size);
}

bool ArticulatedKktAssembly::accelerations(double t, const State& y, Eigen::VectorXd* udot, Eigen::VectorXd* lambda,
                                           std::string* why) {
  const ArticulatedSystem& s = *system_;
  s.accelerations(t, y, udot);
  if (!udot->allFinite()) {
    if (why) *why = "the accelerations of the tree with its loops are not finite";
    return false;
  }
  const Eigen::VectorXd& l = s.lastClosureMultipliers();
  lambda->resize(m_);
  for (int i = 0; i < m_; ++i) (*lambda)[i] = -l[rows_[i]];
  return true;
}

void ArticulatedKktAssembly::rowsAt(double t, const State& y) {
  system_->closureRowsAt(t, y, &G_all_, &phi_all_);
  G_.resize(m_, n_);
  phi_.resize(mp_);
  for (int i = 0; i < m_; ++i) G_.row(i) = G_all_.row(rows_[i]);
  for (int i = 0; i < mp_; ++i) phi_[i] = phi_all_[rows_[i]];
}

void ArticulatedKktAssembly::startStep(double t, const State& y) {
  if (!stabilized_ || mp_ == 0) return;
  rowsAt(t, y);
  Gp_start_ = G_.topRows(mp_);
  system_->secondOrderTerms(t, y, &M_start_, &g_, nullptr, nullptr);
  M_start_llt_.compute(M_start_);
  Gp_mid_ = Gp_start_;
  P_ = Gp_mid_.transpose();
  M_start_llt_.solveInPlace(P_);
  mid_fixed_ = false;
}

void ArticulatedKktAssembly::addStartCorrection(const Eigen::VectorXd& nu, Eigen::VectorXd* dq) const {
  if (!stabilized_ || mp_ == 0) return;
  dq->noalias() += P_ * nu;
}

double ArticulatedKktAssembly::residual(double t, const State& y, const Eigen::VectorXd& udot,
                                        const Eigen::VectorXd& lambda, Eigen::VectorXd* r, Eigen::VectorXd* c) {
  t_ = t;
  system_->secondOrderTerms(t, y, &M_, &g_, nullptr, nullptr);
  rowsAt(t, y);
  Mu_.noalias() = M_ * udot;
  GTl_.noalias() = G_.transpose() * lambda;
  *r = Mu_ + g_ + GTl_;
  // Kept for the tangents of matrix(), at the same iterate.
  udot_ = udot;
  lambda_ = lambda;
  r_ = *r;
  c->resize(stabilized_ ? mp_ + m_ : m_);
  c->head(mp_) = phi_;
  if (stabilized_)
    c->tail(m_).noalias() = G_ * y.u;
  else if (m_ > mp_)
    c->tail(m_ - mp_).noalias() = G_.bottomRows(m_ - mp_) * y.u;
  return std::max({Mu_.lpNorm<Eigen::Infinity>(), g_.lpNorm<Eigen::Infinity>(), GTl_.lpNorm<Eigen::Infinity>()});
}

void ArticulatedKktAssembly::tangents(const State& y) {
  // Forward differences of r = M u̇ + g + Gᵀλ along each coordinate
  // (q ⊕ ε e_k) and each rate (u + ε e_k), and of the rows' G u along each
  // coordinate: an iteration matrix needs the derivatives to a few digits.
  const double step = kDifferenceStep;
  Gu_.noalias() = G_ * y.u;
  Kfull_.resize(n_, n_);
  Cfull_.resize(n_, n_);
  dGu_.resize(m_, n_);
  dq_unit_.setZero(n_);
  for (int k = 0; k < n_; ++k) {
    dq_unit_[k] = step;
    advanceInto(y, dq_unit_, y.u, &moved_);
    dq_unit_[k] = 0.0;
    system_->secondOrderTerms(t_, moved_, &M_moved_, &g_moved_, nullptr, nullptr);
    column_.noalias() = M_moved_ * udot_;
    column_ += g_moved_;
    if (m_ > 0) {
      system_->closureRowsAt(t_, moved_, &G_moved_, &phi_moved_);
      for (int i = 0; i < m_; ++i) {
        const int row = rows_[i];
        column_.noalias() += G_moved_.row(row).transpose() * lambda_[i];
        dGu_(i, k) = (G_moved_.row(row).dot(y.u) - Gu_[i]) / step;
      }
    }
    Kfull_.col(k) = (column_ - r_) / step;
    // The rates: only g depends on them.
    const double du = step * std::max(1.0, std::abs(y.u[k]));
    moved_ = y;
    moved_.u[k] += du;
    system_->secondOrderTerms(t_, moved_, &M_moved_, &g_moved_, nullptr, nullptr);
    Cfull_.col(k) = (g_moved_ - g_) / du;
  }
}

const Eigen::SparseMatrix<double>& ArticulatedKktAssembly::matrix(const State& y, const Eigen::VectorXd& dq,
                                                                  double damping_factor, double stiffness_factor,
                                                                  const Eigen::VectorXd& /*lambda: residual()'s*/) {
  SecondOrderStateTraits<ArticulatedState>::tangentOperatorInto(y, dq, &T_);
  tangents(y);
  Eigen::MatrixXd& D = dense_;
  D.setZero();
  // The force rows: M + c_C ∂r/∂u + c_K ∂r/∂q T, and Gᵀ.
  D.topLeftCorner(n_, n_).noalias() = stiffness_factor * (Kfull_ * T_);
  D.topLeftCorner(n_, n_) += M_ + damping_factor * Cfull_;
  D.block(0, n_, n_, m_) = G_.transpose();
  // 1/γ' = c_K / c_C: the velocity rows' ∂(G u)/∂q T / γ'.
  const double velocity_factor = stiffness_factor / damping_factor;
  if (!stabilized_) {
    // Position rows G_p T (index 3); gear rows (G_v + ∂(G_v u)/∂q / γ') T.
    D.block(n_, 0, m_, n_).noalias() = G_ * T_;
    if (m_ > mp_) D.block(n_ + mp_, 0, m_ - mp_, n_).noalias() += velocity_factor * (dGu_.bottomRows(m_ - mp_) * T_);
  } else if (m_ > 0) {
    if (!mid_fixed_ && mp_ > 0) {
      // Ḡ_p = ½ (G_p(q_n) + G_p(q̃_{n+1})) at the step's first iterate, held.
      Gp_mid_ = 0.5 * (Gp_start_ + G_.topRows(mp_));
      P_ = Gp_mid_.transpose();
      M_start_llt_.solveInPlace(P_);
    }
    mid_fixed_ = true;
    // Velocity rows G + ∂(G u)/∂q T / γ'; position rows G_p T; the ν
    // columns −(M + c_C C_t) P and −G P.
    D.block(n_, 0, m_, n_) = G_;
    D.block(n_, 0, m_, n_).noalias() += velocity_factor * (dGu_ * T_);
    if (mp_ > 0) {
      D.block(n_ + m_, 0, mp_, n_).noalias() = G_.topRows(mp_) * T_;
      MP_ = M_ + damping_factor * Cfull_;
      D.block(0, n_ + m_, n_, mp_).noalias() -= MP_ * P_;
      D.block(n_, n_ + m_, m_, mp_).noalias() -= G_ * P_;
    }
  }
  std::copy(D.data(), D.data() + D.size(), A_.valuePtr());
  return A_;
}

}  // namespace articulated
}  // namespace lieflow
