/// \file
/// The generalized-α method in joint coordinates on a tree whose coupling
/// rows (α q̇₁ + q̇₂ = 0, URDF <mimic>, MJCF joint equalities) are constant
/// and linear there: G u = 0 with G fixed, so the motion lives on an affine
/// subspace and the rows are exact in reduced coordinates. With N an
/// orthonormal basis of ker G (identity on the coordinates no row touches,
/// so the rotation blocks keep their geometry), u = N w and
///   Nᵀ M N ẇ + Nᵀ g = 0
/// (the multipliers' forces Gᵀλ drop out: Nᵀ Gᵀ = 0). The generic stepper
/// (integrators/generalized_alpha.hpp) runs on w; the configuration moves
/// by N dq, so G q stays where it started to rounding.
/// CoupledGeneralizedAlphaStepper wraps it behind the full state, so the
/// run's observers see an ArticulatedState.
#pragma once

#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/QR>

#include "integrators/generalized_alpha.hpp"
#include "dynamics/joint_space/articulated_second_order.hpp"

namespace lieflow {
namespace articulated {

/// N kept as the structure it has: the identity on the coordinates no row
/// touches (free_rows[i] ↔ column free_cols[i]) and a dense block on the
/// touched ones (touched_rows × mixed_cols). Nᵀ A N then costs O(n t k) (t
/// touched coordinates, k mixed columns) where two dense products cost
/// O(n³): on Talos full (twelve gripper rows) they were two thirds of a
/// genalpha step (`perf`: Eigen's gebp kernel 67 %).
struct ReducedBasis {
  std::vector<int> free_rows, free_cols, touched_rows, mixed_cols;
  Eigen::MatrixXd block;  ///< N(touched_rows, mixed_cols)
  /// Scratch of reduce(): A's touched rows and columns and their products with the block.
  struct Scratch {
    Eigen::MatrixXd rows, left, cols, right;
  };

  /// From N (n × (n − m), kernelBasis's: identity columns exactly 1).
  explicit ReducedBasis(const Eigen::MatrixXd& N);
  /// n, the full coordinates' count, and n − m, the reduced ones'.
  Eigen::Index fullSize() const { return static_cast<Eigen::Index>(free_rows.size() + touched_rows.size()); }
  Eigen::Index reducedSize() const { return static_cast<Eigen::Index>(free_cols.size() + mixed_cols.size()); }
  /// u = N w.
  void expand(const Eigen::VectorXd& w, Eigen::VectorXd* u) const;
  /// w = Nᵀ u.
  void project(const Eigen::VectorXd& u, Eigen::VectorXd* w) const;
  /// out = Nᵀ A N (A n × n).
  void reduce(const Eigen::MatrixXd& A, Eigen::MatrixXd* out, Scratch* scratch) const;
};

/// The reduced state: the full one, its reduced velocity w (u = N w) and
/// the basis N it is read through.
struct CoupledArticulatedState {
  using Scalar = double;
  static constexpr int kTangentDim = Eigen::Dynamic;
  ArticulatedState full;
  Eigen::VectorXd w;
  std::shared_ptr<const ReducedBasis> N;
  /// Scratch of the traits below (N dq, N v, the full T and its reduction), sized at
  /// first use and kept by each state: copying a state leaves it alone (the
  /// stepper copies states every step; copied, the scratch would move sizes
  /// between them and allocate).
  struct Scratch {
    Eigen::VectorXd dq_full, v_full;
    Eigen::MatrixXd T_full;
    ReducedBasis::Scratch reduce;
    Scratch() = default;
    Scratch(const Scratch&) {}
    Scratch& operator=(const Scratch&) { return *this; }
  };
  mutable Scratch scratch;
};

/// The tree seen through N, with its full matrices as scratch.
struct CoupledArticulatedSystem {
  using Scalar = double;
  using State = CoupledArticulatedState;
  const ArticulatedSystem* system = nullptr;
  std::shared_ptr<const ReducedBasis> N;
  mutable Eigen::MatrixXd M, Ct, Kt;
  mutable Eigen::VectorXd g;
  mutable ReducedBasis::Scratch scratch;

