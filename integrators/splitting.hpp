/// \file
/// Explicit symplectic splitting of the rigid body (McLachlan, "Explicit
/// Lie–Poisson integration and the Euler equations", PRL 71 (1993); Touma &
/// Wisdom, "Lie–Poisson integrators for rigid body dynamics in the solar
/// system", AJ 107 (1994); Dullweber, Leimkuhler & McLachlan, "Symplectic
/// splitting methods for rigid body molecular dynamics", J. Chem. Phys. 107
/// (1997) 5840; Fassò, "Comparison of splitting algorithms for the rigid
/// body", J. Comput. Phys. 189 (2003) 527).
///
/// In the principal frame (J = Q diag(I) Qᵀ, found once in the constructor;
/// the drift acts on P = Qᵀ Π and on R Q), the kinetic energy is
/// T = Σᵢ Pᵢ²/(2Iᵢ), and the flow of every piece κ Pᵢ²/2 is exact: with
/// φ = τ κ Pᵢ, P ← Rotᵢ(−φ) P and R Q ← R Q Rotᵢ(φ), Rotᵢ the rotation about
/// the principal axis eᵢ. Each substep multiplies R by a rotation and Π by its
/// transpose, so the spatial angular momentum R Π is preserved to rounding.
///
/// Rounding: for a steady motion the same rotation recurs at every step, and
/// so does its rounding; a norm error of O(ε) per step would then accumulate
/// linearly (measured: ‖R Π‖ off by 2e-10 after 10⁶ steps). Hence the drift's
/// rotations are accumulated as one increment D = 1 + d (R_{k+1} = R_k Q D Qᵀ,
/// applied as R + R ⊗ (d_w, Q d_v)), P is rotated through cos φ − 1 = −2S²,
/// only the change P − P₀ goes back through Q, and ω = J⁻¹ Π is refined
/// (integrators/lgvi.hpp, detail::solveInertia): what remains is a random walk
/// (‖R Π‖ within 2e-13 after 10⁶ steps).
///
/// Two second-order Strang compositions (SplittingScheme):
///  * kAxisRotations: X_a(h/2) X_b(h/2) X_c(h) X_b(h/2) X_a(h/2), κ = 1/I,
///    with a = the axis of smallest moment, b = intermediate, and c, the one
///    in the middle taking the full step, = the axis of LARGEST moment.
///    Measured (free bodies with moments uniform in [0.5, 1.5], random ω and
///    R0, h = 0.02, 20 s, against the exact flow of exact_free_body.hpp; 40
///    bodies): the geometric-mean error relative to the best of the six orders
///    is 1.4 for this order, 1.9 and 2.3 for the other two with the largest
///    moment not outermost, and 3.9–4.0 with the smallest moment in the middle;
///    with the largest moment outermost the energy error is 2.5–6× larger.
///  * kSymmetricResidual (default; Touma & Wisdom 1994, Fassò 2003 "symmetric
///    + residual"): T = S + Rs with the exactly integrable axisymmetric part
///    S = |Π|²/(2I_s) + Π_k² (1/I_k − 1/I_s)/2 (its two pieces commute: |Π|² =
///    |R Π|² generates rotations in space, Π_k rotations in the body) and the
///    residual Rs = Π_j² (1/I_j − 1/I_s)/2, where (s, j) are the two axes whose
///    rates 1/I are closest; composition S(h/2) Rs(h) S(h/2), five rotations
///    per step like kAxisRotations. It is exact for an axisymmetric body.
///    Measured as above on 300 bodies with moments in [0.2, 1.2]: its error is
///    smaller than kAxisRotations' in 290 of them, by a geometric mean of
///    15–170× depending on the asymmetry (~30× for the most asymmetric bodies);
///    S(h/2) Rs(h) S(h/2) is 2× more accurate than Rs(h/2) S(h) Rs(h/2), whose
///    leading error term is linear, not quadratic, in the residual.
///
/// With an external torque M(t, R) (body frame), kick–drift–kick:
///   Π += (h/2) M(t_k, R_k);  free-body drift by the splitting;
///   Π += (h/2) M(t_{k+1}, R_{k+1}).
/// Translation (FreeBodyState): velocity Verlet, as in integrators/lgvi.hpp.
/// Explicit: no iterations, no allocation.
#pragma once

