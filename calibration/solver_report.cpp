#include "calibration/solver_report.hpp"

#include <algorithm>

namespace lieflow {
namespace calibration {
namespace {

bool startsWith(const std::string& text, const char* prefix) { return text.rfind(prefix, 0) == 0; }

std::string words(const ceres::Solver::Summary& s, int max_iterations) {
  const std::string& m = s.message;
  switch (s.termination_type) {
    case ceres::CONVERGENCE:
      if (startsWith(m, "Function tolerance"))
        return "converged: the relative change of the cost fell below the function tolerance";
      if (startsWith(m, "Gradient tolerance")) return "converged: the gradient fell below the gradient tolerance";
      if (startsWith(m, "Parameter tolerance"))
        return "converged: the relative step fell below the parameter tolerance";
      return "converged";
    case ceres::NO_CONVERGENCE:
      if (startsWith(m, "Maximum number of iterations"))
        return "stopped at the iteration limit of " + std::to_string(max_iterations) +
               " (--max-iterations) before a tolerance was met";
      if (startsWith(m, "Minimum trust region radius"))
        return "stopped: the trust region shrank to its minimum without a step that lowers the cost";
      if (startsWith(m, "Maximum solver time")) return "stopped at the solver's time limit";
      return "stopped before a tolerance was met";
    case ceres::FAILURE:
      if (m.find("Residual and Jacobian evaluation failed") != std::string::npos ||
          m.find("evaluation failed") != std::string::npos)
        return "failed: the model could not be evaluated (a residual or a derivative is not a finite number)";
      if (m.find("consecutive invalid steps") != std::string::npos)
        return "failed: every step the solver tried took the model out of the finite numbers";
      if (m.find("inear solver") != std::string::npos) return "failed: the linear least-squares step could not be solved";
      return "failed";
    case ceres::USER_SUCCESS:
    case ceres::USER_FAILURE:
      return "stopped by lieflow";
  }
  return "stopped";
}

}  // namespace

std::string stopReason(const ceres::Solver::Summary& summary, int max_iterations) {
  return words(summary, max_iterations) + " (Ceres: " + summary.message + ")";
}

int solverIterations(const ceres::Solver::Summary& summary) {
  return std::max(0, summary.num_successful_steps) + std::max(0, summary.num_unsuccessful_steps);
}

}  // namespace calibration
}  // namespace lieflow
