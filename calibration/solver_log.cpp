#include "calibration/solver_log.hpp"

#include <glog/logging.h>

namespace lieflow {
namespace calibration {

void routeSolverLog(bool verbose) {
  if (!google::IsGoogleLoggingInitialized()) google::InitGoogleLogging("lieflow");
  FLAGS_logtostderr = true;
  FLAGS_minloglevel = verbose ? google::GLOG_INFO : google::GLOG_FATAL;
  FLAGS_v = verbose ? 1 : 0;
}

}  // namespace calibration
}  // namespace lieflow