#include <cmath>
#include <sstream>
#include <type_traits>
#include <utility>

#include <Eigen/Eigenvalues>

#include "integrators/lgvi.hpp"
#include "integrators/rigid_body_state.hpp"
#include "integrators/step_report.hpp"
#include "liegroup/invalid_input.hpp"
#include "liegroup/so3.hpp"

namespace lieflow {

enum class SplittingScheme {
  kAxisRotations,      ///< three principal-axis rotations (McLachlan; Dullweber et al.)
  kSymmetricResidual,  ///< exact axisymmetric flow + one axis rotation (Touma–Wisdom; Fassò)
};

struct SplittingOptions {
  SplittingScheme scheme = SplittingScheme::kSymmetricResidual;
};

template <typename State>
class SplittingStepper {
 public:
  using Scalar = typename State::Scalar;
  static constexpr int kOrder = 2;

  /// inertia: the system's inertia (system.inertia()), symmetric positive
  /// definite. A non-diagonal inertia is diagonalized here (double or float
  /// scalars only; a ceres::Jet scalar needs a diagonal inertia). Throws
  /// InvalidInput("inertia", reason) for a non-positive or non-finite moment.
  explicit SplittingStepper(const Matrix3<Scalar>& inertia, SplittingOptions options = {})
      : options_(options) {
    principalAxes(inertia);
    chooseAxes();
  }

  const SplittingOptions& options() const { return options_; }
  /// Principal moments (in the order of the columns of principalAxes()).
  const Vector3<Scalar>& principalMoments() const { return moments_; }
  /// Q, a rotation whose columns are the principal axes in body coordinates.
  const Matrix3<Scalar>& principalAxes() const { return Q_; }

  /// One step of size h from (t, y). Explicit: the report (reset at entry)
  /// says 0 iterations, converged.
  template <typename System>
  State step(const System& system, const Scalar& t, const State& y, const Scalar& h,
             StepReport* report = nullptr) const {
    using T = Scalar;
    if (report) *report = StepReport{};
    LIEFLOW_ASSERT((scalarValue((system.inertia() - J_).cwiseAbs().maxCoeff()) <=
                    1e-12 * scalarValue(J_.cwiseAbs().maxCoeff())),
                   "SplittingStepper: system inertia differs from the constructor's");
    const bool torqued = system.hasExternalTorque();
    const T half_h = T(0.5) * h;

    // Body-frame momentum Π (with the first half kick) and its principal
    // components P₀ = Qᵀ Π.
    Vector3<T> momentum = system.inertia() * y.omega;
    if (torqued) momentum += half_h * system.externalTorque(t, y.R);
    const Vector3<T> P0 = rotated_ ? Vector3<T>(Q_.transpose() * momentum) : momentum;

    // The drift in the principal frame: P is rotated, and the rotation of the
    // drift, D = 1 + d, is accumulated as an increment (see updateIncrement).
    T P[3] = {P0.x(), P0.y(), P0.z()};
    T d[4] = {T(0), T(0), T(0), T(0)};
    if (options_.scheme == SplittingScheme::kAxisRotations) {
      axisFlow(axis_[0], inv_moments_[axis_[0]], half_h, d, P);
      axisFlow(axis_[1], inv_moments_[axis_[1]], half_h, d, P);
      axisFlow(axis_[2], inv_moments_[axis_[2]], h, d, P);
      axisFlow(axis_[1], inv_moments_[axis_[1]], half_h, d, P);
      axisFlow(axis_[0], inv_moments_[axis_[0]], half_h, d, P);
    } else {
      symmetricFlow(half_h, d, P);
      axisFlow(residual_axis_, residual_rate_, h, d, P);
      symmetricFlow(half_h, d, P);
    }

    // Back to the body frame: R_{k+1} = R_k Q D Qᵀ = R_k (1 + (d_w, Q d_v)), and
    // Π ← Π + Q (P − P₀) (only the change passes through Q, so Q's rounding
    // away from orthogonality cannot accumulate in ‖Π‖).
    State out = y;
    const Vector3<T> P1(P[0], P[1], P[2]);
    Vector3<T> dv(d[1], d[2], d[3]);
    if (rotated_) {
      dv = Q_ * dv;
      momentum += Q_ * (P1 - P0);
    } else {
      momentum = P1;
    }
    out.R = SO3<T>(detail::composeNearIdentity(y.R.quaternion(), d[0], dv));
    if (torqued) momentum += half_h * system.externalTorque(t + h, out.R);
    out.omega = detail::solveInertia(system.inertia(), system.inertiaInverse(), momentum);
    detail::velocityVerletTranslation(system, t, y, h, &out);
    return out;
  }

