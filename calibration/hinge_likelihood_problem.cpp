#include "calibration/hinge_likelihood_problem.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include <Eigen/Cholesky>

#include "calibration/banded_cholesky.hpp"
#include "calibration/hinge_likelihood_terms.hpp"
#include "calibration/unit_axis.hpp"
#include "liegroup/so3.hpp"

namespace lieflow {
namespace calibration {
namespace {

using namespace hinge_likelihood;  // the terms of one sample (hinge_likelihood_terms.hpp)

constexpr int kBand = 2 * kHalfStencil;  // the normal equations' half-bandwidth

/// Levenberg–Marquardt's trust region μ (the damping is diag(JᵀJ)/μ), as
/// Ceres': its limits and the clamp of the diagonal. The first radius is the
/// largest: the start is a constraint fit's, close enough for Gauss–Newton
/// steps, and damping of even 1e-8 diag(JᵀJ) (Ceres' widest first radius)
/// holds back a weak direction of the angles — on a 1000-sample recording
/// the cost crept by 1e-6 per iteration for five iterations (10 in all),
/// where Gauss–Newton converges in 5. A refused step shrinks it (halved, then
/// by 4, 8, …: from here to 1e8 in seven refusals).
constexpr double kInitialRadius = 1e16;
constexpr double kMaxRadius = 1e16;
constexpr double kMinRadius = 1e-32;
constexpr double kMinDiagonal = 1e-6;
constexpr double kMaxDiagonal = 1e32;
/// A step is taken when the cost falls by at least this share of the
/// linear model's prediction.
constexpr double kMinRelativeDecrease = 1e-3;
/// A pivot below this share of its diagonal, or a Schur complement whose
/// squared pivot ratio is below it, is singular: the data do not determine
/// the unknowns (Ceres' covariance takes the same threshold of its
/// reciprocal condition).
constexpr double kSingular = 1e-14;

void checkSizes(const HingeRates& m, const HingeUnknowns& t) {
  const int n = m.samples();
  if (t.main_bias.cols() < 1 || t.secondary_bias.cols() != t.main_bias.cols() || t.main_bias.cols() > m.runs() ||
      t.offset_fraction.size() < 1 || t.offset_fraction.size() > m.runs())
    throw std::invalid_argument("hinge likelihood: the biases' or offsets' sets are not one or one per recording");
  if (static_cast<int>(m.secondary.size()) != n || static_cast<int>(t.phi.size()) != n ||
      (!m.secondary_slope.empty() && static_cast<int>(m.secondary_slope.size()) != n))
    throw std::invalid_argument("hinge likelihood: the rates, slopes and angles differ in length");
  if (m.runs() < 1 || static_cast<int>(m.run_begin.size()) != m.runs() + 1 || m.run_begin.front() != 0 ||
      m.run_begin.back() != n)
    throw std::invalid_argument("hinge likelihood: the recordings' bounds do not cover the samples");
  for (int r = 0; r < m.runs(); ++r)
    if (m.run_begin[r + 1] - m.run_begin[r] < 2 * kHalfStencil + 2 || !(m.run_step[r] > 0.0))
      throw std::invalid_argument("hinge likelihood: a recording has fewer than " +
                                  std::to_string(2 * kHalfStencil + 2) + " samples or no positive interval");
}


/// The normal equations JᵀJ δ = −Jᵀρ at θ: the angles' block banded
/// (band[k][d] = H(k, k − d), d ≤ 4), their border with the globals, the
/// globals' block, and the gradient. φ₀'s row is the identity (held).
template <int G, int Total>
struct Normal {
  int n = 0;
  int total = 0;  ///< free globals
  std::vector<double> band;
  Eigen::Matrix<double, Eigen::Dynamic, Total, Eigen::RowMajor> border;  ///< N × total
  GlobalMatrix<Total> globals;
  Eigen::VectorXd grad_phi;
  Globals<Total> grad_globals;
  double cost = 0.0;
  Eigen::Matrix<double, 3, 2> tangent;  ///< the j₁ tangent basis of this linearization

  Normal(int samples, int globals_count) : n(samples), total(globals_count) {
    band.resize(static_cast<std::size_t>(n) * (kBand + 1));
    border.resize(n, total);
    globals.resize(total, total);
    grad_phi.resize(n);
    grad_globals.resize(total);
  }
  double& at(int k, int d) { return band[static_cast<std::size_t>(k) * (kBand + 1) + d]; }
  double at(int k, int d) const { return band[static_cast<std::size_t>(k) * (kBand + 1) + d]; }

