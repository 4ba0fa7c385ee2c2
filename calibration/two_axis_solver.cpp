#include "calibration/two_axis_solver.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <stdexcept>

#include <ceres/covariance.h>
#include <ceres/loss_function.h>
#include <ceres/solver.h>
#include <ceres/sphere_manifold.h>
#include <Eigen/Eigenvalues>

#include "calibration/unit_axis.hpp"

namespace lieflow {
namespace calibration {
namespace {

/// Median of the χ² distribution with d = 1, 2, 3 degrees of freedom.
double chiSquareMedian(int dof) {
  switch (dof) {
    case 1: return 0.45493642311957283;
    case 2: return 1.3862943611198906;  // 2 ln 2
    case 3: return 2.3659738843753377;
    default: throw std::logic_error("chiSquareMedian: 1 to 3 noise components per sample");
  }
}

double median(std::vector<double> v) {
  const std::size_t n = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + n, v.end());
  if (v.size() % 2) return v[n];
  const double upper = v[n];
  return 0.5 * (upper + *std::max_element(v.begin(), v.begin() + n));
}

std::string number(double x, const char* format) {
  char buf[32];
  std::snprintf(buf, sizeof buf, format, x);
  return buf;
}

std::unique_ptr<ceres::LossFunction> makeLoss(const AxisFitOptions& options) {
  switch (options.loss) {
    case RobustLoss::kHuber: return std::make_unique<ceres::HuberLoss>(options.loss_scale);
    case RobustLoss::kCauchy: return std::make_unique<ceres::CauchyLoss>(options.loss_scale);
    case RobustLoss::kNone: break;
  }
  return nullptr;
}

/// The problem: parameter blocks, residual blocks per kind and their weights.
class AxisProblem {
 public:
  AxisProblem(const std::vector<const ResidualKind*>& kinds, const AxisFitOptions& options,
              const NuisanceSelection& nuisance)
      : kinds_(kinds), weights_(kinds.size(), 1.0), ids_(kinds.size()), loss_(makeLoss(options)),
        problem_(problemOptions()) {
    bool uses_nuisance = false;
    for (std::size_t k = 0; k < kinds_.size(); ++k) {
      kinds_[k]->addBlocks(&problem_, loss_.get(), &weights_[k], axis1_, axis2_, nuisance_, &ids_[k]);
      uses_nuisance = uses_nuisance || kinds_[k]->usesNuisance();
    }
    problem_.SetManifold(axis1_, &sphere_);
    problem_.SetManifold(axis2_, &sphere_);
    active_ = uses_nuisance ? nuisance.count() : 0;
    if (uses_nuisance && active_ == 0) throw std::logic_error("two-axis fit: a nuisance kind with nothing to estimate");
    if (active_ > 0 && active_ < kNuisanceSize) {
      std::vector<int> constant;
      for (int i = 0; i < kNuisanceSize; ++i)
        if (!nuisance.active[i]) constant.push_back(i);
      subset_ = std::make_unique<ceres::SubsetManifold>(kNuisanceSize, constant);
      problem_.SetManifold(nuisance_, subset_.get());
    }
    for (int i = 0; i < kNuisanceSize; ++i)
      if (nuisance.active[i]) active_index_.push_back(i);
  }

  /// Estimated nuisance coordinates (0 without a nuisance block).
  int nuisanceCount() const { return active_; }
  double* nuisance() { return nuisance_; }
  /// The parameter blocks whose Jacobian the analyses use: the axes, then the nuisance.
  std::vector<double*> blocks() {
    std::vector<double*> b = {axis1_, axis2_};
    if (active_ > 0) b.push_back(nuisance_);
    return b;
  }
  void resetNuisance() {
    for (double& x : nuisance_) x = 0.0;
  }
  /// The estimated coordinates of the nuisance block, in order.
  Eigen::VectorXd activeNuisance() const {
    Eigen::VectorXd v(active_);
    for (int i = 0; i < active_; ++i) v[i] = nuisance_[active_index_[i]];
    return v;
  }
  void setActiveNuisance(const Eigen::VectorXd& v) {
    for (int i = 0; i < active_; ++i) nuisance_[active_index_[i]] = v[i];
  }