 private:
  using T = Scalar;

  /// d ← d + e + d ⊗ e, i.e. 1 + d ← (1 + d) ⊗ (1 + e), for e = (e_w, e_v)
  /// given by its real part e_w = cos − 1 and the index/value of a vector
  /// along one axis or a full vector. Increments keep the norm error of each
  /// factor at O(ε φ²) instead of O(ε) (see detail::composeNearIdentity in
  /// integrators/lgvi.hpp): a steady rotation would otherwise drift linearly.
  static void updateIncrement(T* d, const T& ew, const T* ev) {
    const T dw = d[0], dx = d[1], dy = d[2], dz = d[3];
    d[0] = dw + (ew + (dw * ew - (dx * ev[0] + dy * ev[1] + dz * ev[2])));
    d[1] = dx + (ev[0] + (dw * ev[0] + ew * dx + (dy * ev[2] - dz * ev[1])));
    d[2] = dy + (ev[1] + (dw * ev[1] + ew * dy + (dz * ev[0] - dx * ev[2])));
    d[3] = dz + (ev[2] + (dw * ev[2] + ew * dz + (dx * ev[1] - dy * ev[0])));
  }

  /// Exact flow of κ Πᵢ²/2 over τ: φ = τ κ Πᵢ, Π ← Rotᵢ(−φ) Π, R ← R Rotᵢ(φ),
  /// on the drift increment d and the principal momentum P.
  /// Rotᵢ(φ) = (C, S eᵢ) with C = cos(φ/2), S = sin(φ/2); on P it acts through
  /// cos φ − 1 = −2S² and sin φ = 2CS (one sine and one cosine per substep).
  static void axisFlow(int i, const T& kappa, const T& tau, T* d, T* P) {
    using std::cos;
    using std::sin;
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    const T half_phi = T(0.5) * tau * kappa * P[i];
    const T C = cos(half_phi), S = sin(half_phi);
    const T S_sq = S * S;
    const T m = T(-2) * S_sq, s = T(2) * C * S;
    // (Π_j, Π_k) ← [c s; −s c] (Π_j, Π_k), c = 1 + m.
    const T Pj = P[j], Pk = P[k];
    P[j] = Pj + (m * Pj + s * Pk);
    P[k] = Pk + (m * Pk - s * Pj);
    T ev[3] = {T(0), T(0), T(0)};
    ev[i] = S;
    updateIncrement(d, detail::quaternionRealMinusOne(C, S_sq), ev);
  }

