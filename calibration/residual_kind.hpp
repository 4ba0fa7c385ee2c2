/// \file
/// A kind of residual of a two-axis fit (one block per sample, on the two
/// unit-axis parameter blocks and, for kinds that have them, the nuisance
/// block: gyroscope biases and a clock offset, hinge_fit.hpp), as the solver
/// of two_axis_solver.hpp sees it.
#pragma once

#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <ceres/autodiff_cost_function.h>
#include <ceres/loss_function.h>
#include <ceres/problem.h>
#include <ceres/sized_cost_function.h>

namespace lieflow {
namespace calibration {

/// Size of the nuisance parameter block: the two gyroscope biases in the
/// planes perpendicular to the start axes (2 + 2) and the secondary
/// sensor's clock offset (1). Coordinates a fit does not estimate are held
/// constant (ceres::SubsetManifold).
constexpr int kNuisanceSize = 5;

class ResidualKind {
 public:
  virtual ~ResidualKind() = default;

  virtual const std::string& name() const = 0;
  /// Unit of the residual ("rad/s", "rad").
  virtual const std::string& unit() const = 0;
  /// Independent noise components in one block (a 3-vector residual that
  /// noise moves only within a plane has 2).
  virtual int noiseDof() const = 0;
  virtual int blockCount() const = 0;

  /// Whether the blocks also depend on the nuisance block (kNuisanceSize).
  virtual bool usesNuisance() const { return false; }
  /// Which nuisance block they use: 0, or with several recordings whose
  /// gyroscopes each have their own biases, the recording's index (the
  /// problem holds one block per index, AxisProblem).
  int nuisanceBlock() const { return nuisance_block_; }
  void setNuisanceBlock(int index) { nuisance_block_ = index; }

  /// Adds one block per sample on (axis1, axis2) — and `nuisance` where
  /// usesNuisance() — each with `loss`, its residuals multiplied by *weight
  /// (read at every evaluation, so the solver can re-weight without
  /// rebuilding the problem). Appends the block ids.
  virtual void addBlocks(ceres::Problem* problem, ceres::LossFunction* loss, const double* weight,
                         double* axis1, double* axis2, double* nuisance,
                         std::vector<ceres::ResidualBlockId>* ids) const = 0;

  /// Ceres' cost of all blocks, ½ Σ ρ(‖r‖²) (ρ(s) = s without a loss), at the
  /// given axes, nuisance and weight, calling the functors directly (cheaper
  /// than ceres::Problem::Evaluate, which builds a program on every call).
  virtual double cost(const double* axis1, const double* axis2, const double* nuisance, const double* weight,
                      const ceres::LossFunction* loss) const = 0;

  /// The noise scale this kind's residual should have (its unit), estimated
  /// from the data without the fit, or 0 when unknown. The solver compares the
  /// fitted residual with it (AxisFitOptions::max_residual_to_noise).
  double independentNoise() const { return independent_noise_; }
  /// How it was estimated, for the message ("the gyroscopes' third differences").
  const std::string& independentNoiseSource() const { return independent_noise_source_; }
  void setIndependentNoise(double sigma, std::string source) {
    independent_noise_ = sigma;
    independent_noise_source_ = std::move(source);
  }

 private:
  double independent_noise_ = 0.0;
  std::string independent_noise_source_;
  int nuisance_block_ = 0;
};

/// ½ ρ(‖r‖²) of one block of n residuals (ρ(s) = s without a loss).
inline double blockCost(const double* r, int n, const ceres::LossFunction* loss) {
  double s = 0.0, rho[3];
  for (int i = 0; i < n; ++i) s += r[i] * r[i];
  if (loss) {
    loss->Evaluate(s, rho);
    s = rho[0];
  }
  return 0.5 * s;
}

/// A functor that also has `bool evaluate(const double* axis1, const double*
/// axis2, double* r, double* d1, double* d2) const` (the residuals and, where
/// d1, d2 are not null, their closed-form derivatives, row-major kResiduals × 3)
/// is differentiated by it rather than by ceres::Jet: on the gyroscope hinge
/// constraint the Jets took 44 % of a fit.
template <typename Functor, typename = void>
struct HasClosedFormJacobian : std::false_type {};
template <typename Functor>
struct HasClosedFormJacobian<Functor, std::void_t<decltype(&Functor::evaluate)>> : std::true_type {};

/// ceres::SizedCostFunction around such a functor.
template <typename Functor, int kResiduals>
class ClosedFormSampleCost final : public ceres::SizedCostFunction<kResiduals, 3, 3> {
 public:
  explicit ClosedFormSampleCost(const Functor& f) : f_(f) {}
  bool Evaluate(double const* const* p, double* r, double** d) const override {
    return f_.evaluate(p[0], p[1], r, d ? d[0] : nullptr, d ? d[1] : nullptr);
  }

 private:
  Functor f_;
};

/// The residual kind of a functor with members `const double* weight` and
/// `template <class T> bool operator()(const T* axis1, const T* axis2, T* r)`
/// returning kResiduals residuals — or, with kUsesNuisance,
/// `operator()(const T* axis1, const T* axis2, const T* nuisance, T* r)` on
/// the nuisance block too; one functor per sample, differentiated by
/// ceres::AutoDiffCostFunction.
template <typename Functor, int kResiduals, bool kUsesNuisance = false>
class SampleResidualKind final : public ResidualKind {
 public:
  SampleResidualKind(std::string name, std::string unit, int noise_dof, std::vector<Functor> samples)
      : name_(std::move(name)), unit_(std::move(unit)), noise_dof_(noise_dof), samples_(std::move(samples)) {}

  const std::string& name() const override { return name_; }
  const std::string& unit() const override { return unit_; }
  int noiseDof() const override { return noise_dof_; }
  int blockCount() const override { return static_cast<int>(samples_.size()); }
  bool usesNuisance() const override { return kUsesNuisance; }

  double cost(const double* axis1, const double* axis2, const double* nuisance, const double* weight,
              const ceres::LossFunction* loss) const override {
    double total = 0.0, r[kResiduals];
    for (const Functor& sample : samples_) {
      Functor f(sample);
      f.weight = weight;
      if constexpr (kUsesNuisance)
        f(axis1, axis2, nuisance, r);
      else
        f(axis1, axis2, r);
      total += blockCost(r, kResiduals, loss);
    }
    return total;
  }

  void addBlocks(ceres::Problem* problem, ceres::LossFunction* loss, const double* weight, double* axis1,
                 double* axis2, double* nuisance, std::vector<ceres::ResidualBlockId>* ids) const override {
    ids->reserve(ids->size() + samples_.size());
    for (const Functor& sample : samples_) {
      auto* functor = new Functor(sample);
      functor->weight = weight;
      if constexpr (kUsesNuisance)
        ids->push_back(problem->AddResidualBlock(
            new ceres::AutoDiffCostFunction<Functor, kResiduals, 3, 3, kNuisanceSize>(functor), loss, axis1, axis2,
            nuisance));
      else if constexpr (HasClosedFormJacobian<Functor>::value) {
        ids->push_back(
            problem->AddResidualBlock(new ClosedFormSampleCost<Functor, kResiduals>(*functor), loss, axis1, axis2));
        delete functor;
      } else
        ids->push_back(problem->AddResidualBlock(
            new ceres::AutoDiffCostFunction<Functor, kResiduals, 3, 3>(functor), loss, axis1, axis2));
    }
  }

 private:
  std::string name_;
  std::string unit_;
  int noise_dof_;
  std::vector<Functor> samples_;
};

}  // namespace calibration
}  // namespace lieflow
