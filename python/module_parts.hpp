/// \file
/// The parts of the Python extension module `lieflow._lieflow`, one
/// definition function per file (module.cpp calls them).
#pragma once

#include <pybind11/pybind11.h>

namespace lieflow {
namespace python {

/// lieflow.SO3 / lieflow.SE3 kernels (module_groups.cpp).
void defineGroups(pybind11::module_& m);
/// simulate, study, stability, calibrate and the scene lists (module_commands.cpp).
void defineCommands(pybind11::module_& m);

}  // namespace python
}  // namespace lieflow
