/// \file
/// genalpha on a tree with loops in joint coordinates: the Assembly of
/// integrators/constrained_generalized_alpha.hpp's System concept for an
/// ArticulatedSystem whose closures include loop-closing joints or gear rows
/// (coupling rows alone run in their kernel: articulated_coupled_alpha.hpp).
///
/// Unknowns: the rates' increments (n), then the multipliers of the rows in
/// the stepper's order — a loop's position rows first, then the gear rows —
/// and, stabilized, ν (one per position row). The rows are the closures'
/// G = ∂Φ̇/∂u (articulated_closures.cpp) at the iterate; in joint coordinates
/// Φ_q = G (an angle's rate is its coordinate's derivative, a rotation's
/// body rate its right-trivialized one). The rows must be independent
/// (G M⁻¹ Gᵀ of full rank at the start, ArticulatedSystem::
/// closureRowsIndependent; the stepper table refuses the others, and
/// maximal coordinates run them): a row a loop repeats makes the iteration
/// matrix singular, and which rows repeat changes as a planar loop turns
/// (dropping those of the start failed on the slider-crank at t = 5 s).
/// The scaled matrix (the
/// stepper's file comment) is dense here — M is the joint-space mass matrix
/// (composite-rigid-body), n is tens — and stored with a full pattern:
///   index 3      [ M + c_C C_t + c_K K_t T    Gᵀ ]   force (n)
///                [ G_p T                      0  ]   position (m_p)
///                [ (G_v + ∂(G_v u)/∂q / γ') T 0  ]   gear (m_v)
///   stabilized   [ M + c_C C_t + c_K K_t T    Gᵀ   −(M + c_C C_t) P ]   force (n)
///                [ G + ∂(G u)/∂q T / γ'       0    −G P             ]   velocity (m)
///                [ G_p T                      0    0                ]   position (m_p)
/// with P = M(q_n)⁻¹ Ḡ_pᵀ, Ḡ_p = ½ (G_p(q_n) + G_p(q̃_{n+1})) held for the step
/// (q̃_{n+1} the first iterate),
/// C_t = ∂r/∂u and K_t = ∂r/∂q the exact tangents of r = M u̇ + g + Gᵀλ
/// (springs, dashpots, gyroscopic and Coriolis terms, ∂(M u̇)/∂q, the
/// constraint forces' geometric stiffness) and the velocity rows'
/// ∂(G u)/∂q, by forward differences along each coordinate and rate (2n
/// evaluations per iteration: loops are small; joint-coordinate genalpha on
/// trees leaves ∂(M u̇)/∂q and ∂g/∂u out). Newton then converges
/// quadratically: the four-bar at h = 1e-2 and 1e-3 takes 2.0 and 1.04
/// iterations per step. Prescribed coordinates are not taken (the stepper
/// table refuses them; maximal coordinates run them).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "integrators/constrained_generalized_alpha.hpp"
#include "dynamics/joint_space/articulated_second_order.hpp"
#include "dynamics/joint_space/articulated_system.hpp"

namespace lieflow {
namespace articulated {

class ArticulatedKktAssembly {
 public:
  using State = ArticulatedState;

  /// Binds to `system` (kept by reference); true when the pattern is new.
  bool bind(const ArticulatedSystem& system);
  bool boundTo(const ArticulatedSystem& system) const { return system_ == &system; }

  int dofs() const { return n_; }
  int positionRows() const { return mp_; }
  int velocityRows() const { return m_ - mp_; }

