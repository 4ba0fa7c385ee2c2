/// \file
/// The subcommands of `lieflow`; each takes the arguments after its name and
/// returns the exit status (0 success, 1 computation failed, 2 bad input).
#pragma once

namespace lieflow {
namespace app {

int runSimulate(int argc, char** argv);
int runStudy(int argc, char** argv);
int runMainJob(int argc, char** argv);
int runIntegrators(int argc, char** argv);
int runScenes(int argc, char** argv);
int runLiegroup(int argc, char** argv);
int runStabilityCommand(int argc, char** argv);
/// `lieflow import MODEL`: a model file as a scene file (app/command_import.cpp).
int runImport(int argc, char** argv);
int runView(int argc, char** argv);
/// `lieflow calibrate`: defined in app/command_calibrate.cpp, linked
/// only when the build has Ceres (LIEFLOW_HAVE_CERES).
int runCalibrate(int argc, char** argv);

}  // namespace app
}  // namespace lieflow
