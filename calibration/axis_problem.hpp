/// \file
/// The least-squares problem of the two-axis fits (two_axis_solver.hpp), as
/// its solver and its analyses share it: the axes (SphereManifold), the
/// nuisance block where a kind uses it (residual_kind.hpp), the residual
/// blocks of every kind with their weights; and the analyses at a solution —
/// the information of the axes (marginal over the nuisance) with the noise's
/// share (identifiability.hpp), and the sandwich covariance (step 8).
/// Internal to calibration/.
#pragma once

#include <algorithm>
#include <memory>
#include <stdexcept>
#include <vector>

#include <ceres/loss_function.h>
#include <ceres/manifold.h>
#include <ceres/problem.h>
#include <ceres/sphere_manifold.h>
#include <Eigen/Core>

#include "calibration/fit_types.hpp"
#include "calibration/residual_kind.hpp"
#include "calibration/two_axis_solver.hpp"

namespace lieflow {
namespace calibration {

/// The robust loss of `options` (none: nullptr).
inline std::unique_ptr<ceres::LossFunction> makeLoss(const AxisFitOptions& options) {
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
    // The axes are blocks of the problem whatever the samples give (a
    // recording whose samples all fall to the rates' differencing window
    // adds no residual, and a manifold set on an absent block ends the
    // process inside Ceres).
    problem_.AddParameterBlock(axis1_, 3, &sphere_);
    problem_.AddParameterBlock(axis2_, 3, &sphere_);
    // One nuisance block per index the kinds name (ResidualKind::
    // nuisanceBlock: a recording's own biases), sized before any is added.
    bool uses_nuisance = false;
    int blocks = 1;
    for (const ResidualKind* kind : kinds_)
      if (kind->usesNuisance()) {
        uses_nuisance = true;
        blocks = std::max(blocks, kind->nuisanceBlock() + 1);
      }
    nuisance_.assign(static_cast<std::size_t>(kNuisanceSize) * blocks, 0.0);
    for (std::size_t k = 0; k < kinds_.size(); ++k)
      kinds_[k]->addBlocks(&problem_, loss_.get(), &weights_[k], axis1_, axis2_, nuisanceOf(*kinds_[k]), &ids_[k]);
    if (problem_.NumResidualBlocks() == 0)
      throw NotIdentifiable("no sample is left to fit (the recording is shorter than the rates' differencing "
                            "window and the clock-offset shifts)");
    const int per_block = uses_nuisance ? nuisance.count() : 0;
    if (uses_nuisance && per_block == 0)
      throw std::logic_error("two-axis fit: a nuisance kind with nothing to estimate");
    if (per_block > 0 && per_block < kNuisanceSize) {
      std::vector<int> constant;
      for (int i = 0; i < kNuisanceSize; ++i)
        if (!nuisance.active[i]) constant.push_back(i);
      subset_ = std::make_unique<ceres::SubsetManifold>(kNuisanceSize, constant);
    }
    // The blocks a residual uses (a recording whose samples all fall to the
    // differencing window adds none), in index order: the Jacobian's columns.
    for (int b = 0; b < blocks && per_block > 0; ++b) {
      double* block = nuisance_.data() + kNuisanceSize * b;
      if (!problem_.HasParameterBlock(block)) continue;
      used_blocks_.push_back(block);
      if (subset_) problem_.SetManifold(block, subset_.get());
      for (int i = 0; i < kNuisanceSize; ++i)
        if (nuisance.active[i]) active_index_.push_back(kNuisanceSize * b + i);
    }
    active_ = static_cast<int>(active_index_.size());
  }

  /// Estimated nuisance coordinates (0 without a nuisance block), over all blocks.
  int nuisanceCount() const { return active_; }
  /// The i-th estimated one's coordinate in nuisance(): kNuisanceSize × its
  /// block's index + its coordinate in the block.
  int activeIndex(int i) const { return active_index_[i]; }
  /// The nuisance blocks one after the other (kNuisanceSize × nuisanceBlocks() values).
  const double* nuisance() const { return nuisance_.data(); }
  int nuisanceBlocks() const { return static_cast<int>(nuisance_.size()) / kNuisanceSize; }
  /// The parameter blocks whose Jacobian the analyses use: the axes, then the nuisance blocks.
  std::vector<double*> blocks() {
    std::vector<double*> b = {axis1_, axis2_};
    b.insert(b.end(), used_blocks_.begin(), used_blocks_.end());
    return b;
  }
  void resetNuisance() { std::fill(nuisance_.begin(), nuisance_.end(), 0.0); }
  /// The estimated coordinates of the nuisance blocks, in order (block by block).
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
      cost += kinds_[k]->cost(axis1_, axis2_, nuisanceOf(*kinds_[k]), &weights_[k], loss_.get());
    setAxes(saved);
    if (active_ > 0) setActiveNuisance(saved_nuisance);
    return cost;
  }

 private:
  double* nuisanceOf(const ResidualKind& kind) { return nuisance_.data() + kNuisanceSize * kind.nuisanceBlock(); }

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
  std::vector<double> nuisance_;       ///< kNuisanceSize per block, never resized after the first
  std::vector<double*> used_blocks_;   ///< the blocks residuals use, in index order
  int active_ = 0;
  std::vector<int> active_index_;
  ceres::Problem problem_;
};

/// H = JᵀJ of the whitened residuals per rad² of axis rotation, marginal over
/// the estimated nuisance (the Schur complement H_aa − H_an H_nn⁻¹ H_na), the
/// noise's share H_noise = ⅙ Σ Δ²Jₖᵀ Δ²Jₖ of the axes' columns (second
/// differences over consecutive samples of one kind; identifiability.hpp),
/// the cost, and the nuisance's linear regression on the axes' tangent
/// coordinates, δν = −H_nn⁻¹ H_na δ (empty without nuisance); with `whole`,
/// also JᵀJ over the axes (per rad) and the nuisance, before the
/// marginalisation.
void informationAtAxes(AxisProblem& p, Eigen::Matrix4d* H, Eigen::Matrix4d* H_noise, double* cost,
                       Eigen::MatrixXd* profile, Eigen::MatrixXd* whole = nullptr);

/// One Gauss–Newton step from the problem's current axes and nuisance:
/// g = Jᵀr and H = JᵀJ over the axes' tangent coordinates and the estimated
/// nuisance, δ = −H⁻¹g, and the decrease of the cost it predicts, ½ gᵀH⁻¹g.
/// At a fit without nuisance (ν = 0, the axes' gradient zero) 2·decrease/σ²
/// is the score (Lagrange multiplier) statistic of the nuisance (Rao 1948):
/// the Δχ² that fitting it would gain, to first order, without the refit.
/// False when H is singular.
struct GaussNewtonStep {
  double decrease = 0.0;
  Eigen::VectorXd step;  ///< tangent coordinates of the axes (4), then the nuisance
};
bool gaussNewtonStep(AxisProblem& p, GaussNewtonStep* out);

/// Step 8 of two_axis_solver.hpp: the sandwich covariance of the axes in
/// tangent coordinates (the axes' block of the whole H⁻¹MH⁻¹); `batches`
/// receives B. False when it cannot be formed (too few samples, H singular).
bool sandwichCovariance(AxisProblem& p, Eigen::Matrix4d* tangent, int* batches);

}  // namespace calibration
}  // namespace lieflow
