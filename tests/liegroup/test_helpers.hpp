/// \file
/// Shared helpers of the liegroup/ tests: deterministic sampling of tangent
/// vectors by angle band, central finite differences of right Jacobians,
/// ceres::Jet seeding and derivative extraction, and error measures.
///
/// Right-Jacobian convention of lieflow (liegroup/lie_group_base.hpp): the
/// Jacobian J of f at x satisfies f(x ⊕ δ) ≈ f(x) ⊕ J δ, so a finite-difference
/// column is (g(h e_j) − g(−h e_j)) / 2h with g(δ) = f(x ⊕ δ) ⊖ f(x).
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <iostream>
#include <random>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/LU>

#include "liegroup/scalar.hpp"
#include "liegroup/se3.hpp"
#include "liegroup/so3.hpp"

#ifdef LIEFLOW_HAVE_CERES
#include <ceres/jet.h>
#endif

namespace lieflow {
namespace test {

/// π to long double precision (M_PI is π rounded to double, 1.2e-16 below π).
constexpr long double kPiL = 3.141592653589793238462643383279502884L;
constexpr double kPi = 3.141592653589793;

#ifdef LIEFLOW_HAVE_CERES
/// One Jet type for both groups (6 = DoF of SE(3)); SO(3) seeds the first 3.
using Jet = ceres::Jet<double, 6>;
#endif

// ---- scalar traits ---------------------------------------------------------

/// Per-scalar tolerances of the generic property suite. `tol` bounds errors of
/// unit-scale quantities (matrices with entries ≤ 1, tangents with ‖·‖ ≤ π);
/// Jets carry double values, so they share the double tolerance.
template <typename T>
struct ScalarTraits;

template <>
struct ScalarTraits<double> {
  static constexpr double tol = 1e-12;
  static constexpr double eps = 2.220446049250313e-16;
  static constexpr bool is_jet = false;
  static const char* name() { return "double"; }
};

template <>
struct ScalarTraits<float> {
  static constexpr double tol = 2e-5;
  static constexpr double eps = 1.1920929e-07;
  static constexpr bool is_jet = false;
  static const char* name() { return "float"; }
};

#ifdef LIEFLOW_HAVE_CERES
template <>
struct ScalarTraits<Jet> {
  static constexpr double tol = 1e-12;
  static constexpr double eps = 2.220446049250313e-16;
  static constexpr bool is_jet = true;
  static const char* name() { return "Jet6"; }
};
#endif

// ---- the same group over another scalar ------------------------------------------

/// Rebind<SO3<T>>::As<S> = SO3<S>, Rebind<SE3<T>>::As<S> = SE3<S>.
template <typename G>
struct Rebind;
template <typename T>
struct Rebind<SO3<T>> {
  template <typename S>
  using As = SO3<S>;
  static const char* name() { return "SO3"; }
};
template <typename T>
struct Rebind<SE3<T>> {
  template <typename S>
  using As = SE3<S>;
  static const char* name() { return "SE3"; }
};

// ---- values of scalar / Jet matrices ----------------------------------------

/// Elementwise plain value (the `.a` part of a Jet) as a double matrix.
template <typename Derived>
Eigen::Matrix<double, Derived::RowsAtCompileTime, Derived::ColsAtCompileTime> values(
    const Eigen::MatrixBase<Derived>& m) {
  return m.unaryExpr([](const typename Derived::Scalar& x) { return scalarValue(x); });
}

/// ‖a − b‖_F / ‖b‖_F (b the reference); ‖a − b‖_F when ‖b‖_F = 0.
template <typename A, typename B>
double relativeError(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b) {
  const double diff = (a - b).norm();
  const double ref = b.norm();
  return ref > 0.0 ? diff / ref : diff;
}

// ---- sampling by angle band ---------------------------------------------------

/// A deterministic generator; every test seeds its own.
using Rng = std::mt19937_64;

/// Uniform direction on the unit sphere.
inline Eigen::Vector3d randomUnit(Rng& rng) {
  std::normal_distribution<double> normal;
  Eigen::Vector3d u;
  do {
    u = Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
  } while (u.norm() < 1e-6);
  return u.normalized();
}

/// Uniform point in the unit ball.
inline Eigen::Vector3d randomInBall(Rng& rng) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::Vector3d p;
  do {
    p = Eigen::Vector3d(uniform(rng), uniform(rng), uniform(rng));
  } while (p.squaredNorm() > 1.0);
  return p;
}

/// 10^U(log10 lo, log10 hi).
inline double logUniform(Rng& rng, double lo, double hi) {
  std::uniform_real_distribution<double> u(std::log10(lo), std::log10(hi));
  return std::pow(10.0, u(rng));
}

/// Where a sample's rotation angle θ lies. `theta < 0` means "random":
/// θ uniform in (0, π).
struct AngleBand {
  std::string name;
  double theta;
  bool nearIdentity() const { return theta >= 0.0 && theta < 1e-3; }
};

/// The points of the property and Jacobian suites: identity, near identity,
/// generic, near π.
inline std::vector<AngleBand> standardBands() {
  return {{"identity", 0.0},          {"theta=1e-9", 1e-9},         {"theta=1e-5", 1e-5},
          {"random", -1.0},           {"pi-1e-5", kPi - 1e-5},      {"pi-1e-9", kPi - 1e-9}};
}

/// Angles just below, at and above every series/closed-form switch of
/// detail/series.hpp (read from the header, so the bands follow it).
inline std::vector<AngleBand> thresholdBands() {
  const std::pair<const char*, double> switches[] = {
      {"kSmallAngleSq", detail::kSmallAngleSq},
      {"kHalfAngleThetaSq", detail::kHalfAngleThetaSq},
      {"kHalfCotThetaSq", detail::kHalfCotThetaSq},
      {"kThetaMinusSinThetaSq", detail::kThetaMinusSinThetaSq},
      {"kCosRemainderThetaSq", detail::kCosRemainderThetaSq},
      {"kSinCosMixThetaSq", detail::kSinCosMixThetaSq}};
  std::vector<AngleBand> bands;
  for (const auto& [name, theta_sq] : switches) {
    const std::string n = std::string("theta^2=") + name;
    bands.push_back({n + "*(1-1e-12)", std::sqrt(theta_sq * (1 - 1e-12))});
    bands.push_back({n, std::sqrt(theta_sq)});
    bands.push_back({n + "*(1+1e-12)", std::sqrt(theta_sq * (1 + 1e-12))});
  }
  return bands;
}

inline double bandAngle(const AngleBand& band, Rng& rng) {
  if (band.theta >= 0.0) return band.theta;
  std::uniform_real_distribution<double> u(0.0, kPi);
  return u(rng);
}

/// A rotation vector of the band's angle with a random direction.
inline Eigen::Vector3d sampleRotationVector(const AngleBand& band, Rng& rng) {
  const Eigen::Vector3d u = randomUnit(rng);
  return bandAngle(band, rng) * u;
}

/// A double tangent of group G (SO3 or SE3 over any scalar) in the band. For
/// SE(3) the translation part is random in the unit ball, scaled down with θ
/// near the identity so that the whole of ξ is small there.
template <typename G>
Eigen::Matrix<double, G::DoF, 1> sampleTangent(const AngleBand& band, Rng& rng) {
  const Eigen::Vector3d w = sampleRotationVector(band, rng);
  if constexpr (G::DoF == 3) {
    return w;
  } else {
    Eigen::Matrix<double, 6, 1> xi;
    const double rho_scale = band.nearIdentity() ? band.theta : 1.0;
    xi << rho_scale * randomInBall(rng), w;
    return xi;
  }
}

/// The rotation part of a tangent (all of it for SO(3)).
template <typename V>
Eigen::Vector3d rotationPart(const V& xi) {
  return values(xi.template tail<3>());
}

// ---- the continuous branch of log near π -------------------------------------

/// log(X) on the branch nearest `ref`. The principal log jumps at ‖ω‖ = π
/// (ω ↦ ω − 2π ω/‖ω‖ names the same rotation); finite differences across that
/// seam need the other representative. For SE(3) the translation part of the
/// other branch is V(ω')⁻¹ t with V = Jl, the matrix of SE3::exp.
inline Eigen::Vector3d logNear(const SO3d& X, const Eigen::Vector3d& ref) {
  const Eigen::Vector3d y = X.log();
  const double theta = y.norm();
  if (theta < 1.0) return y;
  const Eigen::Vector3d other = y * (1.0 - 2.0 * kPi / theta);
  return (other - ref).norm() < (y - ref).norm() ? other : y;
}

inline Eigen::Matrix<double, 6, 1> logNear(const SE3d& X, const Eigen::Matrix<double, 6, 1>& ref) {
  const Eigen::Matrix<double, 6, 1> y = X.log();
  const Eigen::Vector3d w = logNear(X.rotation(), ref.tail<3>());
  if ((w - y.tail<3>()).norm() == 0.0) return y;
  Eigen::Matrix<double, 6, 1> other;
  other << SO3d::Jl(w).lu().solve(X.translation()), w;
  return other;
}

// ---- finite differences -------------------------------------------------------

/// Central-difference Jacobian of g: ℝⁿ → ℝᵐ at 0, with g(0) = 0 expected
/// (g is a right-perturbation difference g(δ) = f(x ⊕ δ) ⊖ f(x)).
/// Step 1e-6: truncation O(h²) ~ 1e-12, rounding O(ε/h) ~ 1e-10.
inline Eigen::MatrixXd centralDifference(const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& g,
                                         int n, double h = 1e-6) {
  Eigen::MatrixXd J;
  for (int j = 0; j < n; ++j) {
    Eigen::VectorXd d = Eigen::VectorXd::Zero(n);
    d[j] = h;
    const Eigen::VectorXd col = (g(d) - g(-d)) / (2.0 * h);
    if (j == 0) J.resize(col.size(), n);
    J.col(j) = col;
  }
  return J;
}

// ---- ceres::Jet seeding ---------------------------------------------------------

#ifdef LIEFLOW_HAVE_CERES
/// Jet vector with value x and derivative part e_{offset+i} on component i.
template <int N>
Eigen::Matrix<Jet, N, 1> seed(const Eigen::Matrix<double, N, 1>& x, int offset = 0) {
  Eigen::Matrix<Jet, N, 1> j;
  for (int i = 0; i < N; ++i) j[i] = Jet(x[i], offset + i);
  return j;
}

/// Jet vector with value x and zero derivative.
template <int N>
Eigen::Matrix<Jet, N, 1> constant(const Eigen::Matrix<double, N, 1>& x) {
  return x.template cast<Jet>();
}

/// ∂m/∂(seed k): the k-th derivative part of every entry.
template <typename Derived>
Eigen::Matrix<double, Derived::RowsAtCompileTime, Derived::ColsAtCompileTime> derivative(
    const Eigen::MatrixBase<Derived>& m, int k) {
  return m.unaryExpr([k](const Jet& x) { return x.v[k]; });
}

/// The n×n... Jacobian of a Jet vector v w.r.t. the first n seeds.
template <typename Derived>
Eigen::MatrixXd jetJacobian(const Eigen::MatrixBase<Derived>& v, int n) {
  Eigen::MatrixXd J(v.size(), n);
  for (int i = 0; i < v.size(); ++i)
    for (int k = 0; k < n; ++k) J(i, k) = v[i].v[k];
  return J;
}

/// Right Jacobian of a Jet-valued group element Y(δ) w.r.t. the first DoF
/// seeds, read from its matrix: ∂M/∂δ_j = M₀ (J e_j)^, so column j is
/// vee(M₀⁻¹ ∂M/∂δ_j). This differentiates the group element itself, without
/// going through log.
template <typename GJet>
Eigen::MatrixXd jetRightJacobianOfGroup(const GJet& Y) {
  using Gd = typename std::conditional<GJet::DoF == 3, SO3d, SE3d>::type;
  const auto M = Y.matrix();
  const auto M0inv = values(M).inverse().eval();
  Eigen::MatrixXd J(GJet::DoF, GJet::DoF);
  for (int j = 0; j < GJet::DoF; ++j) {
    const typename Gd::Matrix dM = derivative(M, j);
    J.col(j) = Gd::vee(M0inv * dM);
  }
  return J;
}

/// Left Jacobian of a Jet-valued group element: column j = vee(∂M/∂δ_j M₀⁻¹).
template <typename GJet>
Eigen::MatrixXd jetLeftJacobianOfGroup(const GJet& Y) {
  using Gd = typename std::conditional<GJet::DoF == 3, SO3d, SE3d>::type;
  const auto M = Y.matrix();
  const auto M0inv = values(M).inverse().eval();
  Eigen::MatrixXd J(GJet::DoF, GJet::DoF);
  for (int j = 0; j < GJet::DoF; ++j) {
    const typename Gd::Matrix dM = derivative(M, j);
    J.col(j) = Gd::vee(dM * M0inv);
  }
  return J;
}
#endif

// ---- reporting -------------------------------------------------------------------

/// Running maximum with the point where it occurred, printed at the end.
struct MaxTracker {
  double value = 0.0;
  std::string where;
  void update(double v, const std::string& at) {
    if (std::isnan(value)) return;  // a NaN, once seen, is the verdict
    if (!(v <= value)) {            // also catches NaN
      value = v;
      where = at;
    }
  }
};

}  // namespace test
}  // namespace lieflow
