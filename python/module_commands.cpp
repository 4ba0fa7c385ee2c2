/// \file
/// simulate, study, stability and calibrate for the Python module. Each takes
/// the command's own flags as a list of strings (lieflow/commands.py builds
/// them from keyword arguments), resolves them with the command's own request
/// code (app/simulate_request.hpp, app/study_request.hpp,
/// app/calibrate_outcome.hpp), so input is refused with the command's
/// messages, and returns what the command writes: the trajectory rows and the
/// `--stats` object, the study's and stability scan's CSV files, the
/// calibration's JSON. Long runs release the GIL and check for Ctrl-C
/// (KeyboardInterrupt) at each progress report of the run.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/arguments.hpp"
#include "app/commands.hpp"
#include "app/cli.hpp"
#include "app/flag_spelling.hpp"
#include "app/output_files.hpp"
#include "app/recording_noise.hpp"
#include "app/run_setup.hpp"
#include "app/simulate_request.hpp"
#include "app/study_request.hpp"
#include "model/import/model_import.hpp"
#include "model/scene.hpp"
#include "model/scene_writer.hpp"
#include "liegroup/number_text.hpp"
#include "liegroup/input_number.hpp"
#include "liegroup/invalid_input.hpp"
#include "python/module_parts.hpp"
#ifdef LIEFLOW_HAVE_CERES
#include "app/calibrate_outcome.hpp"
#endif

namespace py = pybind11;

namespace lieflow {
namespace python {
namespace {

/// argv for app::Arguments from a list of strings (kept alive by `storage`).
class Argv {
 public:
  explicit Argv(std::vector<std::string> tokens) : storage_(std::move(tokens)) {
    for (std::string& s : storage_) pointers_.push_back(s.data());
  }
  int argc() const { return static_cast<int>(pointers_.size()); }
  char** argv() { return pointers_.data(); }

