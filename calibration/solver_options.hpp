/// \file
/// The Ceres solver options the shooting fits share (spring_fit.hpp,
/// mechanism_spring_fit.hpp), and what every fit says when a solve fails.
#pragma once

#include <cmath>
#include <string>

#include <ceres/solver.h>
#include <ceres/types.h>

namespace lieflow {
namespace calibration {

/// Levenberg–Marquardt with the limits of `options` (any options struct with
/// max_iterations and the function, gradient and parameter tolerances),
/// single-threaded and silent; sparse normal Cholesky (SuiteSparse, else
/// Eigen's) when `sparse` and available, dense QR otherwise.
template <typename FitOptions>
void configureLevenbergMarquardt(ceres::Solver::Options* o, const FitOptions& options, bool sparse) {
  o->minimizer_type = ceres::TRUST_REGION;
  o->trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  o->max_num_iterations = options.max_iterations;
  o->function_tolerance = options.function_tolerance;
  o->gradient_tolerance = options.gradient_tolerance;
  o->parameter_tolerance = options.parameter_tolerance;
  o->num_threads = 1;
  o->logging_type = ceres::SILENT;
  o->minimizer_progress_to_stdout = false;
  o->linear_solver_type = ceres::DENSE_QR;
  if (!sparse) return;
  if (ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::SUITE_SPARSE)) {
    o->linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
    o->sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
  } else if (ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::EIGEN_SPARSE)) {
    o->linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
    o->sparse_linear_algebra_library_type = ceres::EIGEN_SPARSE;
  }
}

/// Why a solve's result cannot be used, in the user's terms: Ceres's own
/// messages for a failed solve ("Residual and Jacobian evaluation failed.",
/// "Linear solver failure ...") name its internals, not the fit's problem.
inline std::string solverFailureReason(const ceres::Solver::Summary& summary) {
  const std::string& m = summary.message;
  if (m.find("evaluation failed") != std::string::npos)
    return "the residuals or their derivatives were not finite numbers at the start values";
  if (m.find("inear solver") != std::string::npos)
    return "the least-squares system was singular: the data do not determine the parameters";
  if (!std::isfinite(summary.final_cost)) return "the cost became infinite or not a number";
  return "the solver stopped without a usable result (" + m + ")";
}

}  // namespace calibration
}  // namespace lieflow
