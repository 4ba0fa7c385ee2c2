#include "app/study.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <limits>
#include <sstream>

#include "app/plotting.hpp"
#include "app/run_setup.hpp"
#include "integrators/integrate.hpp"
#include "integrators/registry.hpp"
#include "joints/import/mujoco_peer.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {
namespace app {
namespace {

/// Tolerances of the converged reference run, and of the looser run that
/// estimates its error by tolerance proportionality.
constexpr double kReferenceRtol = 1e-13;
constexpr double kReferenceAtol = 1e-15;
constexpr double kCheckRtol = 1e-11;
constexpr double kCheckAtol = 1e-13;
/// Drift curves keep about this many samples per integrator.
constexpr int kDriftSamples = 400;

double omegaError(const std::vector<double>& a, const std::vector<double>& ref) {
  const Eigen::Vector3d w(a[5], a[6], a[7]);
  const Eigen::Vector3d w_ref(ref[5], ref[6], ref[7]);
  return (w - w_ref).norm() / std::max(w_ref.norm(), 1e-300);
}

/// The heartbeat before a run and as the run's progress callback.
void withHeartbeat(const std::function<void()>& heartbeat, SimulationOptions* o) {
  if (!heartbeat) return;
  heartbeat();
  o->progress = [heartbeat](double, long) { heartbeat(); };
}

std::vector<double> referenceRow(const Simulation& sim, double t_end, const std::string& integrator,
                                 double rtol, double atol, double dt, long max_steps,
                                 const std::function<void()>& heartbeat) {
  SimulationOptions o;
  withHeartbeat(heartbeat, &o);
  o.max_steps = max_steps;
  o.integrator = integrator;
  o.dt = dt;
  o.t_end = t_end;
  o.diagnostics = false;
  if (integrator == "rkmk45") o.integrator_options = {{"rtol", rtol}, {"atol", atol}};
  const SimulationResult r = sim.run(o);
  if (r.failed) throw std::runtime_error("the reference run (" + integrator + ") failed: " + r.failure);
  return r.final_row;
}

/// Times a run (`run_once` returns its wall seconds) by repeating it until
/// options.min_timing_seconds were spent (at least min_repeats, at most
/// max_repeats runs) and writes the median, the repeats and ns per step into
/// `row`; a run whose repeats hit the limit first counts in capped_timings.
void timeRow(const StudyOptions& options, const std::function<double()>& run_once, StudyRow* row,
             StudyResult* result) {
  std::vector<double> times;
  double spent = 0.0;
  while (static_cast<int>(times.size()) < options.max_repeats &&
         (static_cast<int>(times.size()) < options.min_repeats || spent < options.min_timing_seconds)) {
    times.push_back(run_once());
    spent += times.back();
  }
  std::sort(times.begin(), times.end());
  if (spent < options.min_timing_seconds) ++result->capped_timings;
  row->repeats = static_cast<int>(times.size());
  row->wall_seconds = times[times.size() / 2];
  row->ns_per_step = row->steps > 0 ? 1e9 * row->wall_seconds / static_cast<double>(row->steps) : 0.0;
}

/// The invariant drifts of a MuJoCo run in the scene's order (NaN, written
/// as an empty cell, for a quantity MuJoCo's run does not measure).
std::vector<double> peerInvariants(const std::vector<std::string>& names, double L, double L_com, double balance) {
  std::vector<double> out;
  for (const std::string& n : names)
    out.push_back(n == "L" ? L : n == "L_com" ? L_com : n == "energy_balance" ? balance
                                                                            : std::numeric_limits<double>::quiet_NaN());
  return out;
}

/// A row with the first body's quaternion and angular velocity where
/// orientationErrorBetweenRows reads them (t, qw, qx, qy, qz, wx, wy, wz).
std::vector<double> peerRow(double t, const MujocoPeerRun& run) {
  const Eigen::Quaterniond& q = run.orientations.front();
  const Eigen::Vector3d& w = run.angular_velocities.front();
  return {t, q.w(), q.x(), q.y(), q.z(), w.x(), w.y(), w.z()};
}

std::string number(double v) {
  if (!std::isfinite(v)) return "nan";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);
  return buffer;
}

std::string csvNumber(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.17g", v);
  return buffer;
}

/// MuJoCo's integrators on the model at the study's steps (--with-mujoco):
/// the same measurements as lieflow's rows, from MuJoCo's own quantities,
/// and MuJoCo RK4 at the reference's step as a check of the reference.
void studyMujoco(const Simulation& sim, double t_end, const std::vector<double>& dts, double drift_dt,
                 const std::vector<double>& ref, const StudyOptions& options, StudyResult* result) {
  std::string why;
  if (!mujocoPeerAvailable(&why)) {
    for (const std::string& name : mujocoPeerIntegrators()) {
      StudyRow row;
      row.integrator = name;
      row.dt = dts.front();
      row.failed = true;
      row.failure = "MuJoCo is absent: " + why;
      result->rows.push_back(row);
    }
    return;
  }
  const MujocoPeer peer(options.mujoco_model, options.mujoco_import, sim.scene());
  const std::vector<std::string>& names = result->invariant_names;
  const std::string version = "MuJoCo " + mujocoPeerVersion();
  int done = 0;
  const int total = static_cast<int>(mujocoPeerIntegrators().size() * dts.size());
  for (const std::string& name : mujocoPeerIntegrators()) {
    for (const double dt : dts) {
      if (options.progress)
        *options.progress << "study: [MuJoCo " << ++done << "/" << total << "] " << name << " dt=" << dt << "\n";
      if (options.heartbeat) options.heartbeat();
      StudyRow row;
      row.integrator = name;
      row.dt = dt;
      row.options = version;
      const long steps = stepCount(0.0, t_end, dt);
      if (steps > options.max_steps)
        throw InvalidInput("--max-steps", "MuJoCo's " + std::to_string(steps) + " steps at dt " + number(dt) +
                                              " exceed the limit " + std::to_string(options.max_steps));
      const MujocoPeerRun diag =
          peer.run(name, dt, t_end, true, std::max(1L, steps / kDriftSamples), options.heartbeat);
      row.steps = diag.steps;
      row.failed = diag.failed;
      row.failure = diag.failure;
      row.momentum_conserved = result->momentum_conserved;
      if (diag.failed) {
        row.orientation_error = row.omega_error = std::numeric_limits<double>::quiet_NaN();
        row.wall_seconds = diag.wall_seconds;
        result->rows.push_back(row);
        continue;
      }
      row.energy_drift = diag.energy_drift;
      row.momentum_drift = diag.momentum_drift;
      row.invariant_drifts = peerInvariants(names, diag.momentum_drift, diag.com_momentum_drift,
                                            diag.energy_balance_drift);
      const std::vector<double> last = peerRow(t_end, diag);
      row.orientation_error = orientationErrorBetweenRows(last, ref);
      row.omega_error = omegaError(last, ref);
      if (dt == drift_dt) {
        const MujocoPeerSample& s0 = diag.samples.front();
        const double e_scale = std::max(std::abs(s0.energy), 1e-300);
        for (const MujocoPeerSample& s : diag.samples) {
          DriftSample d;
          d.integrator = name;
          d.dt = dt;
          d.t = s.t;
          d.energy_error = (s.energy - s0.energy) / e_scale;
          d.momentum_error = (s.L - s0.L).norm() / std::max(s0.L.norm(), 1e-300);
          d.invariant_errors = peerInvariants(names, d.momentum_error,
                                              (s.L_com - s0.L_com).norm() / std::max(s0.L_com.norm(), 1e-300),
                                              std::abs(s.energy + s.dissipated_work - s0.energy) / e_scale);
          result->drift.push_back(d);
        }
      }
      timeRow(options, [&] { return peer.run(name, dt, t_end, false, 1, options.heartbeat).wall_seconds; }, &row,
              result);
      result->rows.push_back(row);
    }
  }
  // The reference against MuJoCo RK4 at the smallest step over 32 (where
  // the reference is a fixed-step run, at its step).
  const double h_check = dts.back() / 32.0;
  if (options.progress) *options.progress << "study: checking the reference against MuJoCo RK4 at h " << h_check << "\n";
  const MujocoPeerRun check = peer.run("mujoco-rk4", h_check, t_end, false, 1, options.heartbeat);
  std::ostringstream s;
  if (check.failed)
    s << "; MuJoCo RK4 at h = " << number(h_check) << " failed: " << check.failure;
  else
    s << "; MuJoCo RK4 at h = " << number(h_check) << " differs from it by "
      << number(orientationErrorBetweenRows(peerRow(t_end, check), ref)) << " rad";
  result->reference += s.str();
}

}  // namespace

