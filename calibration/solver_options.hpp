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

/// Why a solve stopped, in the user's terms, for the fits' `message`: Ceres's
/// own summary line ("Function tolerance reached. |cost_change|/cost:
/// 0.000000e+00 <= 1.000000e-12") names its internals and prints %e.
inline std::string solverStopMessage(const ceres::Solver::Summary& summary) {
  const std::string& m = summary.message;
  const std::string iterations = std::to_string(summary.iterations.size()) + " iterations";
  switch (summary.termination_type) {
    case ceres::CONVERGENCE:
      if (m.rfind("Gradient", 0) == 0) return "converged: the cost's gradient vanished (" + iterations + ")";
      if (m.rfind("Parameter", 0) == 0)
        return "converged: the parameters stopped changing, to a relative step below the tolerance (" + iterations +
               ")";
      return "converged: the cost stopped changing, to a relative change below the tolerance (" + iterations + ")";
    case ceres::NO_CONVERGENCE:
      return "not converged: the solver stopped at its limit of iterations or time (" + iterations +
             "; `max_iterations` raises it)";
    case ceres::USER_SUCCESS:
    case ceres::USER_FAILURE: return "stopped on request after " + iterations;
    case ceres::FAILURE: break;
  }
  return "failed: " + solverFailureReason(summary);
}


}  // namespace calibration
}  // namespace lieflow