  void assemble(const HingeRates& m, const HingeUnknowns& t) {
    std::fill(band.begin(), band.end(), 0.0);
    border.setZero();
    globals.setZero();
    grad_phi.setZero();
    grad_globals.setZero();
    cost = 0.0;
    const Frame f(t, m.weight);
    tangent = f.tangent;
    SampleTerms<G> s;
    Eigen::Matrix<double, 3, Total> wide;
    const int offset_base = 5 + (kHasBiases<G> ? 5 * static_cast<int>(t.main_bias.cols()) : 0);
    forInterior(m, [&](int k, double step, int r) {
      const RecordingSets set = setsOf(t, r);
      sampleTerms(m, t, f, k, step, set, true, &s);
      if (k == kHalfStencil) s.phi.col(0).setZero();  // φ₀ of the first recording is held
      cost += 0.5 * s.rho.squaredNorm();
      const Eigen::Matrix<double, 3, Total>& sg = widened(s, set, total, offset_base, &wide);
      const int first = k - kHalfStencil;
      for (int i = 0; i <= kBand; ++i) {
        for (int l = 0; l <= i; ++l) at(first + i, i - l) += s.phi.col(i).dot(s.phi.col(l));
        border.row(first + i).noalias() += s.phi.col(i).transpose() * sg;
        grad_phi[first + i] += s.phi.col(i).dot(s.rho);
      }
      globals.noalias() += sg.transpose() * sg;
      grad_globals.noalias() += sg.transpose() * s.rho;
    });
    at(0, 0) = 1.0;
  }
};

/// Right-hand sides of the banded solves: one row per angle, a column per
/// global and one for the gradient (row-major: a row's update is one
/// short vector operation).
template <int Columns>
using BandRhs = Eigen::Matrix<double, Eigen::Dynamic, Columns, Eigen::RowMajor>;

/// A Cholesky factor whose squared pivot ratio (min/max)² is above kSingular,
/// as the banded factor's test: a singular Schur complement is refused.
template <typename Llt>
bool wellConditioned(const Llt& llt) {
  if (llt.info() != Eigen::Success) return false;
  const auto pivots = llt.matrixLLT().diagonal();
  const double ratio = pivots.minCoeff() / pivots.maxCoeff();
  return ratio * ratio > kSingular;
}

double clampedDiagonal(double d) { return std::min(std::max(d, kMinDiagonal), kMaxDiagonal); }

/// Buffers of the damped solves, reused across iterations.
template <int Total>
struct SolveWork {
  std::vector<double> band;
  BandRhs<kPlusOne<Total>> x;  ///< N × (total + 1): (H_φφ)⁻¹ [H_φg | −g_φ]
};

/// (H + diag(H)/μ) δ = −g by the banded Cholesky of the angles' block and
/// the Schur complement onto the globals (μ = ∞: undamped). False when
/// singular.
template <int G, int Total>
bool solveNormal(const Normal<G, Total>& h, double radius, SolveWork<Total>* w, Eigen::VectorXd* delta_phi,
                 Globals<Total>* delta_globals) {
  const int g = h.total;
  const double lambda = std::isinf(radius) ? 0.0 : 1.0 / radius;
  w->band = h.band;
  for (int k = 0; k < h.n; ++k)
    w->band[static_cast<std::size_t>(k) * (kBand + 1)] += lambda * clampedDiagonal(h.at(k, 0));
  if (!bandedCholesky<kBand>(&w->band, h.n, kSingular)) return false;
  w->x.resize(h.n, g + 1);
  leftTotal<Total>(w->x, g) = h.border;
  w->x.col(g) = -h.grad_phi;
  bandedSolve<kBand>(w->band, h.n, &w->x);
  GlobalMatrix<Total> s = h.globals;
  for (int i = 0; i < g; ++i) s(i, i) += lambda * clampedDiagonal(h.globals(i, i));
  s.noalias() -= h.border.transpose() * leftTotal<Total>(w->x, g);
  const Globals<Total> r = -h.grad_globals - h.border.transpose() * w->x.col(g);
  const Eigen::LLT<GlobalMatrix<Total>> llt(s);
  if (!wellConditioned(llt)) return false;
  *delta_globals = llt.solve(r);
  *delta_phi = w->x.col(g) - leftTotal<Total>(w->x, g) * *delta_globals;
  return true;
}

/// θ ⊞ δ: φ += δφ, j₁ along its great circle, C ← exp(δ) C, the rest added.
template <int G, int Total>
void plus(const HingeUnknowns& t, const Eigen::Matrix<double, 3, 2>& tangent, const Eigen::VectorXd& delta_phi,
          const Globals<Total>& delta, HingeUnknowns* out_ptr) {
  HingeUnknowns& out = *out_ptr;
  out = t;
  for (std::size_t k = 0; k < out.phi.size(); ++k) out.phi[k] += delta_phi[static_cast<Eigen::Index>(k)];
  const Eigen::Vector3d v = tangent * delta.template head<2>();
  const double angle = v.norm();
  if (angle > 0.0) out.axis_main = (std::cos(angle) * t.axis_main + std::sin(angle) / angle * v).normalized();
  out.mount = (SO3d::exp(delta.template segment<3>(2)).quaternion() * t.mount).normalized();
  int col = 5;
  if constexpr (kHasBiases<G>)
    for (Eigen::Index b = 0; b < out.main_bias.cols(); ++b, col += 5) {
      out.main_bias.col(b) += delta.template segment<3>(col);
      out.secondary_bias.col(b) += delta.template segment<2>(col + 3);
    }
  if constexpr (kHasOffset<G>) out.offset_fraction += delta.segment(col, out.offset_fraction.size());
}

double norm(const HingeUnknowns& t, const HingeFreedoms& free) {
  double s = 2.0;  // |j₁|² + |q|²
  for (double p : t.phi) s += p * p;
  if (free.biases) s += t.main_bias.squaredNorm() + t.secondary_bias.squaredNorm();
  if (free.offset) s += t.offset_fraction.squaredNorm();
  return std::sqrt(s);
}

template <int G, int Total = G>
struct GlobalCounts {
  static constexpr int kSample = G;
  static constexpr int kTotal = Total;
};

/// Calls f(GlobalCounts<G, Total>) for a sample's globals G and all of them.
template <typename F>
auto withGlobals(const HingeFreedoms& free, F&& f) {
  if ((free.biases && free.bias_sets > 1) || (free.offset && free.offset_sets > 1)) {
    if (!free.biases) return f(GlobalCounts<6, Eigen::Dynamic>{});
    return free.offset ? f(GlobalCounts<11, Eigen::Dynamic>{}) : f(GlobalCounts<10, Eigen::Dynamic>{});
  }
  switch (free.sampleGlobals()) {
    case 5: return f(GlobalCounts<5>{});
    case 6: return f(GlobalCounts<6>{});
    case 10: return f(GlobalCounts<10>{});
    default: return f(GlobalCounts<11>{});
  }
}

template <int G>
double costOf(const HingeRates& rates, const HingeUnknowns& theta) {
  const Frame f(theta, rates.weight);
  SampleTerms<G> s;
  double cost = 0.0;
  forInterior(rates, [&](int k, double step, int r) {
    sampleTerms(rates, theta, f, k, step, setsOf(theta, r), false, &s);
    cost += 0.5 * s.rho.squaredNorm();
  });
  return cost;
}

template <int G, int Total>
HingeSolveSummary solve(const HingeRates& rates, HingeUnknowns* theta, const HingeFreedoms& free,
                        const HingeSolveOptions& options, HingeSigmas* sigmas) {
  HingeSolveSummary summary;
  // The linearization at θ and at the trial point: a step is taken by
  // swapping them (the trial's Jacobian is computed with its cost; Gauss–
  // Newton steps are rarely refused, so it is rarely wasted).
  Normal<G, Total> h(rates.samples(), free.globals()), next(rates.samples(), free.globals());
  h.assemble(rates, *theta);
  summary.initial_cost = summary.final_cost = h.cost;
  // h is always the linearization at *theta: the σ come from it, without
  // assembling the solution's normal equations again.
  const auto iterate = [&] {
    if (options.progress) options.progress(0, h.cost);
    const auto gradientVanished = [&] {
      return std::max(h.grad_phi.cwiseAbs().maxCoeff(), h.grad_globals.cwiseAbs().maxCoeff()) <=
             options.gradient_tolerance;
    };
    if (gradientVanished()) {
      summary.stop = HingeSolveSummary::Stop::kGradientVanished;
      return;
    }
    SolveWork<Total> work;
    Eigen::VectorXd delta_phi;
    Globals<Total> delta;
    HingeUnknowns trial;
    double radius = kInitialRadius, decrease = 2.0;
    for (int iteration = 1; iteration <= options.max_iterations; ++iteration) {
      summary.iterations = iteration;
      const auto reject = [&] {
        radius /= decrease;
        decrease *= 2.0;
      };
      if (!solveNormal(h, radius, &work, &delta_phi, &delta)) {
        reject();
        if (radius < kMinRadius) {
          summary.stop = HingeSolveSummary::Stop::kSingular;
          return;
        }
        continue;
      }
      const double step = std::sqrt(delta_phi.squaredNorm() + delta.squaredNorm());
      if (step <= options.parameter_tolerance * (norm(*theta, free) + options.parameter_tolerance)) {
        summary.stop = HingeSolveSummary::Stop::kStepVanished;
        return;
      }
      plus<G, Total>(*theta, h.tangent, delta_phi, delta, &trial);
      next.assemble(rates, trial);
      // The linear model's decrease: −gᵀδ − ½ δᵀHδ = ½ (δᵀ D δ / μ − gᵀδ).
      double damped = 0.0;
      for (int k = 0; k < h.n; ++k) damped += clampedDiagonal(h.at(k, 0)) * delta_phi[k] * delta_phi[k];
      for (int i = 0; i < h.total; ++i) damped += clampedDiagonal(h.globals(i, i)) * delta[i] * delta[i];
      const double predicted = 0.5 * (damped / radius - h.grad_phi.dot(delta_phi) - h.grad_globals.dot(delta));
      const double ratio = (h.cost - next.cost) / predicted;
      if (std::isfinite(next.cost) && predicted > 0.0 && ratio > kMinRelativeDecrease) {
        const double change = h.cost - next.cost;
        std::swap(*theta, trial);
        std::swap(h, next);
        summary.final_cost = h.cost;
        radius = std::min(kMaxRadius, radius / std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * ratio - 1.0, 3)));
        decrease = 2.0;
        if (options.progress) options.progress(iteration, h.cost);
        if (change <= options.function_tolerance * h.cost) {
          summary.stop = HingeSolveSummary::Stop::kCostStopped;
          return;
        }
        if (gradientVanished()) {
          summary.stop = HingeSolveSummary::Stop::kGradientVanished;
          return;
        }
      } else {
        reject();
        if (options.progress) options.progress(iteration, h.cost);
        if (radius < kMinRadius) {
          summary.stop = HingeSolveSummary::Stop::kCostStopped;
          return;
        }
      }
      if (options.interrupt && options.interrupt()) {
        summary.stop = HingeSolveSummary::Stop::kInterrupted;
        return;
      }
    }
    summary.stop = HingeSolveSummary::Stop::kIterationLimit;
    return;
  };
  iterate();
  if (sigmas) summary.covariance = sigmasAt(h, *theta, 1.0, sigmas);
  return summary;
}

/// The σ from the linearization `h` at θ.
template <int G, int Total>
bool sigmasAt(const Normal<G, Total>& h, const HingeUnknowns& theta, double scale, HingeSigmas* sigmas) {
  // The globals' covariance: the inverse of the Schur complement
  // S = H_gg − H_gφ H_φφ⁻¹ H_φg of the undamped Gauss–Newton matrix.
  std::vector<double> band = h.band;
  if (!bandedCholesky<kBand>(&band, h.n, kSingular)) return false;
  BandRhs<Total> x = h.border;
  bandedSolve<kBand>(band, h.n, &x);
  GlobalMatrix<Total> s = h.globals;
  s.noalias() -= h.border.transpose() * x;
  const Eigen::LLT<GlobalMatrix<Total>> llt(s);
  if (!wellConditioned(llt)) return false;
  const GlobalMatrix<Total> covariance = scale * llt.solve(GlobalMatrix<Total>::Identity(h.total, h.total));
  // j₂ = Cᵀ j₁: ∂j₂ = Cᵀ E δj + Cᵀ [j₁]× δC (C ← exp(δC) C).
  const Eigen::Matrix3d ct = theta.mount.normalized().toRotationMatrix().transpose();
  Eigen::Matrix<double, 3, 5> d;
  d << ct * h.tangent, ct * SO3d::hat(theta.axis_main);
  sigmas->axis_main = std::sqrt(covariance.template topLeftCorner<2, 2>().trace());
  sigmas->axis_secondary = std::sqrt((d * covariance.template topLeftCorner<5, 5>() * d.transpose()).trace());
  int col = 5;
  sigmas->main_bias.clear();
  sigmas->secondary_bias.clear();
  if constexpr (kHasBiases<G>)
    for (Eigen::Index b = 0; b < theta.main_bias.cols(); ++b, col += 5) {
      sigmas->main_bias.push_back(std::sqrt(covariance.block(col, col, 3, 3).trace()));
      sigmas->secondary_bias.push_back(std::sqrt(covariance.block(col + 3, col + 3, 2, 2).trace()));
    }
  sigmas->offset_fraction.clear();
  if constexpr (kHasOffset<G>)
    for (Eigen::Index o = 0; o < theta.offset_fraction.size(); ++o)
      sigmas->offset_fraction.push_back(std::sqrt(covariance(col + o, col + o)));
  return std::isfinite(sigmas->axis_main) && std::isfinite(sigmas->axis_secondary);
}

template <int G, int Total>
bool sigmasOf(const HingeRates& rates, const HingeUnknowns& theta, const HingeFreedoms& free, double scale,
              HingeSigmas* sigmas) {
  Normal<G, Total> h(rates.samples(), free.globals());
  h.assemble(rates, theta);
  return sigmasAt(h, theta, scale, sigmas);
}

}  // namespace