StudyResult runStudy(const Simulation& sim, double t_end, const StudyOptions& options) {
  StudyResult result;
  result.scene = sim.scene().name;
  result.t_end = t_end;

  std::vector<double> dts = options.dts;
  if (dts.empty()) {
    const double dt = sim.scene().has_integrator ? sim.scene().integrator.dt : t_end / 1000.0;
    dts = {4 * dt, 2 * dt, dt, dt / 2, dt / 4};
  }
  std::sort(dts.rbegin(), dts.rend());

  // The reference.
  std::vector<double> ref;
  std::string why;
  const bool exact_reference = sim.supports("exact", &why);
  if (exact_reference) {
    ref = referenceRow(sim, t_end, "exact", 0, 0, t_end, options.max_steps, options.heartbeat);
    result.reference = "exact flow (Jacobi elliptic functions)";
    result.reference_error = 0.0;
  } else if (sim.hasConstraints()) {
    // Scenes with joints: the projected rkmk4 at a step 32 times below the
    // smallest studied one; its error is estimated by Richardson from a run
    // at twice that step (order 4: e(h) ≈ |y_h − y_2h| / 15). (Fixed steps:
    // independent of the adaptive driver's projection, which rkmk45 runs
    // with here, and of any integrator the study compares.)
    const double h_ref = dts.back() / 32.0;
    if (options.progress) *options.progress << "study: computing the reference (projected rkmk4, h " << h_ref << ")\n";
    ref = referenceRow(sim, t_end, "rkmk4", 0, 0, h_ref, options.max_steps, options.heartbeat);
    const std::vector<double> check =
        referenceRow(sim, t_end, "rkmk4", 0, 0, 2 * h_ref, options.max_steps, options.heartbeat);
    result.reference_error = orientationErrorBetweenRows(ref, check) / 15.0;
    std::ostringstream s;
    s << "projected rkmk4 at h = " << number(h_ref) << "; its orientation error is estimated at "
      << number(result.reference_error) << " rad by Richardson from a run at h = " << number(2 * h_ref);
    result.reference = s.str();
  } else {
    if (options.progress) *options.progress << "study: computing the reference (rkmk45, rtol 1e-13)\n";
    ref = referenceRow(sim, t_end, "rkmk45", kReferenceRtol, kReferenceAtol, t_end, options.max_steps,
                       options.heartbeat);
    const std::vector<double> check =
        referenceRow(sim, t_end, "rkmk45", kCheckRtol, kCheckAtol, t_end, options.max_steps, options.heartbeat);
    result.reference_error = orientationErrorBetweenRows(ref, check) * (kReferenceRtol / kCheckRtol);
    std::ostringstream s;
    s << "converged rkmk45 run (Dormand-Prince 5(4) on the group, rtol " << kReferenceRtol
      << ", atol " << kReferenceAtol << "); its orientation error is estimated at "
      << number(result.reference_error) << " rad from a run at rtol " << kCheckRtol;
    result.reference = s.str();
  }

  std::vector<std::string> integrators = options.integrators;
  if (integrators.empty())
    for (const IntegratorInfo& info : integratorRegistry())
      if (info.name != "exact" && sim.supports(info.name, nullptr, options.formulation)) integrators.push_back(info.name);
  for (const std::string& name : integrators)
    if (!sim.supports(name, &why, options.formulation)) throw InvalidInput("--integrators", why);
  checkOptionKeysUsed(options.integrator_options, integrators);
  result.invariant_names = sim.invariantNames();

  const std::vector<std::string> columns = sim.columns();
  const auto column = [&](const std::string& c) {
    return static_cast<std::size_t>(std::find(columns.begin(), columns.end(), c) - columns.begin());
  };
  const std::size_t energy_col = column("energy");
  const std::size_t lx_col = column("Lx");
  const double drift_dt = std::find(dts.begin(), dts.end(), sim.scene().integrator.dt) != dts.end()
                              ? sim.scene().integrator.dt
                              : dts[dts.size() / 2];

  int done = 0;
  const int total = static_cast<int>(integrators.size() * dts.size());
  for (const std::string& name : integrators) {
    for (const double dt : dts) {
      ++done;
      if (options.progress)
        *options.progress << "study: [" << done << "/" << total << "] " << name << " dt=" << dt << "\n";
      SimulationOptions o;
      o.integrator = name;
      o.formulation = options.formulation;
      o.dt = dt;
      o.t_end = t_end;
      o.max_steps = options.max_steps;
      withHeartbeat(options.heartbeat, &o);
      applyIntegratorOptions(sim.scene(), options.integrator_options, &o);

      // Diagnostics run: drift figures, failure, Newton iterations; drift
      // curves for the chosen step.
      StudyRow row;
      row.integrator = name;
      row.dt = dt;
      row.options = describeOptions(o);
      const long steps = stepCount(0.0, t_end, dt);
      const bool record_drift = dt == drift_dt;
      o.every = static_cast<int>(std::max(1L, steps / kDriftSamples));
      std::vector<double> first;
      if (record_drift)
        o.invariant_sink = [&](double, const std::vector<double>& errors) {
          result.drift.back().invariant_errors = errors;
        };
      const SimulationResult diag = sim.run(o, [&](const std::vector<double>& r) {
        if (!record_drift) return;
        if (first.empty()) first = r;
        DriftSample s;
        s.integrator = name;
        s.dt = dt;
        s.t = r[0];
        const double e0 = first[energy_col];
        s.energy_error = (r[energy_col] - e0) / std::max(std::abs(e0), 1e-300);
        const Eigen::Vector3d L0(first[lx_col], first[lx_col + 1], first[lx_col + 2]);
        const Eigen::Vector3d L(r[lx_col], r[lx_col + 1], r[lx_col + 2]);
        s.momentum_error = (L - L0).norm() / std::max(L0.norm(), 1e-300);
        result.drift.push_back(s);
      });
      row.steps = diag.steps;
      row.energy_drift = diag.energy_drift;
      row.momentum_conserved = diag.momentum_conserved;
      row.momentum_drift = diag.momentum_drift;
      for (const auto& inv : diag.invariants) row.invariant_drifts.push_back(inv.second);
      row.implicit = diag.implicit;
      row.newton_iterations_mean = diag.newton_iterations_mean;
      row.failed = diag.failed;
      row.failure = diag.failure;
      result.momentum_conserved = diag.momentum_conserved;
      if (diag.failed) {
        row.orientation_error = row.omega_error = std::numeric_limits<double>::quiet_NaN();
        row.wall_seconds = diag.wall_seconds;
        result.rows.push_back(row);
        continue;
      }
      row.orientation_error = orientationErrorBetweenRows(diag.final_row, ref);
      row.omega_error = omegaError(diag.final_row, ref);

      // Timing runs: diagnostics off, repeated; the median is reported.
      o.diagnostics = false;
      o.invariant_sink = nullptr;
      timeRow(options, [&] { return sim.run(o).wall_seconds; }, &row, &result);
      result.rows.push_back(row);
    }
  }
  if (!options.mujoco_model.empty()) studyMujoco(sim, t_end, dts, drift_dt, ref, options, &result);
  return result;
}

