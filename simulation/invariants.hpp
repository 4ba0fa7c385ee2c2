/// \file
/// The quantities a scene conserves besides (or instead of) its spatial
/// angular momentum, for the `invariants` key of `--stats` and the drift
/// plots (../shared/DESIGN.md, Additions). Which ones a scene has follows
/// from its structure, checked once when the scene is assembled:
/// - a torque-free single body: its angular momentum about the centre of
///   mass `L_com` = R J ω (with or without gravity, which exerts no moment
///   about the centre of mass);
/// - a body on a fixed pivot with no torque but gravity g: the component of
///   its angular momentum about the pivot along g, `L_z` (named `L_vertical`
///   when g is not along z): the gravity moment (R c) × m g is ⊥ g; without
///   gravity the whole `L_pivot`;
/// - a body whose inertia (about the centre of mass, or about the pivot)
///   is symmetric about an axis e (two equal principal moments), torque-free
///   or with the centre of mass on that axis: its `spin` ω·e (Euler's third
///   equation J₃ω̇₃ = (J₁ − J₂)ω₁ω₂ + τ·e = 0);
/// - a multibody scene without external moments: its spatial angular
///   momentum `L`;
/// - a multibody scene without external forces but uniform gravity (no
///   joint to the ground, no supported rotation-only body, no loads from a
///   program): its angular momentum about the centre of mass,
///   `L_com` = Σ R_i J_i ω_i + (p_i − c) × m_i (v_i − v_c): gravity
///   m_i g acts at each centre and Σ (p_i − c) × m_i g = 0 (beside `L`
///   without gravity: the quantity a free-floating mechanism's users watch);
/// - a scene whose only non-conservative forces are the joints' dashpots:
///   its `energy_balance`, the energy plus the work W(t) = ∫₀ᵗ Σ c φ̇² dτ the
///   dashpots dissipated, integrated over the observed steps by
///   DissipatedWork (fourth order: the trapezoidal rule alone, second order,
///   would hide a fourth-order integrator's own balance).
/// A drift is relative (relativeDrift): vectors ‖x − x₀‖/‖x₀‖; `L_z` against
/// ‖L₀‖ about the pivot (the component alone may be 0); `spin` against ‖ω₀‖;
/// absolute when the scale is zero or near it.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>

#include "liegroup/so3.hpp"

namespace lieflow {

/// A reference value at or below this magnitude (SI units) counts as zero
/// for relative errors: the reciprocal of the largest input magnitude
/// (kMaxInputMagnitude, liegroup/input_number.hpp), thirty orders below any
/// energy, momentum or rate of a mechanism. A body at rest with 1e-300 of
/// energy, which then falls, would otherwise report its round-off divided
/// by 1e-300.
inline constexpr double kNearZeroScale = 1e-30;

/// error / scale, or the error itself (absolute) when |scale| is zero or
/// near it (kNearZeroScale): every relative drift and error lieflow reports
/// (energy, momentum, invariants, the study's ω error) is taken so.
inline double relativeDrift(double error, double scale) {
  return std::abs(scale) > kNearZeroScale ? error / std::abs(scale) : error;
}

/// W(t) = ∫₀ᵗ P dτ from the values of P ≥ 0 at the observed times t₀ < t₁ < …:
/// the trapezoidal sum T with Gregory's end corrections (the Euler–Maclaurin
/// formula, ∫ = T − h²/12 [P′]₀ᵗ + O(h⁴) on steps h), P′ at either end from
/// the three samples there by the one-sided second-order difference (any
/// spacing), h the end step there: fourth order on fixed steps (second on
/// uneven ones, as the trapezoidal sum alone).
class DissipatedWork {
 public:
  void add(double t, double P) {
    if (n_ > 0) trapezoid_ += 0.5 * (t - t_[2]) * (P_[2] + P);
    t_ = {t_[1], t_[2], t};
    P_ = {P_[1], P_[2], P};
    if (n_ < 3) {
      start_t_[n_] = t;
      start_P_[n_] = P;
    }
    ++n_;
  }
  double value() const {
    if (n_ < 3) return trapezoid_;
    const double h_end = t_[2] - t_[1], h_start = start_t_[1] - start_t_[0];
    const double end = derivative(t_, P_, 2), start = derivative(start_t_, start_P_, 0);
    return trapezoid_ - (h_end * h_end * end - h_start * h_start * start) / 12.0;
  }

