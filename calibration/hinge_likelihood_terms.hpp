/// \file
/// The likelihood hinge fit's residual of one sample and its Kaufman
/// Jacobian (hinge_likelihood_problem.hpp, equation (2)), and where each
/// sample's globals sit among all the free ones (one set of biases and ν,
/// or each recording's own). Internal to hinge_likelihood_problem.cpp.
#pragma once

#include <algorithm>
#include <cmath>

#include <Eigen/Core>

#include "calibration/hinge_likelihood_problem.hpp"
#include "calibration/unit_axis.hpp"
#include "liegroup/so3.hpp"

namespace lieflow {
namespace calibration {
namespace hinge_likelihood {

/// The five-point difference's half-width (fivePointRate) and its weights,
/// for the Jacobian.
constexpr int kHalfStencil = kHingeStencilHalfWidth;
constexpr double kStencil[2 * kHalfStencil + 1] = {1.0, -8.0, 0.0, 8.0, -1.0};

/// The globals one sample depends on, G, are a template parameter (5, 6, 10
/// or 11: withGlobals dispatches once per call), so every per-sample product
/// is of fixed size; so is the count of all free globals, Total, where it is
/// G (one set of biases and ν). With each recording's biases or ν its own,
/// Total is Eigen::Dynamic and a sample's columns are its recording's (widened).
template <int G>
using Globals = Eigen::Matrix<double, G, 1>;
/// Total + 1 columns: the globals' and the gradient's.
template <int Total>
constexpr int kPlusOne = Total == Eigen::Dynamic ? Eigen::Dynamic : Total + 1;
/// The first `total` columns of m, of fixed count where Total is fixed.
template <int Total, typename M>
auto leftTotal(M& m, int total) {
  if constexpr (Total == Eigen::Dynamic)
    return m.leftCols(total);
  else
    return m.template leftCols<Total>();
}
/// Whether G's globals hold the biases (b₁, b₂) and the clock offset ν.
template <int G>
constexpr bool kHasBiases = G >= 10;
template <int G>
constexpr bool kHasOffset = G == 6 || G == 11;
template <int G>
using GlobalMatrix = Eigen::Matrix<double, G, G>;

/// One interior sample's ρ_k, and with `jacobian` its Kaufman Jacobian: on
/// φ_{k−2} … φ_{k+2} (3 × 5) and on the free globals in the order j₁'s
/// tangent (2: perpendicularBasis(j₁)), C's (3: C ← exp(δ) C), b₁ (3), b₂ (2), ν.
template <int G>
struct SampleTerms {
  Eigen::Vector3d rho;
  Eigen::Matrix<double, 3, 2 * kHalfStencil + 1> phi;
  Eigen::Matrix<double, 3, G> globals;
  Eigen::Vector3d main_rate;  ///< x*
};

/// θ's pieces every sample reads, once per evaluation.
struct Frame {
  Eigen::Matrix3d ct;                      ///< Cᵀ
  Eigen::Matrix3d c;                       ///< C
  Eigen::Vector3d j;                       ///< j₁
  Eigen::Matrix<double, 3, 2> tangent;     ///< j₁'s tangent basis
  Eigen::Matrix3Xd b1;                     ///< B₁ b₁, a column per set of biases
  Eigen::Matrix3Xd b2;                     ///< E₂ b₂
  double scale;                            ///< w / √2
  explicit Frame(const HingeUnknowns& t, double weight) {
    c = t.mount.normalized().toRotationMatrix();
    ct = c.transpose();
    j = t.axis_main;
    tangent = perpendicularBasis(j);
    b1 = t.main_bias_basis * t.main_bias;
    b2 = t.secondary_bias_basis * t.secondary_bias;
    scale = weight / std::sqrt(2.0);
  }
};

/// The set of biases and of ν that recording r reads.
struct RecordingSets {
  int bias = 0;
  int offset = 0;
};
inline RecordingSets setsOf(const HingeUnknowns& t, int r) {
  return {std::min(r, static_cast<int>(t.main_bias.cols()) - 1),
          std::min(r, static_cast<int>(t.offset_fraction.size()) - 1)};
}

template <int G>
void sampleTerms(const HingeRates& m, const HingeUnknowns& t, const Frame& f, int k, double step, RecordingSets set,
                 bool jacobian, SampleTerms<G>* out) {
  const double rate = fivePointRate(t.phi, k, step);
  const double c = std::cos(t.phi[k]), s = std::sin(t.phi[k]);
  const Eigen::Vector3d& j = f.j;
  // exp(∓φ j₁) y by Rodrigues' formula.
  const auto turn = [&](const Eigen::Vector3d& y) {
    return (c * y - s * j.cross(y) + (1.0 - c) * j.dot(y) * j).eval();
  };
  const auto back = [&](const Eigen::Vector3d& y) {
    return (c * y + s * j.cross(y) + (1.0 - c) * j.dot(y) * j).eval();
  };
  const Eigen::Vector3d slope = m.secondary_slope.empty() ? Eigen::Vector3d::Zero() : m.secondary_slope[k];
  const Eigen::Vector3d a = m.main[k] - f.b1.col(set.bias);
  // b without its φ̇ term: m₂ − E₂ b₂ − ν ṁ₂.
  const Eigen::Vector3d b = m.secondary[k] - f.b2.col(set.bias) - t.offset_fraction[set.offset] * slope;
  out->rho = f.scale * (f.ct * (turn(a) + rate * j) - b);
  // x* = (a + Rᵀ b_full)/2 with Rᵀ = exp(φ j₁) C and b_full = b − φ̇ Cᵀ j₁.
  out->main_rate = 0.5 * (a + back(f.c * b) - rate * j);
  if (!jacobian) return;
  const Eigen::Vector3d& x = out->main_rate;
  const Eigen::Vector3d z = turn(x);
  const Eigen::Vector3d along = f.scale / (12.0 * step) * (f.ct * j);
  for (int i = 0; i <= 2 * kHalfStencil; ++i) out->phi.col(i) = kStencil[i] * along;
  // ∂/∂φ (Cᵀ exp(−φ j₁) x) = −Cᵀ (j₁ × exp(−φ j₁) x).
  out->phi.col(kHalfStencil) -= f.scale * (f.ct * j.cross(z));
  // ∂/∂j₁ of exp(−φ j₁) x: sin φ [x]× + (1 − cos φ)(j₁ xᵀ + (j₁·x) I); and φ̇ Cᵀ δ.
  Eigen::Matrix3d d = s * SO3d::hat(x) + (1.0 - c) * (j * x.transpose() + j.dot(x) * Eigen::Matrix3d::Identity());
  d.diagonal().array() += rate;
  out->globals.template leftCols<2>() = f.scale * (f.ct * d * f.tangent);
  // Cᵀ ← Cᵀ exp(−δ): ∂(Cᵀ v)/∂δ = Cᵀ [v]×, v = exp(−φ j₁) x + φ̇ j₁.
  out->globals.template middleCols<3>(2) = f.scale * (f.ct * SO3d::hat(z + rate * j));
  int col = 5;
  if constexpr (kHasBiases<G>) {
    for (int i = 0; i < 3; ++i) out->globals.col(col + i) = -f.scale * (f.ct * turn(t.main_bias_basis.col(i)));
    out->globals.template middleCols<2>(col + 3) = f.scale * t.secondary_bias_basis;
    col += 5;
  }
  if constexpr (kHasOffset<G>) out->globals.col(col) = f.scale * slope;
}

/// Calls f(k, h, r) for every interior sample k (a full stencil in its
/// recording r, sampled at interval h).
template <typename F>
void forInterior(const HingeRates& m, F&& f) {
  for (int r = 0; r < m.runs(); ++r)
    for (int k = m.run_begin[r] + kHalfStencil; k + kHalfStencil < m.run_begin[r + 1]; ++k) f(k, m.run_step[r], r);
}

/// A sample's Jacobian on the globals placed in the columns of all free
/// globals: its set's biases at 5 + 5 set, its ν at offset_base + its set
/// (offset_base: after every set of biases); itself where Total = G.
template <int G, int Total>
const Eigen::Matrix<double, 3, Total>& widened(const SampleTerms<G>& s, RecordingSets set, int total,
                                               int offset_base, Eigen::Matrix<double, 3, Total>* wide) {
  if constexpr (Total == G) {
    return s.globals;
  } else {
    wide->setZero(3, total);
    wide->template leftCols<5>() = s.globals.template leftCols<5>();
    if constexpr (kHasBiases<G>) wide->template middleCols<5>(5 + 5 * set.bias) = s.globals.template middleCols<5>(5);
    if constexpr (kHasOffset<G>) wide->col(offset_base + set.offset) = s.globals.col(G - 1);
    return *wide;
  }
}

}  // namespace hinge_likelihood
}  // namespace calibration
}  // namespace lieflow