void writeStudyFiles(const StudyResult& result, const std::string& dir) {
  std::filesystem::create_directories(dir);
  const std::string study_path = dir + "/study.csv";
  std::ofstream study(study_path);
  if (!study) throw InvalidInput(study_path, "cannot open for writing");
  study << "scene,integrator,dt,steps,repeats,wall_seconds,ns_per_step,orientation_error,omega_error,"
           "energy_drift,momentum_drift,newton_iterations_mean,failed,failure,reference,reference_error,options";
  for (const std::string& name : result.invariant_names) study << "," << name << "_drift";
  study << "\n";
  // A failed row has no error, time or drift: empty cells, never NaN.
  const auto cell = [](bool valid, double v) { return valid && std::isfinite(v) ? csvNumber(v) : std::string(); };
  for (const StudyRow& r : result.rows) {
    std::string failure = r.failure;
    std::replace(failure.begin(), failure.end(), '"', '\'');
    const bool ok = !r.failed;
    study << result.scene << "," << r.integrator << "," << csvNumber(r.dt) << "," << r.steps << ","
          << r.repeats << "," << cell(ok, r.wall_seconds) << "," << cell(ok, r.ns_per_step) << ","
          << cell(ok, r.orientation_error) << "," << cell(ok, r.omega_error) << ","
          << cell(ok, r.energy_drift) << "," << cell(ok && r.momentum_conserved, r.momentum_drift) << ","
          << cell(r.implicit, r.newton_iterations_mean) << "," << (r.failed ? "true" : "false") << ",\"" << failure
          << "\",\"" << result.reference << "\"," << csvNumber(result.reference_error) << ",\"" << r.options << "\"";
    for (std::size_t i = 0; i < result.invariant_names.size(); ++i)
      study << "," << cell(ok && i < r.invariant_drifts.size(), i < r.invariant_drifts.size() ? r.invariant_drifts[i] : 0.0);
    study << "\n";
  }
  const std::string drift_path = dir + "/drift.csv";
  std::ofstream drift(drift_path);
  if (!drift) throw InvalidInput(drift_path, "cannot open for writing");
  drift << "integrator,dt,t,energy_error,momentum_error";
  for (const std::string& name : result.invariant_names) drift << "," << name << "_error";
  drift << "\n";
  for (const DriftSample& s : result.drift) {
    drift << s.integrator << "," << csvNumber(s.dt) << "," << csvNumber(s.t) << "," << csvNumber(s.energy_error) << ","
          << (result.momentum_conserved ? csvNumber(s.momentum_error) : "");
    for (std::size_t i = 0; i < result.invariant_names.size(); ++i)
      drift << "," << (i < s.invariant_errors.size() ? csvNumber(s.invariant_errors[i]) : "");
    drift << "\n";
  }
}

bool plotStudy(const std::string& dir, std::string* why) {
  return runPlotScript("plot_study.py", dir, why);
}

void printStudyTable(std::ostream& out, const StudyResult& result) {
  out << "scene " << result.scene << ", t_end = " << result.t_end << " s; errors at t_end against the "
      << result.reference << "\n\n";
  out << "| integrator | dt | steps | time [ms] | ns/step | orientation error [rad] | omega error (rel) | "
         "energy drift | momentum drift | Newton its |\n";
  out << "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const StudyRow& r : result.rows) {
    out << "| " << r.integrator << " | " << number(r.dt) << " | " << r.steps << " | ";
    if (r.failed) {
      out << "failed | failed | failed: " << r.failure << " | | | | |\n";
      continue;
    }
    out << number(1e3 * r.wall_seconds) << " | " << number(r.ns_per_step) << " | ";
    out << number(r.orientation_error) << " | " << number(r.omega_error) << " | "
        << number(r.energy_drift) << " | " << (r.momentum_conserved ? number(r.momentum_drift) : "n/a")
        << " | " << (r.implicit ? number(r.newton_iterations_mean) : "-") << " |\n";
  }
}

}  // namespace app
}  // namespace lieflow