 private:
  std::vector<std::string> storage_;
  std::vector<char*> pointers_;
};

/// Scenes given as JSON text (a dict on the Python side), with where they
/// came from for the error messages.
std::optional<SceneDescription> sceneFrom(const std::optional<std::string>& json, const app::Arguments& args) {
  if (!json) return std::nullopt;
  return parseScene(*json, "scene dict", app::resourceLimitsFrom(args).max_bodies);
}

/// A Python callable held by C++ loads: copies share it, and the last one
/// lets go of it with the GIL held (the run itself holds no GIL).
struct PyFunction {
  py::object f;
  std::string what;  ///< "torques['arm']", for messages
  ~PyFunction() {
    py::gil_scoped_acquire acquire;
    f = py::object();
  }
};

/// The callable's answer as n finite numbers, else InputError naming it.
Eigen::VectorXd finiteAnswer(const PyFunction& fn, const py::object& answer, int n) {
  const auto fail = [&](std::string got) {
    constexpr std::size_t kShown = 60;
    if (got.size() > kShown) got = got.substr(0, kShown) + "…";
    return InvalidInput(fn.what, "the callable returned " + got + " (expected " +
                                     (n == 1 ? std::string("a finite number") : std::to_string(n) +
                                                                                    " finite numbers") +
                                     ", each within ±" + formatNumber(kMaxInputMagnitude) + ")");
  };
  // Real numbers only: a string ("123"), a bool or a complex number is not a
  // moment, although NumPy would cast each to a double.
  py::array_t<double, py::array::c_style | py::array::forcecast> a;
  try {
    const py::array raw = py::array::ensure(answer);
    const char kind = raw ? raw.dtype().kind() : 'O';
    if (kind == 'i' || kind == 'u' || kind == 'f')
      a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(answer);
  } catch (const py::error_already_set&) {
    a = {};
  }
  if (!a || a.size() != n || (n > 1 && a.ndim() != 1)) throw fail(py::str(py::repr(answer)).cast<std::string>());
  Eigen::VectorXd v(n);
  for (int i = 0; i < n; ++i) {
    v[i] = a.data()[i];
    // Finite and within the input bound (liegroup/input_number.hpp), as
    // every number lieflow reads: a moment of 1e308 would overflow the state.
    if (!inputNumberProblem(v[i]).empty()) throw fail(py::str(py::repr(answer)).cast<std::string>());
  }
  return v;
}

py::array_t<double> numpyVector(const double* x, int n) {
  py::array_t<double> a(n);
  std::copy(x, x + n, a.mutable_data());
  return a;
}

/// torques {body: f(t, state)} and moments {joint: f(t, state)} as the
/// scene's UserLoads. A body's state: q (w, x, y, z), omega (body), p, v
/// (world); a joint coordinate's: phi, phidot, coordinate (1 or 2).
UserLoads userLoadsFrom(const py::dict& torques, const py::dict& moments) {
  UserLoads loads;
  for (const auto& [key, value] : torques) {
    const std::string name = py::str(key).cast<std::string>();
    auto fn = std::make_shared<PyFunction>(PyFunction{py::reinterpret_borrow<py::object>(value),
                                                      "torques['" + name + "']"});
    loads.body_torques[name] = [fn](double t, const Eigen::Quaterniond& q, const Eigen::Vector3d& p,
                                    const Eigen::Vector3d& omega, const Eigen::Vector3d& v) -> Eigen::Vector3d {
      py::gil_scoped_acquire acquire;
      const double qa[4] = {q.w(), q.x(), q.y(), q.z()};
      py::dict state;
      state["q"] = numpyVector(qa, 4);
      state["omega"] = numpyVector(omega.data(), 3);
      state["p"] = numpyVector(p.data(), 3);
      state["v"] = numpyVector(v.data(), 3);
      return finiteAnswer(*fn, fn->f(t, state), 3);
    };
  }
  for (const auto& [key, value] : moments) {
    const std::string name = py::str(key).cast<std::string>();
    auto fn = std::make_shared<PyFunction>(PyFunction{py::reinterpret_borrow<py::object>(value),
                                                      "moments['" + name + "']"});
    loads.joint_moments[name] = [fn](double t, int coordinate, double phi, double phidot) {
      py::gil_scoped_acquire acquire;
      py::dict state;
      state["phi"] = phi;
      state["phidot"] = phidot;
      state["coordinate"] = coordinate + 1;
      return finiteAnswer(*fn, fn->f(t, state), 1)[0];
    };
  }
  return loads;
}

/// Progress callback that lets Ctrl-C through: with the GIL, ask Python
/// whether a signal is pending; if so, its KeyboardInterrupt stops the run.
void checkSignals() {
  py::gil_scoped_acquire acquire;
  if (PyErr_CheckSignals() != 0) throw py::error_already_set();
}

py::dict simulate(std::vector<std::string> tokens, const std::optional<std::string>& scene_json,
                  const py::dict& torques, const py::dict& moments) {
  std::optional<SceneDescription> scene;
  if (!torques.empty() || !moments.empty()) {
    // The scene is read here (the loads go into it): from the dict, or from
    // the first token (commands.py puts SCENE first), which then leaves.
    Argv probe(tokens);
    const app::Arguments probe_args(probe.argc(), probe.argv(), app::simulateValueFlags(), app::simulateSwitches());
    if (scene_json) {
      scene = sceneFrom(scene_json, probe_args);
    } else {
      if (probe_args.positional().size() != 1)
        throw app::UsageError("simulate needs exactly one SCENE (see lieflow simulate --help)");
      scene = app::sceneFrom(probe_args, tokens.front());
      tokens.erase(tokens.begin());
    }
    scene->user_loads = userLoadsFrom(torques, moments);
  }
  Argv argv(std::move(tokens));
  const app::Arguments args(argv.argc(), argv.argv(), app::simulateValueFlags(), app::simulateSwitches());
  app::SimulateRequest request = app::simulateRequestFrom(args, scene ? std::move(scene) : sceneFrom(scene_json, args));
  request.options.progress = [](double, long) { checkSignals(); };
  const std::vector<std::string> columns = request.simulation->columns(request.options.imu);
  std::vector<double> data;
  long rows = 0;
  std::string non_finite;
  app::RecordingNoise noisy(columns, request.noise);
  std::vector<double> noisy_row;
  const auto sink = [&](const std::vector<double>& row) {
    const std::vector<double>* out = &row;
    if (request.noise.any()) {
      noisy_row = row;
      noisy.apply(&noisy_row);
      out = &noisy_row;
    }
    // Output never holds NaN or inf: the rows stop before such a row, and
    // the run counts as failed (as the command's CSV writer does).
    if (!non_finite.empty()) return;
    for (std::size_t i = 0; i < out->size(); ++i)
      if (!std::isfinite((*out)[i])) {
        non_finite = "the output would hold a non-finite number: column " + columns[i] + " at t = " +
                     formatNumber((*out)[0]);
        return;
      }
    data.insert(data.end(), out->begin(), out->end());
    ++rows;
  };
  SimulationResult result;
  {
    py::gil_scoped_release release;
    result = request.simulation->run(request.options, sink);
  }
  if (!non_finite.empty() && !result.failed) {
    result.failed = true;
    result.failure = non_finite;
  }
  py::array_t<double> table({static_cast<py::ssize_t>(rows), static_cast<py::ssize_t>(columns.size())});
  std::copy(data.begin(), data.end(), table.mutable_data());
  py::dict out;
  out["columns"] = columns;
  out["data"] = table;
  out["stats"] = app::jsonLine(app::statsJson(result));
  out["failed"] = result.failed;
  out["failure"] = app::spellFlags(result.failure);
  out["scene"] = request.simulation->scene().name;
  return out;
}

/// Runs the study; writes DIR/study.csv and DIR/drift.csv (and the plots when
/// asked) like the command and returns DIR plus the reference it used.
py::dict study(std::vector<std::string> tokens, const std::optional<std::string>& scene_json) {
  Argv argv(std::move(tokens));
  const app::Arguments args(argv.argc(), argv.argv(), app::studyValueFlags(), app::studySwitches());
  app::StudyRequest request = app::studyRequestFrom(args, sceneFrom(scene_json, args));
  request.options.heartbeat = checkSignals;
  app::OutputDirectory directory(request.options.out_dir);
  app::StudyResult result;
  std::string plot_problem;
  {
    py::gil_scoped_release release;
    result = app::runStudy(*request.simulation, request.t_end, request.options);
    app::writeStudyFiles(result, request.options.out_dir);
    directory.keep();
    if (request.options.plots && !app::plotStudy(request.options.out_dir, &plot_problem) && plot_problem.empty())
      plot_problem = "plotting failed";
  }
  py::dict out;
  out["out"] = request.options.out_dir;
  out["reference"] = app::spellFlags(result.reference);
  out["reference_error"] = result.reference_error;
  out["plots"] = request.options.plots && plot_problem.empty();
  out["plot_problem"] = plot_problem;
  return out;
}

py::dict stability(std::vector<std::string> tokens, const std::vector<std::string>& scene_jsons) {
  Argv argv(std::move(tokens));
  const app::Arguments args(argv.argc(), argv.argv(), app::stabilityValueFlags(), app::stabilitySwitches());
  std::vector<SceneDescription> scenes;
  for (const std::string& json : scene_jsons)
    scenes.push_back(parseScene(json, "scene dict", app::resourceLimitsFrom(args).max_bodies));
  app::StabilityRequest request = app::stabilityRequestFrom(args, std::move(scenes));
  request.options.heartbeat = checkSignals;
  app::OutputDirectory directory(request.out_dir);
  std::string plot_problem;
  {
    py::gil_scoped_release release;
    const std::vector<app::StabilityRow> rows = app::runStability(request);
    app::writeStabilityCsv(rows, request.out_dir + "/stability.csv");
    directory.keep();
    if (request.plots && !app::plotStability(request.out_dir, &plot_problem) && plot_problem.empty())
      plot_problem = "plotting failed";
  }
  py::dict out;
  out["out"] = request.out_dir;
  out["plots"] = request.plots && plot_problem.empty();
  out["plot_problem"] = plot_problem;
  return out;
}

#ifdef LIEFLOW_HAVE_CERES
/// (JSON text or "", status, reason): lieflow/commands.py raises or returns.
py::tuple calibrate(std::vector<std::string> tokens) {
  Argv argv(std::move(tokens));
  const app::Arguments args(argv.argc(), argv.argv(), app::calibrateValueFlags(), app::calibrateSwitches());
  // Ctrl-C ends the solve (Ceres is not unwound through): the pending
  // KeyboardInterrupt is kept, the fit stops, and it is raised here.
  auto interrupt = std::make_shared<std::optional<py::error_already_set>>();
  const auto interrupted = [interrupt]() {
    py::gil_scoped_acquire acquire;
    if (!interrupt->has_value() && PyErr_CheckSignals() != 0) interrupt->emplace();
    return interrupt->has_value();
  };
  app::CommandOutcome outcome;
  {
    py::gil_scoped_release release;
    outcome = app::calibrate(args, interrupted);
  }
  if (interrupt->has_value()) {
    py::error_already_set error = std::move(**interrupt);
    interrupt->reset();
    throw error;
  }
  return py::make_tuple(outcome.json.is_null() ? std::string() : app::jsonLine(outcome.json), outcome.status,
                        app::spellFlags(outcome.error));
}
#endif

}  // namespace

void defineCommands(py::module_& m) {
  m.def("simulate", &simulate, py::arg("tokens"), py::arg("scene_json") = py::none(),
        py::arg("torques") = py::dict(), py::arg("moments") = py::dict());
  m.def("study", &study, py::arg("tokens"), py::arg("scene_json") = py::none());
  m.def("stability", &stability, py::arg("tokens"), py::arg("scene_jsons"));
  // lieflow.view: the command itself (its tokens built by commands.py).
  m.def(
      "view",
      [](std::vector<std::string> tokens) {
        Argv argv(std::move(tokens));
        return app::runView(argv.argc(), argv.argv());
      },
      py::arg("tokens"));
#ifdef LIEFLOW_HAVE_CERES
  m.def("calibrate", &calibrate, py::arg("tokens"));
  m.attr("have_calibration") = true;
#else
  m.attr("have_calibration") = false;
#endif
  m.def(
      "import_model",
      [](const std::string& path, const std::string& ignore, const std::string& keyframe, bool floating_base,
         const std::vector<double>& spin) {
        ModelImportOptions options = parseIgnoreList(ignore);
        options.keyframe = keyframe;
        options.floating_base = floating_base;
        if (!spin.empty()) {
          if (spin.size() != 3) throw InvalidInput("spin", "expected three numbers (rad/s, world axes)");
          options.has_spin = true;
          for (int i = 0; i < 3; ++i) options.spin[i] = spin[i];
        }
        const SceneDescription s = importModel(path, options);
        std::vector<std::string> notes;
        for (const std::string& note : s.import_notes) notes.push_back(app::spellFlags(note));
        return py::make_tuple(sceneToJson(s), notes);
      },
      py::arg("path"), py::arg("ignore") = "", py::arg("keyframe") = "", py::arg("floating_base") = false,
      py::arg("spin") = std::vector<double>{});
  m.attr("reads_mjcf") = canReadMjcf();
  m.attr("reads_urdf") = canReadUrdf();
  m.def("scenes", [] {
    py::list names;
    for (const BuiltinScene& s : builtinScenes()) names.append(py::make_tuple(s.name, s.description));
    return names;
  });
}

}  // namespace python
}  // namespace lieflow
