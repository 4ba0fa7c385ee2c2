/// \file
/// `lieflow._lieflow`, the extension module under the Python package
/// `lieflow` (python/lieflow/): the group kernels and the commands. Errors
/// become the package's exceptions: bad input (what the command answers with
/// exit 2: lieflow::InvalidInput, app::UsageError) raises
/// lieflow.InputError, a ValueError; any other failure of a computation
/// (exit 1) raises lieflow.ComputationError, a RuntimeError.
#include <pybind11/pybind11.h>

#include "app/cli.hpp"
#include "app/flag_spelling.hpp"
#include "liegroup/input_number.hpp"
#include "liegroup/invalid_input.hpp"
#include "python/module_parts.hpp"

namespace py = pybind11;

PYBIND11_MODULE(_lieflow, m) {
  m.doc() = "lieflow's compiled core; use the package `lieflow`";
  m.attr("__version__") = LIEFLOW_VERSION;
  // The largest magnitude of any number lieflow reads (liegroup/input_number.hpp).
  m.attr("max_input_magnitude") = lieflow::kMaxInputMagnitude;
  static py::exception<lieflow::InvalidInput> input_error(m, "InputError", PyExc_ValueError);
  static py::exception<std::runtime_error> computation_error(m, "ComputationError", PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const lieflow::InvalidInput& e) {
      input_error(lieflow::app::spellFlags(e.what()).c_str());
    } catch (const lieflow::app::UsageError& e) {
      input_error(e.what());
    } catch (const py::error_already_set&) {
      throw;
    } catch (const py::builtin_exception&) {
      throw;
    } catch (const std::exception& e) {
      computation_error(lieflow::app::spellFlags(e.what()).c_str());
    }
  });
  lieflow::python::defineGroups(m);
  lieflow::python::defineCommands(m);
}