 private:
  /// P′ at t[at] (0 or 2) from the quadratic through the three samples.
  static double derivative(const std::array<double, 3>& t, const std::array<double, 3>& P, int at) {
    const double x = t[at];
    double d = 0.0;
    for (int i = 0; i < 3; ++i) {
      // d/dx of the Lagrange basis polynomial ℓ_i at x.
      double numerator = 0.0, denominator = 1.0;
      for (int j = 0; j < 3; ++j) {
        if (j == i) continue;
        denominator *= t[i] - t[j];
        double product = 1.0;
        for (int k = 0; k < 3; ++k)
          if (k != i && k != j) product *= x - t[k];
        numerator += product;
      }
      d += P[i] * numerator / denominator;
    }
    return d;
  }

  std::array<double, 3> t_{{0.0, 0.0, 0.0}}, P_{{0.0, 0.0, 0.0}};
  std::array<double, 3> start_t_{{0.0, 0.0, 0.0}}, start_P_{{0.0, 0.0, 0.0}};
  double trapezoid_ = 0.0;
  long n_ = 0;
};

class InvariantSet {
 public:
  /// Two principal moments count as equal within this relative difference.
  static constexpr double kSymmetryTolerance = 1e-12;

  /// A single body with inertia J about its centre of mass (or, with a
  /// pivot, about the pivot), centre of mass at `com_from_pivot` (body axes)
  /// when pivoted, gravity g; `torque_free`: no spring, no applied torque.
  static InvariantSet singleBody(const Eigen::Matrix3d& J, bool pivot, const Eigen::Vector3d& com_from_pivot,
                                 const Eigen::Vector3d& gravity, bool torque_free) {
    InvariantSet s;
    s.single_ = true;
    s.J_ = J;
    if (!torque_free) return s;
    const bool gravity_moment = pivot && !gravity.isZero(0) && !com_from_pivot.isZero(0);
    if (!gravity_moment) {
      s.add(pivot ? "L_pivot" : "L_com", Kind::kMomentum);
    } else {
      s.vertical_ = gravity.normalized();
      const bool along_z = std::abs(std::abs(s.vertical_.z()) - 1.0) <= kSymmetryTolerance;
      s.add(along_z ? "L_z" : "L_vertical", Kind::kVerticalMomentum);
    }
    // A symmetry axis: the principal axis of the eigenvalue the other two equal.
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(J);
    const Eigen::Vector3d m = eig.eigenvalues();  // ascending
    const double tol = kSymmetryTolerance * m.cwiseAbs().maxCoeff();
    int axis = -1;
    if (std::abs(m[1] - m[2]) <= tol && std::abs(m[0] - m[1]) > tol) axis = 0;
    if (std::abs(m[0] - m[1]) <= tol && std::abs(m[1] - m[2]) > tol) axis = 2;
    if (axis >= 0) {
      const Eigen::Vector3d e = eig.eigenvectors().col(axis).normalized();
      const double c = com_from_pivot.norm();
      if (!gravity_moment || e.cross(com_from_pivot).norm() <= kSymmetryTolerance * c) {
        s.spin_axis_ = e;
        s.add("spin", Kind::kSpin);
      }
    }
    return s;
  }

  /// A multibody scene: its spatial angular momentum, its angular momentum
  /// about the centre of mass and its energy balance, each if conserved.
  static InvariantSet multibody(bool momentum_conserved, bool com_momentum_conserved, bool energy_balance) {
    InvariantSet s;
    if (momentum_conserved) s.add("L", Kind::kMomentum);
    if (com_momentum_conserved) s.add("L_com", Kind::kComMomentum);
    if (energy_balance) s.add("energy_balance", Kind::kEnergyBalance);
    return s;
  }

  const std::vector<std::string>& names() const { return names_; }
  bool empty() const { return names_.empty(); }