std::string HingeSolveSummary::message() const {
  const std::string its = std::to_string(iterations + 1) + " iterations";
  switch (stop) {
    case Stop::kGradientVanished: return "converged: the cost's gradient vanished (" + its + ")";
    case Stop::kStepVanished:
      return "converged: the parameters stopped changing, to a relative step below the tolerance (" + its + ")";
    case Stop::kCostStopped:
      return "converged: the cost stopped changing, to a relative change below the tolerance (" + its + ")";
    case Stop::kIterationLimit:
      return "not converged: the solver stopped at its limit of iterations (" + its + "; `max_iterations` raises it)";
    case Stop::kInterrupted: return "stopped on request after " + its;
    case Stop::kSingular: break;
  }
  return "failed: the least-squares system was singular: the data do not determine the parameters";
}

double hingeLikelihoodCost(const HingeRates& rates, const HingeUnknowns& theta, const HingeFreedoms& free) {
  checkSizes(rates, theta);
  return withGlobals(free, [&](auto g) { return costOf<decltype(g)::kSample>(rates, theta); });
}

int hingeLikelihoodDegreesOfFreedom(const HingeRates& rates, const HingeFreedoms& free) {
  int interior = 0;
  forInterior(rates, [&](int, double, int) { ++interior; });
  return 3 * interior - (rates.samples() - 1) - free.globals();
}