  ceres::Problem& problem() { return problem_; }
  double* axis1() { return axis1_; }
  double* axis2() { return axis2_; }
  std::size_t kindCount() const { return kinds_.size(); }
  const ResidualKind& kind(std::size_t k) const { return *kinds_[k]; }
  double weight(std::size_t k) const { return weights_[k]; }
  void setWeight(std::size_t k, double w) { weights_[k] = w; }

  void setAxes(const AxisPair& axes) {
    Eigen::Map<Eigen::Vector3d> a1(axis1_), a2(axis2_);
    a1 = axes.axis1.normalized();
    a2 = axes.axis2.normalized();
  }
  AxisPair axes() const {
    return {Eigen::Map<const Eigen::Vector3d>(axis1_), Eigen::Map<const Eigen::Vector3d>(axis2_)};
  }

  /// Unweighted squared norm of every block of kind k at the current axes.
  std::vector<double> blockSquaredNorms(std::size_t k) {
    ceres::Problem::EvaluateOptions eval;
    eval.residual_blocks = ids_[k];
    eval.apply_loss_function = false;
    std::vector<double> r;
    problem_.Evaluate(eval, nullptr, &r, nullptr, nullptr);
    const std::size_t blocks = ids_[k].size(), per_block = blocks ? r.size() / blocks : 0;
    const double w2 = weights_[k] * weights_[k];
    std::vector<double> q(blocks, 0.0);
    for (std::size_t b = 0; b < blocks; ++b)
      for (std::size_t i = 0; i < per_block; ++i) q[b] += r[b * per_block + i] * r[b * per_block + i] / w2;
    return q;
  }

  /// Every residual block, kind by kind, in sample order.
  std::vector<ceres::ResidualBlockId> allBlocks() const {
    std::vector<ceres::ResidualBlockId> all;
    for (const auto& ids : ids_) all.insert(all.end(), ids.begin(), ids.end());
    return all;
  }

  /// Residuals in one block of kind k.
  int residualsPerBlock(std::size_t k) const {
    return ids_[k].empty() ? 0 : problem_.GetCostFunctionForResidualBlock(ids_[k].front())->num_residuals();
  }

  /// Total noise components m.
  int noiseComponents() const {
    int m = 0;
    for (const ResidualKind* k : kinds_) m += k->blockCount() * k->noiseDof();
    return m;
  }

  /// SphereManifold's PlusJacobian at x (3×2, row-major).
  void plusJacobian(const double* x, double* jacobian) const { sphere_.PlusJacobian(x, jacobian); }

  /// The cost (with the loss) at the axes moved by the tangent step δ (4
  /// tangent coordinates) and the estimated nuisance moved by δν.
  double costAt(const AxisPair& base, const Eigen::Vector4d& delta, const Eigen::VectorXd& nuisance_delta) {
    const AxisPair saved = axes();
    const Eigen::VectorXd saved_nuisance = activeNuisance();
    const double b1[3] = {base.axis1.x(), base.axis1.y(), base.axis1.z()};
    const double b2[3] = {base.axis2.x(), base.axis2.y(), base.axis2.z()};
    sphere_.Plus(b1, delta.data(), axis1_);
    sphere_.Plus(b2, delta.data() + 2, axis2_);
    if (active_ > 0) setActiveNuisance(saved_nuisance + nuisance_delta);
    double cost = 0.0;
    for (std::size_t k = 0; k < kinds_.size(); ++k)
      cost += kinds_[k]->cost(axis1_, axis2_, nuisance_, &weights_[k], loss_.get());
    setAxes(saved);
    if (active_ > 0) setActiveNuisance(saved_nuisance);
    return cost;
  }

 private:
  static ceres::Problem::Options problemOptions() {
    ceres::Problem::Options o;
    o.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    o.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    return o;
  }