  void setStabilized(bool stabilized) {
    if (stabilized != stabilized_) system_ = nullptr;
    stabilized_ = stabilized;
  }
  /// Stabilized: G_p(q_n), M(q_n) and P = M(q_n)⁻¹ G_p(q_n)ᵀ.
  void startStep(double t, const State& y);
  /// Stabilized: dq += P ν.
  void addStartCorrection(const Eigen::VectorXd& nu, Eigen::VectorXd* dq) const;
  static void velocityInto(const State& y, Eigen::VectorXd* u) { *u = y.u; }
  static void advanceInto(const State& y, const Eigen::VectorXd& dq, const Eigen::VectorXd& u, State* out) {
    SecondOrderStateTraits<ArticulatedState>::advanceInto(y, dq, u, out);
  }
  static bool identical(const State& a, const State& b) {
    return SecondOrderStateTraits<ArticulatedState>::identical(a, b);
  }
  /// The forward differences' step along a coordinate (rad, m): √ε.
  static constexpr double kDifferenceStep = 1.4901161193847656e-08;

  /// u̇ and λ of the index-1 equations (ArticulatedSystem::accelerations;
  /// λ = −the articulated-body algorithm's multipliers, which act as +Gᵀλ).
  bool accelerations(double t, const State& y, Eigen::VectorXd* udot, Eigen::VectorXd* lambda, std::string* why);

  /// r = M u̇ + g + Gᵀλ and c = [Φ; G_v u] (stabilized: [Φ; G u] over all m
  /// rows); returns max(‖M u̇‖∞, ‖g‖∞, ‖Gᵀλ‖∞).
  double residual(double t, const State& y, const Eigen::VectorXd& udot, const Eigen::VectorXd& lambda,
                  Eigen::VectorXd* r, Eigen::VectorXd* c);

  /// The scaled iteration matrix (file comment) at the y of the last
  /// residual(); dq = hΔq.
  const Eigen::SparseMatrix<double>& matrix(const State& y, const Eigen::VectorXd& dq, double damping_factor,
                                            double stiffness_factor, const Eigen::VectorXd& lambda);

 private:
  /// Sizes the matrix for the rows (a full pattern).
  void shapeMatrix();
  /// G and Φ of the rows at y into G_, phi_ (stepper order).
  void rowsAt(double t, const State& y);
  /// ∂r/∂q, ∂r/∂u (r = M u̇ + g + Gᵀλ at the last residual()'s iterate) and
  /// ∂(G u)/∂q at y by forward differences into Kfull_, Cfull_, dGu_.
  void tangents(const State& y);

  const ArticulatedSystem* system_ = nullptr;
  bool stabilized_ = false;
  int n_ = 0, m_ = 0, mp_ = 0;
  /// The system's closure rows in stepper order (position, then gear rows).
  std::vector<int> rows_;
  double t_ = 0.0;  ///< the time of the last residual()
  Eigen::MatrixXd M_, T_, G_, G_all_, dense_;
  Eigen::VectorXd g_, phi_, phi_all_, GTl_, Mu_, Gu_, udot_, lambda_, r_;
  /// rowDerivatives(): the rows at y moved along one coordinate, and the
  /// derivatives (n × n and m × n).
  State moved_;
  Eigen::MatrixXd G_moved_, M_moved_, Kfull_, Cfull_, dGu_;
  Eigen::VectorXd dq_unit_, phi_moved_, column_, g_moved_;
  /// Stabilized: G_p(q_n), Ḡ_p, M(q_n) factored (SPD: no prescribed
  /// coordinate), P = M(q_n)⁻¹ Ḡ_pᵀ.
  Eigen::MatrixXd Gp_start_, Gp_mid_, M_start_, P_, MP_;
  /// Constructed factored (of a 1 × 1 identity): Eigen's default-constructed
  /// LLT leaves its info unset, and copying the stepper read it (UBSan).
  Eigen::LLT<Eigen::MatrixXd> M_start_llt_{Eigen::MatrixXd::Identity(1, 1)};
  bool mid_fixed_ = false;
  Eigen::SparseMatrix<double> A_;
};

}  // namespace articulated

template <>
struct ConstrainedSystemTraits<articulated::ArticulatedSystem> {
  using Assembly = articulated::ArticulatedKktAssembly;
};

}  // namespace lieflow