  /// N for the coupling rows G (m × n, full row rank): on the coordinates
  /// some row touches, the last columns of the QR factor of that block of Gᵀ
  /// (an orthonormal basis of its kernel); the identity on the others.
  static Eigen::MatrixXd kernelBasis(const Eigen::MatrixXd& G);
};

}  // namespace articulated

template <>
struct SecondOrderStateTraits<articulated::CoupledArticulatedState> {
  using Scalar = double;
  using State = articulated::CoupledArticulatedState;
  using Full = SecondOrderStateTraits<articulated::ArticulatedState>;
  static constexpr int kDof = Eigen::Dynamic;
  using Vector = Eigen::VectorXd;
  using Matrix = Eigen::MatrixXd;

  static int dofs(const State& y) { return static_cast<int>(y.w.size()); }
  static const Vector& velocity(const State& y) { return y.w; }
  static void advanceInto(const State& y, const Vector& dq, const Vector& v, State* out) {
    y.N->expand(dq, &y.scratch.dq_full);
    y.N->expand(v, &y.scratch.v_full);
    Full::advanceInto(y.full, y.scratch.dq_full, y.scratch.v_full, &out->full);
    out->w = v;
    out->N = y.N;
  }
  /// T_r = Nᵀ T(N dq) N: exact, as T is the identity on the coordinates N mixes.
  static void tangentOperatorInto(const State& y, const Vector& dq, Matrix* T) {
    y.N->expand(dq, &y.scratch.dq_full);
    Full::tangentOperatorInto(y.full, y.scratch.dq_full, &y.scratch.T_full);
    y.N->reduce(y.scratch.T_full, T, &y.scratch.reduce);
  }
  static bool identical(const State& a, const State& b) { return Full::identical(a.full, b.full) && a.w == b.w; }
};

template <>
struct SecondOrderSystemTraits<articulated::CoupledArticulatedSystem> {
  using Scalar = double;
  using State = articulated::CoupledArticulatedState;
  using Vector = Eigen::VectorXd;
  using Matrix = Eigen::MatrixXd;
  static void evaluate(const articulated::CoupledArticulatedSystem& s, double t, const State& y, Matrix* M,
                       Vector* g, Matrix* Ct, Matrix* Kt) {
    s.system->secondOrderTerms(t, y.full, &s.M, &s.g, Ct ? &s.Ct : nullptr, Kt ? &s.Kt : nullptr);
    s.N->reduce(s.M, M, &s.scratch);
    s.N->project(s.g, g);
    if (Ct) s.N->reduce(s.Ct, Ct, &s.scratch);
    if (Kt) s.N->reduce(s.Kt, Kt, &s.scratch);
  }
};

namespace articulated {

/// genalpha on a tree with coupling rows, stepping the full state through
/// the reduced one (see the file comment); a stepper for integrateFixedStep.
class CoupledGeneralizedAlphaStepper {
 public:
  using State = ArticulatedState;
  CoupledGeneralizedAlphaStepper(const ArticulatedSystem& system, const Eigen::MatrixXd& G,
                                 GeneralizedAlphaOptions options)
      : inner_(options) {
    reduced_system_.system = &system;
    reduced_system_.N = std::make_shared<const ReducedBasis>(CoupledArticulatedSystem::kernelBasis(G));
  }

  const ArticulatedState& step(const ArticulatedSystem&, double t, const ArticulatedState& y, double h,
                               StepReport* report = nullptr) {
    // Continue from the reduced state when y is the last result (the
    // stepper's history, v̇ and a, belongs to it); else read y through N.
    if (!(have_last_ && SecondOrderStateTraits<ArticulatedState>::identical(y, last_.full))) {
      last_.full = y;
      last_.N = reduced_system_.N;
      reduced_system_.N->project(y.u, &last_.w);
    }
    last_ = inner_.step(reduced_system_, t, last_, h, report);
    have_last_ = true;
    return last_.full;
  }

 private:
  GeneralizedAlphaStepper<CoupledArticulatedState> inner_;
  CoupledArticulatedSystem reduced_system_;
  CoupledArticulatedState last_;
  bool have_last_ = false;
};

}  // namespace articulated
}  // namespace lieflow