  std::vector<const ResidualKind*> kinds_;
  std::vector<double> weights_;
  std::vector<std::vector<ceres::ResidualBlockId>> ids_;
  std::unique_ptr<ceres::LossFunction> loss_;
  ceres::SphereManifold<3> sphere_;
  std::unique_ptr<ceres::SubsetManifold> subset_;
  double axis1_[3] = {1.0, 0.0, 0.0};
  double axis2_[3] = {1.0, 0.0, 0.0};
  double nuisance_[kNuisanceSize] = {0.0, 0.0, 0.0, 0.0, 0.0};
  int active_ = 0;
  std::vector<int> active_index_;
  ceres::Problem problem_;
};

/// σ̂ of kind k from its residuals at the current axes: the median form
/// (robust) or the RMS form with kind k's share of the 4 parameters.
double noiseScale(AxisProblem& p, std::size_t k, bool robust) {
  const std::vector<double> q = p.blockSquaredNorms(k);
  if (q.empty()) return kNoiseScaleFloor;
  const int d = p.kind(k).noiseDof();
  double variance;
  if (robust) {
    variance = median(q) / chiSquareMedian(d);
  } else {
    double sum = 0.0;
    for (double x : q) sum += x;
    const double mk = static_cast<double>(q.size()) * d;
    const double parameters = 4.0 + p.nuisanceCount();
    variance = sum / std::max(1.0, mk - parameters * mk / p.noiseComponents());
  }
  return std::max(std::sqrt(variance), kNoiseScaleFloor);
}

ceres::Solver::Options solverOptions(const AxisFitOptions& options) {
  ceres::Solver::Options o;
  o.linear_solver_type = ceres::DENSE_QR;
  o.max_num_iterations = options.max_iterations;
  o.function_tolerance = options.function_tolerance;
  o.gradient_tolerance = options.gradient_tolerance;
  o.parameter_tolerance = options.parameter_tolerance;
  o.logging_type = ceres::SILENT;
  o.minimizer_progress_to_stdout = false;
  o.num_threads = 1;
  return o;
}

/// Where one start's refinement ended, at the weights of the multi-start.
struct EndPoint {
  AxisPair axes;
  double cost;
  int start;
};

int iterationsOf(const ceres::Solver::Summary& s) {
  return std::max(0, s.num_successful_steps) + std::max(0, s.num_unsuccessful_steps);
}

/// Row r of a Jacobian over the axes' 4 tangent coordinates and the n − 4
/// estimated nuisance coordinates; the axes' columns multiplied by `axis_scale`.
Eigen::VectorXd jacobianRow(const ceres::CRSMatrix& J, int r, double axis_scale) {
  Eigen::VectorXd j = Eigen::VectorXd::Zero(J.num_cols);
  for (int e = J.rows[r]; e < J.rows[r + 1]; ++e) j[J.cols[e]] = (J.cols[e] < 4 ? axis_scale : 1.0) * J.values[e];
  return j;
}

/// The Jacobian of every block over p.blocks() (with or without the loss).
void evaluateJacobian(AxisProblem& p, bool apply_loss, double* cost, std::vector<double>* r, ceres::CRSMatrix* J) {
  ceres::Problem::EvaluateOptions eval;
  eval.parameter_blocks = p.blocks();
  eval.residual_blocks = p.allBlocks();
  eval.apply_loss_function = apply_loss;
  p.problem().Evaluate(eval, cost, r, nullptr, J);
  if (J->num_cols != 4 + p.nuisanceCount())
    throw std::logic_error("two-axis fit: expected a Jacobian in the 4 tangent coordinates and the nuisance");
}

/// H = JᵀJ of the whitened residuals per rad² of axis rotation — marginal
/// over the estimated nuisance (the Schur complement H_aa − H_an H_nn⁻¹ H_na)
/// — the noise's share H_noise = ⅙ Σ Δ²Jₖᵀ Δ²Jₖ of the axes' columns (second
/// differences over consecutive samples of one kind; identifiability.hpp),
/// the cost, and the nuisance's linear regression on the axes' tangent
/// coordinates, δν = −H_nn⁻¹ H_na δ (empty without nuisance).
void informationAtAxes(AxisProblem& p, Eigen::Matrix4d* H, Eigen::Matrix4d* H_noise, double* cost,
                       Eigen::MatrixXd* profile) {
  ceres::CRSMatrix J;
  evaluateJacobian(p, true, cost, nullptr, &J);
  const int n = J.num_cols;
  // Tangent coordinates δ turn an axis by ‖δ‖/2: ∂r/∂θ = 2 ∂r/∂δ.
  const auto row = [&](int r) { return jacobianRow(J, r, kSphereTangentPerRadian); };
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(n, n), hn = Eigen::MatrixXd::Zero(n, n);
  for (int r = 0; r < J.num_rows; ++r) h.selfadjointView<Eigen::Lower>().rankUpdate(row(r));
  int begin = 0;
  for (std::size_t k = 0; k < p.kindCount(); ++k) {
    const int per_block = p.residualsPerBlock(k);
    const int end = begin + p.kind(k).blockCount() * per_block;
    for (int r = begin + per_block; r + per_block < end; ++r)
      hn.selfadjointView<Eigen::Lower>().rankUpdate(row(r + per_block) - 2.0 * row(r) + row(r - per_block), 1.0 / 6.0);
    begin = end;
  }
  h = Eigen::MatrixXd(h.selfadjointView<Eigen::Lower>());
  *H_noise = Eigen::MatrixXd(hn.selfadjointView<Eigen::Lower>()).topLeftCorner<4, 4>();
  *H = h.topLeftCorner<4, 4>();
  profile->resize(n - 4, 4);
  if (n > 4) {
    const Eigen::LDLT<Eigen::MatrixXd> nn(h.bottomRightCorner(n - 4, n - 4));
    const Eigen::MatrixXd regression = nn.solve(h.bottomLeftCorner(n - 4, 4));
    *H -= h.topRightCorner(4, n - 4) * regression;
    *profile = -regression / kSphereTangentPerRadian;  // per tangent coordinate δ = kSphereTangentPerRadian θ
  }
}

/// Step 8: the sandwich covariance of the axes in tangent coordinates
/// (marginal: the axes' block of the whole H⁻¹MH⁻¹; file comment of
/// two_axis_solver.hpp); `batches` receives B. Returns false when it cannot
/// be formed (too few samples, H singular).
bool sandwichCovariance(AxisProblem& p, Eigen::Matrix4d* tangent, int* batches) {
  std::vector<double> r;
  ceres::CRSMatrix J;
  evaluateJacobian(p, true, nullptr, &r, &J);
  const int n = J.num_cols;
  int fewest = std::numeric_limits<int>::max();
  for (std::size_t k = 0; k < p.kindCount(); ++k) fewest = std::min(fewest, p.kind(k).blockCount());
  const int B = std::min(kSandwichBatches, fewest / kSandwichMinBatchSamples);
  if (B < 4) return false;
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(n, n);
  std::vector<Eigen::VectorXd> S(B, Eigen::VectorXd::Zero(n));
  int row = 0;
  for (std::size_t k = 0; k < p.kindCount(); ++k) {
    const int per_block = p.residualsPerBlock(k), blocks = p.kind(k).blockCount();
    for (int b = 0; b < blocks; ++b) {
      Eigen::VectorXd score = Eigen::VectorXd::Zero(n);
      for (int i = 0; i < per_block; ++i, ++row) {
        const Eigen::VectorXd j = jacobianRow(J, row, 1.0);
        H.selfadjointView<Eigen::Lower>().rankUpdate(j);
        score += r[row] * j;
      }
      S[static_cast<std::size_t>(b) * B / blocks] += score;
    }
  }
  H = Eigen::MatrixXd(H.selfadjointView<Eigen::Lower>());
  Eigen::VectorXd mean = Eigen::VectorXd::Zero(n);
  for (const Eigen::VectorXd& s : S) mean += s / B;
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n, n);
  for (const Eigen::VectorXd& s : S) M += (s - mean) * (s - mean).transpose();
  M *= static_cast<double>(B) / (B - 1);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(H);
  if (!(eig.eigenvalues().minCoeff() > 1e-12 * eig.eigenvalues().maxCoeff())) return false;
  const Eigen::MatrixXd Hinv =
      eig.eigenvectors() * eig.eigenvalues().cwiseInverse().asDiagonal() * eig.eigenvectors().transpose();
  *tangent = (Hinv * M * Hinv).topLeftCorner<4, 4>();
  *batches = B;
  return true;
}

}  // namespace

