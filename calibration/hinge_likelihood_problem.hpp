/// \file
/// The least squares of the likelihood hinge fit (hinge_likelihood.hpp) with
/// the main body's true rates eliminated in closed form, and its
/// Levenberg–Marquardt solve on the banded normal equations that remain.
///
/// Per sample k the fit's residuals are, whitened by w = 1/σ,
///   r₁ = w (x − a),   a = m₁ − B₁ b₁,
///   r₂ = w (R x − b), R = Cᵀ exp(−φ j₁) (orthogonal), b = m₂ − E₂ b₂ − ν ṁ₂ − φ̇ Cᵀ j₁,
/// with x = ω₁,k the true rate. For fixed θ = (φ, j₁, C, biases, ν) the
/// x-part is linear with orthonormal columns: x* = (a + Rᵀ b)/2 and
///   min_x |r₁|² + |r₂|² = |ρ|²,   ρ = (w/√2)(R a − b),                      (2)
/// so the 3N unknowns x leave the problem exactly (variable projection,
/// Golub & Pereyra 1973). For its Jacobian the fit takes Kaufman's (1975):
///   J = (w/√2)(R a' + R' x* − b'),
/// whose JᵀJ is the Schur complement of the whole problem's Gauss–Newton
/// matrix onto θ.
/// Its gradient Jᵀρ is the exact gradient of (2) (the two Jacobians differ
/// by ½ R'Rᵀ ρ, and R'Rᵀ is skew), so the minimum is the whole problem's, and
/// (JᵀJ)⁻¹ at it is the whole problem's Gauss–Newton covariance of θ marginal
/// over the x: the same estimate and σ as a solve over every unknown
/// (tests/calibration/hinge_likelihood_problem_test.cpp checks both against
/// Ceres on the whole problem) at a fraction of its cost.
///
/// φ̇_k is the five-point difference of φ_{k−2} … φ_{k+2}, so JᵀJ is banded in
/// φ (half-bandwidth 4) with a dense border of at most 11 columns (j₁ on its
/// sphere: 2, C: 3, b₁: 3, b₂: 2, ν: 1; 5 more per recording whose biases are
/// its own): one banded Cholesky and a small Schur complement per
/// iteration, O(N).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace lieflow {
namespace calibration {

/// Samples on either side of the five-point difference of the joint angle.
constexpr int kHingeStencilHalfWidth = 2;

/// φ̇_k = (φ_{k−2} − 8φ_{k−1} + 8φ_{k+1} − φ_{k+2}) / 12h, error h⁴φ⁽⁵⁾/30
/// (k at least kHingeStencilHalfWidth from either end).
inline double fivePointRate(const std::vector<double>& phi, int k, double h) {
  return (phi[k - 2] - 8.0 * phi[k - 1] + 8.0 * phi[k + 1] - phi[k + 2]) / (12.0 * h);
}

/// What the fit measures: both gyroscopes at N samples in one or more
/// recordings, concatenated.
struct HingeRates {
  std::vector<Eigen::Vector3d> main;       ///< m₁,k
  std::vector<Eigen::Vector3d> secondary;  ///< m₂,k (paired with main k)
  /// ṁ₂ at the paired samples, for the clock offset's fraction ν (empty: zero).
  std::vector<Eigen::Vector3d> secondary_slope;
  /// Where each recording begins, and a last entry N: the five-point stencils
  /// stay within one recording (two recordings' samples are not neighbours).
  std::vector<int> run_begin;
  std::vector<double> run_step;  ///< each recording's sampling interval h [s]
  double weight = 1.0;           ///< w = 1/σ
  int samples() const { return static_cast<int>(main.size()); }
  int runs() const { return static_cast<int>(run_step.size()); }
};

/// The unknowns θ. φ of the first recording's first sample is held (it and
/// C's turn about j₁ are one freedom). b₁ are the main gyroscope's bias's
/// coordinates in `main_bias_basis` (3 × 3, orthonormal), b₂ the secondary's
/// in `secondary_bias_basis` (3 × 2, perpendicular to the start's j₂): one
/// column per set of biases (HingeFreedoms::bias_sets; recording r reads
/// column min(r, sets − 1)).
struct HingeUnknowns {
  std::vector<double> phi;
  Eigen::Vector3d axis_main = Eigen::Vector3d::UnitZ();  ///< j₁, unit
  Eigen::Quaterniond mount = Eigen::Quaterniond::Identity();  ///< C (C j₂ = j₁)
  Eigen::Matrix3Xd main_bias = Eigen::Matrix3Xd::Zero(3, 1);
  Eigen::Matrix2Xd secondary_bias = Eigen::Matrix2Xd::Zero(2, 1);
  /// ν [s]: one, or one per recording (HingeFreedoms::offset_sets; recording
  /// r reads entry min(r, sets − 1), as the biases).
  Eigen::VectorXd offset_fraction = Eigen::VectorXd::Zero(1);
  Eigen::Matrix3d main_bias_basis = Eigen::Matrix3d::Identity();
  Eigen::Matrix<double, 3, 2> secondary_bias_basis = Eigen::Matrix<double, 3, 2>::Zero();
  /// j₂ = Cᵀ j₁.
  Eigen::Vector3d axisSecondary() const { return mount.conjugate() * axis_main; }
};

/// Which of θ's global parts are free (φ, j₁ and C always are): with
/// `biases` (`offset`), one set shared by every recording or (bias_sets,
/// offset_sets = the number of recordings) each recording's own.
struct HingeFreedoms {
  bool biases = false;
  bool offset = false;
  int bias_sets = 1;
  int offset_sets = 1;
  /// The globals one sample's residual depends on: j₁ 2, C 3, its biases 5, its ν 1.
  int sampleGlobals() const { return 5 + (biases ? 5 : 0) + (offset ? 1 : 0); }
  /// All free globals, in the order j₁, C, each set's (b₁, b₂), each set's ν.
  int globals() const { return 5 + (biases ? 5 * bias_sets : 0) + (offset ? offset_sets : 0); }
};

/// Limits of the solve: far below any gyroscope's noise.
struct HingeSolveOptions {
  int max_iterations = 100;
  double function_tolerance = 1e-12;   ///< |Δcost| / cost
  double gradient_tolerance = 1e-12;   ///< max |∂cost/∂θ|
  double parameter_tolerance = 1e-12;  ///< |δθ| / (|θ| + tolerance)
  std::function<void(int, double)> progress;  ///< (iteration, cost) of each iteration
  std::function<bool()> interrupt;            ///< true stops the solve
};

/// Why the solve stopped.
struct HingeSolveSummary {
  enum class Stop { kCostStopped, kGradientVanished, kStepVanished, kIterationLimit, kInterrupted, kSingular };
  Stop stop = Stop::kIterationLimit;
  int iterations = 0;
  double initial_cost = 0.0;
  double final_cost = 0.0;  ///< ½ Σ |ρ|²
  bool covariance = false;  ///< σ asked for and found (the information is regular)
  bool converged() const {
    return stop == Stop::kCostStopped || stop == Stop::kGradientVanished || stop == Stop::kStepVanished;
  }
  std::string message() const;  ///< in the fits' words (solver_options.hpp's)
};

struct HingeSigmas;

/// Levenberg–Marquardt on (2) from `theta` (updated in place; its bias
/// matrices have bias_sets columns). With
/// `sigmas`, also hingeLikelihoodSigmas at the solution with scale 1 (from
/// the last linearization; summary.covariance says whether it was regular).
/// Throws std::invalid_argument when the sizes disagree or a recording has
/// fewer than six samples.
HingeSolveSummary solveHingeLikelihood(const HingeRates& rates, HingeUnknowns* theta, const HingeFreedoms& free,
                                       const HingeSolveOptions& options = {}, HingeSigmas* sigmas = nullptr);

/// ½ Σ |ρ_k|² at θ.
double hingeLikelihoodCost(const HingeRates& rates, const HingeUnknowns& theta, const HingeFreedoms& free);

/// The residuals less the unknowns: 3 per interior sample less (N − 1) angles
/// and the free globals (the x cancel against the 3N residuals of r₁).
int hingeLikelihoodDegreesOfFreedom(const HingeRates& rates, const HingeFreedoms& free);

/// The Gauss–Newton covariance of θ's globals marginal over the angles (and
/// the x), times `scale` (σ̂² for the fit, 1 for a bound with w = 1/σ).
struct HingeSigmas {
  double axis_main = 0.0;       ///< √trace of j₁'s covariance [rad]
  double axis_secondary = 0.0;  ///< √trace of j₂'s [rad]
  std::vector<double> main_bias;       ///< per set of biases: √trace of b₁'s [rad/s] (biases free)
  std::vector<double> secondary_bias;  ///< √trace of b₂'s [rad/s]
  std::vector<double> offset_fraction;  ///< per set of ν: its σ [s] (offset free)
};
/// False when the information matrix is singular (not identifiable).
bool hingeLikelihoodSigmas(const HingeRates& rates, const HingeUnknowns& theta, const HingeFreedoms& free,
                           double scale, HingeSigmas* sigmas);

/// The true main rates x*_k of (2) at θ (edge samples: a).
std::vector<Eigen::Vector3d> hingeMainRates(const HingeRates& rates, const HingeUnknowns& theta);

}  // namespace calibration
}  // namespace lieflow