std::vector<Eigen::Vector3d> hingeMainRates(const HingeRates& rates, const HingeUnknowns& theta) {
  checkSizes(rates, theta);
  const Frame f(theta, rates.weight);
  std::vector<Eigen::Vector3d> x(rates.main.size());
  for (int r = 0; r < rates.runs(); ++r)
    for (int k = rates.run_begin[r]; k < rates.run_begin[r + 1]; ++k)
      x[k] = rates.main[k] - f.b1.col(setsOf(theta, r).bias);
  SampleTerms<5> s;
  forInterior(rates, [&](int k, double step, int r) {
    sampleTerms(rates, theta, f, k, step, setsOf(theta, r), false, &s);
    x[k] = s.main_rate;
  });
  return x;
}

HingeSolveSummary solveHingeLikelihood(const HingeRates& rates, HingeUnknowns* theta, const HingeFreedoms& free,
                                       const HingeSolveOptions& options, HingeSigmas* sigmas) {
  checkSizes(rates, *theta);
  if ((free.biases && theta->main_bias.cols() != free.bias_sets) ||
      (free.offset && theta->offset_fraction.size() != free.offset_sets))
    throw std::invalid_argument("hinge likelihood: the biases' columns or the offsets differ from their sets");
  return withGlobals(free, [&](auto g) {
    return solve<decltype(g)::kSample, decltype(g)::kTotal>(rates, theta, free, options, sigmas);
  });
}

bool hingeLikelihoodSigmas(const HingeRates& rates, const HingeUnknowns& theta, const HingeFreedoms& free,
                           double scale, HingeSigmas* sigmas) {
  checkSizes(rates, theta);
  if ((free.biases && theta.main_bias.cols() != free.bias_sets) ||
      (free.offset && theta.offset_fraction.size() != free.offset_sets))
    throw std::invalid_argument("hinge likelihood: the biases' columns or the offsets differ from their sets");
  return withGlobals(free, [&](auto g) {
    return sigmasOf<decltype(g)::kSample, decltype(g)::kTotal>(rates, theta, free, scale, sigmas);
  });
}

}  // namespace calibration
}  // namespace lieflow