TwoAxisSolution solveTwoAxes(const std::vector<const ResidualKind*>& kinds, const std::vector<NamedStart>& starts,
                             const AxisFitOptions& options, const IdentifiabilityContext& context,
                             const NuisanceSelection& nuisance) {
  if (kinds.empty() || starts.empty()) throw std::logic_error("solveTwoAxes: needs residuals and a start");
  AxisProblem p(kinds, options, nuisance);
  const int parameters = 4 + p.nuisanceCount();
  const bool robust = options.loss != RobustLoss::kNone;

  // 1. Noise scales at the first start.
  p.setAxes(starts.front().axes);
  p.resetNuisance();
  for (std::size_t k = 0; k < p.kindCount(); ++k) p.setWeight(k, 1.0 / noiseScale(p, k, true));

  // 2. Every start; the lowest cost wins. Every end point is kept for the
  // ambiguity check (step 6).
  ceres::Solver::Options solver = solverOptions(options);
  FitProgressCallback progress(options.progress, options.interrupt);
  solver.callbacks.push_back(&progress);
  TwoAxisSolution out;
  ceres::Solver::Summary best;
  std::vector<EndPoint> ends;
  int best_start = -1;
  std::vector<Eigen::VectorXd> end_nuisance;
  for (std::size_t s = 0; s < starts.size(); ++s) {
    p.setAxes(starts[s].axes);
    p.resetNuisance();
    ceres::Solver::Summary summary;
    ceres::Solve(solver, &p.problem(), &summary);
    ends.push_back({p.axes(), summary.final_cost, static_cast<int>(s)});
    end_nuisance.push_back(p.activeNuisance());
    if (best_start < 0 || summary.final_cost < best.final_cost) {
      best = summary;
      best_start = static_cast<int>(s);
    }
  }
  const AxisPair best_axes = ends[best_start].axes;
  const double best_cost = best.final_cost;
  std::vector<double> start_weights(p.kindCount());
  for (std::size_t k = 0; k < p.kindCount(); ++k) start_weights[k] = p.weight(k);
  p.setAxes(best_axes);
  p.setActiveNuisance(end_nuisance[best_start]);
  out.summary.starts = static_cast<int>(starts.size());
  out.summary.start = starts[best_start].origin;
  out.summary.iterations = iterationsOf(best);

  // 3. Re-weighting.
  if (p.kindCount() > 1 || robust) {
    for (int round = 0; round < kMaxReweightings; ++round) {
      double change = 0.0;
      std::vector<double> scales(p.kindCount());
      for (std::size_t k = 0; k < p.kindCount(); ++k) {
        scales[k] = noiseScale(p, k, robust);
        change = std::max(change, std::abs(scales[k] * p.weight(k) - 1.0));
      }
      if (change <= kReweightTolerance) break;
      for (std::size_t k = 0; k < p.kindCount(); ++k) p.setWeight(k, 1.0 / scales[k]);
      ceres::Solve(solver, &p.problem(), &best);
      out.summary.iterations += iterationsOf(best);
      ++out.summary.reweightings;
    }
  }
  out.axes = p.axes();
  out.summary.converged = best.termination_type == ceres::CONVERGENCE;
  out.summary.message = best.message;

  // Residual statistics, and the check against independently estimated noise.
  std::string misfit;
  for (std::size_t k = 0; k < p.kindCount(); ++k) {
    const std::vector<double> q = p.blockSquaredNorms(k);
    double sum = 0.0;
    for (double x : q) sum += x;
    ResidualStats stats;
    stats.kind = p.kind(k).name();
    stats.unit = p.kind(k).unit();
    stats.samples = static_cast<int>(q.size());
    stats.noise_dof = p.kind(k).noiseDof();
    stats.rms = q.empty() ? 0.0 : std::sqrt(sum / (static_cast<double>(q.size()) * stats.noise_dof));
    stats.noise_scale = 1.0 / p.weight(k);
    stats.independent_noise = p.kind(k).independentNoise();
    if (stats.independent_noise > 0.0 && !q.empty()) {
      stats.residual_to_noise = noiseScale(p, k, true) / stats.independent_noise;
      if (options.max_residual_to_noise > 0.0 && stats.residual_to_noise > options.max_residual_to_noise &&
          misfit.empty())
        misfit = "the " + stats.kind + " residual is " + number(stats.residual_to_noise, "%.2f") +
                 " times the noise estimated independently from " + p.kind(k).independentNoiseSource() + " (" +
                 number(stats.independent_noise, "%.3g") + " " + stats.unit + "; at most " +
                 number(options.max_residual_to_noise, "%g") +
                 " accepted): the fit ended in a local minimum that no start escaped, or the model does not "
                 "describe the data (a gyroscope bias, another kind of joint, low-pass-filtered or otherwise "
                 "correlated noise); the axes are not reliable";
    }
    out.summary.residuals.push_back(stats);
  }
  out.summary.rms_residual = out.summary.residuals.front().rms;
  if (!misfit.empty()) {
    out.summary.converged = false;
    out.summary.message = misfit + " (Ceres: " + best.message + ")";
  }

  // 4. Identifiability.
  double cost = 0.0;
  Eigen::Matrix4d H, H_noise;
  Eigen::MatrixXd profile;
  informationAtAxes(p, &H, &H_noise, &cost, &profile);
  const int m = p.noiseComponents();
  const double s2 = m > parameters ? 2.0 * cost / (m - parameters) : 0.0;
  out.summary.reduced_chi_square = s2;
  out.information = analyseInformation(H, H_noise, s2);
  requireIdentifiable(out.information, options, context);

  // 5. Covariance (Ceres: tangent coordinates, unit noise).
  ceres::Covariance::Options cov_options;
  cov_options.algorithm_type = ceres::DENSE_SVD;
  cov_options.num_threads = 1;
  ceres::Covariance covariance(cov_options);
  const std::vector<const double*> blocks = {p.axis1(), p.axis2()};
  std::vector<const double*> all_blocks = blocks;
  if (p.nuisanceCount() > 0) all_blocks.push_back(p.nuisance());
  if (!covariance.Compute(all_blocks, &p.problem()))
    throw NotIdentifiable("the covariance of the axes is rank deficient; " + context.hint);
  if (p.nuisanceCount() > 0) {
    Eigen::Matrix<double, kNuisanceSize, kNuisanceSize, Eigen::RowMajor> cn;
    covariance.GetCovarianceBlock(p.nuisance(), p.nuisance(), cn.data());
    out.nuisance_covariance = s2 * Eigen::Matrix<double, kNuisanceSize, kNuisanceSize>(cn);
    out.nuisance = Eigen::Map<const Eigen::Matrix<double, kNuisanceSize, 1>>(p.nuisance());
  }
  Eigen::Matrix<double, 4, 4, Eigen::RowMajor> tangent;
  Eigen::Matrix<double, 3, 3, Eigen::RowMajor> c1, c2;
  covariance.GetCovarianceMatrixInTangentSpace(blocks, tangent.data());
  covariance.GetCovarianceBlock(p.axis1(), p.axis1(), c1.data());
  covariance.GetCovarianceBlock(p.axis2(), p.axis2(), c2.data());
  const double to_angle = 1.0 / (kSphereTangentPerRadian * kSphereTangentPerRadian);
  out.covariance = s2 * to_angle * Eigen::Matrix4d(tangent);
  out.covariance1 = s2 * Eigen::Matrix3d(c1);
  out.covariance2 = s2 * Eigen::Matrix3d(c2);
  out.sigma1_rad = std::sqrt(out.covariance.topLeftCorner<2, 2>().trace());
  out.sigma2_rad = std::sqrt(out.covariance.bottomRightCorner<2, 2>().trace());

  // 6. A second minimum that fits as well: Δχ² = 2Δcost/s² at the weights of
  // the multi-start, for the end points whose axes lie more than
  // distinct_minimum_sigmas σ from the best's. s² is the best's reduced
  // chi-square there or, if larger, the noise variance estimated without the
  // fit (kinds that have one; the others count with the fit's): a short
  // recording lets the best fit absorb part of the noise (seen: residuals 0.7
  // times the noise), which would inflate Δχ².
  double s2_starts = m > parameters ? 2.0 * best_cost / (m - parameters) : 0.0;
  {
    double independent = 0.0;
    for (std::size_t k = 0; k < p.kindCount(); ++k) {
      const double share = static_cast<double>(p.kind(k).blockCount()) * p.kind(k).noiseDof() / m;
      const double sigma = p.kind(k).independentNoise() * start_weights[k];
      independent += share * (sigma > 0.0 ? sigma * sigma : s2_starts);
    }
    s2_starts = std::max(s2_starts, independent);
  }
  // (Not closer than kQuadraticCheckFloor: on exact data σ is at the
  // rounding level, and two end points of one minimum would look distinct.)
  const double far1 = std::max(options.distinct_minimum_sigmas * out.sigma1_rad, kQuadraticCheckFloor);
  const double far2 = std::max(options.distinct_minimum_sigmas * out.sigma2_rad, kQuadraticCheckFloor);
  const auto near = [&](const AxisPair& a, const AxisPair& b) {
    return angleBetweenLines(a.axis1, b.axis1) <= far1 && angleBetweenLines(a.axis2, b.axis2) <= far2;
  };
  const EndPoint* runner_up = nullptr;
  double runner_up_delta = 0.0;
  std::vector<AxisPair> distinct = {best_axes};
  for (const EndPoint& e : ends) {
    if (near(e.axes, best_axes)) continue;
    if (std::none_of(distinct.begin(), distinct.end(), [&](const AxisPair& d) { return near(e.axes, d); }))
      distinct.push_back(e.axes);
    const double delta = s2_starts > 0.0 ? 2.0 * (e.cost - best_cost) / s2_starts
                                         : std::numeric_limits<double>::infinity();
    if (!runner_up || delta < runner_up_delta) {
      runner_up = &e;
      runner_up_delta = delta;
    }
  }
  out.summary.minima = static_cast<int>(distinct.size());
  if (runner_up) out.summary.runner_up_delta_chi_square = runner_up_delta;
  if (runner_up && runner_up_delta < options.ambiguity_chi_square) {
    const double angle1 = angleBetweenLines(runner_up->axes.axis1, best_axes.axis1) * kRadToDeg;
    const double angle2 = angleBetweenLines(runner_up->axes.axis2, best_axes.axis2) * kRadToDeg;
    throw NotIdentifiable("two axis pairs " + number(angle1, "%.3g") + "° (" + context.axis1 + ") and " +
                          number(angle2, "%.3g") + "° (" + context.axis2 +
                          ") apart fit the data equally well (their costs differ by Δχ² = " +
                          number(std::max(0.0, runner_up_delta), "%.3g") + ", below " +
                          number(options.ambiguity_chi_square, "%g") + ", while the best's 1σ are " +
                          number(out.sigma1_rad * kRadToDeg, "%.3g") + "° and " +
                          number(out.sigma2_rad * kRadToDeg, "%.3g") + "°; starts '" + starts[best_start].origin +
                          "' and '" + starts[runner_up->start].origin +
                          "'): a longer or more varied recording is needed; " + context.hint);
  }

  // 7. σ describes the error where the cost is quadratic over the region it
  // claims. Δχ² at ±k σ along each principal direction of the covariance,
  // over its quadratic value k²:
  //  - above 1 + quadratic_tolerance the cost rises faster than its curvature
  //    at the minimum says: a curved valley (short recordings), along which
  //    the error can be many σ. Not identifiable.
  //  - below kSecantBand (the mean q̄ of both sides) the cost is flatter than
  //    the Gauss–Newton curvature JᵀJ (large noise: its noise-driven part,
  //    and the first-order noise model of the residuals, stretched): σ is
  //    taken from the cost's actual rise, λ/q̄ in that direction; below
  //    kFlatSecant the cost is too flat for that. Not identifiable.
  // (Below kQuadraticCheckFloor the cost is analytic, hence quadratic, and
  // its differences would be rounding errors: exact data are not checked.)
  const double k = options.quadratic_check_sigmas;
  if (options.quadratic_tolerance > 0.0 && s2 > 0.0 &&
      k * std::max(out.sigma1_rad, out.sigma2_rad) > kQuadraticCheckFloor) {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eig(s2 * Eigen::Matrix4d(tangent));
    const AxisPair at = p.axes();
    const double base = p.costAt(at, Eigen::Vector4d::Zero(), Eigen::VectorXd::Zero(p.nuisanceCount()));
    Eigen::Matrix<double, 4, 2> ratio;
    for (int i = 0; i < 4; ++i)
      for (int side = 0; side < 2; ++side) {
        const Eigen::Vector4d step = (side ? 1.0 : -1.0) * k * std::sqrt(std::max(0.0, eig.eigenvalues()[i])) *
                                     eig.eigenvectors().col(i);
        ratio(i, side) = 2.0 * (p.costAt(at, step, profile * step) - base) / s2 / (k * k);
      }
    out.summary.quadratic_ratio_min = ratio.minCoeff();
    out.summary.quadratic_ratio_max = ratio.maxCoeff();
    const auto which = [&](int i) {
      const double share1 = eig.eigenvectors().col(i).head<2>().squaredNorm();
      return share1 > 0.8 ? "mostly " + context.axis1 : share1 < 0.2 ? "mostly " + context.axis2 : "both axes together";
    };
    const auto sigmas = [&] {
      return "the best fit's 1σ would be " + number(out.sigma1_rad * kRadToDeg, "%.3g") + "° and " +
             number(out.sigma2_rad * kRadToDeg, "%.3g") + "°";
    };
    Eigen::Index steep_row, steep_col;
    if (ratio.maxCoeff(&steep_row, &steep_col) > 1.0 + options.quadratic_tolerance)
      throw NotIdentifiable(
          "the cost is far from quadratic over the " + number(k, "%g") + "σ region of the axes: Δχ² at ±" +
          number(k, "%g") + "σ along its principal directions is " + number(ratio.minCoeff() * k * k, "%.3g") +
          " … " + number(ratio.maxCoeff() * k * k, "%.3g") + " instead of " + number(k * k, "%g") +
          " (the steepest turns " + which(static_cast<int>(steep_row)) +
          "): the data leave the axes in a curved valley of the cost, along which axes many σ apart fit about "
          "as well (" + sigmas() + "); a longer or more varied recording is needed; " + context.hint);
    Eigen::Vector4d lambda = eig.eigenvalues().cwiseMax(0.0);
    bool flatter = false;
    for (int i = 0; i < 4; ++i) {
      const double mean = 0.5 * (ratio(i, 0) + ratio(i, 1));
      if (mean >= kSecantBand) continue;
      if (mean < kFlatSecant)
        throw NotIdentifiable("the cost is far from quadratic over the " + number(k, "%g") +
                              "σ region of the axes: it rises by Δχ² = " + number(mean * k * k, "%.3g") +
                              " instead of " + number(k * k, "%g") + " at ±" + number(k, "%g") + "σ in a direction "
                              "that turns " + which(i) + " (" + sigmas() + "); " + context.hint);
      lambda[i] /= mean;
      flatter = true;
    }
    if (flatter) {
      const Eigen::Matrix4d secant = eig.eigenvectors() * lambda.asDiagonal() * eig.eigenvectors().transpose();
      out.covariance = to_angle * secant;
      out.sigma1_rad = std::sqrt(out.covariance.topLeftCorner<2, 2>().trace());
      out.sigma2_rad = std::sqrt(out.covariance.bottomRightCorner<2, 2>().trace());
      Eigen::Matrix<double, 3, 2, Eigen::RowMajor> J1, J2;
      p.plusJacobian(p.axis1(), J1.data());
      p.plusJacobian(p.axis2(), J2.data());
      out.covariance1 = J1 * secant.topLeftCorner<2, 2>() * J1.transpose();
      out.covariance2 = J2 * secant.bottomRightCorner<2, 2>() * J2.transpose();
    }
  }

  // 8. Under a robust loss: the sandwich.
  Eigen::Matrix4d sandwich;
  int batches = 0;
  if (robust && sandwichCovariance(p, &sandwich, &batches)) {
    out.summary.gauss_newton_sigma_rad = std::max(out.sigma1_rad, out.sigma2_rad);
    out.summary.sigma_method = "Gauss-Newton (larger than the sandwich from " + std::to_string(batches) + " batches)";
  }
  if (batches > 0 && to_angle * sandwich.trace() > out.covariance.trace()) {
    out.covariance = to_angle * sandwich;
    out.sigma1_rad = std::sqrt(out.covariance.topLeftCorner<2, 2>().trace());
    out.sigma2_rad = std::sqrt(out.covariance.bottomRightCorner<2, 2>().trace());
    Eigen::Matrix<double, 3, 2, Eigen::RowMajor> J1, J2;
    p.plusJacobian(p.axis1(), J1.data());
    p.plusJacobian(p.axis2(), J2.data());
    out.covariance1 = J1 * sandwich.topLeftCorner<2, 2>() * J1.transpose();
    out.covariance2 = J2 * sandwich.bottomRightCorner<2, 2>() * J2.transpose();
    out.summary.sigma_method = "sandwich (batch means, " + std::to_string(batches) + " batches; larger than Gauss-Newton)";
  }
  return out;
}

}  // namespace calibration
}  // namespace lieflow
