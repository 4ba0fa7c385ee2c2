/// \file
/// Why a Ceres solve stopped, in lieflow's words, from the summary's
/// termination type and message: the `message` key of every calibration and
/// the reason of a failed or unconverged fit. Ceres' own sentence follows in
/// parentheses; its log lines are not shown (solver_log.hpp).
#pragma once

#include <string>

#include <ceres/solver.h>

namespace lieflow {
namespace calibration {

/// "converged: the relative change of the cost fell below the function
/// tolerance (Ceres: Function tolerance reached. ...)", "stopped at the
/// iteration limit of 200 (--max-iterations) before a tolerance was met
/// (...)", "failed: every step the solver tried took the model out of the
/// finite numbers (...)". `max_iterations` is the limit the solve had.
std::string stopReason(const ceres::Solver::Summary& summary, int max_iterations);

/// Iterations (successful and unsuccessful steps) of a solve.
int solverIterations(const ceres::Solver::Summary& summary);

}  // namespace calibration
}  // namespace lieflow
