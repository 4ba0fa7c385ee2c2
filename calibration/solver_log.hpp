/// \file
/// Where Ceres' own log lines go. Ceres logs through glog ("WARNING: Logging
/// before InitGoogleLogging() ...", "E1125 ... trust_region_minimizer.cc:...
/// Terminating: ..."); those lines are for whoever debugs a fit, not for the
/// user's terminal: lieflow says why a fit stopped in its own words
/// (solver_report.hpp). `lieflow calibrate --verbose` shows them.
#pragma once

namespace lieflow {
namespace calibration {

/// Initialises glog once per process (a second InitGoogleLogging aborts) with
/// its lines on stderr, and shows them only when `verbose` (everything from
/// INFO, and the per-iteration lines Ceres writes at VLOG(1) when a fit's
/// `log_iterations` is set); otherwise only FATAL, a Ceres bug that aborts.
/// Never stdout: that holds the JSON.
void routeSolverLog(bool verbose);

}  // namespace calibration
}  // namespace lieflow