  /// Exact flow of S = |Π|²/(2I_s) + Π_k²(1/I_k − 1/I_s)/2 over τ: the two
  /// commuting flows R ← R exp(τ Π/I_s) (Π unchanged) and the axis-k rotation.
  void symmetricFlow(const T& tau, T* d, T* P) const {
    T c, s;  // exp(w) = (c, s w) with w = τ Π/I_s (liegroup/detail/so3_kernels.hpp)
    const T scale = tau * inv_moments_[symmetric_axis_];
    const T w[3] = {scale * P[0], scale * P[1], scale * P[2]};
    detail::halfAngle(w[0] * w[0] + w[1] * w[1] + w[2] * w[2], &c, &s);
    const T ev[3] = {s * w[0], s * w[1], s * w[2]};
    const T ev_sq = ev[0] * ev[0] + ev[1] * ev[1] + ev[2] * ev[2];
    updateIncrement(d, detail::quaternionRealMinusOne(c, ev_sq), ev);
    axisFlow(unique_axis_, unique_rate_, tau, d, P);
  }

  /// J = Q diag(I) Qᵀ with det Q = +1 (so R Q is a rotation).
  void principalAxes(const Matrix3<T>& J) {
    J_ = J;
    const bool diagonal = J(0, 1) == T(0) && J(0, 2) == T(0) && J(1, 2) == T(0) &&
                          J(1, 0) == T(0) && J(2, 0) == T(0) && J(2, 1) == T(0);
    if (diagonal) {
      Q_.setIdentity();
      moments_ = J.diagonal();
      rotated_ = false;
    } else {
      if constexpr (std::is_floating_point<T>::value) {
        Eigen::SelfAdjointEigenSolver<Matrix3<T>> eig(J);
        Q_ = eig.eigenvectors();
        if (Q_.determinant() < T(0)) Q_.col(2) = -Q_.col(2);
        moments_ = eig.eigenvalues();
        rotated_ = true;
      } else {
        throw InvalidInput("inertia",
                           "SplittingStepper with a non-floating-point scalar (ceres::Jet) needs a "
                           "diagonal inertia (principal axes)");
      }
    }
    for (int i = 0; i < 3; ++i) {
      const double I = scalarValue(moments_[i]);
      if (!(I > 0.0) || !std::isfinite(I)) {
        std::ostringstream reason;
        reason << "principal moment " << I << " is not positive and finite";
        throw InvalidInput("inertia", reason.str());
      }
      inv_moments_[i] = T(1) / moments_[i];
    }
  }

  void chooseAxes() {
    const double I[3] = {scalarValue(moments_[0]), scalarValue(moments_[1]),
                         scalarValue(moments_[2])};
    // Axes sorted by moment: smallest, intermediate, largest.
    int order[3] = {0, 1, 2};
    for (int a = 0; a < 3; ++a)
      for (int b = a + 1; b < 3; ++b)
        if (I[order[b]] < I[order[a]]) std::swap(order[a], order[b]);
    // kAxisRotations: outer = smallest, then intermediate, middle = largest.
    axis_[0] = order[0];
    axis_[1] = order[1];
    axis_[2] = order[2];
    // kSymmetricResidual: (s, j) = the pair whose rates 1/I are closest (the
    // residual rate 1/I_j − 1/I_s is then the smallest), k the third; s = the
    // one of the pair farther from k (either gives the same |residual rate|).
    const bool low_pair = 1.0 / I[order[0]] - 1.0 / I[order[1]] <=
                          1.0 / I[order[1]] - 1.0 / I[order[2]];
    symmetric_axis_ = low_pair ? order[0] : order[2];
    residual_axis_ = order[1];
    unique_axis_ = low_pair ? order[2] : order[0];
    unique_rate_ = inv_moments_[unique_axis_] - inv_moments_[symmetric_axis_];
    residual_rate_ = inv_moments_[residual_axis_] - inv_moments_[symmetric_axis_];
  }

  SplittingOptions options_;
  Matrix3<T> J_;
  Matrix3<T> Q_;
  bool rotated_ = false;
  Vector3<T> moments_;
  Vector3<T> inv_moments_;
  int axis_[3] = {0, 1, 2};
  int symmetric_axis_ = 0, residual_axis_ = 1, unique_axis_ = 2;
  T unique_rate_, residual_rate_;
};

}  // namespace lieflow
