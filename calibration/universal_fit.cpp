#include "calibration/universal_fit.hpp"

#include <chrono>
#include <memory>
#include <vector>

#include "calibration/data_selection.hpp"
#include "calibration/residual_kind.hpp"
#include "calibration/two_axis_solver.hpp"
#include "calibration/unit_axis.hpp"
#include "calibration/universal_initial.hpp"
#include "calibration/universal_residuals.hpp"

namespace lieflow {
namespace calibration {

UniversalFit fitUniversal(const JointSamples& samples, const AxisFitOptions& options) {
  const auto start_time = std::chrono::steady_clock::now();
  const DataSelection data = selectData(samples, options.use, "universal joint");
  if (!data.orientations)
    throw NotIdentifiable(
        "a universal joint's axes need both bodies' orientations (" + samples.main.name + ".qw.. and " +
        samples.secondary.name +
        ".qw..): from gyroscopes alone there is no per-sample constraint (two unmeasured joint angles and "
        "their rates against three measured relative rates)");
  requireEnoughSamples(samples.size(), options);

  const std::vector<Eigen::Matrix3d> R12 = relativeOrientations(samples);
  std::vector<std::unique_ptr<ResidualKind>> kinds;
  {
    std::vector<OrientationUniversalResidual> blocks;
    blocks.reserve(R12.size());
    for (const Eigen::Matrix3d& R : R12) blocks.emplace_back(R);
    kinds.push_back(std::make_unique<SampleResidualKind<OrientationUniversalResidual, 1>>(
        "orientation constraint (R1 a1) . (R2 a2) = 0", "rad", 1, std::move(blocks)));
  }
  if (data.rates) {
    const std::vector<Eigen::Vector3d> u = relativeRates(samples, R12);
    std::vector<RelativeRateUniversalResidual> blocks;
    blocks.reserve(R12.size());
    for (std::size_t k = 0; k < R12.size(); ++k) blocks.emplace_back(R12[k], u[k]);
    kinds.push_back(std::make_unique<SampleResidualKind<RelativeRateUniversalResidual, 1>>(
        "relative angular velocity in span{R1 a1, R2 a2}", "rad/s", 1, std::move(blocks)));
  }
  std::vector<NamedStart> starts;
  const std::vector<AxisPair> closed_form = universalStartsFromOrientations(R12);
  for (std::size_t i = 0; i < closed_form.size(); ++i)
    starts.push_back({closed_form[i], i == 0 ? std::string("closed form (orientations)")
                                             : "closed form (orientations), near-null alternative " +
                                                   std::to_string(i)});
  for (std::size_t i = 0; i < options.extra_starts.size(); ++i)
    starts.push_back({options.extra_starts[i], "given start " + std::to_string(i + 1)});

  IdentifiabilityContext context;
  context.axis1 = "axis 1 in the main body '" + samples.main.name + "'";
  context.axis2 = "axis 2 in the secondary body '" + samples.secondary.name + "'";
  context.hint =
      "both joint angles must move (a universal joint turned about one of its axes only acts as a hinge and "
      "leaves the other axis undetermined)";

  std::vector<const ResidualKind*> kind_list;
  for (const auto& k : kinds) kind_list.push_back(k.get());
  const TwoAxisSolution solution = solveTwoAxes(kind_list, starts, options, context);

  UniversalFit fit;
  fit.axis1_main = canonicalSign(solution.axes.axis1) * solution.axes.axis1;
  fit.axis2_secondary = canonicalSign(solution.axes.axis2) * solution.axes.axis2;
  fit.sigma1_deg = solution.sigma1_rad * kRadToDeg;
  fit.sigma2_deg = solution.sigma2_rad * kRadToDeg;
  fit.covariance = solution.covariance;
  fit.information = solution.information;
  fit.summary = solution.summary;
  fit.summary.data = data.name();
  fit.summary.samples = samples.size();
  fit.summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count();
  return fit;
}

}  // namespace calibration
}  // namespace lieflow