  /// Records the values of a single body's state (ω in the body frame).
  void observe(const SO3d& R, const Eigen::Vector3d& omega) {
    const Eigen::Vector3d L = R * (J_ * omega);
    observeEach([&](Kind kind) -> std::pair<Eigen::Vector3d, double> {
      switch (kind) {
        case Kind::kMomentum: return {L, L.norm()};
        case Kind::kVerticalMomentum: return {Eigen::Vector3d(L.dot(vertical_), 0, 0), L.norm()};
        case Kind::kSpin: return {Eigen::Vector3d(omega.dot(spin_axis_), 0, 0), omega.norm()};
        default: break;  // multibody kinds
      }
      return {Eigen::Vector3d::Zero(), 0.0};
    });
  }

  /// What a multibody state contributes to its invariants.
  struct MultibodyValues {
    Eigen::Vector3d L = Eigen::Vector3d::Zero();      ///< about the world origin
    Eigen::Vector3d L_com = Eigen::Vector3d::Zero();  ///< about the centre of mass
    double energy = 0.0;
  };

  /// Whether observe(t, MultibodyValues) needs L_com and the energy (else
  /// only L).
  bool needsMultibodyValues() const { return has(Kind::kComMomentum) || has(Kind::kEnergyBalance); }

  /// Whether the dissipated work integrates the dashpots' power: then
  /// addPower takes it at every step (the quadrature of a power sampled only
  /// at the output rows would be the error of the figure).
  bool integratesPower() const { return has(Kind::kEnergyBalance); }

  /// Adds the dashpots' power P at time t (t increasing) to the dissipated
  /// work (DissipatedWork).
  void addPower(double t, double P) { work_.add(t, P); }

  /// Records a multibody state at time t, whose power addPower took.
  void observe(double, const MultibodyValues& v) {
    const double dissipated = work_.value();
    observeEach([&](Kind kind) -> std::pair<Eigen::Vector3d, double> {
      switch (kind) {
        case Kind::kComMomentum: return {v.L_com, v.L_com.norm()};
        case Kind::kEnergyBalance: {
          const double balance = v.energy + dissipated;
          return {Eigen::Vector3d(balance, 0, 0), std::abs(balance)};
        }
        default: return {v.L, v.L.norm()};
      }
    });
  }
  /// The work the dashpots dissipated up to the last observation.
  double dissipatedWork() const { return work_.value(); }

  /// Relative error of each invariant at the last observation and its
  /// maximum over all observations, in the order of names().
  const std::vector<double>& current() const { return current_; }
  const std::vector<double>& maxDrift() const { return max_; }

 private:
  enum class Kind { kMomentum, kVerticalMomentum, kSpin, kComMomentum, kEnergyBalance };

  bool has(Kind kind) const { return std::find(kinds_.begin(), kinds_.end(), kind) != kinds_.end(); }

  void add(const std::string& name, Kind kind) {
    names_.push_back(name);
    kinds_.push_back(kind);
    x0_.emplace_back(Eigen::Vector3d::Zero());
    scale_.push_back(0.0);
    current_.push_back(0.0);
    max_.push_back(0.0);
  }

  template <typename Value>
  void observeEach(Value&& value) {
    for (std::size_t i = 0; i < kinds_.size(); ++i) {
      const std::pair<Eigen::Vector3d, double> v = value(kinds_[i]);
      if (!started_) {
        x0_[i] = v.first;
        scale_[i] = v.second;
        continue;
      }
      const double e = (v.first - x0_[i]).norm();
      current_[i] = relativeDrift(e, scale_[i]);
      max_[i] = std::max(max_[i], current_[i]);
    }
    started_ = true;
  }

  bool single_ = false;
  bool started_ = false;
  DissipatedWork work_;
  Eigen::Matrix3d J_ = Eigen::Matrix3d::Identity();
  Eigen::Vector3d vertical_ = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d spin_axis_ = Eigen::Vector3d::UnitZ();
  std::vector<std::string> names_;
  std::vector<Kind> kinds_;
  std::vector<Eigen::Vector3d> x0_;
  std::vector<double> scale_, current_, max_;
};

}  // namespace lieflow
